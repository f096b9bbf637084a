"""Mesh files and fonts: numbers that are not numbers (OBJ/PLY/STL), counts in a header that the file cannot hold,
truncated binary data, a zero-area mesh that must bake, and files passed to ``glyphs``/``text`` that are not fonts."""
from __future__ import annotations

import struct

from corpus.case import Case, Expect

MESH = {"bake": ("bake", "{input}", "-o", "{output}", "--bakes", "edges"), "inspect": ("inspect", "{input}")}
# thickness and curvature too: the numeric bakes where NaN used to spread (numpy warnings, NaN in the output)
NUMERIC = {"bake": ("bake", "{input}", "-o", "{output}", "--bakes", "thickness,curvature,edges", "--thickness-rays",
                    "8", "--thickness-texture-size", "32"), "inspect": ("inspect", "{input}")}
FONT = {"glyphs": ("glyphs", "{input}", "-o", "{output}"),
        "text": ("text", "Hi", "--font", "{input}", "-o", "{output}")}
TETRA = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
FACES = "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
PLY = ("ply\nformat {fmt} 1.0\nelement vertex {n}\nproperty float x\nproperty float y\nproperty float z\n"
       "element face {m}\nproperty list uchar int vertex_indices\nend_header\n")


def both(words, inspect_words=None) -> dict:
    return {"bake": Expect(2, words), "inspect": Expect(2, inspect_words or words)}


def _write(name, data):
    def make(folder, env):
        path = folder / name
        path.write_bytes(data if isinstance(data, bytes) else data.encode())
        return path
    return make


def _stl(triangles: int, count: int) -> bytes:
    record = struct.pack("<12fH", 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0)
    return b"\0" * 80 + struct.pack("<I", count) + record * triangles


def _binary_ply(cut: int) -> bytes:
    body = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1)
    body += b"".join(struct.pack("<B3i", 3, *f) for f in ((0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)))
    return PLY.format(fmt="binary_little_endian", n=4, m=4).encode() + body[:cut]


CASES = [
    Case("obj-nan-coordinate", "NaN position in an OBJ: exit 2 naming the line",
         _write("nan.obj", TETRA.replace("v 0 1 0", "v 0 nan 0") + FACES),
         both(("nan.obj", "line 3", "'nan'")), commands=NUMERIC),
    Case("obj-inf-coordinate", "infinite position in an OBJ: exit 2 naming the line",
         _write("inf.obj", TETRA.replace("v 0 0 1", "v 0 0 inf") + FACES),
         both(("inf.obj", "line 4", "'inf'")), commands=NUMERIC),
    Case("obj-float32-overflow", "a coordinate finite in float64 but infinite as glTF's float32",
         _write("big.obj", TETRA.replace("v 1 0 0", "v 1e39 0 0") + FACES),
         both(("big.obj", "line 2", "float32")), commands=MESH),
    Case("obj-nan-uv", "NaN texture coordinate in an OBJ: exit 2 naming the line",
         _write("uv.obj", TETRA + "vt 0 0\nvt 1 0\nvt nan 1\nvt 1 1\n"
                + "f 1/1 3/3 2/2\nf 1/1 2/2 4/4\nf 1/1 4/4 3/3\nf 2/2 3/3 4/4\n"),
         both(("uv.obj", "line 7", "texture coordinate")), commands=NUMERIC),
    Case("ply-nan-vertex", "NaN in a PLY vertex: exit 2 naming the element",
         _write("nan.ply", PLY.format(fmt="ascii", n=4, m=1) + "0 0 0\n1 0 0\n0 1 0\n0 nan 1\n3 0 1 2\n"),
         both(("nan.ply", "vertex 3", "'y'")), commands=MESH),
    Case("ply-huge-vertex-count", "a PLY vertex count larger than the file could hold, refused before reading",
         _write("count.ply", PLY.format(fmt="binary_little_endian", n=10 ** 12, m=1).encode() + b"\0" * 40),
         both(("count.ply", "1000000000000", "'vertex'")), commands=MESH),
    Case("ply-ascii-count-lies", "an ASCII PLY whose counts need more lines than it has",
         _write("lines.ply", PLY.format(fmt="ascii", n=3, m=10 ** 8) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
         both(("lines.ply", "'face'")), commands=MESH),
    Case("ply-binary-truncated", "a binary PLY cut short in its vertex data",
         _write("cut.ply", _binary_ply(30)), both(("cut.ply", "truncated")), commands=MESH),
    Case("ply-binary-truncated-faces", "a binary PLY cut short in its face data",
         _write("cutfaces.ply", _binary_ply(48 + 30)), both(("cutfaces.ply",)), commands=MESH),
    Case("stl-count-lies", "a binary STL whose triangle count is larger than the file",
         _write("lie.stl", _stl(1, 4_000_000_000)), both(("lie.stl", "4000000000 triangles")), commands=MESH),
    Case("stl-count-short", "a binary STL with more triangles than its count says",
         _write("short.stl", _stl(3, 1)), both(("short.stl", "1 triangles")), commands=MESH),
    Case("obj-zero-area", "a zero-area mesh (collinear vertices) and an isolated vertex bake without NaN",
         _write("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nv 9 9 9\nf 1 2 3\nf 2 3 4\n"),
         {"bake": Expect(0), "inspect": Expect(0)}, commands=NUMERIC),
    Case("font-not-a-font", "a file passed as a font that is not one",
         _write("font.ttf", b"this is a text file, not a font\n" * 8),
         {"glyphs": Expect(2, ("font.ttf", "not a TrueType/OpenType font")),
          "text": Expect(2, ("font.ttf", "not a TrueType/OpenType font"))},
         commands=FONT, side_outputs=(".png", ".json")),
    Case("font-truncated", "a font cut inside its table directory",
         _write("cut.otf", b"OTTO\x00\x0b\x00\x80\x00\x03\x00\x30" + b"CFF \0\0\0\0\0\0\x01\0\0\0\x10\0"),
         {"glyphs": Expect(2, ("cut.otf",)), "text": Expect(2, ("cut.otf",))},
         commands=FONT, side_outputs=(".png", ".json")),
]
