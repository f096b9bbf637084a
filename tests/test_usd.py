"""USD input (read_usd through baker.readers.read) and output (write_usd through pipeline.save)."""
from __future__ import annotations

import math
import zipfile
from pathlib import Path

import numpy as np
import pytest

pxr = pytest.importorskip("pxr")
trimesh = pytest.importorskip("trimesh")

from pxr import Gf, Sdf, Usd, UsdGeom, UsdShade, Vt  # noqa: E402

import baker  # noqa: E402
from baker.gltf.vertex_attributes import unpadded  # noqa: E402
from baker.geometry.asset import Asset  # noqa: E402
from baker import readers  # noqa: E402
from baker.errors import BakerError  # noqa: E402
from baker.gltf.document import GltfDocument  # noqa: E402
from baker.gltf.usd import node_matrix, write_usd  # noqa: E402
from baker.pipeline import save  # noqa: E402

RADIUS = 2.0


@pytest.fixture(scope="module")
def baked_sphere(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sphere")
    glb = folder / "sphere.glb"
    glb.write_bytes(trimesh.exchange.gltf.export_glb(trimesh.Scene(trimesh.creation.icosphere(3, radius=RADIUS))))
    return baker.bake(glb, options={"thickness": {"rays": 64, "texture_size": 64}})


def _only_mesh(stage) -> UsdGeom.Mesh:
    # fins are guide meshes (runtime geometry no final render draws)
    meshes = [UsdGeom.Mesh(p) for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)
              and UsdGeom.Imageable(p).ComputePurpose() != UsdGeom.Tokens.guide]
    assert len(meshes) == 1
    return meshes[0]


@pytest.mark.parametrize("suffix", [".usda", ".usdc", ".usdz"])
def test_thickness_round_trip(baked_sphere, tmp_path, suffix):
    doc = baked_sphere.doc
    prim = doc.json["meshes"][0]["primitives"][0]
    thickness = doc.accessor(prim["attributes"]["_THICKNESS"])
    out = tmp_path / f"sphere{suffix}"
    save(baked_sphere, out)
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary files left behind

    stage = Usd.Stage.Open(str(out))
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.y
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    assert stage.GetDefaultPrim().GetPath() == Sdf.Path("/Root")
    mesh = _only_mesh(stage)
    assert len(mesh.GetPointsAttr().Get()) == doc.json["accessors"][prim["attributes"]["POSITION"]]["count"]
    assert set(mesh.GetFaceVertexCountsAttr().Get()) == {3}

    primvar = UsdGeom.PrimvarsAPI(mesh.GetPrim()).GetPrimvar("baker:thickness")
    assert primvar and primvar.GetInterpolation() == UsdGeom.Tokens.vertex
    # the data's own width (a thickness-only bake's blender layout is SCALAR too; beside vectors it pads to VEC3)
    assert doc.json["accessors"][prim["attributes"]["_THICKNESS"]]["type"] == "SCALAR"
    assert primvar.GetTypeName() == Sdf.ValueTypeNames.FloatArray
    values = np.asarray(primvar.Get())
    np.testing.assert_array_equal(values, thickness)
    # mean chord of a ball of radius r, cosine-weighted rays from the surface: 4r/3
    assert abs(values.mean() - 4 * RADIUS / 3) < 0.05 * 4 * RADIUS / 3

    binding = UsdShade.MaterialBindingAPI(mesh.GetPrim()).ComputeBoundMaterial()[0]
    assert binding
    factor = binding.GetInput("baker:thicknessFactor").Get()
    volume = doc.json["materials"][prim["material"]]["extensions"]["KHR_materials_volume"]
    assert factor == pytest.approx(volume["thicknessFactor"])
    source = binding.GetOutput("baker:thickness").GetConnectedSources()[0][0]
    assert source.sourceName == "g"
    shader = UsdShade.Shader(source.source.GetPrim())
    assert shader.GetPath().name == "ThicknessTexture" and shader.GetIdAttr().Get() == "UsdUVTexture"
    asset = shader.GetInput("file").Get()
    assert asset.resolvedPath, asset
    if suffix != ".usdz":
        assert (out.parent / "sphere_textures").is_dir()
    assert binding.GetPrim().GetAttribute("baker:thickness:rays").Get() == 64
    assert binding.GetPrim().GetAttribute("baker:thickness:subsurfaceColor").Get() == Gf.Vec3f(1, 1, 1)

    # the UV set the texture reads exists on the mesh, flipped to USD's t-up convention
    varname = shader.GetInput("st").GetConnectedSources()[0][0].source.GetInput("varname").Get()
    st = np.asarray(UsdGeom.PrimvarsAPI(mesh.GetPrim()).GetPrimvar(varname).Get())
    texcoord = volume["thicknessTexture"].get("texCoord", 0)
    uv = doc.accessor(prim["attributes"][f"TEXCOORD_{texcoord}"])
    np.testing.assert_allclose(st[:, 1], 1.0 - uv[:, 1], atol=1e-6)


@pytest.mark.parametrize("suffix", [".usda", ".usdc", ".usdz"])
def test_output_is_deterministic(baked_sphere, tmp_path, suffix):
    a, b = tmp_path / "a" / f"x{suffix}", tmp_path / "b" / f"x{suffix}"
    save(baked_sphere, a)
    save(baked_sphere, b)
    assert a.read_bytes() == b.read_bytes()
    if suffix != ".usdz":
        assert (a.parent / "x_textures" / "thickness_m0.png").read_bytes() == \
            (b.parent / "x_textures" / "thickness_m0.png").read_bytes()
    else:  # two quick writes share a timestamp anyway: check there is none
        with zipfile.ZipFile(a) as z:
            assert {i.date_time for i in z.infolist()} == {(1980, 1, 1, 0, 0, 0)}
            assert z.namelist()[0].endswith(".usdc")  # the root layer comes first
        zf = Sdf.ZipFile.Open(str(a))
        assert all(zf.GetFileInfo(n).dataOffset % 64 == 0 for n in zf.GetFileNames())  # USDZ alignment


def test_usd_output_reads_back(baked_sphere, tmp_path):
    out = tmp_path / "again.usdc"
    save(baked_sphere, out)
    again = readers.read(out)
    source = baked_sphere.primitive(0, 0)
    back = again.primitive(0, 0)
    # a stage baker wrote comes back as the document it was written from (baker.readers.usd_baked): the same
    # vertices, UVs and baked thickness; the glTF had no normals (flat shading) and neither has the document read back
    assert source.normals is None and back.normals is None
    np.testing.assert_array_equal(back.faces, source.faces)
    np.testing.assert_allclose(back.positions, source.positions, atol=1e-6)
    np.testing.assert_allclose(back.texcoords[0], source.texcoords[0], atol=1e-6)
    prim, prim_back = (a.doc.json["meshes"][0]["primitives"][0] for a in (baked_sphere, again))
    np.testing.assert_array_equal(again.doc.accessor(prim_back["attributes"]["_THICKNESS"]),
                                  unpadded(baked_sphere.doc.accessor(prim["attributes"]["_THICKNESS"]), 1))


def test_node_transforms(tmp_path):
    q = [0.0, np.sin(np.pi / 4), 0.0, np.cos(np.pi / 4)]  # 90 degrees about +Y
    trs = {"translation": [1.0, 2.0, 3.0], "rotation": q, "scale": [2.0, 2.0, 2.0]}
    matrix = node_matrix(trs)
    np.testing.assert_allclose(matrix @ [1, 0, 0, 1], [1, 2, 1, 1], atol=1e-12)  # x -> -z, scaled, moved
    column_major = list(matrix.T.reshape(-1))
    np.testing.assert_allclose(node_matrix({"matrix": column_major}), matrix)

    doc = GltfDocument()
    doc.json.update({"scene": 0, "scenes": [{"nodes": [0]}],
                     "nodes": [{"name": "parent node", "children": [1], **trs},
                               {"name": "parent node", "matrix": column_major}]})
    out = tmp_path / "nodes.usda"
    write_usd(doc, out)
    stage = Usd.Stage.Open(str(out))
    parent = stage.GetPrimAtPath("/Root/parent_node")
    child = stage.GetPrimAtPath("/Root/parent_node/parent_node")
    assert parent and child
    world = UsdGeom.Xformable(parent).ComputeLocalToWorldTransform(Usd.TimeCode.Default())
    assert np.allclose(world.Transform(Gf.Vec3d(1, 0, 0)), [1, 2, 1])
    world = UsdGeom.Xformable(child).ComputeLocalToWorldTransform(Usd.TimeCode.Default())
    np.testing.assert_allclose(world.Transform(Gf.Vec3d(1, 0, 0)), (matrix @ matrix @ [1, 0, 0, 1])[:3], atol=1e-9)


def _quad_cube(path, translate=(10.0, 0.0, 0.0)):
    """A unit cube of six quads with face-varying UVs (each face the full [0, 1] square) under a translate op."""
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    xform = UsdGeom.Xform.Define(stage, "/World")
    xform.AddTranslateOp().Set(Gf.Vec3d(*translate))
    stage.SetDefaultPrim(xform.GetPrim())
    mesh = UsdGeom.Mesh.Define(stage, "/World/Cube")
    mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)  # a hard-edged polygon mesh: flat normals
    points = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], np.float32) - 0.5
    quads = np.array([[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]])
    mesh.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(points))
    mesh.CreateFaceVertexCountsAttr(Vt.IntArray.FromNumpy(np.full(6, 4, np.int32)))
    mesh.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(quads.reshape(-1).astype(np.int32)))
    st = np.tile(np.array([[0, 0], [0.5, 0], [0.5, 0.25], [0, 0.25]], np.float32), (6, 1))
    UsdGeom.PrimvarsAPI(mesh.GetPrim()).CreatePrimvar("st", Sdf.ValueTypeNames.TexCoord2fArray,
                                                      UsdGeom.Tokens.faceVarying).Set(Vt.Vec2fArray.FromNumpy(st))
    stage.GetRootLayer().Save()
    return points, quads


def test_usd_input(tmp_path):
    path = tmp_path / "cube.usda"
    points, _ = _quad_cube(path)
    asset = readers.read(path)
    vertices, faces = asset.mesh_triangles(0)
    assert len(faces) == 12
    np.testing.assert_allclose(vertices.min(0), [9.5, -0.5, -0.5], atol=1e-6)
    np.testing.assert_allclose(vertices.max(0), [10.5, 0.5, 0.5], atol=1e-6)
    g = asset.primitive(0, 0)
    assert 0 in g.texcoords and len(g.texcoords[0]) == len(g.positions) == 24  # split per face corner
    assert set(np.round(g.texcoords[0][:, 0], 6)) == {0.0, 0.5}
    assert set(np.round(g.texcoords[0][:, 1], 6)) == {1.0, 0.75}  # glTF v = 1 - USD t
    assert np.allclose(np.sort(np.abs(g.normals), axis=1), [0, 0, 1])  # flat, axis-aligned
    # outward winding: every face normal points away from the cube centre
    tri = vertices[faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    assert np.all(np.einsum("ij,ij->i", normals, tri.mean(1) - [10, 0, 0]) > 0)

    baked = baker.bake(asset, options={"thickness": {"rays": 8, "texture_size": 32}})
    out = tmp_path / "cube.glb"
    save(baked, out)
    doc = GltfDocument.load(out)
    assert "_THICKNESS" in doc.json["meshes"][0]["primitives"][0]["attributes"]
    assert "thicknessTexture" in doc.json["materials"][0]["extensions"]["KHR_materials_volume"]


def test_usd_input_left_handed_and_holes(tmp_path):
    path = tmp_path / "lh.usda"
    _quad_cube(path, translate=(0.0, 0.0, 0.0))
    stage = Usd.Stage.Open(str(path))
    mesh = UsdGeom.Mesh(stage.GetPrimAtPath("/World/Cube"))
    mesh.CreateHoleIndicesAttr(Vt.IntArray([5]))
    # reverse every quad and call it left-handed: the same surface, so winding must still face outwards
    quads = np.asarray(mesh.GetFaceVertexIndicesAttr().Get()).reshape(-1, 4)[:, ::-1]
    mesh.GetFaceVertexIndicesAttr().Set(Vt.IntArray.FromNumpy(quads.reshape(-1).astype(np.int32)))
    mesh.CreateOrientationAttr(UsdGeom.Tokens.leftHanded)
    stage.GetRootLayer().Save()
    vertices, faces = readers.read(path).mesh_triangles(0)
    assert len(faces) == 10
    tri = vertices[faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    assert np.all(np.einsum("ij,ij->i", normals, tri.mean(1)) > 0)


def test_usd_without_meshes(tmp_path):
    path = tmp_path / "empty.usda"
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.Xform.Define(stage, "/World")
    UsdGeom.Sphere.Define(stage, "/World/Ball")  # an implicit surface is not a mesh
    stage.GetRootLayer().Save()
    with pytest.raises(BakerError, match="empty.usda"):
        readers.read(path)


def test_unreadable_usd(tmp_path):
    path = tmp_path / "broken.usda"
    path.write_text("#usda 1.0\ndef Xform \"World\" {\n")
    with pytest.raises(BakerError, match="cannot open USD stage"):
        readers.read(path)


def test_materials_and_custom_attributes(tmp_path):
    from PIL import Image

    box = trimesh.creation.box()
    uv = np.random.default_rng(0).random((len(box.vertices), 2))
    image = Image.fromarray(np.full((4, 4, 3), 200, np.uint8))
    box.visual = trimesh.visual.TextureVisuals(uv=uv, material=trimesh.visual.material.PBRMaterial(
        name="painted wood", baseColorTexture=image, baseColorFactor=[255, 128, 0, 255], roughnessFactor=0.5))
    glb = tmp_path / "box.glb"
    glb.write_bytes(trimesh.exchange.gltf.export_glb(trimesh.Scene(box)))
    doc = GltfDocument.load(glb)
    prim = doc.json["meshes"][0]["primitives"][0]
    n = doc.json["accessors"][prim["attributes"]["POSITION"]]["count"]
    prim["attributes"]["_OUTLINE_NORMAL"] = doc.add_accessor(np.tile(np.float32([0, 1, 0]), (n, 1)))
    out = tmp_path / "box.usda"
    write_usd(doc, out)

    stage = Usd.Stage.Open(str(out))
    mesh = _only_mesh(stage)
    primvar = UsdGeom.PrimvarsAPI(mesh.GetPrim()).GetPrimvar("baker:outline_normal")
    assert primvar.GetTypeName() == Sdf.ValueTypeNames.Float3Array and len(primvar.Get()) == n
    material = UsdShade.MaterialBindingAPI(mesh.GetPrim()).ComputeBoundMaterial()[0]
    assert material.GetPath() == Sdf.Path("/Root/Materials/painted_wood")
    surface = material.ComputeSurfaceSource()[0]
    assert surface.GetInput("roughness").Get() == pytest.approx(0.5)
    texture = UsdShade.Shader(surface.GetInput("diffuseColor").GetConnectedSources()[0][0].source.GetPrim())
    assert texture.GetInput("sourceColorSpace").Get() == "sRGB"
    assert texture.GetInput("scale").Get()[1] == pytest.approx(128 / 255, abs=1e-2)
    assert Path(texture.GetInput("file").Get().resolvedPath).is_file()
    st = np.asarray(UsdGeom.PrimvarsAPI(mesh.GetPrim()).GetPrimvar("st").Get())
    np.testing.assert_allclose(st[:, 1], 1.0 - doc.accessor(prim["attributes"]["TEXCOORD_0"])[:, 1], atol=1e-6)


def test_usd_input_skips_hidden_and_reads_instances(tmp_path):
    path = tmp_path / "scene.usda"
    _quad_cube(path, translate=(0.0, 0.0, 0.0))
    stage = Usd.Stage.Open(str(path))
    for name, offset in (("A", 5.0), ("B", -5.0)):  # two instances of the cube
        xform = UsdGeom.Xform.Define(stage, f"/Instances/{name}")
        xform.AddTranslateOp().Set(Gf.Vec3d(0, offset, 0))
        xform.GetPrim().GetReferences().AddInternalReference("/World")
        xform.GetPrim().SetInstanceable(True)
    guide = UsdGeom.Mesh.Define(stage, "/Guide")
    guide.CreatePurposeAttr(UsdGeom.Tokens.guide)
    hidden = UsdGeom.Mesh.Define(stage, "/Hidden")
    hidden.MakeInvisible()
    for mesh in (guide, hidden):
        mesh.CreatePointsAttr([(0, 0, 0), (1, 0, 0), (0, 1, 0)])
        mesh.CreateFaceVertexCountsAttr([3])
        mesh.CreateFaceVertexIndicesAttr([0, 1, 2])
    stage.GetRootLayer().Save()

    from baker.readers.usd import read_usd

    scene = read_usd(path)
    assert sorted(scene.geometry) == ["/Instances/A/Cube", "/Instances/B/Cube", "/World/Cube"]
    assert np.isclose(scene.geometry["/Instances/A/Cube"].vertices[:, 1].min(), 4.5)


def test_usd_input_broken_topology(tmp_path):
    path = tmp_path / "broken_topology.usda"
    _quad_cube(path)
    stage = Usd.Stage.Open(str(path))
    UsdGeom.Mesh(stage.GetPrimAtPath("/World/Cube")).GetFaceVertexIndicesAttr().Set(Vt.IntArray([0, 1, 99] * 8))
    stage.GetRootLayer().Save()
    with pytest.raises(BakerError, match="/World/Cube.*out of range"):
        readers.read(path)


def test_extension_textures_and_edge_curves_reach_usd(tmp_path):
    # every texture a BAKER_* material extension references becomes a UsdUVTexture feeding a material output,
    # and BAKER_edges' crease/boundary edges become a BasisCurves prim beside the mesh
    import trimesh
    from pxr import Usd, UsdGeom, UsdShade

    import baker
    from baker.pipeline import save

    src = tmp_path / "box.glb"
    trimesh.creation.box().export(str(src))
    asset = baker.bake(src, bakes=["edges", "skin"], options={"skin": {"width": 16, "height": 16, "penumbra": False}})
    out = tmp_path / "box.usda"
    save(asset, out)
    stage = Usd.Stage.Open(str(out))
    curves = [UsdGeom.BasisCurves(p) for p in stage.Traverse() if p.IsA(UsdGeom.BasisCurves)]
    assert len(curves) == 1
    assert len(curves[0].GetCurveVertexCountsAttr().Get()) == 12  # the box's 12 crease edges
    # their dihedral angles (not stored in the glTF by default: derived from the triangles) are the box's +90 degrees
    angles = UsdGeom.PrimvarsAPI(curves[0].GetPrim()).GetPrimvar("baker:dihedralAngle").Get()
    assert len(angles) == 12 and all(abs(a - math.pi / 2) < 1e-5 for a in angles)
    material = UsdShade.Material([p for p in stage.Traverse() if p.IsA(UsdShade.Material)][0])
    output = material.GetOutput("baker:skin_lut:lutTexture")
    assert output and output.HasConnectedSource()
    shader = UsdShade.Shader(output.GetConnectedSources()[0][0].source.GetPrim())
    assert shader.GetIdAttr().Get() == "UsdUVTexture"
    assert (out.parent / shader.GetInput("file").Get().path).is_file()


def _textured_spot():
    """spot with a base colour, a metallic-roughness, an occlusion (strength 0.5) and a normal texture, so every
    bake runs (normal-blur needs the normal map) and every core texture has a UsdPreviewSurface input to reach."""
    from baker.gltf.images import encode_image

    asset = readers.read(Path(__file__).parents[1] / "examples" / "spot" / "spot.obj")
    doc = asset.doc
    rng = np.random.default_rng(3)
    y, x = np.mgrid[0:64, 0:64] / 64.0
    slope = 0.3 * np.sin(2 * np.pi * 4 * x)  # bumps along u: a tangent-space normal map
    normal = np.stack([-slope, np.zeros_like(slope), np.ones_like(slope)], -1)
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    images = {"normal": np.rint((normal + 1) / 2 * 255).astype(np.uint8),
              "color": rng.integers(0, 256, (32, 32, 3), dtype=np.uint8),
              "orm": rng.integers(0, 256, (16, 16, 3), dtype=np.uint8),
              "occlusion": rng.integers(0, 256, (8, 8, 3), dtype=np.uint8)}
    textures = {k: doc.add_texture(doc.add_image(encode_image(v, ".png"), "image/png", k)) for k, v in images.items()}
    material = doc.json["materials"][0]
    material["normalTexture"] = {"index": textures["normal"]}
    material["occlusionTexture"] = {"index": textures["occlusion"], "strength": 0.5}
    material["pbrMetallicRoughness"].update(baseColorTexture={"index": textures["color"]},
                                            metallicRoughnessTexture={"index": textures["orm"]})
    return asset


def test_every_bake_on_spot_gives_clean_usd(tmp_path):
    """issue 39: no glTF index in USD; every texture the glTF names is a UsdUVTexture reachable from its material,
    same pixels as the glTF output's image, right UV set and colour space; pxr's validators find no error."""
    from baker.registry import bakes
    from usd_checks import assert_usd_matches_gltf, gltf_index_attributes, texture_references, validation_errors

    fast = {"thickness": {"rays": 8, "texture_size": 64}, "curvature": {"per_texel": True, "texture_size": 64},
            "skin": {"width": 32, "height": 32, "penumbra_size": 16, "encoding": "srgb"}, "edges": {"fins": True},
            "tam": {"size": 64, "levels": 2}, "fur": {"fins": True, "shells": 4, "texture_size": 32, "hairs": 100},
            "caustics": {"size": 32, "frames": 4, "waves": 16}, "normal-blur": {"texture_size": 64}}
    names = list(bakes())
    asset = baker.bake(_textured_spot(), bakes=names, options={k: v for k, v in fast.items() if k in names})
    extensions = set(asset.doc.json["extensionsUsed"])
    assert {"BAKER_thickness", "BAKER_fur", "BAKER_skin_lut", "BAKER_normal_blur", "BAKER_tonal_art_map",
            "BAKER_toon_ramp", "BAKER_caustics", "BAKER_curvature"} <= extensions
    gltf = save(asset, tmp_path / "gltf" / "spot.gltf")[-1]
    usda = save(asset, tmp_path / "usd" / "spot.usda")[-1]

    counts = assert_usd_matches_gltf(usda, GltfDocument.load(gltf))
    material = GltfDocument.load(gltf).json["materials"][0]
    expected = sum(1 for name, ext in material["extensions"].items() if name.startswith("BAKER_")
                   for _ in texture_references(ext))
    assert counts == {"core": 4, "baker": expected} and expected >= 10
    assert validation_errors(usda) == []

    stage = Usd.Stage.Open(str(usda))
    prim = UsdShade.Material(next(p for p in stage.Traverse() if p.IsA(UsdShade.Material))).GetPrim()
    # factors and other non-index fields stay attributes; the UV set and attribute names become USD names
    assert prim.GetAttribute("baker:thickness:thicknessFactor").Get() == pytest.approx(
        material["extensions"]["BAKER_thickness"]["thicknessFactor"])
    # the TAM reads its stroke parameterization, the set after spot's own UVs
    assert prim.GetAttribute("baker:tonal_art_map:texCoordPrimvar").Get() == "st1"
    assert prim.GetAttribute("baker:thickness:attribute").Get() == "primvars:baker:thickness"
    mesh = _only_mesh(stage)
    assert UsdGeom.PrimvarsAPI(mesh.GetPrim()).GetPrimvar("baker:thickness")
    occlusion = UsdShade.Shader(stage.GetPrimAtPath(prim.GetPath().AppendChild("OcclusionTexture")))
    assert occlusion.GetInput("scale").Get()[0] == pytest.approx(0.5)  # 1 + 0.5 (r - 1) = 0.5 r + 0.5
    assert occlusion.GetInput("bias").Get()[0] == pytest.approx(0.5)
    # the checker itself sees an index when there is one
    prim.CreateAttribute("baker:thickness:thicknessTexture:index", Sdf.ValueTypeNames.Int, custom=True).Set(3)
    assert gltf_index_attributes(stage)



def test_usd_stage_outlives_a_collection_before_export(tmp_path):
    """The authored in-memory stage must stay alive until it is exported: Python holds a USD layer by a weak handle,
    and a collection between authoring and export once freed the stage, so the export dereferenced an expired layer
    (a fatal USD error that aborted the whole test run). Runs in a subprocess: that failure aborts the process."""
    import subprocess
    import sys

    script = (
        "import gc, sys\n"
        "import baker\n"
        "from baker.gltf.usd import build_stage, write_stage_and_textures\n"
        "asset = baker.bake(sys.argv[1], bakes=[])\n"
        "stage, images = build_stage(asset.doc, 'textures')\n"
        "gc.collect()\n"
        "write_stage_and_textures(stage, __import__('pathlib').Path(sys.argv[2]), [])\n"
    )
    spot = Path(__file__).resolve().parents[1] / "examples" / "spot" / "spot.obj"
    out = tmp_path / "spot.usda"
    result = subprocess.run([sys.executable, "-c", script, str(spot), str(out)], capture_output=True, text=True,
                            timeout=600)
    assert result.returncode == 0, result.stderr[-2000:]
    stage = Usd.Stage.Open(str(out))
    assert any(p.IsA(UsdGeom.Mesh) for p in stage.Traverse())
