"""Compressed inputs are decoded, not refused (issue 15, item 6): KHR_draco_mesh_compression through DracoPy and
EXT_meshopt_compression through meshopt (baker/gltf/compression.py).

The compressed GLBs are made here: the geometry encoded by the codecs' own Python encoders, the glTF JSON around the
encoded bytes written by hand. Each is baked; the output is read back with the hand-written reader of
tests/test_preservation.py and compared with the source mesh (Draco may reorder vertices and triangles: triangles
are compared as sets of source vertices found by position), and Khronos glTF-Validator reports no errors.
"""
from __future__ import annotations

import json
import struct
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh
from scipy.spatial import cKDTree

from conftest import assert_khronos_clean, khronos_validate
from test_preservation import read_accessor, read_gltf

FAST = ["--thickness-rays", "4", "--thickness-per-texel", "false"]


def source_mesh():
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=1.0)
    return (np.asarray(sphere.vertices, np.float32), np.asarray(sphere.vertex_normals, np.float32),
            np.asarray(sphere.faces, np.int64))


def write_glb(path: Path, gltf: dict, binary: bytes) -> None:
    text = json.dumps(gltf).encode()
    text += b" " * (-len(text) % 4)
    binary = binary + b"\0" * (-len(binary) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(binary), 0x004E4942) + binary
    path.write_bytes(struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks)


def scene(extensions_used: list, extensions_required: list) -> dict:
    return {"asset": {"version": "2.0", "generator": "tests/test_compressed.py (by hand)"},
            "extensionsUsed": extensions_used, "extensionsRequired": extensions_required,
            "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": "ball"}],
            "materials": [{"name": "grey", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1.0]}}]}


def bake(src: Path, out: Path, bakes: str = "thickness,edges") -> None:
    result = subprocess.run([sys.executable, "-m", "baker.cli", "bake", str(src), "-o", str(out), "--bakes", bakes,
                             "-q", *FAST], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr


def triangles_by_source_vertex(positions, faces, source_positions, tolerance) -> list:
    """Each triangle as the source vertices at its corners (found by position), rotated to start at the smallest
    so winding counts; sorted."""
    distance, nearest = cKDTree(source_positions).query(positions)
    assert distance.max() < tolerance, distance.max()
    tris = nearest[faces]
    rolled = [tuple(np.roll(t, -int(np.argmin(t)))) for t in tris]
    return sorted(rolled)


def assert_decoded_output(out: Path, extension: str) -> dict:
    assert_khronos_clean(out)
    report = khronos_validate(out)
    # nothing of the input is left unused (the compressed bufferView took decoded data); baker's own accessors are
    # referenced from BAKER_* extensions, which Khronos does not follow
    input_objects = ("/bufferViews/0", "/bufferViews/1", "/bufferViews/2", "/accessors/0", "/accessors/1",
                     "/accessors/2", "/buffers")
    assert not [m for m in report["issues"]["messages"] if m["code"] == "UNUSED_OBJECT"
                and any(m.get("pointer", "") == p or m.get("pointer", "").startswith(p + "/") for p in input_objects)]
    g, buffers = read_gltf(out)
    assert extension not in g.get("extensionsUsed", []) and extension not in g.get("extensionsRequired", [])
    prim = g["meshes"][0]["primitives"][0]
    assert extension not in prim.get("extensions", {})
    assert all(extension not in v.get("extensions", {}) for v in g["bufferViews"])
    assert len(g["buffers"]) == 1
    record = g["asset"]["extras"]["baker"]["decompressed"]
    assert [r["extension"] for r in record] == [extension]
    assert {"_THICKNESS", "_OUTLINE_NORMAL"} <= set(prim["attributes"])  # the bakes ran on real geometry
    return g, buffers, record[0]


# ---------------------------------------------------------------------------------------------- Draco
def draco_glb(path: Path, nan_vertex: int | None = None):
    """``nan_vertex``: that vertex's position is NaN (encoded without quantization, which keeps it)."""
    import DracoPy

    positions, normals, faces = source_mesh()
    if nan_vertex is not None:
        positions[nan_vertex] = np.nan
    encoded = DracoPy.encode(positions.astype(np.float64), faces.astype(np.uint32),
                             quantization_bits=14 if nan_vertex is None else 0,
                             normals=normals.astype(np.float64),
                             normal_quantization_bits=10, compression_level=7)
    probe = DracoPy.decode(encoded)  # the counts and ids the JSON must state, from the encoder's side
    ids = {a["attribute_type"]: a["unique_id"] for a in probe.attributes}
    n = len(probe.points)
    points = np.asarray(probe.points, np.float32)
    gltf = scene(["KHR_draco_mesh_compression"], ["KHR_draco_mesh_compression"])
    gltf["accessors"] = [
        {"componentType": 5126, "count": n, "type": "VEC3", "min": np.nanmin(points, 0).tolist(),
         "max": np.nanmax(points, 0).tolist()},
        {"componentType": 5126, "count": n, "type": "VEC3"},
        {"componentType": 5125 if n > 65535 else 5123, "count": int(probe.faces.size), "type": "SCALAR"},
    ]
    gltf["meshes"] = [{"name": "ball", "primitives": [{
        "attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0,
        "extensions": {"KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": ids[0],
                                                                                      "NORMAL": ids[1]}}}}]}]
    gltf["bufferViews"] = [{"buffer": 0, "byteLength": len(encoded)}]
    gltf["buffers"] = [{"byteLength": len(encoded)}]
    write_glb(path, gltf, encoded)
    return positions, normals, faces


def test_draco_input_is_decoded_and_baked(tmp_path):
    src = tmp_path / "draco.glb"
    positions, normals, faces = draco_glb(src)
    assert_khronos_clean(src)
    out = tmp_path / "out.glb"
    bake(src, out)
    g, buffers, record = assert_decoded_output(out, "KHR_draco_mesh_compression")
    assert record["decoder"].startswith("DracoPy") and record["primitives"] == ["/meshes/0/primitives/0"]
    prim = g["meshes"][0]["primitives"][0]
    got_pos = read_accessor(g, buffers, prim["attributes"]["POSITION"]).astype(np.float64)
    got_nor = read_accessor(g, buffers, prim["attributes"]["NORMAL"]).astype(np.float64)
    got_idx = read_accessor(g, buffers, prim["indices"])[:, 0].astype(np.int64).reshape(-1, 3)
    step = 2.0 / (1 << 14)  # 14-bit quantization over the sphere's extent
    assert triangles_by_source_vertex(got_pos, got_idx, positions, 2 * step) == sorted(
        tuple(np.roll(t, -int(np.argmin(t)))) for t in faces)
    nearest = cKDTree(positions).query(got_pos)[1]
    assert np.abs(got_nor - normals[nearest]).max() < 0.01  # 10-bit normals
    acc = g["accessors"][prim["attributes"]["POSITION"]]
    assert np.allclose(acc["min"], got_pos.min(0)) and np.allclose(acc["max"], got_pos.max(0))


def test_draco_output_as_gltf_is_clean(tmp_path):
    src = tmp_path / "draco.glb"
    draco_glb(src)
    out = tmp_path / "out" / "ball.gltf"
    out.parent.mkdir()
    bake(src, out, bakes="edges")
    assert_khronos_clean(out)
    g = json.loads(out.read_text())
    assert "KHR_draco_mesh_compression" not in g.get("extensionsUsed", []) + g.get("extensionsRequired", [])
    assert not g["meshes"][0]["primitives"][0].get("extensions", {}).get("KHR_draco_mesh_compression")


# ---------------------------------------------------------------------------------------------- meshopt
def meshopt_glb(path: Path, nan_vertex: int | None = None, extension: str = "EXT_meshopt_compression",
                version: int = 0, colors: np.ndarray | None = None):
    """``nan_vertex``: that vertex's position is NaN (the vertex codec keeps the bytes). ``extension``: EXT_ or
    KHR_meshopt_compression; ``version``: the vertex codec's (1 is KHR's addition); ``colors``: (n, 4) in [0, 1],
    written as COLOR_0 through the COLOR filter (KHR's addition) as a fourth bufferView."""
    import meshopt

    positions, normals, faces = source_mesh()
    if nan_vertex is not None:
        positions[nan_vertex] = np.nan
    n = len(positions)
    indices = faces.reshape(-1).astype(np.uint16)
    oct_rows = meshopt.encode_filter_oct(np.hstack([normals, np.zeros((n, 1), np.float32)]), 4, 8)
    streams = [  # (data as rows, count, byteStride, mode, filter, target)
        (positions, n, 12, "ATTRIBUTES", None, 34962),
        (oct_rows.view(np.int8).reshape(n, 4), n, 4, "ATTRIBUTES", "OCTAHEDRAL", 34962),
        (indices, len(indices), 2, "TRIANGLES", None, 34963),
    ]
    if colors is not None:
        streams.append((meshopt.encode_filter_color(colors, 4, 8), n, 4, "ATTRIBUTES", "COLOR", 34962))
    binary, views, fallback = bytearray(), [], 0
    for data, count, stride, mode, filt, target in streams:
        encoded = meshopt.encode_gltf_buffer(np.ascontiguousarray(data), mode, version if mode == "ATTRIBUTES" else 0)
        binary.extend(b"\0" * (-len(binary) % 4))
        ext = {"buffer": 0, "byteOffset": len(binary), "byteLength": len(encoded), "byteStride": stride,
               "count": count, "mode": mode}
        if filt:
            ext["filter"] = filt
        binary.extend(encoded)
        view = {"buffer": 1, "byteOffset": fallback, "byteLength": count * stride, "target": target,
                "extensions": {extension: ext}}
        if mode == "ATTRIBUTES":
            view["byteStride"] = stride
        fallback += count * stride + (-(count * stride) % 4)
        views.append(view)
    names = [extension, "KHR_mesh_quantization"]
    gltf = scene(list(names), list(names))
    gltf["accessors"] = [
        {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3",
         "min": np.nanmin(positions, 0).tolist(), "max": np.nanmax(positions, 0).tolist()},
        {"bufferView": 1, "componentType": 5120, "normalized": True, "count": n, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5123, "count": len(indices), "type": "SCALAR"},
    ]
    gltf["meshes"] = [{"name": "ball", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
                                                       "material": 0}]}]
    if colors is not None:
        gltf["accessors"].append({"bufferView": 3, "componentType": 5121, "normalized": True, "count": n,
                                  "type": "VEC4"})
        gltf["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = 3
    gltf["bufferViews"] = views
    gltf["buffers"] = [{"byteLength": len(binary)},
                       {"byteLength": fallback, "extensions": {extension: {"fallback": True}}}]
    write_glb(path, gltf, bytes(binary))
    return positions, normals, indices


def test_meshopt_input_is_decoded_and_baked(tmp_path):
    src = tmp_path / "meshopt.glb"
    positions, normals, indices = meshopt_glb(src)
    assert_khronos_clean(src)
    out = tmp_path / "out.glb"
    bake(src, out)
    g, buffers, record = assert_decoded_output(out, "EXT_meshopt_compression")
    assert record["decoder"].startswith("meshopt") and record["bufferViews"] == [0, 1, 2]
    assert g["extensionsRequired"] == ["KHR_mesh_quantization"]
    prim = g["meshes"][0]["primitives"][0]
    assert prim["attributes"]["POSITION"] == 0 and prim["indices"] == 2  # nothing renumbered
    # the vertex codec is lossless (same bytes, same order); the index codec keeps each triangle and its winding
    # but may rotate its corners
    assert np.array_equal(read_accessor(g, buffers, 0), positions)

    def canonical(tris):
        return [tuple(np.roll(t, -int(np.argmin(t)))) for t in tris]

    got = read_accessor(g, buffers, 2)[:, 0].astype(np.int64).reshape(-1, 3)
    assert canonical(got) == canonical(indices.astype(np.int64).reshape(-1, 3))
    normal = read_accessor(g, buffers, 1).astype(np.float64) / 127.0
    assert np.abs(normal - normals).max() < 0.03  # 8-bit octahedral
    # the fallback buffer is gone with the compressed bytes: what is left is the decoded data and the bakes' own
    assert g["buffers"][0]["byteLength"] < 4 * len(positions) * 200


def test_khr_meshopt_is_decoded_like_ext(tmp_path):
    """KHR_meshopt_compression (the ratified successor): the same JSON, data in the vertex codec's version 1 and a
    COLOR-filtered COLOR_0; decoded, recorded and removed like EXT_meshopt_compression."""
    src = tmp_path / "khr.glb"
    colors = np.random.default_rng(4).random((len(source_mesh()[0]), 4)).astype(np.float32)
    positions, normals, indices = meshopt_glb(src, extension="KHR_meshopt_compression", version=1, colors=colors)
    assert src.read_bytes().count(b"\xa1") >= 1  # a version-1 vertex stream header is in the file
    out = tmp_path / "out.glb"
    bake(src, out)
    g, buffers, record = assert_decoded_output(out, "KHR_meshopt_compression")
    assert record["decoder"].startswith("meshopt") and record["bufferViews"] == [0, 1, 2, 3]
    assert all("EXT_meshopt_compression" not in b.get("extensions", {}) for b in g["buffers"])
    assert np.array_equal(read_accessor(g, buffers, 0), positions)
    got = read_accessor(g, buffers, 2)[:, 0].astype(np.int64).reshape(-1, 3)
    assert sorted(map(sorted, got.tolist())) == sorted(map(sorted, indices.astype(np.int64).reshape(-1, 3).tolist()))
    assert np.abs(read_accessor(g, buffers, 1).astype(np.float64) / 127.0 - normals).max() < 0.03
    assert np.abs(read_accessor(g, buffers, 3).astype(np.float64) / 255.0 - colors).max() < 0.02  # 8-bit YCoCg


def test_khr_meshopt_unknown_filter_is_one_line(tmp_path):
    src = tmp_path / "khr.glb"
    meshopt_glb(src, extension="KHR_meshopt_compression")
    data = bytearray(src.read_bytes())
    length = struct.unpack_from("<I", data, 12)[0]
    gltf = json.loads(data[20: 20 + length])
    gltf["bufferViews"][1]["extensions"]["KHR_meshopt_compression"]["filter"] = "WAVELET"
    bad = tmp_path / "bad.glb"
    write_glb(bad, gltf, bytes(data[28 + length:]))
    out = tmp_path / "o.glb"
    result = subprocess.run([sys.executable, "-m", "baker.cli", "bake", str(bad), "-o", str(out), "-q", *FAST],
                            capture_output=True, text=True)
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "/bufferViews/1/extensions/KHR_meshopt_compression" in lines[0] \
        and "WAVELET" in lines[0], lines
    assert not out.exists()


def test_undecodable_meshopt_is_one_line(tmp_path):
    src = tmp_path / "meshopt.glb"
    meshopt_glb(src)
    data = bytearray(src.read_bytes())
    length = struct.unpack_from("<I", data, 12)[0]
    gltf = json.loads(data[20: 20 + length])
    binary = bytes(data[28 + length:])
    binary = b"\xff" * len(binary)  # garbage where the compressed streams were
    bad = tmp_path / "bad.glb"
    write_glb(bad, gltf, binary)
    out = tmp_path / "o.glb"
    result = subprocess.run([sys.executable, "-m", "baker.cli", "bake", str(bad), "-o", str(out), "-q", *FAST],
                            capture_output=True, text=True)
    assert result.returncode == 2, result.stderr
    assert len(result.stderr.strip().splitlines()) == 1 and "EXT_meshopt_compression" in result.stderr
    assert not out.exists()


@pytest.mark.parametrize("make, extension", [(draco_glb, "KHR_draco_mesh_compression"),
                                             (meshopt_glb, "EXT_meshopt_compression")])
def test_decoded_nan_positions_are_refused(tmp_path, make, extension):
    """The NaN/inf check runs on what the decoder made (the load's check saw only the compressed placeholders):
    exit 2, one line naming the accessor, nothing written."""
    src = tmp_path / "nan.glb"
    make(src, nan_vertex=5)
    out = tmp_path / "o.glb"
    result = subprocess.run([sys.executable, "-m", "baker.cli", "bake", str(src), "-o", str(out), "--bakes", "edges",
                             "-q"], capture_output=True, text=True)
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "/accessors/0" in lines[0] and "NaN" in lines[0] and extension in lines[0], lines
    assert not out.exists()
    result = subprocess.run([sys.executable, "-m", "baker.cli", "inspect", str(src)], capture_output=True, text=True)
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1, result.stderr


@pytest.mark.parametrize("module", ["DracoPy", "meshopt"])
def test_decoders_are_declared_dependencies(module):
    pyproject = (Path(__file__).parents[1] / "pyproject.toml").read_text()
    deps = pyproject.split("dependencies = [", 1)[1].split("]", 1)[0]
    assert f'"{module}' in deps
