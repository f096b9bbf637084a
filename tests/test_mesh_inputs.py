"""Hostile and degenerate OBJ/PLY/STL inputs and fonts (issue 15, items 4, 5 and 7).

- Header counts are not trusted: a PLY element count or a binary STL triangle count that the file cannot hold is
  refused (exit 2, one line) before anything is allocated; a working-memory estimate refuses a job above
  ``--max-memory``.
- NaN / infinite / beyond-float32 coordinates, normals and UVs are refused naming the OBJ line, the PLY element or
  the STL triangle; degenerate triangles, zero-area meshes and isolated vertices bake with every float of the output
  finite (read back with this file's own GLB reader).
- Fonts that are not fonts, truncated fonts, fonts without the requested glyphs and empty charsets: exit 2, one line,
  nothing written.
"""
from __future__ import annotations

import json
import math
import struct
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

from baker import memory
from baker.cli import main

FONT = Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
PLY_HEADER = ("ply\nformat {fmt} 1.0\nelement vertex {n}\nproperty float x\nproperty float y\nproperty float z\n"
              "element face {m}\nproperty list uchar int vertex_indices\nend_header\n")
TETRA = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], np.float32)
TETRA_FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def run(argv, capsys) -> tuple[int, list[str]]:
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # a numpy warning would be a second line on stderr
        code = main([str(a) for a in argv])
    return code, capsys.readouterr().err.strip().splitlines()


def refused(argv, capsys, *words) -> str:
    code, lines = run(argv, capsys)
    assert code == 2, lines
    assert len(lines) == 1 and lines[0].startswith("baker: error: "), lines
    for word in words:
        assert word in lines[0], lines
    return lines[0]


def bake(path, out, capsys, *words, bakes="edges"):
    refused(["bake", path, "-o", out, "--bakes", bakes, "-q"], capsys, *words)
    assert not out.exists()
    assert not [p for p in out.parent.iterdir() if ".tmp" in p.name]


def binary_ply(vertices, faces, n=None, m=None) -> bytes:
    head = PLY_HEADER.format(fmt="binary_little_endian", n=len(vertices) if n is None else n,
                             m=len(faces) if m is None else m).encode()
    body = np.asarray(vertices, "<f4").tobytes()
    for f in faces:
        body += struct.pack("<B3i", 3, *f)
    return head + body


def binary_stl(triangles, count=None) -> bytes:
    body = b"".join(struct.pack("<12fH", 0, 0, 1, *np.ravel(t), 0) for t in triangles)
    return b"\0" * 80 + struct.pack("<I", len(triangles) if count is None else count) + body


# ------------------------------------------------------------------------------------------------ header counts
def test_ply_huge_vertex_count_refused_at_once(tmp_path, capsys):
    path = tmp_path / "huge.ply"
    path.write_bytes(PLY_HEADER.format(fmt="binary_little_endian", n=10 ** 12, m=1).encode() + b"\0" * 64)
    start = time.perf_counter()
    bake(path, tmp_path / "out.glb", capsys, "1000000000000", "vertex")
    assert time.perf_counter() - start < 1.0


def test_ascii_ply_count_beyond_file(tmp_path, capsys):
    path = tmp_path / "huge.ply"
    path.write_text(PLY_HEADER.format(fmt="ascii", n=10 ** 9, m=1) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    bake(path, tmp_path / "out.glb", capsys, "ASCII", "truncated")


def test_ply_huge_face_count(tmp_path, capsys):
    path = tmp_path / "faces.ply"
    path.write_bytes(binary_ply(TETRA, TETRA_FACES, m=10 ** 10))
    bake(path, tmp_path / "out.glb", capsys, "'face'")


def test_truncated_binary_ply(tmp_path, capsys):
    data = binary_ply(TETRA, TETRA_FACES)
    cut = tmp_path / "cut.ply"
    cut.write_bytes(data[:data.index(b"end_header\n") + 11 + 20])  # inside the vertex data
    bake(cut, tmp_path / "out.glb", capsys, "truncated")
    cut.write_bytes(data[:-5])  # inside the faces: trimesh's own length check
    bake(cut, tmp_path / "out.glb", capsys, "cut.ply")


def test_ply_header_without_end(tmp_path, capsys):
    path = tmp_path / "open.ply"
    path.write_bytes(b"ply\nformat ascii 1.0\nelement vertex 3\n")
    bake(path, tmp_path / "out.glb", capsys, "end_header")


def test_binary_stl_count_lies(tmp_path, capsys):
    tri = [[[0, 0, 0], [1, 0, 0], [0, 1, 0]]]
    path = tmp_path / "lie.stl"
    path.write_bytes(binary_stl(tri, count=10 ** 9))
    bake(path, tmp_path / "out.glb", capsys, "1000000000 triangles", "134 bytes")
    path.write_bytes(binary_stl(tri * 3, count=2))
    bake(path, tmp_path / "out.glb", capsys, "2 triangles")


def test_good_stl_and_ply_bake(tmp_path, capsys):
    tris = TETRA[TETRA_FACES]
    (tmp_path / "ok.stl").write_bytes(binary_stl(tris))
    (tmp_path / "ok.ply").write_bytes(binary_ply(TETRA, TETRA_FACES))
    ascii_stl = "solid t\n" + "".join("facet normal 0 0 1\nouter loop\n" + "".join(
        f"vertex {x} {y} {z}\n" for x, y, z in t) + "endloop\nendfacet\n" for t in tris) + "endsolid t\n"
    (tmp_path / "ascii.stl").write_text(ascii_stl)
    for name in ("ok.stl", "ok.ply", "ascii.stl"):
        code, lines = run(["bake", tmp_path / name, "-o", tmp_path / f"{name}.glb", "--bakes", "edges", "-q"], capsys)
        assert code == 0, lines


# ------------------------------------------------------------------------------------------------ numbers
OBJ_TETRA = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
OBJ_FACES = "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"


@pytest.mark.parametrize("text, line, token", [
    (OBJ_TETRA.replace("v 0 1 0", "v 0 nan 0") + OBJ_FACES, 3, "nan"),
    (OBJ_TETRA.replace("v 0 0 1", "v 0 0 -inf") + OBJ_FACES, 4, "-inf"),
    (OBJ_TETRA.replace("v 1 0 0", "v 1e39 0 0") + OBJ_FACES, 2, "1e39"),  # finite in float64, inf in float32
    (OBJ_TETRA + "vt 0 0\nvt 1 0\nvt NaN 1\nvt 1 1\n" + OBJ_FACES.replace("f 1 3 2", "f 1/1 3/3 2/2")
     .replace("f 1 2 4", "f 1/1 2/2 4/4").replace("f 1 4 3", "f 1/1 4/4 3/3").replace("f 2 3 4", "f 2/2 3/3 4/4"),
     7, "NaN"),
    (OBJ_TETRA + "vn 0 0 1\nvn 0 0 1\nvn 0 inf 1\nvn 0 0 1\n" + "".join(
        f"f {a}//{a} {b}//{b} {c}//{c}\n" for a, b, c in TETRA_FACES + 1), 7, "inf"),
], ids=["nan-position", "inf-position", "float32-overflow", "nan-uv", "inf-normal"])
def test_obj_non_finite_names_the_line(tmp_path, capsys, text, line, token):
    path = tmp_path / "bad.obj"
    path.write_text(text)
    for bakes in ("edges", "thickness,curvature"):
        bake(path, tmp_path / "out.glb", capsys, "bad.obj", f"line {line}:", repr(token), bakes=bakes)


def test_ply_non_finite_names_the_element(tmp_path, capsys):
    path = tmp_path / "bad.ply"
    path.write_text(PLY_HEADER.format(fmt="ascii", n=4, m=4) + "0 0 0\n1 0 0\n0 nan 0\n0 0 1\n"
                    + "".join(f"3 {a} {b} {c}\n" for a, b, c in TETRA_FACES))
    bake(path, tmp_path / "out.glb", capsys, "vertex 2", "'y'", "nan")
    v = TETRA.copy()
    v[3, 2] = np.inf
    path.write_bytes(binary_ply(v, TETRA_FACES))
    bake(path, tmp_path / "out.glb", capsys, "vertex 3", "'z'", "inf")


def test_stl_non_finite_names_the_triangle(tmp_path, capsys):
    tris = TETRA[TETRA_FACES].copy()
    tris[2, 1, 0] = np.nan
    path = tmp_path / "bad.stl"
    path.write_bytes(binary_stl(tris))
    bake(path, tmp_path / "out.glb", capsys, "triangle 2")


# ------------------------------------------------------------------------------------------------ degenerate meshes
def glb_floats(path: Path) -> tuple[dict, list]:
    """(glTF JSON, [(accessor index, float32 array)]) of a GLB, read without baker."""
    data = path.read_bytes()
    magic, version, total = struct.unpack_from("<4sII", data)
    assert magic == b"glTF" and version == 2 and total == len(data)
    length, kind = struct.unpack_from("<II", data, 12)
    gltf = json.loads(data[20:20 + length])
    binary = data[20 + length + 8:] if len(data) > 20 + length else b""
    sizes = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
    out = []
    for i, acc in enumerate(gltf.get("accessors", [])):
        if acc["componentType"] != 5126 or "bufferView" not in acc:
            continue
        view = gltf["bufferViews"][acc["bufferView"]]
        n = sizes[acc["type"]]
        stride = view.get("byteStride", 4 * n)
        start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
        rows = [np.frombuffer(binary, "<f4", n, start + k * stride) for k in range(acc["count"])]
        out.append((i, np.array(rows, np.float32).reshape(acc["count"], n)))
    return gltf, out


def json_non_finite(value, where="") -> list:
    if isinstance(value, float):
        return [] if math.isfinite(value) else [where]
    if isinstance(value, dict):
        return [w for k, v in value.items() for w in json_non_finite(v, f"{where}/{k}")]
    if isinstance(value, list):
        return [w for k, v in enumerate(value) for w in json_non_finite(v, f"{where}/{k}")]
    return []


def _obj(vertices, faces, uvs=True) -> str:
    lines = [f"v {x} {y} {z}" for x, y, z in vertices]
    if uvs:
        lines += [f"vt {(i % 7) / 7} {(i % 5) / 5}" for i in range(len(vertices))]
        lines += ["f " + " ".join(f"{a + 1}/{a + 1}" for a in f) for f in faces]
    else:
        lines += ["f " + " ".join(str(a + 1) for a in f) for f in faces]
    return "\n".join(lines) + "\n"


DEGENERATE = {
    # every triangle of zero area: the vertices on one line
    "collinear": _obj([[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]], [[0, 1, 2], [1, 2, 3], [0, 2, 3]]),
    # all three corners of every triangle at one point
    "point": _obj([[0.5, 0.5, 0.5]] * 3, [[0, 1, 2], [2, 1, 0]]),
    # a closed tetrahedron plus repeated-index triangles, a sliver and two isolated vertices
    "tetra-degenerate": _obj(np.vstack([TETRA, [[5, 5, 5], [-3, 2, 1], [0.5, 0, 0]]]),
                             [*TETRA_FACES.tolist(), [0, 0, 1], [2, 2, 2], [0, 1, 6]]),
    # flat (planar) mesh: area but no volume
    "planar": _obj([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2], [0, 2, 3]]),
}


@pytest.mark.parametrize("name", sorted(DEGENERATE))
def test_degenerate_meshes_bake_finite(tmp_path, capsys, name):
    path = tmp_path / f"{name}.obj"
    path.write_text(DEGENERATE[name])
    out = tmp_path / "out.glb"
    code, lines = run(["bake", path, "-o", out, "--bakes", "thickness,curvature,edges,skin,fur", "-q",
                       "--thickness-rays", "16", "--thickness-texture-size", "64"], capsys)
    assert code == 0 and not lines, lines
    gltf, floats = glb_floats(out)
    attributes = {k for m in gltf["meshes"] for p in m["primitives"] for k in p["attributes"]}
    assert {"_THICKNESS", "_CURVATURE", "_OUTLINE_NORMAL"} <= attributes
    bad = [i for i, values in floats if not np.isfinite(values).all()]
    assert not bad, [(i, gltf["accessors"][i]) for i in bad]
    assert not json_non_finite(gltf)
    from conftest import assert_khronos_clean

    assert_khronos_clean(out)  # the converted normals are unit length even where every triangle is degenerate


def test_mesh_collapsed_to_a_point_bakes_valid_thickness(tmp_path, capsys):
    """Every vertex at one place: the default maxDistance (the bounding-box diagonal, here 0) falls back to one mesh
    unit, so BAKER_thickness keeps its schema's maxDistance > 0 and ``baker validate`` (schemas, semantics and
    Khronos) passes, on the glTF form and on the OBJ form (whose converted normals are zero-length until made unit)."""
    from conftest import assert_khronos_clean

    point = np.full((3, 3), 0.5, np.float32)
    indices = np.array([0, 1, 2, 2, 1, 0], np.uint16)
    data = point.tobytes() + indices.tobytes()
    gltf = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                           "min": [0.5] * 3, "max": [0.5] * 3},
                          {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
            "bufferViews": [{"buffer": 0, "byteLength": point.nbytes, "target": 34962},
                            {"buffer": 0, "byteOffset": point.nbytes, "byteLength": indices.nbytes, "target": 34963}],
            "buffers": [{"byteLength": len(data), "uri": "point.bin"}]}
    (tmp_path / "point.bin").write_bytes(data)
    src = tmp_path / "point.gltf"
    src.write_text(json.dumps(gltf))
    obj = tmp_path / "point.obj"
    obj.write_text(DEGENERATE["point"])
    for path, validate in ((src, ["validate"]), (obj, ["validate"])):
        out = tmp_path / f"{path.stem}-{path.suffix[1:]}.glb"
        code, lines = run(["bake", path, "-o", out, "--bakes", "thickness", "-q", "--thickness-rays", "8",
                           "--thickness-texture-size", "32"], capsys)
        assert code == 0 and not lines, lines
        ext = glb_floats(out)[0]["materials"][0]["extensions"]["BAKER_thickness"]
        assert ext["maxDistance"] == 1.0 and ext["attenuationDistance"] > 0
        assert main([*validate, str(out)]) == 0, capsys.readouterr().out
        capsys.readouterr()
    assert_khronos_clean(tmp_path / "point-gltf.glb")
    assert_khronos_clean(tmp_path / "point-obj.glb")


# ------------------------------------------------------------------------------------------------ memory
def test_max_memory_refuses_a_job_that_would_not_fit(tmp_path, capsys):
    path = tmp_path / "t.obj"
    path.write_text(_obj(TETRA, TETRA_FACES))
    out = tmp_path / "out.glb"
    refused(["bake", path, "-o", out, "--bakes", "edges", "--max-memory", "1M"], capsys, "--max-memory", "1.0 MiB")
    assert not out.exists()
    code, lines = run(["bake", path, "-o", out, "--bakes", "edges", "--max-memory", "none", "-q"], capsys)
    assert code == 0, lines
    refused(["bake", path, "-o", out, "--bakes", "edges", "--max-memory", "lots"], capsys, "--max-memory")


@pytest.mark.parametrize("command", [["inspect"], ["lines", "-o", "{out}.svg"], ["preview", "-o", "{out}.png"],
                                     ["hair", "-o", "{out}.glb"]])
def test_max_memory_on_every_command_that_loads_a_mesh(tmp_path, capsys, command):
    """inspect, lines, preview and hair take ``--max-memory`` as bake does: a limit below the process itself is
    refused with one line (exit 2) and nothing is written."""
    path = tmp_path / "t.obj"
    path.write_text(_obj(TETRA, TETRA_FACES))
    verb, *rest = [a.replace("{out}", str(tmp_path / "out")) for a in command]
    refused([verb, path, *rest, "--max-memory", "1M"], capsys, "--max-memory", "1.0 MiB")
    assert not [p for p in tmp_path.iterdir() if p.name.startswith("out")]
    refused([verb, path, *rest, "--max-memory", "lots"], capsys, "--max-memory")


def test_max_memory_refuses_before_reading(tmp_path, capsys, monkeypatch):
    """The file estimate comes before trimesh: a binary PLY's counts alone decide."""
    path = tmp_path / "big.ply"
    path.write_bytes(binary_ply(TETRA, TETRA_FACES))
    import trimesh

    monkeypatch.setattr(trimesh, "load", lambda *a, **k: pytest.fail("read before the memory check"))
    refused(["bake", path, "-o", tmp_path / "o.glb", "--max-memory", "10M"], capsys, "reading this PLY file")


def test_memory_estimate_and_limits():
    assert memory.parse_limit("512M") == 512 << 20
    assert memory.parse_limit("1.5GiB") == int(1.5 * (1 << 30))
    assert memory.parse_limit("2gb") == 2 * 1000 ** 3
    assert memory.parse_limit("1000") == 1000
    assert memory.parse_limit("none") is None
    total = memory.physical_memory()
    assert total and total > 1 << 28
    assert memory.parse_limit(None) == int(total * 0.75)
    assert memory.parse_limit("50%") == int(total * 0.5)
    small, large = (memory.bake_estimate(n, ["thickness", "edges"]) for n in (10_000, 10_000_000))
    assert large - small == pytest.approx(9_990_000 * (memory.LOAD_PER_TRIANGLE + memory.PER_TRIANGLE["thickness"]
                                                       + memory.PER_TRIANGLE["edges"]))
    # a bigger texture costs more
    from baker.pipeline import resolve_options

    big = {"thickness": resolve_options("thickness", {"texture_size": 8192})}
    assert memory.bake_estimate(1000, ["thickness"], big) > memory.bake_estimate(1000, ["thickness"]) + (5 << 30)
    # automatic sizes (texel density): counted from the triangles, within [64^2, 2048^2] per material
    auto = {"thickness": resolve_options("thickness", {})}
    assert auto["thickness"].texture_size is None
    forced_2048 = {"thickness": resolve_options("thickness", {"texture_size": 2048})}
    huge = memory.bake_estimate(50_000_000, ["thickness"], auto, materials=3)
    assert huge == memory.bake_estimate(50_000_000, ["thickness"], forced_2048, materials=3)  # every set at 2048^2
    few = [memory.bake_estimate(6720, ["thickness"], auto, materials=m) for m in (1, 7)]
    assert few[0] == few[1]  # 128 texels per triangle lies between 7 x 64^2 and 2048^2: the materials do not matter
    assert memory.texture_texels(6720, 7, None) == 6720 * memory.AUTO_TEXELS_PER_TRIANGLE <= 7 * 512 ** 2


# ------------------------------------------------------------------------------------------------ fonts
@pytest.fixture(scope="module")
def fonts(tmp_path_factory):
    if not FONT.exists():
        pytest.skip("DejaVu Sans is not installed (scripts/test installs fonts-dejavu-core)")
    from fontTools.ttLib import TTFont

    folder = tmp_path_factory.mktemp("fonts")
    (folder / "text.ttf").write_text("this is not a font\n" * 20)
    (folder / "empty.otf").write_bytes(b"")
    data = FONT.read_bytes()
    (folder / "head-cut.ttf").write_bytes(data[:3000])  # the table directory promises tables past the end
    # glyf table cut: head, cmap and the rest read, the outlines fail only when glyphs are drawn
    TTFont(str(FONT)).save(str(folder / "ordered.ttf"), reorderTables=True)
    ordered = (folder / "ordered.ttf").read_bytes()
    glyf = TTFont(str(folder / "ordered.ttf")).reader.tables["glyf"]
    (folder / "glyf-cut.ttf").write_bytes(ordered[:glyf.offset + 1000])
    garbled = bytearray(ordered)
    garbled[glyf.offset:glyf.offset + 200_000] = b"\x7f" * 200_000
    (folder / "glyf-garbled.ttf").write_bytes(bytes(garbled))
    return folder


@pytest.mark.parametrize("name, words", [
    ("text.ttf", ("a text file, not a TrueType/OpenType font",)),
    ("empty.otf", ("an empty file, not a TrueType/OpenType font",)),
    ("head-cut.ttf", ("not a readable",)),
    ("glyf-cut.ttf", ("damaged or truncated font", "glyf")),
    ("glyf-garbled.ttf", ("damaged or truncated font",)),
])
def test_not_a_font(fonts, tmp_path, capsys, name, words):
    refused(["glyphs", fonts / name, "-o", tmp_path / "atlas"], capsys, name, *words)
    refused(["text", "Hi", "--font", fonts / name, "-o", tmp_path / "t.glb"], capsys, name, *words)
    assert not list(tmp_path.iterdir())


def test_font_without_the_requested_glyphs(fonts, tmp_path, capsys):
    refused(["glyphs", FONT, "-o", tmp_path / "atlas", "--charset", "0x4E00-0x4E10"], capsys,
            "none of the 17 requested characters", "U+4E00")
    refused(["text", "\u4e2d\u6587", "--font", FONT, "-o", tmp_path / "t.glb"], capsys, "none of the 2")
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("charset", ["str:", ",", ""])
def test_empty_charset(fonts, tmp_path, capsys, charset):
    refused(["glyphs", FONT, "-o", tmp_path / "atlas", "--charset", charset], capsys, "empty charset")
    assert not list(tmp_path.iterdir())


def test_empty_text(fonts, tmp_path, capsys):
    refused(["text", "", "--font", FONT, "-o", tmp_path / "t.glb"], capsys, "empty charset")
    assert not list(tmp_path.iterdir())


# ------------------------------------------------------------------------------------------ text that is not UTF-8
def test_latin1_obj_and_stl_read_as_their_utf8_twins(tmp_path, capsys):
    """An OBJ whose material name and an ASCII STL whose solid name are Latin-1 (not UTF-8: trimesh's fallback
    would guess the encoding with charset_normalizer, which baker does not install) read as the same file written in
    UTF-8: the same vertices, faces and names; a binary STL whose 80-byte header is not text reads as with a blank
    header."""
    from baker import readers

    obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nl 1 2\nusemtl caf\xe9\nf 1 2 3\nf 1 3 4\n"
    stl = ("solid caf\xe9\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
           "endfacet\nendsolid caf\xe9\n")
    for name, text in (("m.obj", obj), ("m.stl", stl)):
        (tmp_path / "latin1").mkdir(exist_ok=True)
        (tmp_path / "utf8").mkdir(exist_ok=True)
        (tmp_path / "latin1" / name).write_bytes(text.encode("latin-1"))
        (tmp_path / "utf8" / name).write_bytes(text.encode("utf-8"))
        a, b = (readers.read(tmp_path / enc / name) for enc in ("latin1", "utf8"))
        assert [m.get("name") for m in a.meshes()] == [m.get("name") for m in b.meshes()]
        for m in range(len(b.meshes())):
            for p in b.triangle_primitives(m):
                assert np.array_equal(a.primitive(m, p).positions, b.primitive(m, p).positions)
                assert np.array_equal(a.primitive(m, p).faces, b.primitive(m, p).faces)
    tri = [TETRA[[0, 1, 2]], TETRA[[0, 1, 3]]]
    blank = binary_stl(tri)
    (tmp_path / "blank.stl").write_bytes(blank)
    (tmp_path / "header.stl").write_bytes(bytes(range(128, 208)) + blank[80:])
    a, b = readers.read(tmp_path / "header.stl"), readers.read(tmp_path / "blank.stl")
    assert np.array_equal(a.primitive(0, 0).positions, b.primitive(0, 0).positions)


SPOT = Path(__file__).parents[1] / "examples" / "spot" / "spot.obj"


@pytest.mark.parametrize("suffix", ["ply", "stl", "glb", "usdc"])
def test_truncated_real_files_are_one_line(tmp_path, capsys, suffix):
    """spot written as a binary PLY, STL, GLB and USD crate, then cut at half its length: bake and inspect exit 2 with
    one line naming the file, nothing written."""
    import trimesh

    whole = tmp_path / f"whole.{suffix}"
    if suffix == "usdc":
        assert main(["bake", str(SPOT), "-o", str(whole), "--bakes", "edges", "-q"]) == 0
    else:
        trimesh.load(str(SPOT), process=False, force="mesh").export(str(whole))
    data = whole.read_bytes()
    cut = tmp_path / f"cut.{suffix}"
    cut.write_bytes(data[: len(data) // 2])
    capsys.readouterr()
    refused(["inspect", cut], capsys, str(cut))
    bake(cut, tmp_path / "out.glb", capsys, str(cut))
