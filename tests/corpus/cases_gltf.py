"""glTF documents that are well-formed containers but not what baker may read: JSON of the wrong type where baker reads
an object or an index (the shapes of Khronos glTF-Validator's ``buffer/invalid_object``, ``image/invalid_object``,
``mesh/empty_object``, ``mesh/unresolved_indices``, ``mesh/unresolved_positions``,
``mesh/position_accessor_invalid_format`` test files, written here by hand), indices out of range, byte ranges outside
their view or buffer, buffers without data, NaN and infinite positions, and buffer and image URIs that leave the
asset's folder. One valid case: integers written as ``3.0`` (valid JSON, common from JavaScript tools).

Every failing case: ``bake`` and ``inspect`` exit 2 with the JSON pointer in their one line, ``validate`` exits 1 with
the pointer in its report; nothing outside the case's folder is opened and no HTTP request is made."""
from __future__ import annotations

import base64
import os
import struct

import numpy as np

from corpus.case import Case, Expect, glb_bytes, triangle_gltf, write_glb, write_gltf

VALID = {"bake": Expect(0), "inspect": Expect(0), "validate": Expect(0)}


def fails(*words: str) -> dict:
    """bake/inspect exit 2 naming ``words`` (the pointer); validate exit 1 with them in its report."""
    return {"bake": Expect(2, words), "inspect": Expect(2, words), "validate": Expect(1, words)}


def refused(*words: str) -> dict:
    """A container no command can parse: bake, inspect and validate all exit 2 with ``words`` in their one line."""
    return {"bake": Expect(2, words), "inspect": Expect(2, words), "validate": Expect(2, words)}


def glb_case(edit, binary=True):
    """A case writing the one-triangle GLB after ``edit(gltf, env)`` changed its JSON."""
    def make(folder, env):
        gltf, data = triangle_gltf()
        edit(gltf, env)
        return write_glb(folder / "asset.glb", gltf, data if binary else None)
    return make


def gltf_case(edit, uri="asset.bin"):
    """A case writing the one-triangle .gltf + .bin after ``edit(gltf, env)`` changed its JSON."""
    def make(folder, env):
        gltf, data = triangle_gltf(uri=uri)
        (folder / "asset.bin").write_bytes(data)
        edit(gltf, env)
        return write_gltf(folder / "asset.gltf", gltf)
    return make


def set_uri(uri):
    """An edit giving buffer 0 the URI ``uri`` (``{outside}`` and ``{http}`` filled in from the case's env)."""
    def edit(gltf, env):
        gltf["buffers"][0]["uri"] = uri.format(outside=env["outside"], http=env["http"])
    return edit


def image_uri(uri):
    """An edit adding an image (used by a texture of the triangle's material) whose URI is ``uri``."""
    def edit(gltf, env):
        gltf["images"] = [{"uri": uri.format(outside=env["outside"], http=env["http"]), "mimeType": "image/png"}]
        gltf["textures"] = [{"source": 0}]
        gltf["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]
        gltf["meshes"][0]["primitives"][0]["material"] = 0
    return edit


def prim(gltf) -> dict:
    return gltf["meshes"][0]["primitives"][0]


def _ints_as_floats(folder, env):
    """An indexed triangle whose every index, count, offset and enum is written as a float: valid glTF."""
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    indices = np.array([0, 1, 2, 0], np.uint16)  # padded to 4 bytes; the accessor reads 3
    data = positions.tobytes() + indices.tobytes()
    body = (
        '{"asset": {"version": "2.0"}, "scene": 0.0, "scenes": [{"nodes": [0.0]}], "nodes": [{"mesh": 0e0}],'
        ' "meshes": [{"primitives": [{"attributes": {"POSITION": 0.0}, "indices": 1.0, "mode": 4.0}]}],'
        ' "accessors": [{"bufferView": 0.0, "componentType": 5126.0, "count": 3.0, "type": "VEC3",'
        '                "min": [0, 0, 0], "max": [1, 1, 0]},'
        '               {"bufferView": 1.0, "byteOffset": 0.0, "componentType": 5123.0, "count": 3.0,'
        '                "type": "SCALAR"}],'
        ' "bufferViews": [{"buffer": 0.0, "byteLength": 36.0, "target": 34962.0},'
        '                 {"buffer": 0.0, "byteOffset": 36.0, "byteLength": 6.0, "target": 34963.0}],'
        f' "buffers": [{{"uri": "asset.bin", "byteLength": {float(len(data))}}}]}}'
    )
    (folder / "asset.bin").write_bytes(data)
    (folder / "asset.gltf").write_text(body)
    return folder / "asset.gltf"


def _no_bin_chunk(folder, env):
    gltf, _ = triangle_gltf()
    return write_glb(folder / "asset.glb", gltf, None)


def _no_buffer_uri(folder, env):
    gltf, _ = triangle_gltf()  # byteLength 36, no uri, no .bin: nothing to read
    return write_gltf(folder / "asset.gltf", gltf)


def _positions(values):
    def make(folder, env):
        gltf, data = triangle_gltf(positions=values)
        return write_glb(folder / "asset.glb", gltf, data)
    return make


def _attribute(name, type_, values):
    """The triangle plus a float attribute ``name`` holding ``values`` (accessor 1)."""
    def make(folder, env):
        gltf, data = triangle_gltf()
        extra = np.array(values, np.float32).tobytes()
        gltf["bufferViews"].append({"buffer": 0, "byteOffset": len(data), "byteLength": len(extra)})
        gltf["accessors"].append({"bufferView": 1, "componentType": 5126, "count": 3, "type": type_})
        gltf["buffers"][0]["byteLength"] = len(data) + len(extra)
        prim(gltf)["attributes"][name] = 1
        return write_glb(folder / "asset.glb", gltf, data + extra)
    return make


def _data_uri_short(gltf, env):
    gltf["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(b"\0" * 12).decode()


def _symlink_out(folder, env):
    os.symlink(env["outside"] / "secret.bin", folder / "link.bin")
    gltf, _ = triangle_gltf(uri="link.bin")
    gltf["buffers"][0]["byteLength"] = 36
    return write_gltf(folder / "asset.gltf", gltf)


def _glb_version(folder, env):
    gltf, data = triangle_gltf()
    blob = bytearray(glb_bytes(gltf, data))
    struct.pack_into("<I", blob, 4, 1)
    (folder / "v1.glb").write_bytes(bytes(blob))
    return folder / "v1.glb"


def _glb_trailing(folder, env):
    gltf, data = triangle_gltf()
    (folder / "trailing.glb").write_bytes(glb_bytes(gltf, data) + b"\0" * 8)  # header length < file size
    return folder / "trailing.glb"


def _glb_bin_first(folder, env):
    gltf, data = triangle_gltf()
    text = glb_bytes(gltf, data)
    json_len = struct.unpack_from("<I", text, 12)[0]
    json_chunk, bin_chunk = text[12: 20 + json_len], text[20 + json_len:]
    (folder / "binfirst.glb").write_bytes(text[:12] + bin_chunk + json_chunk)
    return folder / "binfirst.glb"


def _node_loop(gltf, env):
    gltf["nodes"] = [{"mesh": 0}, {"children": [2]}, {"children": [1]}]  # 1 -> 2 -> 1, each with one parent


def _view_past_buffer(gltf, env):
    gltf["bufferViews"][0]["byteOffset"] = 8


def _accessor_past_view(gltf, env):
    gltf["accessors"][0]["byteOffset"] = 12


def _indices_unresolved(gltf, env):
    prim(gltf)["indices"] = 5


def _positions_unresolved(gltf, env):
    del gltf["accessors"]
    prim(gltf)["attributes"]["POSITION"] = 3


def _position_vec4(gltf, env):
    gltf["accessors"][0]["type"] = "VEC4"
    gltf["accessors"][0]["count"] = 2


def _position_string(gltf, env):
    prim(gltf)["attributes"]["POSITION"] = "0"


def _index_fraction(gltf, env):
    prim(gltf)["attributes"]["POSITION"] = 0.5


def _set(path, value):
    """An edit setting ``gltf[path[0]][path[1]]... = value``."""
    def edit(gltf, env):
        obj = gltf
        for key in path[:-1]:
            obj = obj[key]
        obj[path[-1]] = value
    return edit


def _with_texture(edit):
    def both(gltf, env):
        image_uri("image.png")(gltf, env)
        edit(gltf, env)
    return both


def _make_image_file(make):
    def wrapped(folder, env):
        (folder / "image.png").write_bytes(b"\x89PNG\r\n\x1a\n")
        return make(folder, env)
    return wrapped


SECRET_REL = "..%2F..%2Foutside%2Fsecret.bin"  # from cases/<name>/ to the sentinel beside the case folders

CASES = [
    # ------------------------------------------------------------------ valid
    Case("gltf-ints-as-floats", "integers written as floats (3.0) are valid JSON numbers", _ints_as_floats, VALID),
    # ------------------------------------------------------------------ JSON types (Khronos validator suite shapes)
    Case("gltf-buffer-invalid-object", "a list where a buffer object is expected (buffer/invalid_object)",
         glb_case(_set(("buffers",), [["byteLength", 10]])), fails("/buffers/0")),
    Case("gltf-image-invalid-object", "a list where an image object is expected (image/invalid_object)",
         glb_case(_set(("images",), [["uri", "image.png"]])), fails("/images/0")),
    Case("gltf-mesh-empty-object", "a mesh without primitives (mesh/empty_object)",
         glb_case(_set(("meshes",), [{}])), fails("/meshes/0")),
    Case("gltf-mesh-primitives-object", "primitives that are an object, not an array (mesh/empty_object)",
         glb_case(_set(("meshes",), [{"primitives": {}}])), fails("/meshes/0/primitives")),
    Case("gltf-mesh-primitive-list", "a list where a primitive object is expected (mesh/empty_object)",
         glb_case(_set(("meshes",), [{"primitives": [[]]}])), fails("/meshes/0/primitives/0")),
    Case("gltf-mesh-attributes-list", "attributes that are a list (mesh/empty_object)",
         glb_case(_set(("meshes",), [{"primitives": [{"attributes": []}]}])),
         fails("/meshes/0/primitives/0/attributes")),
    Case("gltf-mesh-unresolved-indices", "indices naming a missing accessor (mesh/unresolved_indices)",
         glb_case(_indices_unresolved), fails("/meshes/0/primitives/0/indices")),
    Case("gltf-mesh-unresolved-positions", "POSITION naming an accessor of a document without accessors "
         "(mesh/unresolved_positions)", glb_case(_positions_unresolved),
         fails("/meshes/0/primitives/0/attributes/POSITION")),
    Case("gltf-position-invalid-format", "a VEC4 POSITION accessor (mesh/position_accessor_invalid_format)",
         glb_case(_position_vec4), fails("/meshes/0/primitives/0/attributes/POSITION")),
    Case("gltf-index-is-string", "a string where an accessor index is expected", glb_case(_position_string),
         fails("/meshes/0/primitives/0/attributes/POSITION")),
    Case("gltf-index-is-fraction", "0.5 where an accessor index is expected (only integral floats are integers)",
         glb_case(_index_fraction), fails("/meshes/0/primitives/0/attributes/POSITION")),
    Case("gltf-node-invalid-object", "a list where a node object is expected",
         glb_case(_set(("nodes",), [[0]])), fails("/nodes/0")),
    Case("gltf-collection-not-array", "an object where the accessors array is expected",
         glb_case(_set(("accessors",), {"0": {}})), fails("/accessors")),
    Case("gltf-node-matrix-short", "a node matrix of 3 numbers", glb_case(_set(("nodes", 0, "matrix"), [1, 0, 0])),
         fails("/nodes/0/matrix")),
    Case("gltf-extensions-list", "a list where an extensions object is expected",
         glb_case(_set(("meshes", 0, "primitives", 0, "extensions"), ["BAKER_edges"])),
         fails("/meshes/0/primitives/0/extensions")),
    # ------------------------------------------------------------------ indices in range
    Case("gltf-node-mesh-unresolved", "a node naming a missing mesh", glb_case(_set(("nodes", 0, "mesh"), 4)),
         fails("/nodes/0/mesh")),
    Case("gltf-node-child-unresolved", "a child naming a missing node",
         glb_case(_set(("nodes", 0, "children"), [7])), fails("/nodes/0/children/0")),
    Case("gltf-node-skin-unresolved", "a node naming a missing skin", glb_case(_set(("nodes", 0, "skin"), 0)),
         fails("/nodes/0/skin")),
    Case("gltf-node-camera-unresolved", "a node naming a missing camera",
         glb_case(_set(("nodes", 0, "camera"), 2)), fails("/nodes/0/camera")),
    Case("gltf-node-loop", "a node that is its own ancestor (would loop forever)", glb_case(_node_loop),
         fails("/nodes/", "ancestor")),
    Case("gltf-scene-unresolved", "scene naming a missing scene", glb_case(_set(("scene",), 3)), fails("/scene")),
    Case("gltf-material-unresolved", "a primitive naming a missing material",
         glb_case(_set(("meshes", 0, "primitives", 0, "material"), 2)), fails("/meshes/0/primitives/0/material")),
    Case("gltf-accessor-view-unresolved", "an accessor naming a missing bufferView",
         glb_case(_set(("accessors", 0, "bufferView"), 7)), fails("/accessors/0/bufferView")),
    Case("gltf-view-buffer-unresolved", "a bufferView naming a missing buffer",
         glb_case(_set(("bufferViews", 0, "buffer"), 2)), fails("/bufferViews/0/buffer")),
    Case("gltf-texture-source-unresolved", "a texture naming a missing image",
         _make_image_file(glb_case(_with_texture(_set(("textures", 0, "source"), 3)))), fails("/textures/0/source")),
    Case("gltf-texture-sampler-unresolved", "a texture naming a missing sampler",
         _make_image_file(glb_case(_with_texture(_set(("textures", 0, "sampler"), 0)))),
         fails("/textures/0/sampler")),
    Case("gltf-material-texture-unresolved", "a material naming a missing texture",
         _make_image_file(glb_case(_with_texture(_set(("materials", 0, "pbrMetallicRoughness", "baseColorTexture",
                                                       "index"), 9)))),
         fails("/materials/0/pbrMetallicRoughness/baseColorTexture/index")),
    Case("gltf-skin-joint-unresolved", "a skin naming a missing joint node",
         glb_case(_set(("skins",), [{"joints": [5]}])), fails("/skins/0/joints/0")),
    # ------------------------------------------------------------------ byte ranges
    Case("gltf-view-past-buffer", "a bufferView running past the end of its buffer", glb_case(_view_past_buffer),
         fails("/bufferViews/0")),
    Case("gltf-accessor-past-view", "an accessor running past the end of its bufferView",
         glb_case(_accessor_past_view), fails("/accessors/0")),
    # ------------------------------------------------------------------ data that is not there, or not numbers
    Case("gltf-glb-no-bin-chunk", "a buffer with a byteLength and no BIN chunk: never read as zeros",
         _no_bin_chunk, fails("/buffers/0")),
    Case("gltf-buffer-no-uri", "a .gltf buffer with a byteLength and no uri: never read as zeros", _no_buffer_uri,
         fails("/buffers/0")),
    Case("gltf-position-nan", "a NaN position", _positions([[0, 0, 0], [np.nan, 0, 0], [0, 1, 0]]),
         fails("/accessors/0")),
    Case("gltf-position-inf", "an infinite position", _positions([[0, 0, 0], [1, 0, 0], [0, np.inf, 0]]),
         fails("/accessors/0")),
    Case("gltf-normal-nan", "a NaN normal", _attribute("NORMAL", "VEC3", [[0, 0, 1], [0, 0, np.nan], [0, 0, 1]]),
         fails("/accessors/1")),
    Case("gltf-texcoord-inf", "an infinite texture coordinate",
         _attribute("TEXCOORD_0", "VEC2", [[0, 0], [1, 0], [-np.inf, 1]]), fails("/accessors/1")),
    # ------------------------------------------------------------------ GLB header
    Case("gltf-glb-version-1", "a GLB of container version 1", _glb_version, refused("version")),
    Case("gltf-glb-trailing-bytes", "bytes after the length a GLB header gives are ignored (a warning, as in "
         "Khronos' validator)", _glb_trailing, VALID),
    Case("gltf-glb-bin-first", "a GLB whose first chunk is not JSON", _glb_bin_first, refused("first chunk")),
    # ------------------------------------------------------------------ buffer URIs
    Case("uri-buffer-dotdot", "a buffer URI with .. leaving the folder",
         gltf_case(set_uri("../outside/secret.bin")), fails("/buffers/0/uri", "../outside/secret.bin")),
    Case("uri-buffer-dotdot-encoded", "a percent-encoded .. leaving the folder",
         gltf_case(set_uri(SECRET_REL)), fails("/buffers/0/uri", SECRET_REL)),
    Case("uri-buffer-backslash", "backslashes leaving the folder",
         gltf_case(set_uri("..\\..\\outside\\secret.bin")), fails("/buffers/0/uri")),
    Case("uri-buffer-absolute", "an absolute buffer path", gltf_case(set_uri("{outside}/secret.bin")),
         fails("/buffers/0/uri", "absolute")),
    Case("uri-buffer-file", "a file: buffer URI", gltf_case(set_uri("file://{outside}/secret.bin")),
         fails("/buffers/0/uri", "file:")),
    Case("uri-buffer-http", "an http: buffer URI (never fetched)", gltf_case(set_uri("{http}secret.bin")),
         fails("/buffers/0/uri", "http:")),
    Case("uri-buffer-other-scheme", "a buffer URI of another scheme", gltf_case(set_uri("ftp://example.com/a.bin")),
         fails("/buffers/0/uri", "ftp:")),
    Case("uri-buffer-symlink", "a symbolic link in the folder pointing outside it", _symlink_out,
         fails("/buffers/0/uri", "link.bin")),
    Case("uri-buffer-data-short", "a data: URI holding fewer bytes than byteLength", gltf_case(_data_uri_short),
         fails("/buffers/0", "byteLength")),
    Case("uri-buffer-data-broken", "a data: URI that is not base64", gltf_case(set_uri(
        "data:application/octet-stream;base64,@@@")), fails("/buffers/0/uri")),
    # ------------------------------------------------------------------ image URIs
    Case("uri-image-dotdot", "an image URI with .. leaving the folder",
         gltf_case(image_uri("../outside/secret.bin")), fails("/images/0/uri", "../outside/secret.bin")),
    Case("uri-image-dotdot-encoded", "a percent-encoded image URI leaving the folder",
         gltf_case(image_uri(SECRET_REL)), fails("/images/0/uri", SECRET_REL)),
    Case("uri-image-absolute", "an absolute image path", gltf_case(image_uri("{outside}/secret.bin")),
         fails("/images/0/uri", "absolute")),
    Case("uri-image-file", "a file: image URI", gltf_case(image_uri("file://{outside}/secret.bin")),
         fails("/images/0/uri", "file:")),
    Case("uri-image-http", "an http: image URI (never fetched)", gltf_case(image_uri("{http}secret.png")),
         fails("/images/0/uri", "http:")),
    Case("uri-image-data-broken", "an image data: URI that is not base64",
         gltf_case(image_uri("data:image/png;base64,@@@")), fails("/images/0/uri")),
]
