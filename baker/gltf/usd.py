"""USD stages out: ``write_usd`` (glTF -> USD); :mod:`baker.readers.usd` reads them.

Writing
-------
The default glTF scene becomes ``/Root`` (``defaultPrim``, kind ``component``, ``upAxis = "Y"``,
``metersPerUnit = 1``), each node a ``UsdGeom.Xform`` with its local matrix as one ``xformOp:transform``, and each
triangle primitive of a node's mesh a ``UsdGeom.Mesh`` child with ``subdivisionScheme = "none"`` (a mesh used by
several nodes is written under each). Not carried over: points/lines primitives, skins, morph targets, animations,
cameras, lights, ``KHR_texture_transform``. Per primitive:

- ``points``, ``faceVertexCounts`` (all 3), ``faceVertexIndices``, ``extent``;
- ``normals`` (vertex interpolation) from ``NORMAL``; ``primvars:tangents`` (float4, vertex) from ``TANGENT``;
- ``primvars:st`` from ``TEXCOORD_0``, ``primvars:st<n>`` from ``TEXCOORD_<n>`` (``texCoord2f``, vertex
  interpolation, ``t = 1 - v``);
- ``primvars:displayColor`` / ``primvars:displayOpacity`` from ``COLOR_0``;
- every custom attribute ``_NAME`` as ``primvars:baker:name`` at its data's width whatever the glTF layout (baker's
  own attributes: ``float[]`` for ``_THICKNESS``, ``float2[]`` for pairs; others as stored: float, float2, float3 or
  float4 array, vertex
  interpolation; integer data is converted to float, normalized integers to [0, 1]).

Primitive extensions that hold accessors and list them in their module's ``USD_PRIMITIVE_ACCESSORS``
(``BAKER_edges``, ``EXT_mesh_primitive_edge_visibility``) are custom attributes on the Mesh prim,
``baker:<name>:<field>`` (``BAKER_`` dropped: ``baker:edges:creaseAngle``; ``baker:EXT_mesh_primitive_edge_visibility:
visibility``): fields as for materials (below), each accessor a flat ``int[]``/``uint[]``/``float[]`` with its glTF
``:componentType`` and ``:type`` (``baker:edges:edges:type = "VEC2"``), data indexed by vertex being indexed by the
Mesh's points. A fin primitive (``finsOf`` of ``BAKER_edges``/``BAKER_fur``: zero-area quads a runtime extrudes) is a
Mesh ``<surface>_fins`` beside its surface with ``purpose = "guide"`` (no final render draws it), its ``_FIN_*``
primvars, the relationship ``baker:finsOf`` to the surface and ``baker:finsOf:extension``. So a stage reads back
into the document it was written from (:mod:`baker.readers.usd_baked`).

Each glTF material a written primitive uses becomes a ``UsdShade.Material`` under ``/Root/Materials`` with a
``UsdPreviewSurface`` (``diffuseColor``, ``opacity``, ``metallic``, ``roughness``, ``emissiveColor`` times
``KHR_materials_emissive_strength``; the base color texture (and its alpha as ``opacity`` when the alpha mode is
MASK or BLEND, with ``opacityThreshold`` = ``alphaCutoff`` for MASK), the metallic-roughness texture (blue, green),
the occlusion texture (red), the emissive texture and the normal texture through ``UsdUVTexture`` (glTF's factors,
scale and strength as its ``scale``/``bias``) and a ``UsdPrimvarReader_float2`` per UV set). ``metallic`` and
``roughness`` follow glTF: a factor the material does not write is 1 (its default), so a material without
``pbrMetallicRoughness`` is metallic; baker's mesh-format conversion writes both factors (``metallic`` 0, see
:mod:`baker.readers.mtl`). Images are written beside the stage in ``<stem>_textures/`` (``.usda``/``.usdc``/
``.usd``) or inside the package (``.usdz``).

Baked data on materials (no glTF index of any kind is written: a texture, accessor or mesh number means nothing in
a stage):

- Every texture a ``BAKER_<name>`` material extension names is a ``UsdUVTexture`` shader under the material
  (``Baker_<name>_<json path>``; ``file`` = the written image, ``st`` from the primvar reader of its UV set,
  ``sourceColorSpace`` ``raw`` for data and ``sRGB`` for colour, as the extension's ``usd_color_space`` says)
  whose ``outputs:rgb`` feeds the material output ``outputs:baker:<name>:<json path>`` (float3) and, for an image
  with alpha, ``outputs:a`` feeds ``outputs:baker:<name>:<json path>:a`` (float); e.g.
  ``outputs:baker:skin_lut:lutTexture``, ``outputs:baker:fur:shellTextures:_0:a``. Material outputs are
  UsdShade's terminals, the place a consumer starts from (as ``outputs:surface``). One shader serves every
  reference to the same texture, UV set and colour space.
- ``BAKER_thickness.thicknessTexture`` (or, without it, ``KHR_materials_volume.thicknessTexture``) is the shader
  ``ThicknessTexture``, whose ``outputs:g`` (the thickness) also feeds ``outputs:baker:thickness`` (float); the
  material input ``inputs:baker:thicknessFactor`` (float) holds ``thicknessFactor`` (texel value 1.0 = that many
  units).
- Every other field of a ``BAKER_<name>`` material extension is a typed **custom attribute** on the Material prim,
  ``baker:<name>:<key>`` (e.g. ``baker:thickness:rays`` int, ``baker:thickness:subsurfaceColor`` double3,
  ``baker:thickness:distribution`` string; numbers are doubles, so reading them back gives the JSON's numbers),
  by :func:`usd_parameters`: a texture reference keeps its non-index
  fields (``baker:<name>:<field>:scale``), a top-level ``texCoord`` becomes ``texCoordPrimvar`` (``"st"``), a
  vertex attribute name becomes its primvar's (``"primvars:baker:thickness"``), lists of objects carrying indices
  are left out and lists of plain-data objects become ``_0``, ``_1``, ... namespaces. Attributes rather than ``customData`` so they are typed, can be time-sampled or
  overridden from a stronger layer like any other property, and show up in every USD tool.

Output bytes depend only on the document: no timestamps, no absolute paths, ordered iteration everywhere.
"""
from __future__ import annotations

import mimetypes
import re
import tempfile
from pathlib import Path

import numpy as np

from baker.errors import BakerError
from baker.gltf.atomic import atomic_files, atomic_path
from baker.gltf.document import node_matrix

WRAP_MODES = {10497: "repeat", 33071: "clamp", 33648: "mirror"}
IMAGE_EXTENSIONS = {"image/png": ".png", "image/jpeg": ".jpg", "image/webp": ".webp", "image/ktx2": ".ktx2",
                    "image/avif": ".avif"}


def write_usd(doc, path, primitive_hooks=None, attribute_widths=None, texture_color_spaces=None,
              primitive_accessors=None) -> list[Path]:
    """Write ``doc`` (a :class:`~baker.gltf.document.GltfDocument`) as ``.usda``, ``.usdc``, ``.usd`` or ``.usdz``.

    The file is written atomically; textures go to ``<stem>_textures/`` beside it, or into the ``.usdz`` package.
    Returns every file written (the stage last). ``primitive_hooks`` maps an extension name to a function
    ``(stage, prim_path, parent_path, doc, mesh, primitive)`` that adds that extension's USD beside each mesh
    primitive carrying it (see :func:`baker.registry.usd_primitive_hooks`). ``attribute_widths`` maps a custom
    attribute name to its data's width (:func:`baker.registry.vertex_attribute_widths`): its primvar takes that many
    components whatever the glTF layout padded it to. ``texture_color_spaces`` maps an extension name to a function
    ``(params, json_path) -> "sRGB" | "raw"`` naming the colour space of each texture it references
    (:func:`baker.registry.usd_texture_color_spaces`; without one, its textures are data: ``raw``).
    ``primitive_accessors`` maps a primitive extension's name to its members that are accessors
    (:func:`baker.registry.usd_primitive_accessors`): that extension is written on the mesh prim (see the module
    docstring) so that :mod:`baker.readers.usd_baked` reads it back.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".usd", ".usda", ".usdc", ".usdz"):
        raise BakerError(path, "output must end in .usd, .usda, .usdc or .usdz")
    if suffix == ".usdz":
        _write_usdz(doc, path, primitive_hooks, attribute_widths, texture_color_spaces, primitive_accessors)
        return [path]
    folder = f"{path.stem}_textures"
    stage, images = build_stage(doc, folder, primitive_hooks, attribute_widths, texture_color_spaces,
                                primitive_accessors)
    # one atomic group, textures renamed first and the stage last: a reader never sees a stage whose textures are
    # missing, and a failed or killed run keeps every earlier file
    return write_stage_and_textures(stage, path, [(path.parent / folder / name, data) for name, data in images])


def write_stage_and_textures(stage, path: Path, textures) -> list[Path]:
    """Export ``stage``'s root layer to ``path`` and write ``textures`` ((path, bytes) pairs) as one atomic group."""
    targets = [p for p, _ in textures] + [path]
    with atomic_files(targets) as temps:
        for tmp, (_, data) in zip(temps, textures):
            tmp.write_bytes(data)
        export_stage(stage, temps[-1], path)
    return targets


def _write_usdz(doc, path: Path, primitive_hooks=None, attribute_widths=None, texture_color_spaces=None,
                primitive_accessors=None) -> None:
    from pxr import Sdf, UsdUtils

    stage, images = build_stage(doc, "textures", primitive_hooks, attribute_widths, texture_color_spaces,
                                primitive_accessors)
    with tempfile.TemporaryDirectory(prefix=".baker-usdz-") as work:
        work = Path(work)
        root = work / f"{path.stem}.usdc"
        for name, data in images:
            (work / "textures").mkdir(exist_ok=True)
            (work / "textures" / name).write_bytes(data)
        export_stage(stage, root, path)
        package = work / "package.usdz"
        if not UsdUtils.CreateNewUsdzPackage(Sdf.AssetPath(str(root)), str(package)):
            raise BakerError(path, "cannot write the USDZ package")
        with atomic_path(path) as tmp:
            _copy_zip_without_timestamps(package, tmp)


def _copy_zip_without_timestamps(source: Path, target: Path) -> None:
    """Copy a zip entry by entry with every modification time set to 1980-01-01 (the zip epoch).

    The USDZ writer stamps entries with the current time; everything else (order, names, the extra fields that
    pad each file to the 64-byte alignment USDZ requires, stored = uncompressed data) is kept, so the layout and
    offsets are unchanged.
    """
    import zipfile

    with zipfile.ZipFile(source) as zin, zipfile.ZipFile(target, "w") as zout:
        for info in zin.infolist():
            clean = zipfile.ZipInfo(info.filename, date_time=(1980, 1, 1, 0, 0, 0))
            clean.compress_type = info.compress_type
            clean.extra = info.extra
            clean.create_system = info.create_system
            clean.create_version = info.create_version
            clean.extract_version = info.extract_version
            clean.external_attr = info.external_attr
            clean.internal_attr = info.internal_attr
            zout.writestr(clean, zin.read(info.filename))
            if zout.getinfo(info.filename).header_offset != info.header_offset:
                raise RuntimeError("USDZ entry moved while removing timestamps; alignment would break")


def export_stage(stage, target: Path, path: Path) -> None:
    # the caller holds the stage: a layer handle from Python is a weak pointer, and an in-memory stage's root layer
    # dies with the stage (an expired handle is a fatal error in USD, which aborts the process)
    if not stage.GetRootLayer().Export(str(target)):
        raise BakerError(path, "cannot write the USD layer")


class _Names:
    """Valid, unique prim names among siblings, assigned in a fixed order."""

    def __init__(self):
        self.used: dict[str, set] = {}

    def make(self, parent: str, name: str | None, fallback: str) -> str:
        from pxr import Tf

        base = Tf.MakeValidIdentifier(name) if name else fallback
        taken = self.used.setdefault(parent, set())
        candidate, k = base, 1
        while candidate in taken:
            candidate = f"{base}_{k}"
            k += 1
        taken.add(candidate)
        return candidate


def build_stage(doc, texture_folder: str, primitive_hooks=None, attribute_widths=None, texture_color_spaces=None,
                primitive_accessors=None):
    """Author the stage in memory; returns (stage, [(texture file name, bytes)]) in a fixed order. The stage, not its
    root layer, is returned: Python holds a layer by a weak handle, which expires once the stage is collected."""
    from pxr import Gf, Kind, Usd, UsdGeom

    stage = Usd.Stage.CreateInMemory("baker.usda")
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    root = UsdGeom.Xform.Define(stage, "/Root").GetPrim()
    stage.SetDefaultPrim(root)
    Usd.ModelAPI(root).SetKind(Kind.Tokens.component)  # one asset: what USDZ viewers and assemblies expect

    writer = _Writer(doc, stage, texture_folder, primitive_hooks or {}, attribute_widths or {},
                     texture_color_spaces or {}, primitive_accessors or {})
    writer.names.make("/Root", "Materials", "Materials")  # reserved: a node named "Materials" becomes Materials_1
    gltf = doc.json
    nodes = gltf.get("nodes", [])
    scenes = gltf.get("scenes", [])
    if scenes:
        roots = scenes[gltf.get("scene", 0) if gltf.get("scene", 0) < len(scenes) else 0].get("nodes", [])
    else:
        children = {c for n in nodes for c in n.get("children", [])}
        roots = [i for i in range(len(nodes)) if i not in children]

    def visit(index: int, parent: str, depth: int) -> None:
        if depth > len(nodes):  # a cycle in the node graph: invalid glTF, do not recurse forever
            raise BakerError(doc.path, f"node {index} is its own ancestor")
        node = nodes[index]
        name = writer.names.make(parent, node.get("name"), f"node{index}")
        prim_path = f"{parent}/{name}"
        xform = UsdGeom.Xform.Define(stage, prim_path)
        matrix = node_matrix(node)
        if not np.array_equal(matrix, np.eye(4)):
            xform.AddTransformOp().Set(Gf.Matrix4d(matrix.T.tolist()))  # column vectors -> USD row vectors
        if "mesh" in node:
            writer.mesh(node["mesh"], prim_path)
        for child in node.get("children", []):
            visit(child, prim_path, depth + 1)

    for index in roots:
        visit(index, "/Root", 0)
    return stage, writer.image_files


class _Writer:
    def __init__(self, doc, stage, texture_folder: str, primitive_hooks: dict, attribute_widths: dict,
                 texture_color_spaces: dict, primitive_accessors: dict):
        self.doc = doc
        self.primitive_accessors = primitive_accessors
        self.primitive_hooks = primitive_hooks
        self.attribute_widths = attribute_widths
        self.stage = stage
        self.texture_folder = texture_folder
        self.names = _Names()
        self.materials: dict[int, object] = {}  # glTF material -> UsdShade.Material
        self.image_paths: dict[int, str] = {}  # glTF image -> asset path
        self.image_alpha: dict[int, bool] = {}  # glTF image -> has an alpha channel
        self.data_textures: dict[tuple, object] = {}  # (material path, texture, texCoord, colour space) -> shader
        self.texture_color_spaces = texture_color_spaces
        self.image_files: list = []

    # ------------------------------------------------------------------ geometry
    def mesh(self, mesh_index: int, parent: str) -> None:
        from pxr import Sdf, UsdGeom, UsdShade

        from baker.gltf.accessors import MODE_FAN, MODE_STRIP, MODE_TRIANGLES, is_derived_fins

        doc = self.doc
        mesh = doc.json["meshes"][mesh_index]
        prims = [(p, prim) for p, prim in enumerate(mesh.get("primitives", []))
                 if prim.get("mode", MODE_TRIANGLES) in (MODE_TRIANGLES, MODE_STRIP, MODE_FAN)
                 and "POSITION" in prim.get("attributes", {})
                 and not is_derived_fins(prim)]  # fins are glTF runtime geometry
        base = mesh.get("name") or f"mesh{mesh_index}"
        written = {}  # glTF primitive -> (its mesh prim path, name)
        for p, prim in prims:
            name = self.names.make(parent, base if len(prims) == 1 else f"{base}_{p}", f"mesh{mesh_index}")
            usd_mesh = self._triangles(f"{parent}/{name}", mesh_index, p, prim)
            written[p] = (f"{parent}/{name}", name)
            if "material" in prim:
                material = self.material(prim["material"])
                UsdShade.MaterialBindingAPI.Apply(usd_mesh.GetPrim()).Bind(material)
            self._primitive_extensions(usd_mesh.GetPrim(), prim)
            # extensions add their own USD beside the mesh (e.g. BAKER_edges' crease curves)
            for ext_name, hook in self.primitive_hooks.items():
                if ext_name in (prim.get("extensions") or {}):
                    hook(self.stage, self.names.make(parent, f"{name}_{ext_name[6:]}", "extra"), parent, doc,
                         mesh_index, p)
        # fins (zero-area quads a runtime extrudes, BAKER_edges / BAKER_fur ``finsOf``) as guide meshes: no final
        # render draws them, and the stage reads back with them (baker.readers.usd_baked)
        for p, prim in enumerate(mesh.get("primitives", [])):
            if not (is_derived_fins(prim) and "POSITION" in prim.get("attributes", {})):
                continue
            ext_name, ext = next((k, v) for k, v in prim["extensions"].items() if isinstance(v, dict) and "finsOf" in v)
            if ext.get("finsOf") not in written:
                continue
            source_path, source_name = written[ext["finsOf"]]
            name = self.names.make(parent, f"{source_name}_fins", "fins")
            usd_mesh = self._triangles(f"{parent}/{name}", mesh_index, p, prim)
            usd_mesh.CreatePurposeAttr(UsdGeom.Tokens.guide)
            fins = usd_mesh.GetPrim()
            fins.CreateRelationship("baker:finsOf", custom=True).SetTargets([Sdf.Path(source_path)])
            fins.CreateAttribute("baker:finsOf:extension", Sdf.ValueTypeNames.String, custom=True).Set(ext_name)

    def _triangles(self, path: str, mesh_index: int, p: int, prim: dict):
        """A ``UsdGeom.Mesh`` at ``path`` with one glTF triangle primitive's points, faces and primvars."""
        from pxr import Sdf, UsdGeom, Vt

        from baker.gltf.accessors import MODE_TRIANGLES, faces_from_indices, to_float

        doc = self.doc
        attrs = prim["attributes"]
        positions = doc.accessor(attrs["POSITION"]).astype(np.float32)
        n = len(positions)
        indices = doc.accessor(prim["indices"]).astype(np.int64) if "indices" in prim else np.arange(n)
        if len(indices) and (indices.min() < 0 or indices.max() >= n):
            raise BakerError(doc.path, f"mesh {mesh_index} primitive {p} has indices out of range")
        faces = faces_from_indices(indices, prim.get("mode", MODE_TRIANGLES))
        usd_mesh = UsdGeom.Mesh.Define(self.stage, path)
        usd_mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)  # glTF triangles are the final surface
        usd_mesh.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(positions))
        usd_mesh.CreateFaceVertexCountsAttr(Vt.IntArray.FromNumpy(np.full(len(faces), 3, np.int32)))
        usd_mesh.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(faces.reshape(-1).astype(np.int32)))
        lo, hi = (positions.min(0), positions.max(0)) if n else (np.zeros(3, np.float32),) * 2
        usd_mesh.CreateExtentAttr(Vt.Vec3fArray.FromNumpy(np.stack([lo, hi]).astype(np.float32)))
        primvars = UsdGeom.PrimvarsAPI(usd_mesh.GetPrim())
        for key in sorted(attrs, key=_attribute_order):
            acc = attrs[key]
            if key == "NORMAL":
                usd_mesh.CreateNormalsAttr(Vt.Vec3fArray.FromNumpy(doc.accessor(acc).astype(np.float32)))
                usd_mesh.SetNormalsInterpolation(UsdGeom.Tokens.vertex)
            elif key.startswith("TEXCOORD_"):
                uv = to_float(doc, acc)
                st = np.column_stack([uv[:, 0], 1.0 - uv[:, 1]]).astype(np.float32)
                pv = primvars.CreatePrimvar(_st_name(int(key[9:])), Sdf.ValueTypeNames.TexCoord2fArray,
                                            UsdGeom.Tokens.vertex)
                pv.Set(Vt.Vec2fArray.FromNumpy(st))
            elif key == "TANGENT":  # xyz and the bitangent sign w, for normal maps (no UsdGeom name for it)
                primvars.CreatePrimvar("tangents", Sdf.ValueTypeNames.Float4Array, UsdGeom.Tokens.vertex).Set(
                    Vt.Vec4fArray.FromNumpy(np.ascontiguousarray(to_float(doc, acc).astype(np.float32))))
            elif key == "COLOR_0":
                color = to_float(doc, acc).astype(np.float32)
                usd_mesh.CreateDisplayColorPrimvar(UsdGeom.Tokens.vertex).Set(
                    Vt.Vec3fArray.FromNumpy(np.ascontiguousarray(color[:, :3])))
                if color.shape[1] == 4:
                    usd_mesh.CreateDisplayOpacityPrimvar(UsdGeom.Tokens.vertex).Set(
                        Vt.FloatArray.FromNumpy(np.ascontiguousarray(color[:, 3])))
            elif key.startswith("_"):
                self._custom_primvar(primvars, key, acc)
        return usd_mesh

    def _primitive_extensions(self, usd_prim, prim: dict) -> None:
        """Each primitive extension listed in ``primitive_accessors`` as custom attributes on the mesh prim,
        ``baker:<name>:<field>`` (``BAKER_edges`` -> ``baker:edges``, others by their full name): fields as
        :func:`usd_parameters` writes a material's, each accessor as a flat array (``int[]``, ``uint[]`` or
        ``float[]``) with its glTF ``:componentType`` and ``:type``, so its exact data reads back."""
        from pxr import Sdf, Vt

        for ext_name, members in sorted(self.primitive_accessors.items()):
            ext = (prim.get("extensions") or {}).get(ext_name)
            if not isinstance(ext, dict):
                continue
            namespace = "baker:" + _valid_name(ext_name[6:] if ext_name.startswith("BAKER_") else ext_name)
            rest = {k: v for k, v in ext.items() if k not in members and k != "fins"}  # fins: the guide mesh's
            custom_attributes(usd_prim, namespace, usd_parameters(rest))
            accessors = self.doc.json.get("accessors") or []
            for member in members:
                index = ext.get(member)
                if not isinstance(index, int) or isinstance(index, bool) or not 0 <= index < len(accessors):
                    continue
                info = accessors[index]
                data = np.ascontiguousarray(self.doc.accessor(index).reshape(-1))
                if info["componentType"] == 5126:
                    type_name, value = Sdf.ValueTypeNames.FloatArray, Vt.FloatArray.FromNumpy(data.astype(np.float32))
                elif info["componentType"] == 5125:
                    type_name, value = Sdf.ValueTypeNames.UIntArray, Vt.UIntArray.FromNumpy(data.astype(np.uint32))
                else:
                    type_name, value = Sdf.ValueTypeNames.IntArray, Vt.IntArray.FromNumpy(data.astype(np.int32))
                at = f"{namespace}:{member}"
                usd_prim.CreateAttribute(at, type_name, custom=True).Set(value)
                usd_prim.CreateAttribute(f"{at}:componentType", Sdf.ValueTypeNames.Int, custom=True).Set(
                    int(info["componentType"]))
                usd_prim.CreateAttribute(f"{at}:type", Sdf.ValueTypeNames.String, custom=True).Set(info["type"])

    def _custom_primvar(self, primvars, key: str, acc: int) -> None:
        from pxr import Sdf, UsdGeom, Vt

        from baker.gltf.accessors import to_float
        from baker.gltf.vertex_attributes import TYPE_WIDTHS, WIDTH_TYPES, unpadded

        kind = self.doc.json["accessors"][acc]["type"]
        data = to_float(self.doc, acc).astype(np.float32)
        width = self.attribute_widths.get(key)
        if width and TYPE_WIDTHS.get(kind, 0) >= width:  # a known attribute: the data's own width, not the padding
            kind, data = WIDTH_TYPES[width], unpadded(data, width)
        types = {"SCALAR": (Sdf.ValueTypeNames.FloatArray, Vt.FloatArray),
                 "VEC2": (Sdf.ValueTypeNames.Float2Array, Vt.Vec2fArray),
                 "VEC3": (Sdf.ValueTypeNames.Float3Array, Vt.Vec3fArray),
                 "VEC4": (Sdf.ValueTypeNames.Float4Array, Vt.Vec4fArray)}
        if kind not in types:
            return  # matrices: no vertex primvar type fits
        value_type, array_type = types[kind]
        data = np.ascontiguousarray(data)
        name = primvar_name(key)[len("primvars:"):]
        primvars.CreatePrimvar(name, value_type, UsdGeom.Tokens.vertex).Set(array_type.FromNumpy(data))

    # ------------------------------------------------------------------ materials
    def material(self, index: int):
        if index in self.materials:
            return self.materials[index]
        from pxr import Gf, Sdf, UsdShade

        gltf = self.doc.json["materials"][index]
        self.stage.DefinePrim("/Root/Materials", "Scope")
        name = self.names.make("/Root/Materials", gltf.get("name"), f"material{index}")
        mat_path = f"/Root/Materials/{name}"
        material = UsdShade.Material.Define(self.stage, mat_path)
        self.materials[index] = material
        readers: dict[int, object] = {}

        surface = UsdShade.Shader.Define(self.stage, f"{mat_path}/PreviewSurface")
        surface.CreateIdAttr("UsdPreviewSurface")
        pbr = gltf.get("pbrMetallicRoughness", {})
        color = [float(c) for c in pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0])]
        surface.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).Set(Gf.Vec3f(*color[:3]))
        surface.CreateInput("opacity", Sdf.ValueTypeNames.Float).Set(color[3])
        surface.CreateInput("metallic", Sdf.ValueTypeNames.Float).Set(float(pbr.get("metallicFactor", 1.0)))
        surface.CreateInput("roughness", Sdf.ValueTypeNames.Float).Set(float(pbr.get("roughnessFactor", 1.0)))
        # KHR_materials_emissive_strength multiplies the factor (UsdPreviewSurface's emissiveColor is unbounded)
        strength = float(((gltf.get("extensions") or {}).get("KHR_materials_emissive_strength") or {})
                         .get("emissiveStrength", 1.0))
        emissive = [float(c) * strength for c in gltf.get("emissiveFactor") or [0.0, 0.0, 0.0]]
        if any(emissive):
            surface.CreateInput("emissiveColor", Sdf.ValueTypeNames.Color3f).Set(Gf.Vec3f(*emissive))
        if gltf.get("alphaMode") == "MASK":
            surface.CreateInput("opacityThreshold", Sdf.ValueTypeNames.Float).Set(float(gltf.get("alphaCutoff", 0.5)))
        material.CreateSurfaceOutput().ConnectToSource(surface.ConnectableAPI(), "surface")

        base_texture = pbr.get("baseColorTexture")
        if base_texture is not None:
            tex = self._texture(mat_path, "BaseColorTexture", base_texture, "sRGB", readers)
            if tex is not None:
                tex.CreateInput("scale", Sdf.ValueTypeNames.Float4).Set(Gf.Vec4f(*color))
                tex.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
                surface.GetInput("diffuseColor").ConnectToSource(tex.ConnectableAPI(), "rgb")
                if gltf.get("alphaMode") in ("MASK", "BLEND"):  # glTF's alpha is the base colour's
                    tex.CreateOutput("a", Sdf.ValueTypeNames.Float)
                    surface.GetInput("opacity").ConnectToSource(tex.ConnectableAPI(), "a")
        emissive_texture = gltf.get("emissiveTexture")
        if emissive_texture is not None and any(emissive):
            tex = self._texture(mat_path, "EmissiveTexture", emissive_texture, "sRGB", readers)
            if tex is not None:
                tex.CreateInput("scale", Sdf.ValueTypeNames.Float4).Set(Gf.Vec4f(*emissive, 1.0))
                tex.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
                surface.GetInput("emissiveColor").ConnectToSource(tex.ConnectableAPI(), "rgb")
        metal_rough_texture = pbr.get("metallicRoughnessTexture")
        if metal_rough_texture is not None:  # glTF: roughness in green, metalness in blue, times the factors
            tex = self._texture(mat_path, "MetallicRoughnessTexture", metal_rough_texture, "raw", readers)
            if tex is not None:
                metallic = float(pbr.get("metallicFactor", 1.0))
                roughness = float(pbr.get("roughnessFactor", 1.0))
                tex.CreateInput("scale", Sdf.ValueTypeNames.Float4).Set(Gf.Vec4f(1.0, roughness, metallic, 1.0))
                surface.GetInput("roughness").ConnectToSource(tex.CreateOutput("g", Sdf.ValueTypeNames.Float))
                surface.GetInput("metallic").ConnectToSource(tex.CreateOutput("b", Sdf.ValueTypeNames.Float))
        occlusion_texture = gltf.get("occlusionTexture")
        if occlusion_texture is not None:  # glTF: occlusion in red, 1 + strength (r - 1)
            tex = self._texture(mat_path, "OcclusionTexture", occlusion_texture, "raw", readers)
            if tex is not None:
                strength = float(occlusion_texture.get("strength", 1.0))
                tex.CreateInput("scale", Sdf.ValueTypeNames.Float4).Set(Gf.Vec4f(strength, strength, strength, 1))
                tex.CreateInput("bias", Sdf.ValueTypeNames.Float4).Set(Gf.Vec4f(1 - strength, 1 - strength,
                                                                                1 - strength, 0))
                surface.CreateInput("occlusion", Sdf.ValueTypeNames.Float).ConnectToSource(
                    tex.CreateOutput("r", Sdf.ValueTypeNames.Float))
        normal_texture = gltf.get("normalTexture")
        if normal_texture is not None:
            tex = self._texture(mat_path, "NormalTexture", normal_texture, "raw", readers)
            if tex is not None:  # [0, 1] texels -> [-1, 1] tangent-space normal, x and y scaled by glTF's scale
                scale = float(normal_texture.get("scale", 1.0))
                tex.CreateInput("scale", Sdf.ValueTypeNames.Float4).Set(Gf.Vec4f(2 * scale, 2 * scale, 2, 1))
                tex.CreateInput("bias", Sdf.ValueTypeNames.Float4).Set(Gf.Vec4f(-scale, -scale, -1, 0))
                tex.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
                surface.CreateInput("normal", Sdf.ValueTypeNames.Normal3f).ConnectToSource(tex.ConnectableAPI(), "rgb")

        # the thickness texture: BAKER_thickness's (on every material baker bakes), else KHR_materials_volume's;
        # outputs:baker:thickness is its green channel (the thickness), for a consumer that wants the scalar
        volume = gltf.get("extensions", {}).get("KHR_materials_volume", {})
        baked = gltf.get("extensions", {}).get("BAKER_thickness", {})
        if not isinstance(baked.get("thicknessTexture"), dict):
            baked = volume
        if "thicknessTexture" in baked:
            tex = self._data_texture(mat_path, "ThicknessTexture", baked["thicknessTexture"], "raw", readers)
            if tex is not None:
                out = tex.CreateOutput("g", Sdf.ValueTypeNames.Float)
                material.CreateOutput("baker:thickness", Sdf.ValueTypeNames.Float).ConnectToSource(out)
        if "thicknessFactor" in baked:
            material.CreateInput("baker:thicknessFactor", Sdf.ValueTypeNames.Float).Set(
                float(baked.get("thicknessFactor", 0.0)))

        prim = material.GetPrim()
        for ext_name, params in gltf.get("extensions", {}).items():
            if ext_name.startswith("BAKER_") and isinstance(params, dict):
                namespace = "baker:" + _valid_name(ext_name[6:])
                custom_attributes(prim, namespace, usd_parameters(params))
                # every texture the extension names: a UsdUVTexture shader feeding material outputs named after its
                # JSON path, e.g. outputs:baker:skin_lut:lutTexture (rgb) and ...:lutTexture:a (alpha, if any)
                color_space = self.texture_color_spaces.get(ext_name)
                default_texcoord = params.get("texCoord") if isinstance(params.get("texCoord"), int) else 0
                for path, info in _texture_infos(params):
                    name = ":".join([namespace, *(f"_{k}" if isinstance(k, int) else _valid_name(k) for k in path)])
                    shader = "Baker_" + _valid_name("_".join([ext_name[6:], *map(str, path)]))
                    space = color_space(params, path) if color_space else "raw"
                    self.baker_texture(material, name, shader, info, space, readers, default_texcoord)
                if isinstance(params.get("coverageMips"), list):
                    self._coverage_mips(prim, namespace + ":coverageMips", params["coverageMips"])
        return material

    def baker_texture(self, material, output: str, shader_name: str, info: dict, color_space: str, readers: dict,
                      default_texcoord: int = 0):
        """One texture an extension names, as a USD consumer follows it: a ``UsdUVTexture`` under the material
        (shared by every reference to the same texture, UV set and colour space) whose ``rgb`` feeds the material
        output ``outputs:<output>`` (float3) and, when the image has alpha, ``a`` feeds ``outputs:<output>:a``.
        Returns the shader, or None when the reference leads to no image."""
        from pxr import Sdf, UsdShade

        mat_path = str(material.GetPath())
        tex = self._data_texture(mat_path, shader_name, info, color_space, readers, default_texcoord)
        if tex is None:
            return None
        rgb = tex.GetOutput("rgb") or tex.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
        material.CreateOutput(output, Sdf.ValueTypeNames.Float3).ConnectToSource(rgb)
        source = self.doc.json["textures"][info["index"]]["source"]
        if self._image_has_alpha(source):
            alpha = tex.GetOutput("a") or tex.CreateOutput("a", Sdf.ValueTypeNames.Float)
            material.CreateOutput(f"{output}:a", Sdf.ValueTypeNames.Float).ConnectToSource(alpha)
        return UsdShade.Shader(tex.GetPrim())

    def _data_texture(self, mat_path: str, shader_name: str, info: dict, color_space: str, readers: dict,
                      default_texcoord: int = 0):
        """A scale-free ``UsdUVTexture`` for ``info``, made once per material, texture, UV set and colour space (the
        same texture named by two extensions, e.g. BAKER_thickness and KHR_materials_volume, is one shader)."""
        if not isinstance(info, dict) or not isinstance(info.get("index"), int):
            return None
        texcoord = info.get("texCoord", default_texcoord)
        key = (mat_path, info["index"], texcoord, color_space)
        if key not in self.data_textures:
            self.data_textures[key] = self._texture(mat_path, shader_name, dict(info, texCoord=texcoord),
                                                    color_space, readers)
        return self.data_textures[key]

    def _image_has_alpha(self, index: int) -> bool:
        """Whether glTF image ``index`` has an alpha channel (PNG/WebP modes LA, RGBA, ...); unreadable: no."""
        if index not in self.image_alpha:
            import io

            from PIL import Image

            try:
                with Image.open(io.BytesIO(self.doc.image_bytes(index))) as image:
                    self.image_alpha[index] = "A" in image.getbands()
            except Exception:  # not an image PIL reads (e.g. KTX2): rgb only
                self.image_alpha[index] = False
        return self.image_alpha[index]

    def _coverage_mips(self, prim, namespace: str, entries: list) -> None:
        """Each coverage-preserving mip chain (:mod:`baker.texels.alpha_mips`) as its KTX2 file beside the textures:
        ``<namespace>:_<i>:file`` (the KTX2), ``:image`` (level 0, the PNG), ``:alphaCutoff``, ``:levelCount``,
        ``:firstLevel`` (1: the KTX2 starts at level 1, level 0 is the image).
        UsdUVTexture reads no KTX2 and its PNG gets mips from the renderer; the chain is there for a runtime
        that loads it, as the glTF plugins do."""
        from pxr import Sdf

        from baker.gltf.ktx2 import coverage_mips_bytes

        textures = self.doc.json.get("textures") or []
        for i, entry in enumerate(entries):
            texture = entry.get("texture") if isinstance(entry, dict) else None
            if not isinstance(texture, int) or not 0 <= texture < len(textures) or "source" not in textures[texture]:
                continue
            try:
                data = coverage_mips_bytes(self.doc, entry)
            except Exception:  # an unreadable chain is `baker validate`'s to report; the stage does without it
                continue
            image = self._image(textures[texture]["source"])
            key = ("coverageMips", entry["accessor"])
            if key not in self.image_paths:
                self.image_paths[key] = self._add_file(Path(image).stem + "_mips", ".ktx2", data)
            at = f"{namespace}:_{i}"
            prim.CreateAttribute(f"{at}:file", Sdf.ValueTypeNames.Asset, custom=True).Set(
                Sdf.AssetPath(self.image_paths[key]))
            prim.CreateAttribute(f"{at}:image", Sdf.ValueTypeNames.Asset, custom=True).Set(Sdf.AssetPath(image))
            for field, type_name in (("alphaCutoff", Sdf.ValueTypeNames.Float), ("levelCount", Sdf.ValueTypeNames.Int),
                                     ("firstLevel", Sdf.ValueTypeNames.Int)):
                if isinstance(entry.get(field), (int, float)):
                    prim.CreateAttribute(f"{at}:{field}", type_name, custom=True).Set(entry[field])

    def _texture(self, mat_path: str, shader_name: str, info: dict, color_space: str, readers: dict):
        from pxr import Sdf, UsdShade

        textures = self.doc.json.get("textures", [])
        if not isinstance(info, dict) or info.get("index", -1) >= len(textures):
            return None
        texture = textures[info["index"]]
        source = texture.get("source")
        if source is None:
            return None
        asset = self._image(source)
        tex = UsdShade.Shader.Define(self.stage, f"{mat_path}/{shader_name}")
        tex.CreateIdAttr("UsdUVTexture")
        tex.CreateInput("file", Sdf.ValueTypeNames.Asset).Set(Sdf.AssetPath(asset))
        tex.CreateInput("sourceColorSpace", Sdf.ValueTypeNames.Token).Set(color_space)
        sampler = self.doc.json.get("samplers", [])[texture["sampler"]] if "sampler" in texture else {}
        tex.CreateInput("wrapS", Sdf.ValueTypeNames.Token).Set(WRAP_MODES.get(sampler.get("wrapS", 10497), "repeat"))
        tex.CreateInput("wrapT", Sdf.ValueTypeNames.Token).Set(WRAP_MODES.get(sampler.get("wrapT", 10497), "repeat"))
        tex.CreateInput("st", Sdf.ValueTypeNames.Float2).ConnectToSource(
            self._reader(mat_path, int(info.get("texCoord", 0)), readers))
        return tex

    def _reader(self, mat_path: str, texcoord: int, readers: dict):
        from pxr import Sdf, UsdShade

        if texcoord not in readers:
            varname = _st_name(texcoord)
            reader = UsdShade.Shader.Define(self.stage, f"{mat_path}/PrimvarReader_{varname}")
            reader.CreateIdAttr("UsdPrimvarReader_float2")
            reader.CreateInput("varname", Sdf.ValueTypeNames.String).Set(varname)
            readers[texcoord] = reader.CreateOutput("result", Sdf.ValueTypeNames.Float2)
        return readers[texcoord]

    def _image(self, index: int) -> str:
        if index in self.image_paths:
            return self.image_paths[index]
        from pxr import Tf

        data = self.doc.image_bytes(index)
        image = self.doc.json["images"][index]
        from baker.gltf.document import sniff_mime

        mime = image.get("mimeType") or sniff_mime(data)
        ext = IMAGE_EXTENSIONS.get(mime) or mimetypes.guess_extension(mime) or ".bin"
        stem = Tf.MakeValidIdentifier(Path(image.get("name") or image.get("uri", "") or f"image{index}").stem
                                      or f"image{index}")
        self.image_paths[index] = self._add_file(stem, ext, data)
        return self.image_paths[index]

    def _add_file(self, stem: str, ext: str, data: bytes) -> str:
        """Queue ``data`` as a file of the texture folder under a name no other file has; its asset path."""
        taken = {name for name, _ in self.image_files}
        name, k = f"{stem}{ext}", 1
        while name in taken:
            name, k = f"{stem}_{k}{ext}", k + 1
        self.image_files.append((name, data))
        return f"./{self.texture_folder}/{name}"


def _valid_name(name: str) -> str:
    from pxr import Tf

    return Tf.MakeValidIdentifier(name)


def custom_attributes(prim, namespace: str, params: dict) -> None:
    """Write a JSON object as typed custom attributes ``<namespace>:<key>`` (nested objects nest namespaces)."""
    from pxr import Gf, Sdf, Vt

    for key, value in params.items():
        name = f"{namespace}:{_valid_name(str(key))}"
        if isinstance(value, dict):
            custom_attributes(prim, name, value)
            continue
        if isinstance(value, bool):
            type_name, value = Sdf.ValueTypeNames.Bool, value
        elif isinstance(value, int):
            type_name = Sdf.ValueTypeNames.Int if -2**31 <= value < 2**31 else Sdf.ValueTypeNames.Int64
        elif isinstance(value, float):  # double: a JSON number read back is the number written
            type_name = Sdf.ValueTypeNames.Double
        elif isinstance(value, str):
            type_name = Sdf.ValueTypeNames.String
        elif isinstance(value, list) and value and all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                                       for v in value):
            value = [float(v) for v in value]
            vectors = {2: (Sdf.ValueTypeNames.Double2, Gf.Vec2d), 3: (Sdf.ValueTypeNames.Double3, Gf.Vec3d),
                       4: (Sdf.ValueTypeNames.Double4, Gf.Vec4d)}
            type_name, make = vectors.get(len(value), (Sdf.ValueTypeNames.DoubleArray, Vt.DoubleArray))
            value = make(*value) if len(value) in vectors else make(value)
        elif isinstance(value, list) and value and all(isinstance(v, str) for v in value):
            type_name, value = Sdf.ValueTypeNames.StringArray, Vt.StringArray(value)
        else:
            continue  # null, empty or mixed lists: nothing typed to write
        prim.CreateAttribute(name, type_name, custom=True).Set(value)


def usd_parameters(params: dict) -> dict:
    """An extension object's parameters as they mean something in USD (written by :func:`custom_attributes`).

    glTF indices have no meaning in a stage, so none is kept: a texture reference keeps only its non-index fields
    (``scale``, ``strength``; its image and UV set are the ``UsdUVTexture`` and primvar reader the writer connects);
    a top-level ``texCoord`` (the UV set the extension's textures read) becomes ``texCoordPrimvar``, the primvar's
    name; lists of objects that hold accessor, mesh or texture indices (``coverageMips``, ``fins``, TAM ``levels``)
    are left out, lists of plain-data objects (normal blur's ``kernels``) become namespaces ``_0``, ``_1``, ...; and a custom vertex attribute name (``"_THICKNESS"``) becomes the primvar USD carries it as
    (``"primvars:baker:thickness"``).
    """
    out = {}
    for key, value in params.items():
        if key in ("extensions", "extras"):
            continue
        if _is_texture_info(value):
            rest = {k: v for k, v in value.items() if k not in ("index", "texCoord", "extensions", "extras")}
            if rest:
                out[key] = rest
        elif key == "texCoord" and isinstance(value, int) and not isinstance(value, bool):
            out["texCoordPrimvar"] = _st_name(value)
        elif isinstance(value, dict):
            out[key] = usd_parameters(value)
        elif isinstance(value, list) and any(isinstance(v, (dict, list)) for v in value):
            if not _names_gltf_object(value):
                out[key] = _list_items(value)  # plain data: items _0, _1, ...
            continue
        elif isinstance(value, str) and _CUSTOM_ATTRIBUTE.fullmatch(value):
            out[key] = primvar_name(value)
        else:
            out[key] = value
    return out


_CUSTOM_ATTRIBUTE = re.compile(r"_[A-Z][A-Z0-9_]*")
# members that hold a glTF index (or a texture reference): meaningless in a stage
GLTF_INDEX_MEMBERS = {"index", "texture", "textures", "accessor", "mesh", "primitive", "node", "material", "image",
                      "source", "sampler", "bufferView", "buffer", "skin", "camera", "scene", "texCoord"}


def _list_items(items: list) -> dict:
    """A list of objects or lists as ``{"_0": ..., "_1": ...}``, nested lists likewise (numbers stay arrays)."""
    out = {}
    for i, item in enumerate(items):
        if isinstance(item, dict):
            out[f"_{i}"] = usd_parameters(item)
        elif isinstance(item, list) and any(isinstance(v, (dict, list)) for v in item):
            out[f"_{i}"] = _list_items(item)
        else:
            out[f"_{i}"] = item
    return out


def _names_gltf_object(node) -> bool:
    """Whether a JSON value holds a glTF index anywhere (a member named like one, at any depth)."""
    if isinstance(node, dict):
        return any(k in GLTF_INDEX_MEMBERS or _names_gltf_object(v) for k, v in node.items())
    if isinstance(node, list):
        return any(_names_gltf_object(v) for v in node)
    return False


def primvar_name(attribute: str) -> str:
    """The USD primvar a custom glTF vertex attribute is written as (``_PRINCIPAL_CURVATURES`` ->
    ``primvars:baker:principal_curvatures``)."""
    from pxr import Tf

    return "primvars:baker:" + Tf.MakeValidIdentifier(attribute.lstrip("_").lower())


def _is_texture_info(node) -> bool:
    return isinstance(node, dict) and isinstance(node.get("index"), int) and not isinstance(node.get("index"), bool) \
        and set(node) <= {"index", "texCoord", "scale", "strength", "extensions", "extras"}


def _texture_infos(node, path=()):
    """(JSON path, textureInfo) of every ``{"index": n, ...}`` texture reference nested in an extension object."""
    if isinstance(node, dict):
        if _is_texture_info(node):
            yield path, node
            return
        for key, value in node.items():
            if key not in ("extensions", "extras"):
                yield from _texture_infos(value, path + (key,))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield from _texture_infos(value, path + (i,))


def _st_name(texcoord: int) -> str:
    return "st" if texcoord == 0 else f"st{texcoord}"


def _attribute_order(key: str):
    return (key.startswith("_"), key)
