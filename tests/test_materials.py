"""Materials of mesh formats and spec-clean material bakes (issue 26, items 2 and 4).

- An OBJ + MTL written here with every supported statement bakes to glTF materials that say what the MTL says:
  the output GLB is parsed here (struct + json, not baker's reader) and every field is compared with the MTL's
  numbers and the analytic Ns -> roughness mapping (Walter et al. 2007: alpha = sqrt(2 / (Ns + 2)),
  roughness = sqrt(alpha)); texture images are compared byte for byte (PNG kept) or pixel for pixel (map_d merged).
- PLY, STL and an OBJ without MTL get an explicit dielectric (metallicFactor 0), in glTF and in USD (read with pxr).
- Untrusted MTL: a malformed number or a texture outside the asset's folder is exit 2 and one line naming the file
  and the line.
- Optional pieces (issue 35, item 2): a missing or unreadable ``mtllib`` file, or a missing texture map, is one
  warning line naming the file and line that name it; the bake (run as a process) exits 0 with the dielectric
  default, or the material without that map; ``baker build`` over such a folder succeeds.
- A Blender-like glTF (a double-sided material, an unlit material) baked with every material bake gains no Khronos
  glTF-Validator code its input did not have; the thickness texture stays in BAKER_thickness on the double-sided
  material and the bake says so once.
"""
from __future__ import annotations

import json
import math
import struct
import subprocess
import sys
import warnings

import numpy as np
import pytest

from baker.cli import main
from baker.gltf.images import decode_image, encode_image
from conftest import assert_khronos_clean, khronos_validate

QUAD_OBJ = """mtllib {mtl}
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
usemtl {first}
f 1/1/1 2/2/1 3/3/1
f 1/1/1 3/3/1 4/4/1
usemtl {second}
f 1/1/1 5/4/1 6/3/1
f 1/1/1 6/3/1 2/2/1
"""


def read_glb(path) -> tuple[dict, bytes]:
    data = path.read_bytes()
    magic, version, length = struct.unpack_from("<4sII", data)
    assert magic == b"glTF" and version == 2 and length == len(data)
    json_length, = struct.unpack_from("<I", data, 12)
    gltf = json.loads(data[20:20 + json_length])
    binary = data[20 + json_length + 8:]
    return gltf, binary


def image_bytes(gltf, binary, texture: int) -> bytes:
    view = gltf["bufferViews"][gltf["images"][gltf["textures"][texture]["source"]]["bufferView"]]
    return binary[view.get("byteOffset", 0):view.get("byteOffset", 0) + view["byteLength"]]


def run(argv, capsys) -> tuple[int, list]:
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        code = main([str(a) for a in argv])
    return code, capsys.readouterr().err.strip().splitlines()


def bake_ok(argv, capsys) -> list:
    code, lines = run(argv, capsys)
    assert code == 0, lines
    return lines


def refused(argv, capsys, *words) -> str:
    code, lines = run(argv, capsys)
    assert code == 2 and len(lines) == 1 and lines[0].startswith("baker: error: "), lines
    for word in words:
        assert word in lines[0], lines
    return lines[0]


def materials_by_name(gltf) -> dict:
    return {m["name"]: m for m in gltf["materials"]}


@pytest.fixture
def textures(tmp_path):
    """A colour map, a tangent-space normal map, a grey height map, a cut-out mask and an emission map."""
    rng = np.random.default_rng(7)
    colour = rng.integers(0, 256, (8, 8, 3), dtype=np.uint8)
    normal = np.zeros((8, 8, 3), np.uint8)
    normal[..., 0], normal[..., 1], normal[..., 2] = 128, rng.integers(100, 156, (8, 8)), 255
    height = np.repeat(rng.integers(0, 256, (8, 8, 1), dtype=np.uint8), 3, axis=2)
    mask = np.where(rng.random((4, 4)) > 0.5, 255, 0).astype(np.uint8)  # half the size of the colour map
    glow = rng.integers(0, 256, (8, 8, 3), dtype=np.uint8)
    files = {"colour": colour, "normal": normal, "height": height, "mask": mask, "glow": glow}
    for name, pixels in files.items():
        (tmp_path / f"{name}.png").write_bytes(encode_image(pixels))
    return files


EVERY_STATEMENT = """# every statement baker maps
newmtl Glossy Red
Ka 0.1 0.1 0.1
Kd 0.8 0.2 0.1
Ks 0.5 0.5 0.5
Ns 98
d 0.5
illum 2
map_Kd -s 1 1 1 -o 0 0 colour.png
map_Bump -bm 0.5 normal.png
Ke 4 2 0
map_Ke glow.png

newmtl cutout
Kd 1 1 1
Tr 0
Ns 0
map_Kd colour.png
map_d mask.png
bump height.png
Ke 0.25 0.5 0.75
"""


def test_obj_mtl_every_statement(tmp_path, textures, capsys):
    (tmp_path / "m.mtl").write_text(EVERY_STATEMENT)
    obj = tmp_path / "quad.obj"
    obj.write_text(QUAD_OBJ.format(mtl="m.mtl", first="Glossy Red", second="cutout"))
    out = tmp_path / "quad.glb"
    bake_ok(["bake", obj, "-o", out, "--bakes", "edges", "-q"], capsys)
    assert_khronos_clean(out)
    gltf, binary = read_glb(out)
    mats = materials_by_name(gltf)
    assert set(mats) == {"Glossy Red", "cutout"}

    red = mats["Glossy Red"]
    pbr = red["pbrMetallicRoughness"]
    assert pbr["baseColorFactor"] == pytest.approx([0.8, 0.2, 0.1, 0.5])
    assert pbr["metallicFactor"] == 0
    assert pbr["roughnessFactor"] == pytest.approx(math.sqrt(math.sqrt(2 / 100)))  # alpha = 0.1414
    assert red["alphaMode"] == "BLEND"
    assert image_bytes(gltf, binary, pbr["baseColorTexture"]["index"]) == (tmp_path / "colour.png").read_bytes()
    assert red["normalTexture"]["scale"] == 0.5
    assert image_bytes(gltf, binary, red["normalTexture"]["index"]) == (tmp_path / "normal.png").read_bytes()
    assert red["emissiveFactor"] == pytest.approx([1.0, 0.5, 0.0])
    assert red["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] == 4.0
    assert "KHR_materials_emissive_strength" in gltf["extensionsUsed"]
    assert image_bytes(gltf, binary, red["emissiveTexture"]["index"]) == (tmp_path / "glow.png").read_bytes()

    cut = mats["cutout"]
    pbr = cut["pbrMetallicRoughness"]
    assert pbr["baseColorFactor"] == [1, 1, 1, 1]  # Tr 0 = d 1
    assert pbr["roughnessFactor"] == pytest.approx(1.0)  # Ns 0: alpha = 1
    assert cut["alphaMode"] == "MASK" and cut.get("alphaCutoff", 0.5) == 0.5
    rgba = decode_image(image_bytes(gltf, binary, pbr["baseColorTexture"]["index"]))
    assert rgba.shape == (8, 8, 4)
    assert np.array_equal(rgba[..., :3], textures["colour"])
    assert np.array_equal(rgba[..., 3], np.repeat(np.repeat(textures["mask"], 2, axis=0), 2, axis=1))
    assert "normalTexture" not in cut  # a grey bump map is a height map: glTF has no slot for it
    assert cut["emissiveFactor"] == pytest.approx([0.25, 0.5, 0.75]) and "extensions" not in cut


def test_usd_output_of_mesh_formats(tmp_path, textures, capsys):
    from pxr import Usd, UsdShade

    (tmp_path / "m.mtl").write_text(EVERY_STATEMENT)
    obj = tmp_path / "quad.obj"
    obj.write_text(QUAD_OBJ.format(mtl="m.mtl", first="Glossy Red", second="cutout"))
    bare = tmp_path / "bare.obj"
    bare.write_text("\n".join(line for line in QUAD_OBJ.splitlines() if not line.startswith(("mtllib", "usemtl"))))
    for source, expected in ((obj, {"Glossy_Red": (0.0, math.sqrt(math.sqrt(0.02)), 0.5)}),
                             (bare, {"baker_dielectric": (0.0, 0.5, 1.0)})):
        out = tmp_path / f"{source.stem}.usda"
        bake_ok(["bake", source, "-o", out, "--bakes", "edges", "-q"], capsys)
        stage = Usd.Stage.Open(str(out))
        found = {}
        for prim in stage.Traverse():
            if prim.IsA(UsdShade.Material):
                surface = UsdShade.Shader(stage.GetPrimAtPath(prim.GetPath().AppendChild("PreviewSurface")))
                found[prim.GetName()] = (surface.GetInput("metallic").Get(), surface.GetInput("roughness").Get(),
                                         surface.GetInput("opacity").Get())
        for name, values in expected.items():
            assert found[name] == pytest.approx(values, rel=1e-6), found


PLY = ("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
       "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")


def binary_ply() -> bytes:
    head = PLY.split("end_header\n")[0].replace("ascii", "binary_little_endian") + "end_header\n"
    body = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], "<f4").tobytes()
    body += b"".join(struct.pack("<B3i", 3, *f) for f in ((0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)))
    return head.encode() + body


@pytest.mark.parametrize("kind", ["ascii.ply", "binary.ply", "stl", "obj"])
def test_formats_without_materials_are_dielectric(tmp_path, kind, capsys):
    import trimesh

    path = tmp_path / f"tetra.{kind.split('.')[-1]}"
    if kind == "ascii.ply":
        path.write_text(PLY)
    elif kind == "binary.ply":
        path.write_bytes(binary_ply())  # baker's direct binary PLY reader
    else:
        trimesh.load(trimesh.util.wrap_as_stream(PLY.encode()), file_type="ply", process=False).export(str(path))
    out = tmp_path / "out.glb"
    bake_ok(["bake", path, "-o", out, "--bakes", "edges", "-q"], capsys)
    assert_khronos_clean(out)
    gltf, _ = read_glb(out)
    used = {p["material"] for m in gltf["meshes"] for p in m["primitives"] if p.get("mode", 4) == 4}
    assert used and all(gltf["materials"][i]["pbrMetallicRoughness"]["metallicFactor"] == 0 for i in used)
    assert all(gltf["materials"][i]["pbrMetallicRoughness"]["roughnessFactor"] == 0.5 for i in used)


def test_untrusted_mtl(tmp_path, textures, capsys):
    obj = tmp_path / "quad.obj"
    obj.write_text(QUAD_OBJ.format(mtl="m.mtl", first="a", second="b"))
    out = tmp_path / "out.glb"
    for text, words in (("newmtl a\nKd 1 0.5 x\n", ("m.mtl", "line 2", "'x'")),
                        ("newmtl a\n\nNs nan\n", ("m.mtl", "line 3", "finite")),
                        ("newmtl a\nmap_Bump -bm\n", ("m.mtl", "line 2", "-bm")),
                        ("newmtl a\nmap_Kd ../outside/colour.png\n", ("m.mtl", "line 2", "leaves the asset's folder"))):
        (tmp_path / "m.mtl").write_text(text)
        refused(["bake", obj, "-o", out, "--bakes", "edges", "-q"], capsys, *words)
        assert not out.exists()
    obj.write_text(QUAD_OBJ.format(mtl="../elsewhere.mtl", first="a", second="b"))
    (tmp_path.parent / "elsewhere.mtl").write_text("newmtl a\nKd 1 0 0\n")
    refused(["bake", obj, "-o", out, "--bakes", "edges", "-q"], capsys, "quad.obj", "line 1", "mtllib")
    # --allow-outside widens the policy, as for glTF URIs
    outside = tmp_path.parent / "outside"
    outside.mkdir(exist_ok=True)
    (outside / "colour.png").write_bytes((tmp_path / "colour.png").read_bytes())
    (tmp_path / "m.mtl").write_text("newmtl a\nmap_Kd ../outside/colour.png\n")
    obj.write_text(QUAD_OBJ.format(mtl="m.mtl", first="a", second="b"))
    bake_ok(["bake", obj, "-o", out, "--bakes", "edges", "-q", "--allow-outside", outside], capsys)
    gltf, binary = read_glb(out)
    texture = materials_by_name(gltf)["a"]["pbrMetallicRoughness"]["baseColorTexture"]["index"]
    assert image_bytes(gltf, binary, texture) == (tmp_path / "colour.png").read_bytes()


# ------------------------------------------------------------------------------------ Blender-like glTF inputs
def blender_like_gltf(path) -> None:
    """Two cubes with UVs as Blender exports them: one double-sided lit material, one unlit material."""
    from baker.gltf.document import GltfDocument

    corners = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], np.float32)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    positions, uvs, normals, indices = [], [], [], []
    for q, quad in enumerate(quads):  # split per face, as exporters write flat-shaded boxes
        p = corners[list(quad)]
        n = np.cross(p[1] - p[0], p[2] - p[0])
        base = len(positions)
        positions += list(p)
        normals += [n / np.linalg.norm(n)] * 4
        uvs += [[(q % 3 + u) / 3, (q // 3 + v) / 2] for u, v in ((0, 0), (1, 0), (1, 1), (0, 1))]
        indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    attributes = {"POSITION": np.array(positions, np.float32), "NORMAL": np.array(normals, np.float32),
                  "TEXCOORD_0": np.array(uvs, np.float32)}
    doc = GltfDocument.from_triangles(path, "Cube", attributes, np.array(indices, np.uint32), "Khronos glTF Blender I/O")
    doc.json["meshes"].append({"name": "Lamp", "primitives": [dict(doc.json["meshes"][0]["primitives"][0],
                                                                     material=1)]})
    doc.json["meshes"][0]["primitives"][0]["material"] = 0
    doc.json["nodes"].append({"name": "Lamp", "mesh": 1, "translation": [3, 0, 0]})
    doc.json["scenes"][0]["nodes"] = [0, 1]
    doc.json["materials"] = [
        {"name": "Skin", "doubleSided": True,
         "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.5, 0.4, 1], "metallicFactor": 0, "roughnessFactor": 0.5}},
        {"name": "Glow", "extensions": {"KHR_materials_unlit": {}},
         "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 0.5, 1], "metallicFactor": 0, "roughnessFactor": 0.9}}]
    doc.use_extension("KHR_materials_unlit")
    doc.save(path)


def codes(report) -> set:
    return {m["code"] for m in report["issues"]["messages"] if m["severity"] <= 1}


def test_blender_like_materials_stay_khronos_clean(tmp_path, capsys):
    source = tmp_path / "blender.glb"
    blender_like_gltf(source)
    before = codes(khronos_validate(source))
    out = tmp_path / "baked.glb"
    lines = bake_ok(["bake", source, "-o", out, "--bakes", "thickness,curvature,skin,edges,tam,toon,fur", "-q",
                     "--thickness-rays", "8", "--thickness-texture-size", "64"], capsys)
    added = codes(khronos_validate(out)) - before
    assert not added, added
    notes = [line for line in lines if line.startswith("baker: note: ")]
    assert len(notes) == 2 and len(lines) == 2, lines
    assert any("double-sided" in n and "'Skin'" in n for n in notes), notes
    assert any("unlit" in n and "'Glow'" in n for n in notes), notes

    gltf, _ = read_glb(out)
    skin, glow = gltf["materials"][0], gltf["materials"][1]
    assert set(glow["extensions"]) == {"KHR_materials_unlit"}  # nothing lit beside unlit
    assert "KHR_materials_volume" not in skin["extensions"]
    thickness = skin["extensions"]["BAKER_thickness"]
    assert thickness["thicknessTexture"]["index"] < len(gltf["textures"]) and thickness["thicknessFactor"] > 0
    assert {"BAKER_curvature", "BAKER_skin_lut", "BAKER_toon_ramp", "BAKER_tonal_art_map", "BAKER_fur"} \
        <= set(skin["extensions"])
    assert "KHR_materials_volume" not in gltf["extensionsUsed"]

    from baker.techniques.thickness.extension import read
    from baker.gltf.document import GltfDocument

    got = read(GltfDocument.load(out), 0)
    assert got.thickness_texture == thickness["thicknessTexture"]["index"]
    assert got.thickness_factor == thickness["thicknessFactor"]


def test_single_sided_material_keeps_khr_volume(tmp_path, capsys):
    source = tmp_path / "blender.glb"
    blender_like_gltf(source)
    from baker.gltf.document import GltfDocument

    doc = GltfDocument.load(source)
    doc.json["materials"][0]["doubleSided"] = False
    doc.save(source)
    out = tmp_path / "baked.glb"
    lines = bake_ok(["bake", source, "-o", out, "--bakes", "thickness", "-q", "--thickness-rays", "8",
                     "--thickness-texture-size", "64"], capsys)
    assert not [line for line in lines if "double-sided" in line]
    gltf, _ = read_glb(out)
    skin = gltf["materials"][0]["extensions"]
    assert skin["KHR_materials_volume"]["thicknessTexture"] == skin["BAKER_thickness"]["thicknessTexture"]
    assert skin["KHR_materials_volume"]["thicknessFactor"] == skin["BAKER_thickness"]["thicknessFactor"]
    assert not codes(khronos_validate(out)) - codes(khronos_validate(source))


MATERIAL_BAKES = ("caustics", "curvature", "fur", "normal-blur", "skin", "tam", "thickness", "toon")


def test_a_bake_with_nothing_to_cover_is_one_note(tmp_path):
    """One rule for every bake (issue 35, item 2): on an asset of unlit materials only, each material bake says
    ``<bake>: nothing baked: <why>`` once, edges (which covers any triangles) still bakes, exit 0, and the
    materials are the input's; normal-blur on a lit asset without a normal map says so once beside toon's work."""
    from baker.gltf.document import GltfDocument

    source = tmp_path / "blender.glb"
    blender_like_gltf(source)
    unlit = tmp_path / "unlit.glb"
    doc = GltfDocument.load(source)
    for mesh in doc.json["meshes"]:
        for prim in mesh["primitives"]:
            prim["material"] = 1
    doc.save(unlit)
    out = tmp_path / "out.glb"
    result = cli("bake", unlit, "-o", out, "--bakes", ",".join(MATERIAL_BAKES + ("edges",)), "-q",
                 "--thickness-rays", "4", "--thickness-texture-size", "16")
    assert result.returncode == 0, result.stderr
    why = "every material is unlit (KHR_materials_unlit): 1 'Glow'"
    assert sorted(result.stderr.splitlines()) == [f"baker: note: {name}: nothing baked: {why}"
                                                  for name in sorted(MATERIAL_BAKES)]
    gltf, _ = read_glb(out)
    assert gltf["materials"] == GltfDocument.load(unlit).json["materials"]
    assert all("BAKER_edges" in p["extensions"] for m in gltf["meshes"] for p in m["primitives"])
    # a lit asset without a normal map: normal-blur has nothing to blur; toon still bakes the lit material
    result = cli("bake", source, "-o", out, "--bakes", "normal-blur,toon", "-q")
    assert result.returncode == 0, result.stderr
    assert result.stderr.splitlines() == [
        "baker: note: unlit (KHR_materials_unlit) materials get no baked material data: 1 'Glow'",
        "baker: note: normal-blur: nothing baked: no material has a normalTexture with texture coordinates"]
    gltf, _ = read_glb(out)
    assert set(gltf["materials"][0]["extensions"]) == {"BAKER_toon_ramp"}
    # true bad input is still an error: an option out of range
    result = cli("bake", source, "-o", out, "--bakes", "tam", "--tam-levels", "0", "-q")
    assert result.returncode == 2 and len(result.stderr.splitlines()) == 1, result.stderr


# ------------------------------------------------------------------------------------ optional pieces missing
def cli(*args, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "baker.cli", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd)


def test_missing_mtl_is_one_warning_and_the_dielectric(tmp_path):
    """An OBJ shared without its .mtl (or with a folder in its place) bakes as the same OBJ without ``mtllib``
    does, byte for byte, and says so in one warning line naming the OBJ, the line and the file; -q keeps it."""
    bare_dir = tmp_path / "bare"
    bare_dir.mkdir()
    text = QUAD_OBJ.format(mtl="absent.mtl", first="a", second="b")
    (bare_dir / "quad.obj").write_text("# no mtllib\n" + text.split("\n", 1)[1])  # same line count
    bare = bare_dir / "out.glb"
    result = cli("bake", bare_dir / "quad.obj", "-o", bare, "--bakes", "edges", "-q")
    assert result.returncode == 0 and result.stderr == "", result.stderr
    obj = tmp_path / "quad.obj"
    obj.write_text(text)
    for problem in ("not found", "is not a file"):
        if problem == "is not a file":
            (tmp_path / "absent.mtl").mkdir()
        out = tmp_path / "out.glb"
        result = cli("bake", obj, "-o", out, "--bakes", "edges", "-q")
        assert result.returncode == 0, result.stderr
        assert result.stderr.splitlines() == [f"baker: warning: {obj}: line 1: mtllib: file 'absent.mtl' {problem}; "
                                              "the materials it defines are the dielectric default"]
        assert out.read_bytes() == bare.read_bytes()
        listed = cli("inspect", obj)  # every command that loads the OBJ says it the same way
        assert listed.returncode == 0 and listed.stderr == result.stderr
        gltf, _ = read_glb(out)
        assert gltf["materials"] == [{"name": "baker_dielectric",
                                      "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.5}}]
        assert {p["material"] for m in gltf["meshes"] for p in m["primitives"]} == {0}
    # structural bad input still exits 2 with one line: a non-finite vertex
    obj.write_text(text.replace("v 1 1 0", "v 1 nan 0"))
    result = cli("bake", obj, "-o", tmp_path / "nan.glb", "--bakes", "edges", "-q")
    assert result.returncode == 2 and len(result.stderr.splitlines()) == 1 and "line 4" in result.stderr


def test_missing_texture_map_is_one_warning(tmp_path, textures):
    """A map the MTL names that is absent leaves only that map out; the rest of the material is the MTL's."""
    (tmp_path / "quad.obj").write_text(QUAD_OBJ.format(mtl="m.mtl", first="a", second="b"))
    (tmp_path / "m.mtl").write_text("newmtl a\nKd 1 0.5 0\nmap_Kd gone.png\nmap_Ke glow.png\nnewmtl b\nPm 1\n")
    out = tmp_path / "out.glb"
    result = cli("bake", "quad.obj", "-o", out, "--bakes", "edges", "-q", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stderr.splitlines() == [f"baker: warning: {(tmp_path / 'm.mtl').resolve()}: line 3: map_Kd: file "
                                          "'gone.png' not found; material 'a' is baked without it"]
    gltf, binary = read_glb(out)
    a = materials_by_name(gltf)["a"]
    assert a["pbrMetallicRoughness"]["baseColorFactor"] == [1.0, 0.5, 0.0, 1.0]
    assert "baseColorTexture" not in a["pbrMetallicRoughness"]
    assert image_bytes(gltf, binary, a["emissiveTexture"]["index"]) == (tmp_path / "glow.png").read_bytes()
    assert len(gltf["images"]) == 1 and materials_by_name(gltf)["b"]["pbrMetallicRoughness"]["metallicFactor"] == 1


def test_build_over_a_folder_with_a_missing_mtl(tmp_path):
    """``baker build``: the asset without its .mtl is baked (exit 0) and the warning names it as the recipe does."""
    (tmp_path / "models").mkdir()
    (tmp_path / "models" / "quad.obj").write_text(QUAD_OBJ.format(mtl="absent.mtl", first="a", second="b"))
    (tmp_path / "baker.toml").write_text('[build]\noutput = "baked"\nformat = "glb"\nbakes = ["edges"]\n\n'
                                         '[[assets]]\ninputs = ["models/*.obj"]\n')
    result = cli("build", "--recipe", tmp_path / "baker.toml", "-q")
    assert result.returncode == 0, result.stdout + result.stderr
    warnings_printed = [line for line in result.stderr.splitlines() if line.startswith("baker: warning:")]
    assert warnings_printed == ["baker: warning: baked/models/quad.glb: models/quad.obj: line 1: mtllib: file "
                                "'absent.mtl' not found; the materials it defines are the dielectric default"]
    gltf, _ = read_glb(tmp_path / "baked" / "models" / "quad.glb")
    assert [m["name"] for m in gltf["materials"]] == ["baker_dielectric"]
