"""The glTF-Transform CLI's standard steps keep the bake, with the shipped config (issue 48, item 3).

spot, baked with thickness, curvature, skin, edges (with fins), TAM, toon and fur, goes through
`gltf-transform meshopt | draco | quantize | optimize --compress meshopt --config
runtime-shaders/gltf-transform/gltf-transform.config.mjs`. Each output must pass `baker validate` (which decodes
Draco and meshopt first) and Khronos' validator. Where the edge data is kept, it is checked against the stepped
mesh itself: the edge list decoded after the step is the set of edges of the stepped triangles (by position), and
each edge keeps its flags, visibility codes and wireframe bits (edge i before = edge i after, matched by the
positions of its endpoints). Where a step cannot keep it (Draco renumbers vertices inside its stream; optimize's
simplify makes new triangle edges) it must be gone, with one warning line, fins included. The quantized attributes
read back through baker's reader within their step.
"""
from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import baker
from baker import validate
from baker.gltf.accessors import to_float
from baker.gltf.compression import decompress
from baker.gltf.document import GltfDocument
from baker.pipeline import save
from conftest import assert_khronos_clean

PACKAGE = Path(__file__).parents[1] / "runtime-shaders" / "gltf-transform"
CONFIG = PACKAGE / "gltf-transform.config.mjs"
CLI = PACKAGE / "node_modules" / ".bin" / "gltf-transform"
SPOT = Path(__file__).parents[1] / "examples" / "spot" / "spot.obj"
EDGES, VISIBILITY = "BAKER_edges", "EXT_mesh_primitive_edge_visibility"
STEPS = {"meshopt": ["meshopt"], "draco": ["draco"], "quantize": ["quantize"],
         "optimize": ["optimize", "--compress", "meshopt"],
         # weld, reorder and meshopt without simplify: the edge data is remapped, not dropped
         "optimize-no-simplify": ["optimize", "--compress", "meshopt", "--simplify", "false"]}
KEEPS_EDGES = {"meshopt": True, "quantize": True, "draco": False, "optimize": False, "optimize-no-simplify": True}


@pytest.fixture(scope="module")
def cli():
    if shutil.which("node") is None or not CLI.exists():
        if os.environ.get("CI", "").lower() in ("1", "true", "yes"):
            pytest.fail("the glTF-Transform CLI is required in CI (scripts/install-node-tools installs it)")
        pytest.skip("node or @gltf-transform/cli not installed (run scripts/install-node-tools)")
    return CLI


@pytest.fixture(scope="module")
def spot(cli, tmp_path_factory):
    path = tmp_path_factory.mktemp("gltf_transform_steps") / "spot.glb"
    save(baker.bake(SPOT, bakes=["thickness", "curvature", "skin", "edges", "tam", "toon", "fur"], options={
        "thickness": {"rays": 8, "texture_size": 64},
        "curvature": {"rings": 1, "smoothing": 1},
        "skin": {"width": 32, "height": 32, "samples": 16, "penumbra_size": 16},
        "tam": {"size": 32, "levels": 2, "candidates": 2},
        "toon": {"width": 16},
        "edges": {"fins": True},
        "fur": {"shells": 3, "texture_size": 16, "hairs": 50},
    }), path)
    return path


def _step(src: Path, out: Path, step: str) -> str:
    result = subprocess.run([str(CLI), *STEPS[step], str(src), str(out), "--config", str(CONFIG)],
                            capture_output=True, text=True, timeout=240)
    assert result.returncode == 0, result.stderr + result.stdout
    return result.stdout + result.stderr


def _load(path: Path) -> GltfDocument:
    doc = GltfDocument.load(path)
    decompress(doc)
    return doc


def _world(doc: GltfDocument, mesh: int) -> np.ndarray:
    """The world matrix of the (one) node drawing ``mesh``: quantize moves the dequantization into the node."""
    nodes = doc.json.get("nodes") or []
    parent = {c: i for i, n in enumerate(nodes) for c in n.get("children", [])}

    def local(n):
        if "matrix" in n:
            return np.array(n["matrix"], float).reshape(4, 4).T
        t, s = np.array(n.get("translation", [0, 0, 0]), float), np.array(n.get("scale", [1, 1, 1]), float)
        x, y, z, w = n.get("rotation", [0, 0, 0, 1])
        r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                      [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                      [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
        m = np.eye(4)
        m[:3, :3], m[:3, 3] = r * s, t
        return m

    node = next(i for i, n in enumerate(nodes) if n.get("mesh") == mesh)
    matrix = local(nodes[node])
    while node in parent:
        node = parent[node]
        matrix = local(nodes[node]) @ matrix
    return matrix


def _edge_data(doc: GltfDocument):
    """Positions (world), triangles and the edge data of the mesh's first (baked) primitive."""
    prim = doc.json["meshes"][0]["primitives"][0]
    local = to_float(doc, prim["attributes"]["POSITION"])
    world = local @ _world(doc, 0)[:3, :3].T + _world(doc, 0)[:3, 3]
    tris = doc.accessor(prim["indices"]).reshape(-1, 3).astype(np.int64)
    ext = (prim.get("extensions") or {})
    return local, world, tris, ext.get(EDGES), ext.get(VISIBILITY)


def _key(points: np.ndarray, a, b) -> tuple:
    pa, pb = tuple(points[a]), tuple(points[b])
    return (pa, pb) if pa <= pb else (pb, pa)


def _per_edge(doc, local, tris, edges_ext, vis_ext):
    """edge index -> (sorted nonzero visibility codes, wireframe bit count) over the half-edges on that edge."""
    edges = doc.accessor(edges_ext["edges"]).astype(np.int64)
    index = {_key(local, a, b): i for i, (a, b) in enumerate(edges)}
    vis = np.unpackbits(doc.accessor(vis_ext["visibility"]).astype(np.uint8), bitorder="little")
    codes = (vis[0::2] + 2 * vis[1::2])[: tris.size]
    mask = doc.accessor(edges_ext["wireframeMask"]).astype(np.int64)
    out = {i: ([], 0) for i in range(len(edges))}
    for t, tri in enumerate(tris):
        for k in range(3):
            i = index[_key(local, tri[k], tri[(k + 1) % 3])]
            c, w = out[i]
            out[i] = (sorted(c + [int(codes[3 * t + k])] if codes[3 * t + k] else c), w + ((mask[t] >> k) & 1))
    return edges, out


@pytest.mark.parametrize("step", list(STEPS))
def test_step_keeps_the_bake(spot, tmp_path, step):
    out = tmp_path / f"spot.{step}.glb"
    log = _step(spot, out, step)
    report = validate.validate_file(out, khronos=False)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert_khronos_clean(out)

    before, after = _load(spot), _load(out)
    kept = EDGES in (after.json["meshes"][0]["primitives"][0].get("extensions") or {})
    assert kept == KEEPS_EDGES[step]
    warnings = [line for line in log.splitlines() if "@baker/gltf-transform" in line]
    if not kept:
        # gone, with one warning line naming the primitive, and its fins with it
        assert len(warnings) == 1 and "edge data" in warnings[0] and "dropped" in warnings[0], log
        assert all(VISIBILITY not in (p.get("extensions") or {}) and EDGES not in (p.get("extensions") or {})
                   for m in after.json["meshes"] for p in m["primitives"])
        return
    assert not warnings, log
    local0, world0, tris0, edges0, vis0 = _edge_data(before)
    local1, world1, tris1, edges1, vis1 = _edge_data(after)
    # the edge list after the step is exactly the edge set of the stepped triangles, by position
    list1 = after.accessor(edges1["edges"]).astype(np.int64)
    decoded = {_key(local1, a, b) for a, b in list1}
    recomputed = {_key(local1, t[k], t[(k + 1) % 3]) for t in tris1 for k in range(3)}
    assert len(decoded) == len(list1) == len(recomputed) and decoded == recomputed
    # edge i is the same edge (its endpoints' world positions) with the same flags, angle, codes and mask bits
    list0, per0 = _per_edge(before, local0, tris0, edges0, vis0)
    _, per1 = _per_edge(after, local1, tris1, edges1, vis1)
    ends1 = world1[list1]
    assert ends1.shape == world0[list0].shape
    tolerance = 2e-3 * np.ptp(world0, axis=0).max()  # int16 positions of quantize/meshopt
    same = np.minimum(np.abs(world0[list0] - ends1).max(axis=(1, 2)),
                      np.abs(world0[list0][:, ::-1] - ends1).max(axis=(1, 2)))
    assert same.max() < tolerance, same.max()
    for name in ("flags", "dihedralAngles"):
        assert (name in edges0) == (name in edges1), name  # dihedralAngles only on request (--edges-dihedral-angles)
        if name in edges0:
            assert np.array_equal(before.accessor(edges0[name]), after.accessor(edges1[name])), name
    assert per0 == per1
    assert after.accessor(vis1["silhouetteMates"]).shape == before.accessor(vis0["silhouetteMates"]).shape


def test_quantized_attributes_read_back_within_their_step(spot, tmp_path):
    out = tmp_path / "spot.quantize.glb"
    _step(spot, out, "quantize")
    before, after = _load(spot), _load(out)
    prim0, prim1 = before.json["meshes"][0]["primitives"][0], after.json["meshes"][0]["primitives"][0]
    quantized = [name for name, a in prim1["attributes"].items()
                 if name.startswith("_") and after.json["accessors"][a].get("normalized")]
    assert {"_THICKNESS", "_OUTLINE_NORMAL", "_PRINCIPAL_DIRECTION"} <= set(quantized), quantized
    for name in quantized:
        acc = after.json["accessors"][prim1["attributes"][name]]
        signed = acc["componentType"] in (5120, 5122)
        values0, values1 = to_float(before, prim0["attributes"][name]), to_float(after, prim1["attributes"][name])
        assert values1.min() >= (-1.0 if signed else 0.0) and values1.max() <= 1.0
        # quantize keeps the vertex order and stores custom attributes with 12 bits (`--quantize-generic`): baker's
        # reader (c / max, glTF 3.11) gives each value back within one 12-bit step
        assert np.abs(values0 - values1).max() <= 1.0 / (2 ** (12 - signed) - 1), name


def test_validator_accepts_quantized_forms_where_precision_permits(spot, tmp_path):
    """KHR_mesh_quantization's normalized forms of `_OUTLINE_NORMAL` pass while they hold unit vectors to their
    step (int8 and int16); int8 of vectors 2% short, or integers not normalized, are refused."""
    def variant(label, dtype, normalized, scale=1.0):
        doc = GltfDocument.load(spot)
        prim = doc.json["meshes"][0]["primitives"][0]
        normals = to_float(doc, prim["attributes"]["_OUTLINE_NORMAL"])[:, :3] * scale
        stored = np.round(normals * np.iinfo(dtype).max).astype(dtype)
        prim["attributes"]["_OUTLINE_NORMAL"] = doc.add_accessor(stored, normalized=normalized)
        path = tmp_path / f"{label}.glb"
        doc.save(path)
        report = validate.validate_file(path, khronos=False)
        return {m["code"] for m in report["issues"]["messages"] if m["severity"] == 0}

    assert variant("int8", np.int8, True) == set()
    assert variant("int16", np.int16, True) == set()
    assert variant("int8_short", np.int8, True, scale=0.98) == {"BAKER_EDGES_OUTLINE_NOT_UNIT"}
    assert variant("int16_raw", np.int16, False) == {"BAKER_EDGES_OUTLINE_ACCESSOR_FORMAT"}


def test_hair_keeps_its_strands_through_optimize(cli, tmp_path):
    """optimize's join would merge the guide and child strand primitives and drop BAKER_hair: the classes keep them
    apart, and the strands keep their vertex order (each strand a run of verticesPerStrand vertices)."""
    from baker.cli import main as baker_main
    from test_gltf_transform import _write_sphere_obj

    sphere, hair, out = tmp_path / "sphere.obj", tmp_path / "hair.glb", tmp_path / "hair.optimize.glb"
    _write_sphere_obj(sphere)
    assert baker_main(["hair", str(sphere), "--guides", "12", "--children", "2", "--segments", "4",
                       "--iterations", "2", "-o", str(hair), "-q"]) == 0
    log = _step(hair, out, "optimize")
    assert "@baker/gltf-transform" not in log, log
    report = validate.validate_file(out, khronos=False)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert_khronos_clean(out)
    before, after = _load(hair), _load(out)
    strands = 0
    for m, mesh in enumerate(before.json["meshes"]):
        m1 = next(i for i, x in enumerate(after.json["meshes"]) if x.get("name") == mesh.get("name"))
        for p, prim in enumerate(mesh["primitives"]):
            ext = (prim.get("extensions") or {}).get("BAKER_hair")
            if not ext:
                continue
            prim1 = after.json["meshes"][m1]["primitives"][p]
            assert (prim1.get("extensions") or {}).get("BAKER_hair", {}).get("strandCount") == ext["strandCount"]
            x0 = to_float(before, prim["attributes"]["POSITION"]) @ _world(before, m)[:3, :3].T + _world(before, m)[:3, 3]
            x1 = to_float(after, prim1["attributes"]["POSITION"]) @ _world(after, m1)[:3, :3].T + _world(after, m1)[:3, 3]
            assert x1.shape == x0.shape == (ext["strandCount"] * ext["verticesPerStrand"], 3)
            assert np.abs(x0 - x1).max() < 1e-3 * np.ptp(x0, axis=0).max()  # int16 positions
            strands += ext["strandCount"]
    assert strands > 12
