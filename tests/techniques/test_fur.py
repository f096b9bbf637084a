"""Fur shells and fins: shell coverage against the analytic union of the hair discs, files written and read back."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

import baker
from baker.techniques.fur.options import FurOptions
from baker.techniques.fur.kernel import bake_fur_textures, make_volume, shell_heights
from baker.gltf.document import GltfDocument
from baker.pipeline import save
from baker.validate import validate_file
from conftest import assert_khronos_clean

SPOT = str(Path(__file__).resolve().parents[2] / "examples" / "spot" / "spot.obj")


def test_shell_coverage_is_the_union_of_hair_discs():
    opts = FurOptions(shells=8, texture_size=256, hairs=600)
    tex = bake_fur_textures(opts, seed=4)
    vol = make_volume(opts, seed=4)
    for i, h in enumerate(shell_heights(opts.shells)):
        alive = vol.height > h
        r = opts.root_radius + (opts.tip_radius - opts.root_radius) * h / vol.height[alive]
        # independent discs at uniform positions in a periodic unit tile: P(texel uncovered) = prod(1 - pi r^2)
        expected = 1.0 - np.prod(1.0 - math.pi * r ** 2)
        assert abs(tex.shells[i, ..., 3].mean() / 255.0 - expected) < 0.02 + 0.1 * expected, (i, expected)
    # taller shells hold fewer, thinner hairs
    assert (np.diff(tex.coverage) < 0).all()
    # the fin: sparse at the tip (row 0), dense at the root
    alpha = tex.fin[..., 3].mean(axis=1)
    assert alpha[: len(alpha) // 4].mean() < alpha[-len(alpha) // 4:].mean()


def test_tileable():
    # a hair crossing the tile border shows up on the other side: opposite edges continue each other
    tex = bake_fur_textures(FurOptions(shells=2, texture_size=128, hairs=3000), seed=1)
    a = tex.shells[0, ..., 3].astype(float)
    seam = np.abs(a[:, 0] - a[:, -1]).mean()
    inner = np.abs(a[:, 64] - a[:, 63]).mean()
    assert seam < 2.0 * inner + 1.0


def test_fur_bake_writes_valid_gltf(tmp_path):
    opts = {"fins": True, "shells": 4, "texture_size": 32, "hairs": 200}
    asset = baker.bake(SPOT, bakes=["fur"], options={"fur": opts}, seed=2)
    out = tmp_path / "fur.glb"
    save(asset, out)
    report = validate_file(out, khronos=False)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert_khronos_clean(out)
    doc = GltfDocument.load(out)
    material = doc.json["materials"][doc.json["meshes"][0]["primitives"][0]["material"]]
    ext = material["extensions"]["BAKER_fur"]
    assert ext["shellCount"] == 4 and len(ext["shellTextures"]) == 4
    assert math.isclose(ext["shellSpacing"] * 4, ext["length"], rel_tol=1e-9)
    # shell texture 0 read back from the file is the kernel's
    kernel = bake_fur_textures(FurOptions(**opts), seed=2)
    image = doc.json["textures"][ext["shellTextures"][0]["index"]]["source"]
    from PIL import Image
    import io

    stored = np.array(Image.open(io.BytesIO(doc.image_bytes(image))))  # PIL: straight alpha, as PNG stores it
    assert np.array_equal(stored, kernel.shells[0])
    # fins: one degenerate quad per edge of the (closed) mesh: E = 3F / 2 after welding
    (fin_ref,) = ext["fins"]
    fin = doc.json["meshes"][fin_ref["mesh"]]["primitives"][fin_ref["primitive"]]
    assert fin["extensions"]["BAKER_fur"]["finsOf"] == 0
    faces = len(doc.accessor(doc.json["meshes"][0]["primitives"][0]["indices"])) // 3
    pos = doc.accessor(fin["attributes"]["POSITION"])
    assert len(pos) == 4 * (3 * faces // 2)
    tri = pos[doc.accessor(fin["indices"]).reshape(-1, 3)]
    area = np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    assert area.max() < 1e-6  # plain viewers rasterize nothing
    n = doc.accessor(fin["attributes"]["_FUR_FIN_NORMAL"])
    assert np.allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-5)
    # same seed, same bytes
    again = tmp_path / "again.glb"
    save(baker.bake(SPOT, bakes=["fur"], options={"fur": opts}, seed=2), again)
    assert again.read_bytes() == out.read_bytes()


def test_fur_without_fins(tmp_path):
    """Fins are opt-in (compact by default: on the bunny they are 40 of the 54 MB of all bakes)."""
    asset = baker.bake(SPOT, bakes=["fur"], options={"fur": {"shells": 2, "texture_size": 16, "hairs": 50}})
    doc = asset.doc
    assert len(doc.json["meshes"][0]["primitives"]) == 1
    ext = doc.json["materials"][0]["extensions"]["BAKER_fur"]
    assert ext["fins"] == []
    # no fins, no fin texture: only the shells and their coverage-preserving chains
    assert "finTexture" not in ext and len(doc.json["textures"]) == 2
    assert sorted(chain["texture"] for chain in ext["coverageMips"]) == [t["index"] for t in ext["shellTextures"]]
    out = tmp_path / "no_fins.glb"
    save(asset, out)
    assert validate_file(out, khronos=False)["issues"]["numErrors"] == 0


def test_fur_unwraps_a_mesh_without_uvs(tmp_path):
    """Spot without its ``vt`` lines (issue 35, item 2): ``--bakes thickness,fur,edges`` bakes all three (a process,
    exit 0, nothing on stderr); fur gives the mesh a TEXCOORD_0 (an xatlas layout, as tam and the texture bakes
    do), the file passes ``baker validate`` and Khronos' validator, and tileSize is sqrt(surface area / UV area) /
    tiling measured on the written file."""
    import re
    import subprocess
    import sys

    text = Path(SPOT).read_text()
    bare = tmp_path / "bare.obj"
    bare.write_text(re.sub(r"(\d+)/\d*(/\d+)?", r"\1", "".join(line for line in text.splitlines(True)
                                                                 if not line.startswith("vt "))))
    out = tmp_path / "out.glb"
    cli = [sys.executable, "-m", "baker.cli"]
    result = subprocess.run(cli + ["bake", str(bare), "-o", str(out), "--bakes", "thickness,fur,edges", "-q",
                                   "--thickness-rays", "4", "--thickness-texture-size", "32", "--fur-fins", "true",
                                   "--fur-shells", "2", "--fur-texture-size", "16", "--fur-hairs", "50"],
                            capture_output=True, text=True)
    assert result.returncode == 0 and result.stderr == "", result.stderr
    checked = subprocess.run(cli + ["validate", "--no-khronos", str(out)], capture_output=True, text=True)
    assert checked.returncode == 0, checked.stdout + checked.stderr
    assert_khronos_clean(out)
    doc = GltfDocument.load(out)
    prim = doc.json["meshes"][0]["primitives"][0]
    extensions = doc.json["materials"][prim["material"]]["extensions"]
    assert {"BAKER_fur", "BAKER_thickness"} <= set(extensions) and "BAKER_edges" in prim["extensions"]
    positions = doc.accessor(prim["attributes"]["POSITION"]).astype(np.float64)
    uv = doc.accessor(prim["attributes"]["TEXCOORD_0"]).astype(np.float64)
    faces = doc.accessor(prim["indices"]).reshape(-1, 3)
    source = np.array([line.split()[1:4] for line in text.splitlines() if line.startswith("v ")], np.float64)
    # the unwrap splits vertices along its seams: the same surface, every position one of the file's
    assert len(faces) == sum(1 for line in text.splitlines() if line.startswith("f "))
    assert np.unique(positions, axis=0).shape == np.unique(source.astype(np.float32), axis=0).shape
    assert uv.min() >= 0.0 and uv.max() <= 1.0
    p, t = positions[faces], uv[faces]
    area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1).sum()
    e1, e2 = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
    uv_area = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).sum()
    assert 0.3 < uv_area <= 1.0  # a packed atlas, not a degenerate layout
    fur = extensions["BAKER_fur"]
    assert math.isclose(fur["tileSize"], math.sqrt(area / uv_area) / fur["tiling"], rel_tol=1e-4)
