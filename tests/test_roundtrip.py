"""Lossless round trip: what baker does not touch comes back unchanged, data identical."""
from __future__ import annotations

import base64
import json
import struct
import urllib.parse

import numpy as np
import pytest
import trimesh

import baker
import baker.api
import baker.pipeline
from baker.gltf.document import GltfDocument
from baker.pipeline import save
from conftest import assert_khronos_clean


def _pack(arrays):
    blob, views = bytearray(), []
    for a in arrays:
        blob.extend(b"\0" * (-len(blob) % 4))
        views.append((len(blob), a.nbytes))
        blob.extend(a.tobytes())
    return bytes(blob), views


def rich_gltf(path, embedded: bool):
    """A hand-written glTF with what baker must keep: unknown extensions, extras, animation, skin, camera."""
    mesh = trimesh.creation.icosphere(subdivisions=2, radius=1.0)
    pos = mesh.vertices.astype(np.float32)
    nrm = mesh.vertex_normals.astype(np.float32)
    idx = mesh.faces.astype(np.uint16).reshape(-1)
    times = np.array([0.0, 1.0], np.float32)
    moves = np.array([[0, 0, 0], [0, 1, 0]], np.float32)
    ibm = np.eye(4, dtype=np.float32).reshape(1, 16)
    joints = np.zeros((len(pos), 4), np.uint8)
    weights = np.tile(np.array([[1, 0, 0, 0]], np.float32), (len(pos), 1))
    blob, views = _pack([pos, nrm, idx, times, moves, ibm, joints, weights])
    gltf = {
        "asset": {"version": "2.0", "generator": "baker tests", "extras": {"pipeline": "unit"}},
        "extensionsUsed": ["VENDOR_unknown_thing"],
        "extensions": {"VENDOR_unknown_thing": {"root": True}},
        "extras": {"studio": {"shot": 42}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2], "name": "main", "extras": {"keep": "me"}}],
        "nodes": [
            {"name": "ball", "mesh": 0, "skin": 0, "translation": [1, 2, 3], "extras": {"tag": [1, 2]},
             "extensions": {"VENDOR_unknown_thing": {"node": 1}}},
            {"name": "joint"},
            {"name": "cam", "camera": 0, "rotation": [0, 0.7071068, 0, 0.7071068]},
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}],
        "materials": [{"name": "skin", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.6, 0.5, 1.0]},
                       "extensions": {"VENDOR_unknown_thing": {"material": "x"}}, "extras": {"shader": "sss"}}],
        "meshes": [{"name": "ball", "extras": {"lod": 0}, "primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1, "JOINTS_0": 6, "WEIGHTS_0": 7},
            "indices": 2, "material": 0, "extras": {"p": 1}}]}],
        "skins": [{"joints": [1], "inverseBindMatrices": 5}],
        "animations": [{"name": "bob", "samplers": [{"input": 3, "output": 4, "interpolation": "LINEAR"}],
                        "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3",
             "min": pos.min(0).tolist(), "max": pos.max(0).tolist()},
            {"bufferView": 1, "componentType": 5126, "count": len(pos), "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": len(idx), "type": "SCALAR"},
            {"bufferView": 3, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0.0], "max": [1.0]},
            {"bufferView": 4, "componentType": 5126, "count": 2, "type": "VEC3"},
            {"bufferView": 5, "componentType": 5126, "count": 1, "type": "MAT4"},
            {"bufferView": 6, "componentType": 5121, "count": len(pos), "type": "VEC4"},
            {"bufferView": 7, "componentType": 5126, "count": len(pos), "type": "VEC4"},
        ],
        "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": n} for o, n in views],
        "buffers": [{"byteLength": len(blob)}],
    }
    for i in (0, 1, 6, 7):
        gltf["bufferViews"][i]["target"] = 34962
    gltf["bufferViews"][2]["target"] = 34963
    if embedded:
        gltf["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(blob).decode()
    else:
        gltf["buffers"][0]["uri"] = "rich.bin"
        (path.parent / "rich.bin").write_bytes(blob)
    path.write_text(json.dumps(gltf, indent=1))
    return gltf


UNTOUCHED = ["asset", "extensions", "extras", "scene", "scenes", "nodes", "cameras", "skins", "animations"]


@pytest.mark.parametrize("embedded", [True, False])
@pytest.mark.parametrize("out_name", ["out.glb", "out.gltf"])
def test_untouched_data_survives(tmp_path, embedded, out_name):
    src = tmp_path / "rich.gltf"
    original = rich_gltf(src, embedded)
    before = GltfDocument.load(src)
    asset = baker.bake(src, options={"thickness": {"rays": 8, "texture_size": 32}})
    out = tmp_path / out_name
    save(asset, out)
    assert_khronos_clean(out)
    after = GltfDocument.load(out)
    for key in UNTOUCHED:
        assert after.json[key] == original[key], key
    assert set(original["extensionsUsed"]) <= set(after.json["extensionsUsed"])
    assert "BAKER_thickness" in after.json["extensionsUsed"]
    assert "BAKER_thickness" not in after.json.get("extensionsRequired", [])
    # material: every original field intact, baker only adds extensions
    mat_before, mat_after = original["materials"][0], after.json["materials"][0]
    for key, value in mat_before.items():
        if key != "extensions":
            assert mat_after[key] == value
    assert mat_after["extensions"]["VENDOR_unknown_thing"] == {"material": "x"}
    assert {"BAKER_thickness", "KHR_materials_volume"} <= set(mat_after["extensions"])
    # mesh-level JSON and primitive extras intact; every original accessor's data byte-identical
    assert after.json["meshes"][0]["extras"] == {"lod": 0}
    prim_after = after.json["meshes"][0]["primitives"][0]
    assert prim_after["extras"] == {"p": 1}
    for i, acc in enumerate(original["accessors"]):
        assert after.json["accessors"][i]["count"] == acc["count"]
        assert np.array_equal(before.accessor(i), after.accessor(i)), i
    # the primitive was re-indexed for a UV atlas (it had no UVs): its attributes hold the same data per vertex
    old_pos = before.accessor(0)
    new_pos = after.accessor(prim_after["attributes"]["POSITION"])
    new_joints = after.accessor(prim_after["attributes"]["JOINTS_0"])
    assert set(map(tuple, new_pos.round(6))) == set(map(tuple, old_pos.round(6)))
    assert new_joints.dtype == np.uint8 and len(new_joints) == len(new_pos)


def test_vertex_only_bake_keeps_primitive_accessors(tmp_path):
    src = tmp_path / "rich.gltf"
    original = rich_gltf(src, embedded=True)
    asset = baker.bake(src, options={"thickness": {"rays": 8, "per_texel": False}})
    out = tmp_path / "out.glb"
    save(asset, out)
    assert_khronos_clean(out)
    after = GltfDocument.load(out)
    attrs = after.json["meshes"][0]["primitives"][0]["attributes"]
    expected = dict(original["meshes"][0]["primitives"][0]["attributes"])
    expected["_THICKNESS"] = attrs["_THICKNESS"]
    assert attrs == expected
    assert after.json["meshes"][0]["primitives"][0]["indices"] == 2


def test_existing_images_are_kept_and_embedded(tmp_path):
    # a textured glTF with an external PNG: baking to GLB embeds it byte-identically
    from baker.gltf.images import encode_image

    src = tmp_path / "tex.gltf"
    rich_gltf(src, embedded=False)
    gltf = json.loads(src.read_text())
    png = encode_image(np.full((4, 4, 3), 200, np.uint8))
    (tmp_path / "albedo.png").write_bytes(png)
    gltf["images"] = [{"uri": "albedo.png"}]
    gltf["textures"] = [{"source": 0}]
    gltf["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
    src.write_text(json.dumps(gltf))
    asset = baker.bake(src, options={"thickness": {"rays": 4, "texture_size": 32}})
    for name in ("out.glb", "sub/out.gltf"):
        out = tmp_path / name
        save(asset, out)
        assert_khronos_clean(out)
        after = GltfDocument.load(out)
        assert after.image_bytes(0) == png
        assert after.json["textures"][0] == {"source": 0}
        assert after.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] == {"index": 0}


def test_glb_container_is_well_formed(tmp_path):
    mesh = trimesh.creation.box()
    mesh.export(str(tmp_path / "box.glb"))
    asset = baker.bake(tmp_path / "box.glb", options={"thickness": {"rays": 4, "texture_size": 16}})
    save(asset, tmp_path / "o.glb")
    assert_khronos_clean(tmp_path / "o.glb")
    data = (tmp_path / "o.glb").read_bytes()
    magic, version, length = struct.unpack_from("<III", data)
    assert (magic, version, length) == (0x46546C67, 2, len(data))
    json_len, json_type = struct.unpack_from("<II", data, 12)
    assert json_type == 0x4E4F534A and json_len % 4 == 0
    bin_len, bin_type = struct.unpack_from("<II", data, 20 + json_len)
    assert bin_type == 0x004E4942 and 28 + json_len + bin_len == len(data)


# ---------------------------------------------------------------------------------------------------- input policy
def _triangle_files(folder, uri):
    """A one-triangle .gltf in ``folder`` whose buffer URI is ``uri``; returns (gltf path, buffer bytes)."""
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    data = positions.tobytes()
    gltf = {"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                           "min": [0, 0, 0], "max": [1, 1, 0]}],
            "bufferViews": [{"buffer": 0, "byteLength": len(data)}],
            "buffers": [{"uri": uri, "byteLength": len(data)}]}
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "tri.gltf"
    path.write_text(json.dumps(gltf))
    return path, data


def test_allow_outside_widens_the_root(tmp_path, capsys):
    from baker.cli import main as cli
    from baker.errors import BakerError

    path, data = _triangle_files(tmp_path / "asset", "../shared/tri.bin")
    (tmp_path / "shared").mkdir()
    (tmp_path / "shared" / "tri.bin").write_bytes(data)
    out = tmp_path / "out.glb"
    assert cli(["bake", str(path), "-o", str(out), "--bakes", "edges", "-q"]) == 2
    assert "/buffers/0/uri" in capsys.readouterr().err and not out.exists()
    with pytest.raises(BakerError, match="leaves the asset's folder"):
        GltfDocument.load(path)

    shared = str(tmp_path / "shared")
    assert cli(["bake", str(path), "-o", str(out), "--bakes", "edges", "-q", "--allow-outside", shared]) == 0
    assert bytes(GltfDocument.load(out).bin[:len(data)]) == data
    assert cli(["inspect", str(path), "--allow-outside", shared]) == 0
    assert cli(["validate", "--no-khronos", str(path), "--allow-outside", shared]) == 0
    assert cli(["validate", str(path), "--allow-outside", shared]) == 0  # Khronos' run reads under the same root
    assert cli(["validate", "--no-khronos", str(path)]) == 1
    assert "URI_REFUSED" in capsys.readouterr().out
    # the Python API takes the same root, one path or a list
    asset = baker.api.bake(path, bakes=["edges"], allow_outside=[tmp_path / "shared"])
    assert bytes(asset.doc.bin[:len(data)]) == data
    assert baker.api.validate(path, khronos=False, allow_outside=shared)["issues"]["numErrors"] == 0
    # a root other than the one the URI points into does not help
    (tmp_path / "elsewhere").mkdir()
    with pytest.raises(BakerError, match="/buffers/0/uri"):
        GltfDocument.load(path, allow_outside=tmp_path / "elsewhere")


def test_top_level_bake_takes_allow_outside_and_max_memory(tmp_path):
    """``baker.bake`` is the API's bake: the same URI root and the same memory limit as ``baker.api.bake``."""
    from baker.errors import BakerError

    path, data = _triangle_files(tmp_path / "asset", "../shared/tri.bin")
    (tmp_path / "shared").mkdir()
    (tmp_path / "shared" / "tri.bin").write_bytes(data)
    with pytest.raises(BakerError, match="/buffers/0/uri"):
        baker.bake(path, bakes=["edges"])
    asset = baker.bake(path, bakes=["edges"], allow_outside=tmp_path / "shared")
    assert bytes(asset.doc.bin[:len(data)]) == data
    with pytest.raises(BakerError, match="--max-memory"):
        baker.bake(path, bakes=["edges"], allow_outside=[tmp_path / "shared"], max_memory=1 << 20)


@pytest.mark.parametrize("uri", ["sub/tri.bin", "sub%2Ftri.bin", "./sub/../sub/tri.bin", "tri%20copy.bin"])
def test_relative_uris_inside_the_folder_are_read(tmp_path, uri):
    path, data = _triangle_files(tmp_path, uri)
    target = tmp_path / urllib.parse.unquote(uri)
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_bytes(data)
    assert bytes(GltfDocument.load(path).bin[:len(data)]) == data


def test_integral_floats_are_read_as_integers(tmp_path):
    path, data = _triangle_files(tmp_path, "tri.bin")
    (tmp_path / "tri.bin").write_bytes(data)
    text = path.read_text().replace('"bufferView": 0', '"bufferView": 0.0').replace('"POSITION": 0', '"POSITION": 0e0')
    text = text.replace('"count": 3', '"count": 3.0').replace('"componentType": 5126', '"componentType": 5126.0')
    path.write_text(text)
    doc = GltfDocument.load(path)
    acc = doc.json["accessors"][0]
    assert all(type(acc[k]) is int for k in ("bufferView", "componentType", "count"))
    assert type(doc.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"]) is int
    assert acc["min"] == [0, 0, 0]  # other numbers are left as written
    out = tmp_path / "out.gltf"
    baker.pipeline.save(baker.bake(path, bakes=["edges"]), out)
    written = json.loads(out.read_text())
    assert written["accessors"][0]["count"] == 3 and isinstance(written["accessors"][0]["count"], int)
    assert_khronos_clean(out)
