"""Broken containers: files that are not what their suffix says, damaged GLB headers and chunks, broken JSON, headers
that claim more data than the file holds."""
from __future__ import annotations

import struct

from corpus.case import Case, Expect, glb_bytes, triangle_gltf

# a container that cannot be parsed: every command refuses it in one line (exit 2; validate too, issue 47)
NOT_READABLE = {"bake": Expect(2), "inspect": Expect(2), "validate": Expect(2)}


def _empty(folder, env):
    (folder / "empty.glb").write_bytes(b"")
    return folder / "empty.glb"


def _bad_magic(folder, env):
    gltf, data = triangle_gltf()
    (folder / "magic.glb").write_bytes(b"gLTF" + glb_bytes(gltf, data)[4:])
    return folder / "magic.glb"


def _total_length_lies(folder, env):
    gltf, data = triangle_gltf()
    blob = bytearray(glb_bytes(gltf, data))
    struct.pack_into("<I", blob, 8, len(blob) + 4096)  # header says the file is longer than it is
    (folder / "length.glb").write_bytes(bytes(blob))
    return folder / "length.glb"


def _chunk_past_end(folder, env):
    gltf, data = triangle_gltf()
    blob = bytearray(glb_bytes(gltf, data))
    json_length = struct.unpack_from("<I", blob, 12)[0]
    struct.pack_into("<I", blob, 20 + json_length, 1 << 30)  # BIN chunk claims 1 GiB
    (folder / "chunk.glb").write_bytes(bytes(blob))
    return folder / "chunk.glb"


def _truncated(folder, env):
    gltf, data = triangle_gltf()
    (folder / "cut.glb").write_bytes(glb_bytes(gltf, data)[:-20])
    return folder / "cut.glb"


def _garbage_json(folder, env):
    (folder / "garbage.gltf").write_text('{"asset": {"version": "2.0"}, "meshes": [')
    return folder / "garbage.gltf"


def _json_not_object(folder, env):
    (folder / "list.gltf").write_text("[1, 2, 3]")
    return folder / "list.gltf"


def _ply_huge_header(folder, env):
    # a header that claims 10^12 vertices in a file of a few hundred bytes: refused before memory is allocated
    body = b"ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\n" \
           b"property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
    (folder / "huge.ply").write_bytes(body + b"\0" * 64)
    return folder / "huge.ply"


def _obj_no_faces(folder, env):
    (folder / "points.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\n")
    return folder / "points.obj"


CASES = [
    # an empty file and one without the GLB magic are not GLB files: validate refuses them in one line (exit 2, issue
    # 47) as it does a PNG under that name, instead of reporting them as damaged GLBs
    Case("empty-file", "damaged GLB: an empty file", _empty,
         {**NOT_READABLE, "bake": Expect(2, ("empty.glb",)), "validate": Expect(2, ("an empty file",))}),
    Case("glb-bad-magic", "damaged GLB: wrong magic", _bad_magic,
         {**NOT_READABLE, "validate": Expect(2, ("binary data, not a GLB file",))}),
    Case("glb-length-lies", "damaged GLB: total length beyond the file", _total_length_lies,
         {**NOT_READABLE, "validate": Expect(2, ("length.glb", "truncated GLB: header says"))}),
    Case("glb-chunk-past-end", "damaged GLB: a chunk length beyond the file", _chunk_past_end,
         {**NOT_READABLE, "validate": Expect(2, ("chunk.glb", "runs past the end of the file"))}),
    Case("glb-truncated", "damaged GLB: cut short", _truncated,
         {**NOT_READABLE, "validate": Expect(2, ("cut.glb", "truncated GLB"))}),
    Case("json-garbage", "broken JSON", _garbage_json,
         {**NOT_READABLE, "bake": Expect(2, ("JSON",)), "validate": Expect(2, ("garbage.gltf", "truncated JSON"))}),
    # parsed, but not a glTF document: validate reports it (exit 1), as it does any other error in a document
    Case("json-not-object", "a JSON document that is not an object", _json_not_object,
         {**NOT_READABLE, "validate": Expect(1, ("TYPE_MISMATCH",))}),
    Case("ply-huge-header", "a count from a header larger than the file could hold", _ply_huge_header,
         {"bake": Expect(2, ("huge.ply",)), "inspect": Expect(2, ("huge.ply",))},
         commands={"bake": ("bake", "{input}", "-o", "{output}", "--bakes", "edges"), "inspect": ("inspect", "{input}")}),
    Case("obj-no-faces", "points only", _obj_no_faces, {"bake": Expect(2, ("no triangle faces",)),
                                                         "inspect": Expect(2, ("no triangle faces",))},
         commands={"bake": ("bake", "{input}", "-o", "{output}", "--bakes", "edges"), "inspect": ("inspect", "{input}")}),
]
