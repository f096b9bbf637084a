"""The glTF-Transform CLI's standard steps keep the bake, with the shipped config (issue 48, item 3).

spot, baked with thickness, curvature, skin, edges (with fins), TAM, toon and fur, goes through
`gltf-transform meshopt | draco | quantize | optimize --compress meshopt --config
runtime-shaders/gltf-transform/gltf-transform.config.mjs`. Each output must pass `baker validate` (which decodes
Draco and meshopt first) and Khronos' validator. Where the edge data is kept, it is checked against the stepped
mesh itself: the edge list decoded after the step is the set of edges of the stepped triangles (by position), and
each edge keeps its flags, visibility codes and wireframe bits (edge i before = edge i after, matched by the
positions of its endpoints); Draco renumbers vertices inside its stream, and the data follows the order the stream
decodes to. Where a step cannot keep it (optimize's simplify makes new triangle edges) it must be gone, with one
warning line, fins included. The quantized attributes
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
KEEPS_EDGES = {"meshopt": True, "quantize": True, "draco": True, "optimize": False, "optimize-no-simplify": True}


@pytest.fixture(scope="module")
def cli():
    if shutil.which("node") is None or not CLI.exists():
        if os.environ.get("CI", "").lower() in ("1", "true", "yes"):
            pytest.fail("the glTF-Transform CLI is required in CI (scripts/install-node-tools installs it)")
        pytest.skip("node or @gltf-transform/cli not installed (run scripts/install-node-tools)")
    return CLI


SPOT_BAKES = ["thickness", "curvature", "skin", "edges", "tam", "toon", "fur"]
SPOT_OPTIONS = {
    "thickness": {"rays": 8, "texture_size": 64},
    "curvature": {"rings": 1, "smoothing": 1},
    "skin": {"width": 32, "height": 32, "samples": 16, "penumbra_size": 16},
    "tam": {"size": 32, "levels": 2, "candidates": 2},
    "toon": {"width": 16},
    "edges": {"fins": True},
    "fur": {"shells": 3, "texture_size": 16, "hairs": 50},
}


@pytest.fixture(scope="module")
def spot(cli, tmp_path_factory):
    path = tmp_path_factory.mktemp("gltf_transform_steps") / "spot.glb"
    save(baker.bake(SPOT, bakes=SPOT_BAKES, options=SPOT_OPTIONS), path)
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
    # data in mesh units follows the units the step left (quantize moves the dequantization into the node): each
    # fin vertex sits on its edge's end (POSITION = _FIN_V0 at corners 0 and 3, _FIN_V1 at 1 and 2, as baked), and
    # the fur's lengths times the node's scale are the baked lengths
    scale = np.cbrt(abs(np.linalg.det(_world(after, 0)[:3, :3])))
    for prim in after.json["meshes"][0]["primitives"]:
        if "_FIN_V0" not in prim["attributes"]:
            continue
        at = {name: to_float(after, prim["attributes"][name])[:, :3] for name in ("POSITION", "_FIN_V0", "_FIN_V1")}
        corner = to_float(after, prim["attributes"]["_FIN_CORNER"])[:, 0]
        end = np.where(((corner < 0.5) | (corner > 2.5))[:, None], at["_FIN_V0"], at["_FIN_V1"])
        assert np.abs(at["POSITION"] - end).max() < 1e-3 * np.ptp(at["POSITION"], axis=0).max(), step
    fur0, fur1 = (d.json["materials"][0]["extensions"]["BAKER_fur"] for d in (before, after))
    for name in ("length", "shellSpacing"):
        assert fur1[name] * scale == pytest.approx(fur0[name], rel=1e-5), (step, name)
    kept = EDGES in (after.json["meshes"][0]["primitives"][0].get("extensions") or {})
    assert kept == KEEPS_EDGES[step]
    warnings = [line for line in log.splitlines() if "@baker/gltf-transform" in line]
    if not kept:
        # gone, with one warning line naming the primitive, and its fins with it
        assert len(warnings) == 1 and "edge data" in warnings[0] and "dropped" in warnings[0], log
        assert all(VISIBILITY not in (p.get("extensions") or {}) and EDGES not in (p.get("extensions") or {})
                   for m in after.json["meshes"] for p in m["primitives"])
        # and no longer listed as used
        assert not {EDGES, VISIBILITY} & set(after.json.get("extensionsUsed", [])), after.json["extensionsUsed"]
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


BUNNY = Path(__file__).parents[2] / "shared" / "assets" / "meshes" / "stanford-bunny.obj"
EDGE_TECHNIQUES = "fins,outline"  # what the edge data draws (the viewer's switches)


def _clustered_obj(source: Path, out: Path, cell: float) -> Path:
    """``source`` decimated by vertex clustering (one vertex per ``cell``-sized grid cell, at its vertices' mean;
    triangles that collapse or repeat are dropped): a scan small enough for a software renderer."""
    vertices, faces = [], []
    for line in source.read_text().splitlines():
        if line.startswith("v "):
            vertices.append([float(x) for x in line.split()[1:4]])
        elif line.startswith("f "):
            faces.append([int(x.split("/")[0]) - 1 for x in line.split()[1:4]])
    vertices, faces = np.array(vertices), np.array(faces)
    _, cluster, counts = np.unique(np.floor((vertices - vertices.min(0)) / cell).astype(np.int64), axis=0,
                                   return_inverse=True, return_counts=True)
    cluster = cluster.reshape(-1)
    centers = np.zeros((len(counts), 3))
    np.add.at(centers, cluster, vertices)
    centers /= counts[:, None]
    tris = cluster[faces]
    tris = tris[(tris[:, 0] != tris[:, 1]) & (tris[:, 1] != tris[:, 2]) & (tris[:, 0] != tris[:, 2])]
    tris = tris[np.sort(np.unique(np.sort(tris, axis=1), axis=0, return_index=True)[1])]
    used = np.unique(tris)
    index = np.full(len(centers), -1)
    index[used] = np.arange(len(used))
    out.write_text("".join(f"v {x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in centers[used]) +
                   "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in index[tris]))
    return out


def test_three_and_babylon_draw_each_step_like_the_bake(spot, tmp_path):
    """Every technique on (?start=all), default view: each step's output of spot and of a scan (the Stanford bunny,
    decimated to 4.6k triangles), drawn by three.js and by Babylon.js (WebGL2), like the uncompressed file.
    quantize and meshopt move the dequantization into the node's scale: the fins' positions and the fur lengths
    follow it (src/units.js), the outline's pixel width is divided by the world scale (the hosts); Draco's custom
    attributes are decoded by the hosts (Babylon's loader decodes only the standard ones) and the edge data follows
    the stream's vertex order. optimize's simplify drops the edge data (with a warning): on the bunny, whose picture
    is much outline and fins, it is compared with the bake drawn without them (the full bake's SSIM is printed).
    """
    from scipy import ndimage
    from skimage.metrics import structural_similarity

    from baker.gltf.images import read_image
    from browser import BACKGROUND_RGB, build_viewer, require_tools, serve, shoot

    require_tools("gltf-transform steps", ("playwright-core", "three", "@babylonjs/core", "@babylonjs/loaders"))
    bunny = tmp_path / "bunny.glb"
    save(baker.bake(_clustered_obj(BUNNY, tmp_path / "bunny.obj", 0.006), bakes=SPOT_BAKES, options=SPOT_OPTIONS),
         bunny)
    steps = ["meshopt", "draco", "quantize", "optimize"]
    for asset, source in (("spot", spot), ("bunny", bunny)):
        shutil.copy(source, tmp_path / f"{asset}.plain.glb")
        for step in steps:
            _step(source, tmp_path / f"{asset}.{step}.glb", step)
    build_viewer(tmp_path, ("viewer.js", "babylon.js"))
    server, url = serve(tmp_path)
    shots = [(asset, name, engine) for asset in ("spot", "bunny") for engine in ("three", "babylon")
             for name in ("plain", "plain-no-edges", *steps)]
    try:
        jobs = [{"url": f"{url}/index.html?hud=0&start=all&src={asset}.{name.replace('-no-edges', '')}.glb"
                        f"{'&off=' + EDGE_TECHNIQUES if name.endswith('-no-edges') else ''}"
                        f"{'&engine=babylon' if engine == 'babylon' else ''}",
                 "out": str(tmp_path / f"{asset}.{name}.{engine}.png"), "width": 256, "height": 256}
                for asset, name, engine in shots]
        infos = shoot(jobs, tmp_path / "jobs.json")
    finally:
        server.shutdown()
    for job, info in zip(jobs, infos):
        assert info["ready"] and not info["errors"], (job["url"], info)

    def luma(asset, name, engine):
        image = read_image(tmp_path / f"{asset}.{name}.{engine}.png")[..., :3].astype(np.float32) / 255.0
        return image, ndimage.gaussian_filter(image, sigma=(1.0, 1.0, 0)) @ np.array([0.2126, 0.7152, 0.0722],
                                                                                       np.float32)

    background = np.array(BACKGROUND_RGB, np.float32) / 255.0
    for asset in ("spot", "bunny"):
        for engine in ("three", "babylon"):
            plain, plain_luma = luma(asset, "plain", engine)
            assert 0.05 < (np.abs(plain - background).max(axis=2) > 0.03).mean() < 0.9  # the asset is on screen
            no_edges = luma(asset, "plain-no-edges", engine)[1]
            for step in steps:
                stepped = luma(asset, step, engine)[1]
                ssim = structural_similarity(plain_luma, stepped, data_range=1.0)
                dropped = structural_similarity(no_edges, stepped, data_range=1.0)
                print(f"{asset} {engine} {step}: SSIM {ssim:.4f}, against the bake without edges {dropped:.4f}")
                edges_dropped = step == "optimize"  # simplify
                assert (dropped if edges_dropped and asset == "bunny" else ssim) >= 0.95, (asset, engine, step, ssim)
                if edges_dropped:
                    assert dropped >= 0.95 and dropped > ssim, (asset, engine, step, dropped, ssim)


def test_webgpu_backends_draw_quantize_and_draco_like_the_bake(spot, tmp_path):
    """The same on the WebGPU backends (three.js's WebGPURenderer, Babylon.js's WebGPUEngine; SwiftShader's adapter):
    the outline width under the quantized node's scale, and Draco's custom attributes and edge data."""
    from scipy import ndimage
    from skimage.metrics import structural_similarity

    from baker.gltf.images import read_image
    from browser import build_viewer, require_tools, serve, shoot

    require_tools("gltf-transform steps", ("playwright-core", "three", "@babylonjs/core", "@babylonjs/loaders"))
    shutil.copy(spot, tmp_path / "plain.glb")
    steps = ["quantize", "draco"]
    for step in steps:
        _step(spot, tmp_path / f"{step}.glb", step)
    build_viewer(tmp_path, ("viewer.js", "babylon.js", "three_webgpu.js"))
    server, url = serve(tmp_path)
    shots = [(name, engine) for engine in ("three-webgpu", "babylon-webgpu") for name in ("plain", *steps)]
    try:
        jobs = [{"url": f"{url}/index.html?hud=0&start=all&src={name}.glb&engine={engine}",
                 "out": str(tmp_path / f"{name}.{engine}.png"), "width": 256, "height": 256} for name, engine in shots]
        infos = shoot(jobs, tmp_path / "jobs.json", webgpu=True, timeout=1200)
    finally:
        server.shutdown()
    for job, info in zip(jobs, infos):
        assert info["ready"] and not info["errors"], (job["url"], info)

    def luma(name, engine):
        image = read_image(tmp_path / f"{name}.{engine}.png")[..., :3].astype(np.float32) / 255.0
        return ndimage.gaussian_filter(image, sigma=(1.0, 1.0, 0)) @ np.array([0.2126, 0.7152, 0.0722], np.float32)

    for engine in ("three-webgpu", "babylon-webgpu"):
        for step in steps:
            ssim = structural_similarity(luma("plain", engine), luma(step, engine), data_range=1.0)
            print(f"{engine} {step}: SSIM {ssim:.4f}")
            assert ssim >= 0.95, (engine, step, ssim)


def test_blender_addon_reads_the_quantized_attributes(tmp_path):
    """Blender's importer skips custom attributes stored as normalized integers (it makes FLOAT, INT and colour
    attributes only) and the add-on matched its edge marks by raw positions: after `gltf-transform quantize`, the
    add-on gives Blender every baked attribute with its value within one 12-bit step of the baked file's, and marks
    the same Freestyle edges (fandisk's creases), as for the baked file."""
    import json

    from scipy.spatial import cKDTree
    from test_blender import ADDON, FANDISK, run_blender

    blender_python = os.environ.get("BAKER_BPY_PYTHON")
    if not blender_python:
        if os.environ.get("CI", "").lower() in ("1", "true", "yes"):
            pytest.fail("BAKER_BPY_PYTHON is required in CI (scripts/install-bpy)")
        pytest.skip("BAKER_BPY_PYTHON not set (scripts/install-bpy)")
    plain, quantized = tmp_path / "fandisk.glb", tmp_path / "fandisk.quantize.glb"
    save(baker.bake(FANDISK, bakes=["thickness", "curvature", "edges"],
                    options={"thickness": {"rays": 8, "texture_size": 32}, "curvature": {"rings": 1}}), plain)
    if not CLI.exists():
        pytest.fail("@gltf-transform/cli is not installed (scripts/install-node-tools)")
    _step(plain, quantized, "quantize")
    report = tmp_path / "report.json"
    run_blender(blender_python, "import_report.py", "--addon", ADDON, "--out", report, "--", plain, quantized)
    entries = json.loads(report.read_text())
    (mesh0,), (mesh1,) = ([o for o in entries[str(p)]["objects"] if o["type"] == "MESH"] for p in (plain, quantized))
    assert entries[str(quantized)]["error"] is None

    doc0, doc1 = GltfDocument.load(plain), GltfDocument.load(quantized)
    prim0, prim1 = doc0.json["meshes"][0]["primitives"][0], doc1.json["meshes"][0]["primitives"][0]
    normalized = {n for n, a in prim1["attributes"].items()
                  if n.startswith("_") and doc1.json["accessors"][a].get("normalized")}
    assert {"_OUTLINE_NORMAL", "_PRINCIPAL_DIRECTION"} <= normalized, normalized  # (fandisk's thickness > 1)
    # Blender's vertices (glTF axes, the node's local space) in world space, against the baked file's vertices
    world = _world(doc1, 0)
    points1 = np.asarray(mesh1["positions"]) @ world[:3, :3].T + world[:3, 3]
    points0 = to_float(doc0, prim0["attributes"]["POSITION"])
    near = cKDTree(points0).query_ball_point(points1, r=2e-4 * np.ptp(points0, axis=0).max())
    assert all(near)
    for name in sorted(n for n in prim0["attributes"] if n.startswith("_")):
        assert name in mesh1["attributes"], f"Blender lacks {name}"
        baked = to_float(doc0, prim0["attributes"][name]).reshape(len(points0), -1)
        got = np.asarray(mesh1["attributes"][name]["values"], np.float64)[:, : baked.shape[1]]
        error = np.array([np.abs(baked[list(candidates)] - value).max(axis=1).min()
                          for candidates, value in zip(near, got)])
        step = 1.0 / (2 ** 11 - 1) if name in normalized else 1e-6 * max(1.0, np.abs(baked).max())
        assert error.max() <= step, (name, error.max())
    marks = [m.get("freestyle_marks", int(np.sum(m["attributes"].get("freestyle_edge", {}).get("values", 0))))
             for m in (mesh0, mesh1)]
    assert marks[0] > 100 and marks[1] == marks[0], marks


def test_preview_reads_the_quantized_attributes(spot, tmp_path):
    """`baker preview` draws what it gathers in world space: after `gltf-transform quantize` (same vertex order) every
    surface it gathers has the baked file's world positions (within the 16-bit step), its custom attributes within
    one 12-bit step (it read the raw integers before), and the fur's world spacing the baked one."""
    from baker import readers
    from baker.preview.core import gather_scene

    out = tmp_path / "spot.quantize.glb"
    _step(spot, out, "quantize")
    items0, items1 = (gather_scene(readers.read(p, require_triangles=False)).items for p in (spot, out))
    assert len(items0) == len(items1) > 0
    for a, b in zip(items0, items1):
        extent = np.ptp(a.positions, axis=0).max()
        assert np.abs(a.positions - b.positions).max() < 2e-4 * extent
        assert set(a.attributes) == set(b.attributes)
        for name in a.attributes:
            quantized = _normalized(out, name)
            step = 1.0 / (2 ** 11 - 1) if quantized else 1e-6 * max(1.0, float(np.abs(a.attributes[name]).max()))
            assert np.abs(a.attributes[name] - b.attributes[name]).max() <= step + 1e-6, name
        fur0, fur1 = a.data.get("fur"), b.data.get("fur")
        if fur0 is not None:
            assert fur1.shell_spacing * b.world_scale == pytest.approx(fur0.shell_spacing * a.world_scale, rel=1e-5)


def _normalized(path: Path, name: str) -> bool:
    doc = GltfDocument.load(path)
    accessor = doc.json["meshes"][0]["primitives"][0]["attributes"].get(name)
    return accessor is not None and bool(doc.json["accessors"][accessor].get("normalized"))


def test_three_and_babylon_read_the_quantized_attributes(spot, tmp_path):
    """three.js's GLTFLoader and @baker/babylon's accessor reader (in Node: examples/viewer/test/attribute_values.mjs,
    bundled here) read `gltf-transform quantize`'s normalized integers as numbers: every attribute of the quantized
    spot within its step of the baked file's values (positions in world space, through the node)."""
    import json

    from browser import VIEWER, require_tools

    require_tools("gltf-transform steps", ("three", "@babylonjs/core", "esbuild"))
    out = tmp_path / "spot.quantize.glb"
    _step(spot, out, "quantize")
    script = tmp_path / "attribute_values.mjs"
    bundle = subprocess.run(
        [str(VIEWER / "node_modules" / ".bin" / "esbuild"), "test/attribute_values.mjs", "--bundle", "--platform=node",
         "--format=esm", "--loader:.glsl=text", "--loader:.wgsl=text",
         "--alias:@baker/shared=../../runtime-shaders/shared/src/index.js", f"--outfile={script}", "--log-level=warning"],
        cwd=VIEWER, env={**os.environ, "NODE_PATH": "node_modules"}, capture_output=True, text=True, timeout=120)
    assert bundle.returncode == 0, bundle.stderr
    result = subprocess.run(["node", str(script), str(out)], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    read = json.loads(result.stdout.strip().splitlines()[-1])

    before, after = _load(spot), _load(out)
    prim0, prim1 = before.json["meshes"][0]["primitives"][0], after.json["meshes"][0]["primitives"][0]
    world = _world(after, 0)
    assert {n for n, a in prim1["attributes"].items() if after.json["accessors"][a].get("normalized")} >= \
        {"POSITION", "NORMAL", "_THICKNESS", "_OUTLINE_NORMAL", "_PRINCIPAL_DIRECTION"}
    for reader in ("three", "babylon"):
        for name, accessor in prim0["attributes"].items():
            baked = to_float(before, accessor)
            values = np.asarray(read[reader][name], np.float64).reshape(baked.shape)
            if name == "POSITION":
                values = values @ world[:3, :3].T + world[:3, 3]
                step = 2e-4 * np.ptp(baked, axis=0).max()
            elif after.json["accessors"][prim1["attributes"][name]].get("normalized"):
                step = 1.0 / (2 ** 11 - 1) if name.startswith("_") else 1.0 / 127  # 12-bit generic; 8-bit normals
            else:
                step = 1e-6 * max(1.0, float(np.abs(baked).max()))
            assert np.abs(values - baked).max() <= step, (reader, name, np.abs(values - baked).max())
