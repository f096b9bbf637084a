"""Compact by default (issue 48): all surface bakes of a scan, the Stanford bunny (2.4 MB OBJ, 69,451 triangles), as
a GLB against the input's bytes, plain and with `--compress meshopt`; and what made it smaller is read back whole.

The issue's bar is 3x plain and 1.5x compressed; this branch measures 3.57x and 1.64x (benchmarks/RESULTS.md,
"compact by default"; `meshopt` stores the float vertex attributes through the EXPONENTIAL and OCTAHEDRAL filters,
2.30x without them), so the bounds here are the measured sizes plus 2% (the bake is deterministic for a seed): they catch a regression,
not the bar, which needs the next steps RESULTS lists (vertex attributes in fewer bytes).
The full bunny, not a decimated one: what dominates is per vertex and per edge, and a coarser mesh would shift the
fixed costs (textures, coverage mips) against the input's bytes, so a scaled target would say little about scans.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import baker
from baker.gltf.document import GltfDocument
from baker.gltf.images import decoded_texture
from baker.gltf.ktx2 import coverage_mips_bytes, decode_ktx2
from baker.pipeline import save
from baker.texels.alpha_mips import alpha_mip_chain, read_coverage_mips

BUNNY = Path("/work/shared/assets/meshes/stanford-bunny.obj")  # as tests/browser.py
SURFACE_BAKES = ["thickness", "curvature", "skin", "edges", "tam", "toon", "fur"]  # `baker bake --bakes` but
# caustics (a water surface of its own) and normal-blur (needs a normal map)
PLAIN_BOUND = 3.57 * 1.02  # x the OBJ's bytes
MESHOPT_BOUND = 1.64 * 1.02


@pytest.fixture(scope="module")
def bunny(tmp_path_factory):
    folder = tmp_path_factory.mktemp("bunny")
    asset = baker.bake(str(BUNNY), bakes=SURFACE_BAKES, seed=0)
    save(asset, folder / "plain.glb")
    save(asset, folder / "meshopt.glb", compress="meshopt")
    return folder


def test_all_bakes_of_a_scan_stay_within_the_measured_ratio(bunny):
    size = BUNNY.stat().st_size
    plain, packed = (bunny / "plain.glb").stat().st_size, (bunny / "meshopt.glb").stat().st_size
    print(f"bunny all bakes: plain {plain:,} ({plain / size:.2f}x), meshopt {packed:,} ({packed / size:.2f}x)")
    assert plain <= PLAIN_BOUND * size and packed <= MESHOPT_BOUND * size
    assert packed < 0.5 * plain


def test_what_is_left_out_is_derivable_and_the_chains_are_whole(bunny):
    doc = GltfDocument.load(bunny / "plain.glb")
    prim = doc.json["meshes"][0]["primitives"][0]
    # the stroke u axis and the dihedral angles are not stored (each derivable: tests/techniques/test_tam_strokes.py,
    # tests/techniques/test_edges.py); the opposite vertices neither
    assert "_HATCHING_DIRECTION" not in prim["attributes"]
    edges = prim["extensions"]["BAKER_edges"]
    assert "dihedralAngles" not in edges and "oppositeVertices" not in edges and "edges" in edges
    # every coverage chain stores levels 1.. only, and read back it is the whole chain of the PNG, level 0 the PNG
    fur = doc.json["materials"][0]["extensions"]["BAKER_fur"]
    assert len(fur["coverageMips"]) == fur["shellCount"]
    for entry in fur["coverageMips"][::5]:
        png = decoded_texture(doc, entry["texture"])
        stored = decode_ktx2(coverage_mips_bytes(doc, entry))["levels"]
        assert entry["firstLevel"] == 1 and stored[0].shape == (png.shape[0] // 2, png.shape[1] // 2, 4)
        levels = read_coverage_mips(doc, entry)
        assert len(levels) == entry["levelCount"] == len(stored) + 1 and np.array_equal(levels[0], png)
        rebuilt = alpha_mip_chain(png, entry["alphaCutoff"], transfer="gamma2.2").levels
        assert all(np.array_equal(a, b) for a, b in zip(levels, rebuilt))
