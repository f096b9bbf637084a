"""``--attribute-layout {blender,native}`` (baker.gltf.vertex_attributes): what each layout writes, read back by an
independent reader (the GLB's JSON chunk parsed here, pxr for USD, Khronos glTF-Validator), and that every baker
reader (read(), validate) takes both. A mesh's own custom attributes set the blender layout's width; what cannot
share it is reported once."""
from __future__ import annotations

import json
import struct
import warnings

import numpy as np
import pytest
import trimesh

import baker
from baker.cli import main as baker_main
from baker.errors import BakerError
from baker.gltf.document import GltfDocument
from baker.gltf.vertex_attributes import BlenderWidthWarning
from baker.pipeline import save
from baker.validate import validate_file
from conftest import assert_khronos_clean

BAKES = ["thickness", "curvature", "edges"]
OPTIONS = {"thickness": {"rays": 32, "per_texel": False}, "edges": {"fins": True}}
# what the native layout writes for each of baker's attributes (the data's width)
NATIVE = {"_THICKNESS": "SCALAR", "_CURVATURE": "SCALAR", "_PRINCIPAL_CURVATURES": "VEC2",
          "_PRINCIPAL_DIRECTION": "VEC3", "_OUTLINE_NORMAL": "VEC3", "_FIN_V0": "VEC3", "_FIN_CORNER": "SCALAR",
          "_FIN_FLAGS": "SCALAR"}


def glb_json(path) -> dict:
    """The JSON chunk of a GLB, parsed without baker."""
    data = path.read_bytes()
    length, kind = struct.unpack_from("<II", data, 12)
    assert kind == 0x4E4F534A
    return json.loads(data[20:20 + length])


def attribute_types(gltf: dict) -> dict:
    return {name: gltf["accessors"][index]["type"] for mesh in gltf["meshes"] for prim in mesh["primitives"]
            for name, index in prim["attributes"].items() if name.startswith("_")}


@pytest.fixture(scope="module")
def sphere(tmp_path_factory):
    path = tmp_path_factory.mktemp("layout") / "sphere.glb"
    path.write_bytes(trimesh.exchange.gltf.export_glb(trimesh.Scene(trimesh.creation.icosphere(2, radius=1.0))))
    return path


@pytest.fixture(scope="module")
def baked(sphere, tmp_path_factory):
    """{layout: written .glb} of the same bakes."""
    out = tmp_path_factory.mktemp("layout_out")
    files = {}
    for layout in ("blender", "native"):
        files[layout] = out / f"{layout}.glb"
        save(baker.bake(sphere, bakes=BAKES, options=OPTIONS, attribute_layout=layout), files[layout])
    return files


def test_native_layout_writes_each_attribute_at_its_width(baked):
    assert attribute_types(glb_json(baked["native"])) == {**NATIVE, "_FIN_V1": "VEC3", "_FIN_V2": "VEC3",
                                                          "_FIN_V3": "VEC3"}
    assert set(attribute_types(glb_json(baked["blender"])).values()) == {"VEC3"}
    assert baked["native"].stat().st_size < baked["blender"].stat().st_size


def test_blender_layout_is_as_wide_as_the_widest_baked_data(sphere, baked, tmp_path):
    """One width per mesh, no wider than the run needs: scalar bakes alone stay SCALAR (a third of the bytes), and a
    bake that writes a vector widens every attribute of the mesh (the fixture's curvature + edges: all VEC3)."""
    out = tmp_path / "thickness.glb"
    save(baker.bake(sphere, bakes=["thickness", "toon"], options=OPTIONS), out)
    gltf = glb_json(out)
    assert attribute_types(gltf) == {"_THICKNESS": "SCALAR"}
    assert_khronos_clean(out)
    assert validate_file(out, khronos=False)["issues"]["numErrors"] == 0
    wide = GltfDocument.load(baked["blender"])
    narrow = GltfDocument.load(out)
    np.testing.assert_array_equal(
        narrow.accessor(gltf["meshes"][0]["primitives"][0]["attributes"]["_THICKNESS"]),
        wide.accessor(wide.json["meshes"][0]["primitives"][0]["attributes"]["_THICKNESS"])[:, 0])


@pytest.mark.parametrize("layout", ["blender", "native"])
def test_both_validators_accept_both_layouts(baked, layout):
    assert_khronos_clean(baked[layout])
    report = validate_file(baked[layout], khronos=False)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]


def test_readers_give_the_same_values_in_both_layouts(baked):
    from baker.techniques.edges.extension import read as read_edges

    docs = {layout: GltfDocument.load(path) for layout, path in baked.items()}
    for name, width in (("_THICKNESS", 1), ("_CURVATURE", 1), ("_PRINCIPAL_CURVATURES", 2)):
        blender = docs["blender"].accessor(docs["blender"].json["meshes"][0]["primitives"][0]["attributes"][name])
        native = docs["native"].accessor(docs["native"].json["meshes"][0]["primitives"][0]["attributes"][name])
        assert blender.shape == (len(native), 3)
        np.testing.assert_array_equal(blender[:, :width].reshape(native.shape), native)
        assert not blender[:, width:].any()  # the blender layout's padding is zero
    fin_primitive = docs["native"].json["meshes"][0]["primitives"][0]["extensions"]["BAKER_edges"]["fins"]
    fins = {layout: read_edges(doc, 0, fin_primitive).fin_attributes for layout, doc in docs.items()}
    assert fins["native"].keys() == fins["blender"].keys() and fins["native"]["_FIN_CORNER"].ndim == 1
    for name in fins["native"]:
        np.testing.assert_array_equal(fins["native"][name], fins["blender"][name])
    corner = fins["native"]["_FIN_CORNER"]
    np.testing.assert_array_equal(corner, np.tile(np.arange(4), len(corner) // 4))


@pytest.mark.parametrize("layout", ["blender", "native"])
def test_usd_primvars_have_the_data_width(sphere, tmp_path, layout):
    from pxr import Sdf, Usd, UsdGeom

    asset = baker.bake(sphere, bakes=["thickness", "curvature"], options=OPTIONS, attribute_layout=layout)
    doc = asset.doc
    attrs = doc.json["meshes"][0]["primitives"][0]["attributes"]
    save(asset, tmp_path / "out.usda")
    stage = Usd.Stage.Open(str(tmp_path / "out.usda"))
    mesh = next(UsdGeom.Mesh(p) for p in stage.Traverse() if p.IsA(UsdGeom.Mesh))
    primvars = UsdGeom.PrimvarsAPI(mesh.GetPrim())
    expected = {"thickness": (Sdf.ValueTypeNames.FloatArray, "_THICKNESS", 1),
                "curvature": (Sdf.ValueTypeNames.FloatArray, "_CURVATURE", 1),
                "principal_curvatures": (Sdf.ValueTypeNames.Float2Array, "_PRINCIPAL_CURVATURES", 2),
                "principal_direction": (Sdf.ValueTypeNames.Float3Array, "_PRINCIPAL_DIRECTION", 3)}
    for primvar_name, (type_name, attribute, width) in expected.items():
        primvar = primvars.GetPrimvar(f"baker:{primvar_name}")
        assert primvar.GetTypeName() == type_name, primvar_name
        stored = doc.accessor(attrs[attribute]).reshape(len(primvar.Get()), -1)[:, :width]
        np.testing.assert_array_equal(np.asarray(primvar.Get()).reshape(stored.shape), stored)


def with_own_attributes(path, columns: dict) -> None:
    """A sphere .glb carrying custom attributes of the user's own (name -> (N,) or (N, k) values)."""
    mesh = trimesh.creation.icosphere(1, radius=1.0)
    attributes = {"POSITION": mesh.vertices.astype(np.float32), **columns}
    GltfDocument.from_triangles(path, "pressured", attributes, mesh.faces.reshape(-1), "test").save(path)


def test_blender_layout_takes_the_width_of_the_users_own_attributes(tmp_path):
    n = len(trimesh.creation.icosphere(1).vertices)
    pressure = np.linspace(0.0, 1.0, n, dtype=np.float32)
    source = tmp_path / "pressure.glb"
    with_own_attributes(source, {"_PRESSURE": pressure})
    with warnings.catch_warnings():
        warnings.simplefilter("error", BlenderWidthWarning)  # a scalar fits: nothing to report
        asset = baker.bake(source, bakes=["thickness"], options=OPTIONS)
    save(asset, tmp_path / "out.glb")
    gltf = glb_json(tmp_path / "out.glb")
    assert attribute_types(gltf) == {"_PRESSURE": "SCALAR", "_THICKNESS": "SCALAR"}
    doc = GltfDocument.load(tmp_path / "out.glb")
    np.testing.assert_array_equal(doc.accessor(gltf["meshes"][0]["primitives"][0]["attributes"]["_PRESSURE"]),
                                  pressure)  # the user's data unchanged
    assert_khronos_clean(tmp_path / "out.glb")
    # a user's VEC4 (e.g. a colour): baker's scalars and vectors pad to 4
    with_own_attributes(source, {"_TINT": np.ones((n, 4), np.float32)})
    asset = baker.bake(source, bakes=["thickness", "edges"], options=OPTIONS)
    assert set(attribute_types(asset.doc.json).values()) == {"VEC4"}


def test_data_wider_than_the_users_width_warns_once(tmp_path, capsys):
    n = len(trimesh.creation.icosphere(1).vertices)
    source = tmp_path / "pressure.glb"
    with_own_attributes(source, {"_PRESSURE": np.zeros(n, np.float32)})
    with pytest.warns(BlenderWidthWarning) as caught:
        baker.bake(source, bakes=["curvature"], options=OPTIONS)
    assert len(caught) == 1
    message = str(caught[0].message)
    assert "'_PRESSURE' (1)" in message and "'_PRINCIPAL_CURVATURES'" in message
    assert "--curvature-directions false" in message
    # the CLI: one line on stderr, and the option it names resolves it
    assert baker_main(["bake", str(source), "--bakes", "curvature", "-o", str(tmp_path / "a.glb"), "-q"]) == 0
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("baker: warning: pressure.glb: mesh 0 ('pressured')"), lines
    assert baker_main(["bake", str(source), "--bakes", "curvature", "--curvature-directions", "false",
                       "-o", str(tmp_path / "b.glb"), "-q"]) == 0
    assert capsys.readouterr().err == ""
    assert attribute_types(glb_json(tmp_path / "b.glb")) == {"_PRESSURE": "SCALAR", "_CURVATURE": "SCALAR"}


def test_cli_and_recipe_take_the_layout(sphere, tmp_path, capsys):
    assert baker_main(["bake", str(sphere), "--bakes", "thickness", "--thickness-per-texel", "false",
                       "--thickness-rays", "8", "--attribute-layout", "native", "-o", str(tmp_path / "c.glb"),
                       "-q"]) == 0
    assert attribute_types(glb_json(tmp_path / "c.glb")) == {"_THICKNESS": "SCALAR"}
    with pytest.raises(SystemExit) as exit_info:
        baker_main(["bake", str(sphere), "--attribute-layout", "compact", "-o", str(tmp_path / "d.glb")])
    assert exit_info.value.code == 2
    with pytest.raises(BakerError, match="attribute layout must be one of blender, native"):
        baker.bake(sphere, attribute_layout="compact")
    capsys.readouterr()

    from baker.commands.build import build, load_recipe

    (tmp_path / "models").mkdir()
    (tmp_path / "models" / "sphere.glb").write_bytes(sphere.read_bytes())
    (tmp_path / "baker.toml").write_text(
        '[build]\noutput = "out"\nbakes = ["thickness"]\nattribute-layout = "native"\n'
        '[options.thickness]\nrays = 8\nper_texel = false\n'
        '[[assets]]\ninputs = ["models/*.glb"]\n')
    report = build(load_recipe(tmp_path / "baker.toml"))
    assert report["baked"] == ["out/models/sphere.glb"] and not report["failed"]
    assert attribute_types(glb_json(tmp_path / "out" / "models" / "sphere.glb")) == {"_THICKNESS": "SCALAR"}
    (tmp_path / "baker.toml").write_text('[build]\nattribute-layout = "compact"\n')
    with pytest.raises(BakerError, match="attribute-layout"):
        load_recipe(tmp_path / "baker.toml")


def test_preview_draws_both_layouts_alike(baked):
    """``baker preview`` binds either layout's attributes the same way: identical panels."""
    from baker.preview.core import preview

    sheets = {layout: preview(path, size=96) for layout, path in baked.items()}
    names = [name for name, _, _ in sheets["native"].panels]
    assert {"thickness", "translucency", "outline"} <= set(names)
    assert names == [name for name, _, _ in sheets["blender"].panels]
    np.testing.assert_array_equal(sheets["native"].sheet, sheets["blender"].sheet)
