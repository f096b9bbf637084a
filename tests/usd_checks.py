"""What a USD output must be next to the glTF of the same asset: no glTF index anywhere, every texture the glTF
material names (core or BAKER_* extension) a UsdUVTexture reachable from its material, whose file holds the same
pixels as the glTF's image, read through the primvar of the right UV set, in the right colour space; and no error
from pxr's validators (UsdValidation, the successor of usdchecker's ComplianceChecker)."""
from __future__ import annotations

import io
from pathlib import Path

import numpy as np
from PIL import Image

# the names glTF gives its indices (textureInfo, image, sampler, accessor, buffer, scene graph): a USD attribute
# whose last name part is one of these and holds a number carries an index that means nothing in a stage (a file,
# or a string such as BAKER_thickness's ray "sampler" name, is no index)
GLTF_INDEX_NAMES = {"index", "texCoord", "texture", "textures", "source", "sampler", "samplers", "image", "images",
                    "accessor", "accessors", "bufferView", "buffer", "material", "materials", "mesh", "meshes",
                    "node", "nodes", "primitive", "primitives", "skin", "camera", "scene", "finsOf"}

# core glTF textures -> (UsdPreviewSurface input, output of the UsdUVTexture it reads, colour space)
CORE_TEXTURES = {("pbrMetallicRoughness", "baseColorTexture"): ("diffuseColor", "rgb", "sRGB"),
                 ("pbrMetallicRoughness", "metallicRoughnessTexture"): ("roughness", "g", "raw"),
                 ("normalTexture",): ("normal", "rgb", "raw"),
                 ("occlusionTexture",): ("occlusion", "r", "raw"),
                 ("emissiveTexture",): ("emissiveColor", "rgb", "sRGB")}


def gltf_index_attributes(stage) -> list[str]:
    """Every attribute of the stage named like a glTF index and holding a number."""
    from pxr import Sdf

    words = {Sdf.ValueTypeNames.Asset, Sdf.ValueTypeNames.String, Sdf.ValueTypeNames.Token}
    found = []
    for prim in stage.TraverseAll():
        for attr in prim.GetAttributes():
            parts = attr.GetName().split(":")
            if parts[-2:-1] == ["counts"]:  # BAKER_edges' counts per edge class (e.g. material boundaries)
                continue
            if parts[-1] in GLTF_INDEX_NAMES and attr.GetTypeName().scalarType not in words:
                found.append(f"{attr.GetPath()} = {attr.Get()}")
    return found


def texture_references(node, path=()):
    """(JSON path, textureInfo) of every texture reference in a glTF extension object."""
    if isinstance(node, dict):
        if isinstance(node.get("index"), int) and set(node) <= {"index", "texCoord", "scale", "strength",
                                                                 "extensions", "extras"}:
            yield path, node
            return
        for key, value in node.items():
            yield from texture_references(value, path + (key,))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield from texture_references(value, path + (i,))


def decoded(data: bytes) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(data)))


def expected_color_space(ext_name: str, params: dict, path: tuple) -> str:
    """Independent of the writer: the colour the extension READMEs say each texture holds."""
    if ext_name == "BAKER_fur" and path[0] in ("shellTextures", "finTexture"):
        return "sRGB"  # schemas/BAKER_fur: RGBA = hair colour (sRGB) + coverage
    if ext_name == "BAKER_skin_lut" and params.get("encoding") == "srgb":
        return "sRGB"
    return "raw"


def follow(attribute):
    """The shader and output name an input/output is connected to (exactly one source)."""
    from pxr import UsdShade

    sources = attribute.GetConnectedSources()[0]
    assert len(sources) == 1, attribute.GetAttr().GetPath()
    return UsdShade.Shader(sources[0].source.GetPrim()), str(sources[0].sourceName)


def check_texture(shader, doc, info: dict, color_space: str, meshes, default_texcoord: int = 0) -> None:
    """``shader`` is a UsdUVTexture of glTF ``info``: its file exists and decodes to the glTF image's pixels, in
    ``color_space``, and its ``st`` comes from a primvar reader of the UV set, a primvar the meshes carry as
    glTF's TEXCOORD_n with t = 1 - v."""
    from pxr import UsdGeom

    assert shader.GetIdAttr().Get() == "UsdUVTexture", shader.GetPath()
    asset = shader.GetInput("file").Get()
    file = Path(asset.resolvedPath)
    assert asset.resolvedPath and file.is_file(), asset
    source = doc.json["textures"][info["index"]]["source"]
    np.testing.assert_array_equal(decoded(file.read_bytes()), decoded(doc.image_bytes(source)))
    assert shader.GetInput("sourceColorSpace").Get() == color_space, shader.GetPath()
    reader, output = follow(shader.GetInput("st"))
    assert reader.GetIdAttr().Get() == "UsdPrimvarReader_float2" and output == "result"
    texcoord = info.get("texCoord", default_texcoord)
    varname = reader.GetInput("varname").Get()
    assert varname == ("st" if texcoord == 0 else f"st{texcoord}")
    for usd_mesh, primitive in meshes:
        st = np.asarray(UsdGeom.PrimvarsAPI(usd_mesh).GetPrimvar(varname).Get())
        uv = doc.accessor(primitive["attributes"][f"TEXCOORD_{texcoord}"])
        np.testing.assert_allclose(st, np.column_stack([uv[:, 0], 1 - uv[:, 1]]), atol=1e-6)


def assert_usd_matches_gltf(usd_path, doc) -> dict:
    """Check the USD stage at ``usd_path`` against ``doc`` (the glTF written from the same asset); returns how many
    textures were followed per kind."""
    from pxr import Tf, Usd, UsdGeom, UsdShade

    stage = Usd.Stage.Open(str(usd_path))
    assert not gltf_index_attributes(stage), gltf_index_attributes(stage)

    usd_materials = {p.GetName(): UsdShade.Material(p) for p in stage.Traverse() if p.IsA(UsdShade.Material)}
    bound: dict[str, list] = {}
    # fins are guide meshes (runtime geometry a final render does not draw), beside their surface
    mesh_prims = [p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)
                  and UsdGeom.Imageable(p).ComputePurpose() != UsdGeom.Tokens.guide]
    gltf_primitives = [prim for mesh in doc.json["meshes"] for prim in mesh["primitives"]
                       if prim.get("mode", 4) == 4 and "POSITION" in prim.get("attributes", {})
                       and not any("finsOf" in e for e in prim.get("extensions", {}).values())]
    assert len(mesh_prims) == len(gltf_primitives)  # one node per mesh in these assets: same order
    for usd_mesh, primitive in zip(mesh_prims, gltf_primitives):
        material = UsdShade.MaterialBindingAPI(usd_mesh).ComputeBoundMaterial()[0]
        bound.setdefault(material.GetPath().name, []).append((usd_mesh, primitive))

    counts = {"core": 0, "baker": 0}
    for index, gltf in enumerate(doc.json.get("materials", [])):
        name = Tf.MakeValidIdentifier(gltf["name"]) if gltf.get("name") else f"material{index}"
        if name not in bound:
            continue
        material, meshes = usd_materials[name], bound[name]
        surface = material.ComputeSurfaceSource()[0]
        for path, (usd_input, channel, color_space) in CORE_TEXTURES.items():
            info = gltf
            for key in path:
                info = info.get(key, {})
            if "index" not in info:
                continue
            shader, output = follow(surface.GetInput(usd_input))
            assert output == channel
            check_texture(shader, doc, info, color_space, meshes)
            counts["core"] += 1
        for ext_name, params in gltf.get("extensions", {}).items():
            if not ext_name.startswith("BAKER_"):
                continue
            default_texcoord = params.get("texCoord", 0)
            for path, info in texture_references(params):
                output = ":".join(["baker", ext_name[6:], *(f"_{k}" if isinstance(k, int) else k for k in path)])
                shader, channel = follow(material.GetOutput(output))
                assert channel == "rgb"
                check_texture(shader, doc, info, expected_color_space(ext_name, params, path), meshes,
                              default_texcoord)
                source = doc.json["textures"][info["index"]]["source"]
                if "A" in Image.open(io.BytesIO(doc.image_bytes(source))).getbands():
                    alpha_shader, alpha = follow(material.GetOutput(output + ":a"))
                    assert alpha == "a" and alpha_shader.GetPath() == shader.GetPath()
                counts["baker"] += 1
    return counts


def validation_errors(usd_path) -> list[str]:
    """Errors pxr's validators (every registered one but physics) find in the stage."""
    from pxr import Usd, UsdValidation

    registry = UsdValidation.ValidationRegistry()
    names = [m.name for m in registry.GetAllValidatorMetadata() if not str(m.name).startswith("usdPhysics")]
    context = UsdValidation.ValidationContext(registry.GetOrLoadValidatorsByName(names))
    errors = context.Validate(Usd.Stage.Open(str(usd_path)))
    return [f"{e.GetName()}: {e.GetMessage()}" for e in errors
            if e.GetType() == UsdValidation.ValidationErrorType.Error]
