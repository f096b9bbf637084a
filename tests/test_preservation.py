"""Everything the input held comes out (issue 15, item 6 and the second test of item 8).

A feature-rich, valid glTF is written here by hand (numpy + struct + json, no baker writer): two meshes, named nodes
with extras, TRS and a matrix, an animation (translation and rotation), a skin (joints, inverseBindMatrices,
JOINTS_0/WEIGHTS_0), morph targets (POSITION and NORMAL deltas, weights), two UV sets with KHR_texture_transform, a
camera, KHR_lights_punctual, an unknown extension on a node and on the root, extras on every object, a sparse
accessor, a KHR_mesh_quantization primitive (normalized SHORT positions and normals), an interleaved bufferView and
an embedded PNG with its sampler. It is baked with every bake to .glb and to .gltf, and read back by a reader of its
own (struct + json + numpy, no baker code): every input accessor (sparse applied) and every JSON property of the
input is in the output unchanged. baker may renumber bufferViews and buffers (it merges buffers); every other index
must be the same. Khronos glTF-Validator reports no errors on the input nor on the outputs.
"""
from __future__ import annotations

import json
import struct
import subprocess
import sys
import zlib
from pathlib import Path

import numpy as np
import pytest

from conftest import assert_khronos_clean

BAKES = "thickness,curvature,skin,edges,tam,toon,fur"
SMALL = ["--thickness-rays", "4", "--thickness-texture-size", "32", "--skin-width", "16", "--skin-height", "16",
         "--skin-penumbra", "false", "--tam-size", "32", "--tam-levels", "1", "--toon-width", "16",
         "--fur-fins", "true", "--fur-shells", "2", "--fur-texture-size", "16", "--fur-hairs", "20",
         "--edges-fins", "true"]

DTYPES = {5120: "<i1", 5121: "<u1", 5122: "<i2", 5123: "<u2", 5125: "<u4", 5126: "<f4"}
COMPONENTS = {np.dtype(v): k for k, v in DTYPES.items()}
SIZES = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}


# ---------------------------------------------------------------------------------------------- writing by hand
def png_rgba(width: int, height: int) -> bytes:
    raw = b"".join(b"\0" + b"".join(bytes((x * 60 % 256, y * 60 % 256, 128, 255)) for x in range(width))
                   for y in range(height))

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def grid_cube(n: int = 3):
    """A cube of 6 faces, each an n x n grid with its own vertices (seams), UVs in a 3 x 2 atlas without overlaps."""
    axes = [(0, 1, 2, 1), (0, 1, 2, -1), (1, 2, 0, 1), (1, 2, 0, -1), (2, 0, 1, 1), (2, 0, 1, -1)]
    pos, nor, uv, faces = [], [], [], []
    t = np.linspace(-1.0, 1.0, n + 1)
    for f, (a, b, c, s) in enumerate(axes):
        base = len(pos)
        cell = np.array([f % 3, f // 3], float)
        for j in range(n + 1):
            for i in range(n + 1):
                p = np.zeros(3)
                p[a], p[b], p[c] = t[i], t[j] * s, s
                pos.append(p)
                nn = np.zeros(3)
                nn[c] = s
                nor.append(nn)
                uv.append((cell + 0.05 + 0.9 * np.array([i, j]) / n) / np.array([3.0, 2.0]))
        for j in range(n):
            for i in range(n):
                v = base + j * (n + 1) + i
                q = [v, v + 1, v + n + 2, v + n + 1]
                tri = [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
                for tr in tri:
                    e1 = pos[tr[1]] - pos[tr[0]]
                    e2 = pos[tr[2]] - pos[tr[0]]
                    faces.append(tr if np.dot(np.cross(e1, e2), nor[tr[0]]) > 0 else tr[::-1])
    return (np.array(pos, np.float32), np.array(nor, np.float32), np.array(uv, np.float32),
            np.array(faces, np.uint16).reshape(-1))


class Builder:
    def __init__(self):
        self.bin = bytearray()
        self.views: list[dict] = []
        self.accessors: list[dict] = []

    def view(self, data: bytes, target: int | None = None, stride: int | None = None, name: str | None = None) -> int:
        self.bin.extend(b"\0" * (-len(self.bin) % 4))
        view = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if stride:
            view["byteStride"] = stride
        if target:
            view["target"] = target
        view["name"] = name or f"view{len(self.views)}"
        view["extras"] = {"view": len(self.views)}
        self.bin.extend(data)
        self.views.append(view)
        return len(self.views) - 1

    def accessor(self, array, kind: str, view: int | None = None, offset: int = 0, normalized: bool = False,
                 min_max: bool = False, target: int | None = None, count: int | None = None, **extra) -> int:
        array = np.asarray(array)
        if view is None and array.size:
            view = self.view(array.tobytes(), target=target)
        acc = {"componentType": COMPONENTS[array.dtype.newbyteorder("<") if array.dtype.byteorder == ">"
                                           else array.dtype],
               "count": int(count if count is not None else len(array)), "type": kind}
        if view is not None:
            acc["bufferView"] = view
            if offset:
                acc["byteOffset"] = offset
        if normalized:
            acc["normalized"] = True
        if min_max:
            flat = array.reshape(len(array), -1)
            cast = float if array.dtype.kind == "f" else int
            acc["min"] = [cast(v) for v in flat.min(0)]
            acc["max"] = [cast(v) for v in flat.max(0)]
        acc["name"] = f"accessor{len(self.accessors)}"
        acc["extras"] = {"accessor": len(self.accessors)}
        acc.update(extra)
        self.accessors.append(acc)
        return len(self.accessors) - 1


def rich_glb(path: Path) -> dict:
    """Write the feature-rich GLB; return its JSON."""
    b = Builder()
    pos, nor, uv0, idx = grid_cube(3)
    n = len(pos)
    uv1 = (uv0 * 0.5 + 0.25).astype(np.float32)
    # interleaved POSITION + NORMAL (byteStride 24)
    inter = np.hstack([pos, nor]).astype(np.float32)
    v_inter = b.view(inter.tobytes(), target=34962, stride=24, name="interleaved")
    a_pos = b.accessor(pos, "VEC3", view=v_inter, min_max=True)
    b.accessors[a_pos]["count"] = n
    a_nor = b.accessor(nor, "VEC3", view=v_inter, offset=12)
    a_uv0 = b.accessor(uv0, "VEC2", target=34962)
    a_uv1 = b.accessor(uv1, "VEC2", target=34962)
    joints = np.zeros((n, 4), np.uint8)
    joints[:, 1] = 1
    w1 = ((pos[:, 1] + 1.0) / 2.0).astype(np.float32)
    weights = np.zeros((n, 4), np.float32)
    weights[:, 0] = 1.0 - w1
    weights[:, 1] = w1
    a_joints = b.accessor(joints, "VEC4", target=34962)
    a_weights = b.accessor(weights, "VEC4", target=34962)
    a_idx = b.accessor(idx, "SCALAR", target=34963)
    # morph target: POSITION delta as a sparse accessor without a bufferView, NORMAL delta as a sparse one over data
    top = np.nonzero(pos[:, 1] > 0.99)[0].astype(np.uint16)
    delta = np.zeros((n, 3), np.float32)
    delta[top, 1] = 0.5
    sp_idx = b.view(top.tobytes(), name="sparse_indices")
    sp_val = b.view(delta[top].tobytes(), name="sparse_values")
    a_dpos = b.accessor(delta, "VEC3", view=None, count=n, min_max=True,
                        sparse={"count": int(len(top)), "indices": {"bufferView": sp_idx, "componentType": 5123},
                                "values": {"bufferView": sp_val}, "extras": {"sparse": True}})
    dnor_base = np.zeros((n, 3), np.float32)
    dnor_base[:, 0] = 0.01
    dnor = dnor_base.copy()
    dnor[top] = [0.0, 0.0, 0.02]
    sp_val2 = b.view(dnor[top].tobytes(), name="sparse_values_normal")
    a_dnor = b.accessor(dnor_base, "VEC3", target=34962,
                        sparse={"count": int(len(top)), "indices": {"bufferView": sp_idx, "componentType": 5123},
                                "values": {"bufferView": sp_val2}})
    # mesh 1: KHR_mesh_quantization, normalized SHORT positions and normals (byteStride 8)
    q = np.zeros((n, 4), np.int16)
    q[:, :3] = np.round(pos * 0.5 * 32767).astype(np.int16)
    qn = np.zeros((n, 4), np.int16)
    qn[:, :3] = np.round(nor * 32767).astype(np.int16)
    v_q = b.view(q.tobytes(), target=34962, stride=8, name="quantized_positions")
    v_qn = b.view(qn.tobytes(), target=34962, stride=8, name="quantized_normals")
    a_qpos = b.accessor(q[:, :3], "VEC3", view=v_q, normalized=True, min_max=True)
    a_qnor = b.accessor(qn[:, :3], "VEC3", view=v_qn, normalized=True)
    a_quv = b.accessor(uv0, "VEC2", target=34962)
    a_qidx = b.accessor(idx, "SCALAR", target=34963)
    # skin: two joints
    ibm = np.stack([np.eye(4, dtype=np.float32), np.eye(4, dtype=np.float32)])
    ibm[1, 3, 1] = -0.5  # column-major: translation in the last column
    a_ibm = b.accessor(ibm.reshape(2, 16), "MAT4")
    # animation: translation and rotation of node 2
    times = np.array([0.0, 0.5, 1.0], np.float32)
    a_time = b.accessor(times, "SCALAR", min_max=True)
    a_tr = b.accessor(np.array([[0, 0.5, 0], [0, 0.7, 0], [0, 0.5, 0]], np.float32), "VEC3")
    s = np.sin(np.radians(15))
    c = np.cos(np.radians(15))
    a_rot = b.accessor(np.array([[0, 0, 0, 1], [s, 0, 0, c], [0, 0, 0, 1]], np.float32), "VEC4")
    a_w = b.accessor(np.array([0.0, 1.0, 0.0], np.float32), "SCALAR")
    png = png_rgba(4, 4)
    v_png = b.view(png, name="png")

    gltf = {
        "asset": {"version": "2.0", "generator": "tests/test_preservation.py (by hand)", "copyright": "CC0",
                  "extras": {"asset": "extras"}},
        "extensionsUsed": ["KHR_texture_transform", "KHR_lights_punctual", "KHR_mesh_quantization", "VENDOR_thing"],
        "extensionsRequired": ["KHR_mesh_quantization"],
        "extensions": {
            "KHR_lights_punctual": {"lights": [{"type": "point", "color": [1.0, 0.9, 0.8], "intensity": 3.5,
                                                "range": 20.0, "name": "lamp", "extras": {"light": 0}}]},
            "VENDOR_thing": {"root": [1, 2, 3], "nested": {"a": "b"}},
        },
        "extras": {"root": {"list": [1, 2.5, "x"], "flag": True}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 3, 4, 5], "name": "the scene", "extras": {"scene": 0}}],
        "nodes": [
            {"name": "skinned", "mesh": 0, "skin": 0, "weights": [0.25], "extras": {"node": 0},
             "extensions": {"VENDOR_thing": {"node": "skinned", "value": 7}}},
            {"name": "root_joint", "translation": [0.0, -0.5, 0.0], "rotation": [0.0, 0.0, 0.0, 1.0],
             "scale": [1.0, 1.0, 1.0], "children": [2], "extras": {"node": 1}},
            {"name": "child_joint", "translation": [0.0, 0.5, 0.0], "extras": {"node": 2}},
            {"name": "quantized", "mesh": 1,
             "matrix": [2.0, 0, 0, 0, 0, 2.0, 0, 0, 0, 0, 2.0, 0, 3.0, 0, 0, 1.0], "extras": {"node": 3}},
            {"name": "camera", "camera": 0, "translation": [0.0, 0.0, 6.0], "rotation": [0.0, 0.0, 0.0, 1.0],
             "extras": {"node": 4}},
            {"name": "light", "translation": [2.0, 3.0, 4.0], "extras": {"node": 5},
             "extensions": {"KHR_lights_punctual": {"light": 0}}},
        ],
        "meshes": [
            {"name": "skinned_cube", "weights": [0.0], "extras": {"mesh": 0, "targetNames": ["raise"]},
             "primitives": [{
                 "attributes": {"POSITION": a_pos, "NORMAL": a_nor, "TEXCOORD_0": a_uv0, "TEXCOORD_1": a_uv1,
                                "JOINTS_0": a_joints, "WEIGHTS_0": a_weights},
                 "indices": a_idx, "material": 0, "mode": 4,
                 "targets": [{"POSITION": a_dpos, "NORMAL": a_dnor}],
                 "extras": {"primitive": 0}}]},
            {"name": "quantized_cube", "extras": {"mesh": 1},
             "primitives": [{"attributes": {"POSITION": a_qpos, "NORMAL": a_qnor, "TEXCOORD_0": a_quv},
                             "indices": a_qidx, "material": 1, "extras": {"primitive": 1}}]},
        ],
        "materials": [
            {"name": "textured", "extras": {"material": 0}, "doubleSided": False,
             "pbrMetallicRoughness": {
                 "baseColorFactor": [1.0, 0.9, 0.8, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.7,
                 "baseColorTexture": {"index": 0, "texCoord": 0, "extras": {"textureInfo": 0},
                                      "extensions": {"KHR_texture_transform": {
                                          "offset": [0.1, 0.2], "rotation": 0.3, "scale": [2.0, 2.0],
                                          "texCoord": 1}}}}},
            {"name": "plain", "extras": {"material": 1},
             "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1.0]}},
        ],
        "textures": [{"sampler": 0, "source": 0, "name": "albedo", "extras": {"texture": 0}}],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 33648, "wrapT": 10497, "name": "mirror",
                      "extras": {"sampler": 0}}],
        "images": [{"bufferView": v_png, "mimeType": "image/png", "name": "albedo_png", "extras": {"image": 0}}],
        "cameras": [{"type": "perspective", "name": "cam", "extras": {"camera": 0},
                     "perspective": {"yfov": 0.8, "znear": 0.05, "zfar": 100.0, "aspectRatio": 1.5}}],
        "skins": [{"joints": [1, 2], "inverseBindMatrices": a_ibm, "skeleton": 1, "name": "rig",
                   "extras": {"skin": 0}}],
        "animations": [{"name": "wiggle", "extras": {"animation": 0},
                        "samplers": [{"input": a_time, "output": a_tr, "interpolation": "LINEAR",
                                      "extras": {"sampler": "t"}},
                                     {"input": a_time, "output": a_rot, "interpolation": "STEP"},
                                     {"input": a_time, "output": a_w}],
                        "channels": [{"sampler": 0, "target": {"node": 2, "path": "translation"},
                                      "extras": {"channel": 0}},
                                     {"sampler": 1, "target": {"node": 2, "path": "rotation"}},
                                     {"sampler": 2, "target": {"node": 0, "path": "weights"}}]}],
        "accessors": b.accessors,
        "bufferViews": b.views,
        "buffers": [{"byteLength": len(b.bin), "name": "the buffer", "extras": {"buffer": 0}}],
    }
    text = json.dumps(gltf).encode()
    text += b" " * (-len(text) % 4)
    binary = bytes(b.bin) + b"\0" * (-len(b.bin) % 4)
    gltf["buffers"][0]["byteLength"] = len(b.bin)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(binary), 0x004E4942) + binary
    path.write_bytes(struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks)
    return gltf


# ---------------------------------------------------------------------------------------------- reading by hand
def read_gltf(path: Path) -> tuple[dict, list[bytes]]:
    """The JSON and every buffer's bytes of a .glb or .gltf (external .bin or data URIs), read without baker."""
    data = path.read_bytes()
    chunk_bin = None
    if data[:4] == b"glTF":
        magic, version, length = struct.unpack_from("<III", data)
        assert version == 2 and length == len(data)
        offset, gltf = 12, None
        while offset < length:
            size, kind = struct.unpack_from("<II", data, offset)
            body = data[offset + 8: offset + 8 + size]
            if kind == 0x4E4F534A:
                gltf = json.loads(body)
            elif kind == 0x004E4942:
                chunk_bin = body
            offset += 8 + size
    else:
        gltf = json.loads(data)
    buffers = []
    for i, buf in enumerate(gltf.get("buffers", [])):
        if "uri" in buf:
            assert not buf["uri"].startswith("data:")
            raw = (path.parent / buf["uri"]).read_bytes()
        else:
            assert i == 0 and chunk_bin is not None
            raw = chunk_bin
        assert len(raw) >= buf["byteLength"]
        buffers.append(raw[: buf["byteLength"]])
    return gltf, buffers


def view_bytes(gltf: dict, buffers: list[bytes], index: int) -> bytes:
    view = gltf["bufferViews"][index]
    start = view.get("byteOffset", 0)
    return buffers[view.get("buffer", 0)][start: start + view["byteLength"]]


def read_accessor(gltf: dict, buffers: list[bytes], index: int) -> np.ndarray:
    """Accessor ``index`` as stored (normalized integers not converted), byteStride and sparse applied."""
    acc = gltf["accessors"][index]
    dtype = np.dtype(DTYPES[acc["componentType"]])
    k = SIZES[acc["type"]]
    count = acc["count"]
    out = np.zeros((count, k), dtype)
    if "bufferView" in acc:
        view = gltf["bufferViews"][acc["bufferView"]]
        data = view_bytes(gltf, buffers, acc["bufferView"])
        elem = dtype.itemsize * k
        stride = view.get("byteStride") or elem
        base = acc.get("byteOffset", 0)
        for row in range(count):
            start = base + row * stride
            out[row] = np.frombuffer(data[start: start + elem], dtype)
    sparse = acc.get("sparse")
    if sparse:
        m = sparse["count"]
        ii = sparse["indices"]
        raw = view_bytes(gltf, buffers, ii["bufferView"])[ii.get("byteOffset", 0):]
        rows = np.frombuffer(raw, np.dtype(DTYPES[ii["componentType"]]), count=m)
        vv = sparse["values"]
        raw = view_bytes(gltf, buffers, vv["bufferView"])[vv.get("byteOffset", 0):]
        out[rows.astype(np.int64)] = np.frombuffer(raw, dtype, count=m * k).reshape(m, k)
    return out


# ---------------------------------------------------------------------------------------------- comparing
VIEW_KEYS = {"bufferView", "buffer", "byteOffset"}  # what baker may renumber or move; checked through the data


def compare(before, after, where: str, problems: list[str], view_map: dict) -> None:
    """Every property of ``before`` is in ``after`` and equal; arrays of objects may grow (baker appends)."""
    if isinstance(before, dict):
        if not isinstance(after, dict):
            problems.append(f"{where}: was an object, now {after!r}")
            return
        for key, value in before.items():
            if where == "" and key == "bufferViews":
                continue  # compared one by one through the renumbering (assert_preserved)
            if key not in after:
                problems.append(f"{where}/{key}: dropped")
            elif key == "bufferView" and isinstance(value, int):
                view_map.setdefault(value, set()).add(after[key])
            elif key in VIEW_KEYS and not where.startswith("/bufferViews") and where != "":
                continue  # accessor/image byteOffset inside a view: compared through the decoded data
            elif where.startswith("/bufferViews/") and key in ("buffer", "byteOffset"):
                continue
            elif where.startswith("/buffers/") and key in ("byteLength", "uri"):
                continue  # buffers are merged into one
            else:
                compare(value, after[key], f"{where}/{key}", problems, view_map)
    elif isinstance(before, list):
        if not isinstance(after, list):
            problems.append(f"{where}: was an array, now {after!r}")
        elif where == "/extensionsUsed":
            missing = set(before) - set(after)
            if missing:
                problems.append(f"{where}: dropped {sorted(missing)}")
        elif before and all(isinstance(v, dict) for v in before):
            if len(after) < len(before):
                problems.append(f"{where}: {len(before)} objects, now {len(after)}")
            for i, value in enumerate(before[: len(after)]):
                compare(value, after[i], f"{where}/{i}", problems, view_map)
        elif before != after:
            problems.append(f"{where}: {before!r} became {after!r}")
    elif type(before) is not type(after) or before != after:
        problems.append(f"{where}: {before!r} became {after!r}")


def corners(g: dict, buffers, primitive: dict) -> np.ndarray:
    """The vertex index of every triangle corner of ``primitive`` (its indices, or 0..count-1)."""
    if "indices" in primitive:
        return read_accessor(g, buffers, primitive["indices"]).reshape(-1).astype(np.int64)
    return np.arange(g["accessors"][primitive["attributes"]["POSITION"]]["count"])


def with_split_primitives_mapped(g0: dict, b0, g1: dict, b1) -> dict:
    """``g1`` with the accessors of every primitive whose vertices a bake split (tam's stroke parameterization,
    issue 38) put back to the input's numbers, once each attribute and morph target of the input is checked to hold
    the same value at every triangle corner as before: a split renumbers vertices, it must not change a corner."""
    g1 = json.loads(json.dumps(g1))
    for m, (mesh0, mesh1) in enumerate(zip(g0["meshes"], g1["meshes"])):
        for p, (p0, p1) in enumerate(zip(mesh0["primitives"], mesh1["primitives"])):
            refs = lambda q: (q.get("indices"), q["attributes"], q.get("targets"))  # noqa: E731
            if refs(p0) == (p1.get("indices"), {k: p1["attributes"].get(k) for k in p0["attributes"]},
                            p1.get("targets")):
                continue
            where = f"/meshes/{m}/primitives/{p}"
            c0, c1 = corners(g0, b0, p0), corners(g1, b1, p1)
            assert len(c0) == len(c1), f"{where}: {len(c0)} corners, now {len(c1)}"
            pairs = [(k, a, p1["attributes"].get(k)) for k, a in p0["attributes"].items()]
            for t, target in enumerate(p0.get("targets") or []):
                pairs += [(f"targets/{t}/{k}", a, (p1.get("targets") or [{}] * (t + 1))[t].get(k))
                          for k, a in target.items()]
            for name, before, after in pairs:
                assert after is not None, f"{where}/{name}: dropped by the split"
                a, b = read_accessor(g0, b0, before), read_accessor(g1, b1, after)
                assert a.dtype == b.dtype and np.array_equal(a[c0], b[c1]), f"{where}/{name}: a corner's value changed"
            p1["attributes"].update(p0["attributes"])
            if "indices" in p0:
                p1["indices"] = p0["indices"]
            if "targets" in p0:
                p1["targets"] = p0["targets"]
    return g1


def assert_preserved(src: Path, out: Path) -> dict:
    g0, b0 = read_gltf(src)
    g1, b1 = read_gltf(out)
    problems: list[str] = []
    view_map: dict = {}
    compare(g0, with_split_primitives_mapped(g0, b0, g1, b1), "", problems, view_map)
    assert not problems, "\n".join(problems)
    # baker adds, never requires: extensionsRequired is exactly the input's
    assert g1.get("extensionsRequired", []) == g0.get("extensionsRequired", [])
    # bufferViews may be renumbered, but one to one, with the same bytes and properties (not buffer and byteOffset)
    assert sorted(view_map) == list(range(len(g0["bufferViews"])))  # every input view is used by the fixture
    for old, new in view_map.items():
        assert len(new) == 1, f"bufferView {old} became several: {new}"
        (new,) = new
        compare(g0["bufferViews"][old], g1["bufferViews"][new], f"/bufferViews/{old}", problems, view_map)
        assert view_bytes(g0, b0, old) == view_bytes(g1, b1, new), f"bufferView {old} -> {new}: bytes differ"
    assert not problems, "\n".join(problems)
    assert len(set().union(*view_map.values())) == len(view_map)
    for i in range(len(g0["accessors"])):
        a, b = read_accessor(g0, b0, i), read_accessor(g1, b1, i)
        assert a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b), f"accessor {i} differs"
    for i, image in enumerate(g0.get("images", [])):
        assert view_bytes(g0, b0, image["bufferView"]) == view_bytes(g1, b1, g1["images"][i]["bufferView"])
    return g1


@pytest.fixture(scope="module")
def rich(tmp_path_factory):
    folder = tmp_path_factory.mktemp("preservation")
    src = folder / "rich.glb"
    rich_glb(src)
    return src


def test_the_hand_written_input_is_valid(rich):
    assert_khronos_clean(rich)
    g, buffers = read_gltf(rich)
    # the reader agrees with the arrays it was written from: sparse over zeros, sparse over data, interleaving
    delta = read_accessor(g, buffers, g["meshes"][0]["primitives"][0]["targets"][0]["POSITION"])
    assert delta[:, 1].max() == np.float32(0.5) and (delta[:, [0, 2]] == 0).all()
    normals = read_accessor(g, buffers, g["meshes"][0]["primitives"][0]["attributes"]["NORMAL"])
    assert np.allclose(np.linalg.norm(normals, axis=1), 1.0)


@pytest.mark.parametrize("out_name", ["out.glb", "gltf/out.gltf"])
def test_every_bake_keeps_everything_the_input_held(rich, tmp_path, out_name):
    out = tmp_path / out_name
    out.parent.mkdir(parents=True, exist_ok=True)
    result = subprocess.run([sys.executable, "-m", "baker.cli", "bake", str(rich), "-o", str(out), "--bakes", BAKES,
                             "-q", *SMALL], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert_khronos_clean(out)
    g1 = assert_preserved(rich, out)
    # and the bakes are there (so the test did not pass by baking nothing)
    used = set(g1["extensionsUsed"])
    for name in ("BAKER_thickness", "BAKER_curvature", "BAKER_skin_lut", "BAKER_edges", "BAKER_tonal_art_map",
                 "BAKER_toon_ramp", "BAKER_fur"):
        assert name in used, name
    attrs = g1["meshes"][0]["primitives"][0]["attributes"]
    assert {"_THICKNESS", "_CURVATURE", "_OUTLINE_NORMAL"} <= set(attrs)


def test_fins_of_a_skinned_mesh_carry_its_joints_and_weights(rich, tmp_path):
    """Edge fins and fur fins of the skinned cube get JOINTS_0/WEIGHTS_0: each fin vertex those of the cube vertex
    it sits on (this cube's weights are a function of the position, so any cube vertex at that place tells), stored
    as the source stores them; Khronos finds every primitive with the same joint sets."""
    from scipy.spatial import cKDTree

    from conftest import khronos_validate

    out = tmp_path / "fins.glb"
    result = subprocess.run([sys.executable, "-m", "baker.cli", "bake", str(rich), "-o", str(out), "--bakes",
                             "edges,fur", "--edges-fins", "true", "--fur-fins", "true", "-q"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert_khronos_clean(out)
    codes = {m["code"] for m in khronos_validate(out)["issues"]["messages"]}
    assert "MESH_PRIMITIVES_UNEQUAL_JOINTS_COUNT" not in codes
    g, buffers = read_gltf(out)
    prims = g["meshes"][0]["primitives"]
    source = prims[0]["attributes"]
    cube = read_accessor(g, buffers, source["POSITION"]).astype(np.float64)
    joints, weights = (read_accessor(g, buffers, source[k]) for k in ("JOINTS_0", "WEIGHTS_0"))
    fins = {name: [p for p in prims if (p.get("extensions") or {}).get(name, {}).get("finsOf") == 0]
            for name in ("BAKER_edges", "BAKER_fur")}
    assert all(len(found) == 1 for found in fins.values()), fins
    for fin in (found[0] for found in fins.values()):
        at = fin["attributes"]
        position = read_accessor(g, buffers, at["POSITION"]).astype(np.float64)
        distance, nearest = cKDTree(cube).query(position)
        assert distance.max() < 1e-6  # every fin vertex sits on a cube vertex (corners v0, v1, v1, v0)
        for key, truth in (("JOINTS_0", joints), ("WEIGHTS_0", weights)):
            assert g["accessors"][at[key]]["componentType"] == g["accessors"][source[key]]["componentType"]
            assert np.array_equal(read_accessor(g, buffers, at[key]), truth[nearest]), key
