"""A stage :mod:`baker.gltf.usd` wrote, read back into the glTF document it was written from, so ``baker inspect``,
``baker preview`` and ``baker validate`` see the same baked data in a ``.usda``/``.usdc``/``.usdz`` as in the GLB
of the same bake.

A stage is baker's when a mesh carries a ``primvars:baker:*`` primvar or a bound material a ``baker:*`` attribute or
output (:func:`is_baked_stage`). Its meshes must then be the writer's: triangles only, every primvar of vertex
interpolation with one value per point. Per ``UsdGeom.Mesh`` (in traversal order, world transform baked into the
points as :mod:`baker.readers.usd` does) one glTF mesh and node:

- ``POSITION``, ``NORMAL`` (``normals``), ``TANGENT`` (``primvars:tangents``), ``TEXCOORD_<n>`` (``primvars:st<n>``, ``v = 1 - t``), ``COLOR_0``
  (``displayColor`` + ``displayOpacity``), and ``_NAME`` from every ``primvars:baker:name`` at the width it has in
  USD (scalar, VEC2, VEC3 or VEC4: the ``native`` layout of :mod:`baker.gltf.vertex_attributes`, which every reader
  accepts);
- the bound material: ``UsdPreviewSurface``'s factors and base colour texture, then every ``BAKER_<name>`` material
  extension rebuilt from the ``baker:<name>:*`` attributes (nested namespaces -> nested objects, ``_<i>`` -> list
  items, ``texCoordPrimvar`` -> ``texCoord``, ``primvars:baker:x`` -> ``_X``) and the ``outputs:baker:<name>:<json
  path>`` textures (each ``UsdUVTexture``'s image becomes a glTF image and texture, its primvar reader's ``st<n>``
  the ``texCoord``), ``KHR_materials_volume`` from ``ThicknessTexture`` and ``inputs:baker:thicknessFactor``;
- what the attributes cannot carry (lists of objects holding glTF indices, e.g. TAM level sizes) each extension
  recovers in its ``from_usd(doc, material, params)`` hook (:func:`baker.registry.usd_material_readers`, lent
  through :data:`baker.technique.USD_READ_HOOKS`).

- each ``coverageMips`` chain from its ``baker:<name>:coverageMips:_<i>:*`` attributes (the KTX2 file back into an
  accessor, its level 0's coverage measured again).

- ``BasisCurves`` an extension reads back (``from_usd_curves``, lent as ``curve_readers``: ``BAKER_hair``'s strands
  with their ``primvars:baker:*`` and bound material), one glTF mesh per parent prim.

- the primitive extensions written on the Mesh prim (``baker:edges:*``, ``baker:EXT_mesh_primitive_edge_visibility:*``:
  accessors from their flat arrays, ``:componentType`` and ``:type``) and the fin primitives (guide meshes with
  ``baker:finsOf``), appended to their surface's glTF mesh and named by its extension's ``fins``.

Not recovered: the glTF node hierarchy (one node per mesh, in world space). Broken data (a primvar of the wrong length, NaN or infinity in one,
a texture outside the stage's folder) raises :class:`~baker.errors.BakerError` naming the prim and the attribute.
"""
from __future__ import annotations

import re
import zipfile
from pathlib import Path

import numpy as np

from baker.errors import BakerError
from baker.gltf.document import GltfDocument, sniff_mime
from baker.technique import usd_read_hook

ST_NAME = re.compile(r"st(\d*)")
LIST_ITEM = re.compile(r"_(\d+)")
WRAP_CODES = {"repeat": 10497, "clamp": 33071, "mirror": 33648}
COMPONENT_DTYPES = {5120: np.dtype(np.int8), 5121: np.dtype(np.uint8), 5122: np.dtype(np.int16),
                    5123: np.dtype(np.uint16), 5125: np.dtype(np.uint32), 5126: np.dtype(np.float32)}


def is_baked_stage(stage) -> bool:
    """Whether a mesh of ``stage`` carries baker's primvars or its bound material baker's attributes/outputs."""
    from pxr import Usd, UsdGeom, UsdShade

    for prim in stage.Traverse(Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)):
        if prim.IsA(UsdGeom.BasisCurves) and UsdGeom.PrimvarsAPI(prim).HasPrimvar("baker:strandParam"):
            return True  # baker's hair strands
        if not prim.IsA(UsdGeom.Mesh):
            continue
        if any(p.GetPrimvarName().startswith("baker:") for p in UsdGeom.PrimvarsAPI(prim).GetPrimvars()):
            return True
        material = UsdShade.MaterialBindingAPI(prim).ComputeBoundMaterial()[0]
        if material and any(name.startswith(("baker:", "outputs:baker:", "inputs:baker:"))
                            for name in material.GetPrim().GetPropertyNames()):
            return True
    return False


def read_baked_stage(path: Path, stage, meshes) -> GltfDocument:
    """The glTF document of a baked stage; ``meshes``: (UsdGeom.Mesh, world matrix) of every renderable mesh."""
    from pxr import Usd, UsdGeom

    reader = _StageReader(path, stage)
    for mesh, matrix in meshes:
        reader.mesh(mesh, matrix)
    # fin primitives: guide meshes that name the mesh they belong to (baker.gltf.usd writes them so); hair strands
    cache = UsdGeom.XformCache(Usd.TimeCode.EarliestTime())
    for prim in stage.Traverse(Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)):
        if prim.IsA(UsdGeom.Mesh) and prim.HasRelationship("baker:finsOf"):
            reader.fins(UsdGeom.Mesh(prim), np.array(cache.GetLocalToWorldTransform(prim), dtype=np.float64))
        elif prim.IsA(UsdGeom.BasisCurves):
            reader.curves(prim, np.array(cache.GetLocalToWorldTransform(prim), dtype=np.float64))
    if not reader.doc.json["meshes"]:
        raise BakerError(path, "no triangle faces")
    return reader.doc


class _StageReader:
    def __init__(self, path: Path, stage):
        self.path = path
        self.stage = stage
        self.folder = path.resolve().parent
        self.doc = GltfDocument(json={"asset": {"version": "2.0", "generator": f"baker (read from {path.name})"},
                                      "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": []}, path=path)
        self.materials: dict[str, int] = {}  # material prim path -> glTF material
        self.meshes: dict[str, int] = {}  # mesh prim path -> glTF mesh (its primitive 0)
        self.images: dict[str, int] = {}  # resolved asset path -> glTF image
        self.curve_meshes: dict[str, int] = {}  # parent prim path of read-back curves -> glTF mesh

    # ------------------------------------------------------------------ geometry
    def mesh(self, mesh, matrix: np.ndarray) -> None:
        from pxr import UsdShade

        primitive = self.primitive(mesh, matrix)
        if primitive is None:
            return
        material = UsdShade.MaterialBindingAPI(mesh.GetPrim()).ComputeBoundMaterial()[0]
        if material:
            primitive["material"] = self.material(material)
        doc = self.doc
        name = mesh.GetPrim().GetName()
        doc.json["meshes"].append({"name": name, "primitives": [primitive]})
        index = len(doc.json["meshes"]) - 1
        self.meshes[str(mesh.GetPath())] = index
        self.primitive_extensions(mesh.GetPrim(), index, 0)
        doc.json["nodes"].append({"name": name, "mesh": index})
        doc.json["scenes"][0]["nodes"].append(len(doc.json["nodes"]) - 1)

    def curves(self, prim, matrix: np.ndarray) -> None:
        """A ``BasisCurves`` prim an extension reads back (``curve_readers``: BAKER_hair's strands), appended to
        the glTF mesh of its parent prim (``/Root/Hair``: guides, then children), its bound material read."""
        from pxr import UsdShade

        for reader in usd_read_hook("curve_readers").values():
            try:
                primitive = reader(self.doc, prim, matrix)
            except BakerError as exc:
                raise BakerError(self.path, str(exc).split(": ", 1)[-1]) from None
            if primitive is None:
                continue
            material = UsdShade.MaterialBindingAPI(prim).ComputeBoundMaterial()[0]
            if material:
                primitive["material"] = self.material(material)
            parent = str(prim.GetParent().GetPath())
            if parent not in self.curve_meshes:
                doc = self.doc
                doc.json["meshes"].append({"name": prim.GetParent().GetName(), "primitives": []})
                self.curve_meshes[parent] = len(doc.json["meshes"]) - 1
                doc.json["nodes"].append({"name": prim.GetParent().GetName(), "mesh": self.curve_meshes[parent]})
                doc.json["scenes"][0]["nodes"].append(len(doc.json["nodes"]) - 1)
            self.doc.json["meshes"][self.curve_meshes[parent]]["primitives"].append(primitive)
            return

    def fins(self, mesh, matrix: np.ndarray) -> None:
        """A fin primitive (``finsOf``) of the mesh its ``baker:finsOf`` names, and the reference to it: its
        extension's ``fins`` on that primitive (BAKER_edges) or on its material (BAKER_fur's list)."""
        prim = mesh.GetPrim()
        targets = prim.GetRelationship("baker:finsOf").GetTargets()
        extension = prim.GetAttribute("baker:finsOf:extension").Get()
        where = f"mesh {mesh.GetPath()}"
        if len(targets) != 1 or str(targets[0]) not in self.meshes or not isinstance(extension, str):
            raise BakerError(self.path, f"{where}: baker:finsOf names no mesh read from the stage")
        m = self.meshes[str(targets[0])]
        primitive = self.primitive(mesh, matrix)
        if primitive is None:
            return
        primitive["extensions"] = {extension: {"finsOf": 0}}
        self.doc.use_extension(extension)
        primitives = self.doc.json["meshes"][m]["primitives"]
        primitives.append(primitive)
        fin = len(primitives) - 1
        source = primitives[0]
        if isinstance((source.get("extensions") or {}).get(extension), dict):
            source["extensions"][extension]["fins"] = fin
        elif "material" in source:
            material = self.doc.json["materials"][source["material"]]
            params = (material.get("extensions") or {}).get(extension)
            if isinstance(params, dict):
                params.setdefault("fins", []).append({"mesh": m, "primitive": fin})

    def primitive_extensions(self, prim, mesh: int, primitive: int) -> None:
        """The primitive extensions written on the mesh prim (``baker:<name>:*``, see :mod:`baker.gltf.usd`), their
        accessors rebuilt from the flat arrays and their ``:componentType`` and ``:type``."""
        known = usd_read_hook("primitive_accessors")
        found: dict = {}
        for attr in prim.GetAttributes():
            name = attr.GetName()
            parts = name.split(":")
            if parts[0] != "baker" or len(parts) < 3 or not attr.HasAuthoredValue():
                continue
            ext = f"BAKER_{parts[1]}" if f"BAKER_{parts[1]}" in known else parts[1]
            if ext in known:
                found.setdefault(ext, {})[tuple(parts[2:])] = attr.Get()
        for ext, fields in sorted(found.items()):
            params: dict = {}
            members = known[ext]
            for key, value in sorted(fields.items()):
                if key[0] in members:
                    if len(key) == 1:
                        params[key[0]] = self._accessor(value, fields, key[0], f"mesh {prim.GetPath()} {ext}.{key[0]}")
                    continue
                _put(params, list(key), self._json_value(value, f"{prim.GetPath()}.{':'.join(key)}"))
            self.doc.set_primitive_extension(mesh, primitive, ext, _with_lists(params))

    def _accessor(self, value, fields: dict, member: str, where: str) -> int:
        component = fields.get((member, "componentType"))
        kind = fields.get((member, "type"))
        width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}.get(kind)
        dtype = COMPONENT_DTYPES.get(component)
        data = np.asarray(value)
        if dtype is None or width is None or len(data) % width:
            raise BakerError(self.path, f"{where}: {len(data)} values of type {kind} / componentType {component}")
        if dtype.kind in "iu":
            info = np.iinfo(dtype)
            if len(data) and (data.min() < info.min or data.max() > info.max):
                raise BakerError(self.path, f"{where}: values outside the range of componentType {component}")
        else:
            self._finite(data.astype(np.float64), where, "values")
        data = data.astype(dtype)
        return self.doc.add_accessor(data if width == 1 else data.reshape(-1, width), target=None)

    def primitive(self, mesh, matrix: np.ndarray) -> dict | None:
        """One triangle primitive from a writer's mesh prim (None when it has no faces)."""
        from pxr import UsdGeom

        where = f"mesh {mesh.GetPath()}"
        points = _values(mesh.GetPointsAttr().Get(), 3)
        counts = _values(mesh.GetFaceVertexCountsAttr().Get(), 1).astype(np.int64)
        indices = _values(mesh.GetFaceVertexIndicesAttr().Get(), 1).astype(np.int64)
        if not len(counts):
            return None
        if (counts != 3).any() or len(indices) != 3 * len(counts):
            raise BakerError(self.path, f"{where}: baker's meshes are triangles (faceVertexCounts all 3)")
        if indices.min() < 0 or indices.max() >= len(points):
            raise BakerError(self.path, f"{where}: faceVertexIndices out of range (>= {len(points)} points)")
        self._finite(points, where, "points")
        doc = self.doc
        linear = matrix[:3, :3]
        positions = points @ linear + matrix[3, :3]  # USD matrices act on row vectors
        faces = indices.reshape(-1, 3)
        if (np.linalg.det(linear) < 0) != (mesh.GetOrientationAttr().Get() == UsdGeom.Tokens.leftHanded):
            faces = faces[:, [0, 2, 1]]  # front faces stay counter-clockwise
        attributes = {"POSITION": doc.add_accessor(positions.astype(np.float32), min_max=True)}
        if mesh.GetNormalsAttr().HasValue():
            normals = self._per_point(_values(mesh.GetNormalsAttr().Get(), 3), mesh.GetNormalsInterpolation(),
                                      len(points), where, "normals")
            normals = normals @ np.linalg.inv(linear).T
            normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-20)
            attributes["NORMAL"] = doc.add_accessor(normals.astype(np.float32))
        primvars = UsdGeom.PrimvarsAPI(mesh.GetPrim())
        color = opacity = None
        for primvar in sorted(primvars.GetPrimvarsWithValues(), key=lambda p: str(p.GetPrimvarName())):
            name = str(primvar.GetPrimvarName())
            uv = ST_NAME.fullmatch(name)
            if not (uv or name.startswith("baker:") or name in ("displayColor", "displayOpacity", "tangents")):
                continue
            value = primvar.ComputeFlattened()
            if value is None:
                continue
            data = np.asarray(value, np.float64)
            data = data.reshape(len(data), -1) if data.ndim > 1 else data.reshape(-1, 1)
            data = self._per_point(data, primvar.GetInterpolation(), len(points), where, f"primvars:{name}")
            if uv:
                data = np.column_stack([data[:, 0], 1.0 - data[:, 1]])  # USD's t points up, glTF's v down
                attributes[f"TEXCOORD_{int(uv.group(1) or 0)}"] = doc.add_accessor(data.astype(np.float32))
            elif name == "tangents" and data.shape[1] == 4:
                attributes["TANGENT"] = doc.add_accessor(data.astype(np.float32))
            elif name == "displayColor":
                color = data
            elif name == "displayOpacity":
                opacity = data
            else:
                attribute = "_" + name[len("baker:"):].upper()
                values = data[:, 0] if data.shape[1] == 1 else data
                attributes[attribute] = doc.add_accessor(values.astype(np.float32))
        if color is not None:
            rgba = color if opacity is None else np.column_stack([color[:, :3], opacity[:, :1]])
            attributes["COLOR_0"] = doc.add_accessor(rgba.astype(np.float32))
        return {"attributes": attributes, "mode": 4,
                "indices": doc.add_accessor(faces.reshape(-1).astype(np.uint32), target=34963)}

    def _per_point(self, data: np.ndarray, interpolation, n_points: int, where: str, attribute: str) -> np.ndarray:
        """Values of a writer's primvar: vertex (or varying) interpolation, one per point, all finite."""
        from pxr import UsdGeom

        if interpolation not in (UsdGeom.Tokens.vertex, UsdGeom.Tokens.varying):
            raise BakerError(self.path, f"{where} {attribute}: interpolation {interpolation}, baker writes vertex")
        if len(data) != n_points:
            raise BakerError(self.path, f"{where} {attribute}: {len(data)} values for {n_points} points")
        self._finite(data, where, attribute)
        return data

    def _finite(self, data: np.ndarray, where: str, attribute: str) -> None:
        bad = ~np.isfinite(data)
        if bad.any():
            first = int(np.argwhere(bad.reshape(len(data), -1).any(axis=1))[0, 0])
            raise BakerError(self.path, f"{where} {attribute}: value {first} is not finite "
                                        f"({int(bad.any(axis=-1).sum()) if data.ndim > 1 else int(bad.sum())} such)")

    # ------------------------------------------------------------------ materials
    def material(self, material) -> int:
        from pxr import UsdShade

        key = str(material.GetPath())
        if key in self.materials:
            return self.materials[key]
        gltf = {"name": material.GetPrim().GetName()}
        materials = self.doc.json.setdefault("materials", [])
        materials.append(gltf)
        index = self.materials[key] = len(materials) - 1
        surface = material.ComputeSurfaceSource()[0]
        if surface and surface.GetIdAttr().Get() == "UsdPreviewSurface":
            self._preview_surface(gltf, surface)
        prim = material.GetPrim()
        extensions, mips = {}, {}
        for attr in prim.GetAttributes():
            name = attr.GetName()
            if not (name.startswith("baker:") and attr.HasAuthoredValue()):
                continue
            parts = name.split(":")[1:]
            if len(parts) == 4 and parts[1] == "coverageMips":  # baker:<ns>:coverageMips:_<i>:<field>
                mips.setdefault(parts[0], {}).setdefault(parts[2], {})[parts[3]] = attr.Get()
                continue
            _put(extensions, parts, self._json_value(attr.Get(), f"{key}.{name}"))
        for output in material.GetOutputs():
            parts = output.GetBaseName().split(":")
            if parts[0] != "baker" or len(parts) < 3 or parts[-1] == "a":
                continue  # outputs:baker:thickness (the scalar) and :a (alpha) name the same textures again
            info = self._texture_info(output, parts[1], extensions)
            if info is not None:
                slot = _get(extensions, parts[1:])
                _put(extensions, parts[1:], {**slot, **info} if isinstance(slot, dict) else info)
        volume = material.GetInput("baker:thicknessFactor")
        thickness = material.GetOutput("baker:thickness")
        if volume and thickness and thickness.HasConnectedSource():
            source = thickness.GetConnectedSources()[0][0]
            info = self._shader_texture(UsdShade.Shader(source.source.GetPrim()), 0)
            if info is not None:
                # BAKER_thickness' own factor is a double; the material input a float
                baked = extensions.get("thickness") if isinstance(extensions.get("thickness"), dict) else {}
                factor = baked.get("thicknessFactor", float(volume.Get()))
                gltf.setdefault("extensions", {})["KHR_materials_volume"] = {
                    "thicknessTexture": info, "thicknessFactor": factor}
                self.doc.use_extension("KHR_materials_volume")
        for short, entries in sorted(mips.items()):
            if isinstance(extensions.get(short), dict):
                extensions[short]["coverageMips"] = [self._coverage_mips(entries[k], f"{key}.baker:{short}:{k}")
                                                     for k in sorted(entries, key=lambda k: int(k.lstrip("_") or 0))]
        hooks = usd_read_hook("material_readers")
        for short, params in sorted(extensions.items()):
            if not isinstance(params, dict):
                continue
            name = f"BAKER_{short}"
            params = _with_lists(params)
            if name in hooks:
                hooks[name](self.doc, index, params)
            self.doc.set_material_extension(index, name, params)
        return index

    def _preview_surface(self, gltf: dict, surface) -> None:
        def value(name, default):
            i = surface.GetInput(name)
            v = i.Get() if i else None
            return default if v is None else v

        color = [float(c) for c in value("diffuseColor", (1.0, 1.0, 1.0))] + [float(value("opacity", 1.0))]
        pbr = {"baseColorFactor": color, "metallicFactor": float(value("metallic", 1.0)),
               "roughnessFactor": float(value("roughness", 1.0))}
        if pbr["baseColorFactor"] == [1.0, 1.0, 1.0, 1.0]:
            del pbr["baseColorFactor"]
        diffuse = surface.GetInput("diffuseColor")
        if diffuse and diffuse.HasConnectedSource():
            from pxr import UsdShade

            source = diffuse.GetConnectedSources()[0][0]
            shader = UsdShade.Shader(source.source.GetPrim())
            info = self._shader_texture(shader, 0)
            if info is not None:
                pbr["baseColorTexture"] = info
                scale = shader.GetInput("scale")
                if scale and scale.Get() is not None and list(scale.Get()) != [1.0, 1.0, 1.0, 1.0]:
                    pbr["baseColorFactor"] = [float(c) for c in scale.Get()]
        metal_rough = self._input_texture(surface, "roughness")
        if metal_rough is not None:  # glTF: roughness in green, metalness in blue; the factors are the scale's
            shader, info = metal_rough
            scale = shader.GetInput("scale").Get() if shader.GetInput("scale") else None
            if scale is not None:
                pbr["roughnessFactor"], pbr["metallicFactor"] = float(scale[1]), float(scale[2])
            pbr["metallicRoughnessTexture"] = info
        gltf["pbrMetallicRoughness"] = pbr
        emissive = value("emissiveColor", None)
        if emissive is not None and any(emissive):
            gltf["emissiveFactor"] = [float(c) for c in emissive]
        found = self._input_texture(surface, "emissiveColor")
        if found is not None:
            shader, gltf["emissiveTexture"] = found
            scale = shader.GetInput("scale").Get() if shader.GetInput("scale") else None
            if scale is not None:
                gltf["emissiveFactor"] = [float(c) for c in scale][:3]
        found = self._input_texture(surface, "occlusion")
        if found is not None:  # the writer's scale is the strength
            shader, info = found
            scale = shader.GetInput("scale").Get() if shader.GetInput("scale") else None
            gltf["occlusionTexture"] = info if scale is None or float(scale[0]) == 1.0 else \
                {**info, "strength": float(scale[0])}
        found = self._input_texture(surface, "normal")
        if found is not None:  # the writer's scale is 2 x glTF's scale
            shader, info = found
            scale = shader.GetInput("scale").Get() if shader.GetInput("scale") else None
            gltf["normalTexture"] = info if scale is None or float(scale[0]) == 2.0 else \
                {**info, "scale": float(scale[0]) / 2}
        threshold = surface.GetInput("opacityThreshold")
        if threshold and threshold.Get() is not None:
            gltf["alphaMode"], gltf["alphaCutoff"] = "MASK", float(threshold.Get())

    def _input_texture(self, surface, name: str):
        """(UsdUVTexture shader, textureInfo) feeding a ``UsdPreviewSurface`` input, or None."""
        from pxr import UsdShade

        connected = surface.GetInput(name)
        if not (connected and connected.HasConnectedSource()):
            return None
        shader = UsdShade.Shader(connected.GetConnectedSources()[0][0].source.GetPrim())
        info = self._shader_texture(shader, 0)
        return None if info is None else (shader, info)

    def _json_value(self, value, where: str):
        """A custom attribute's value as JSON (the writer's numbers are doubles: the JSON's numbers)."""
        from pxr import Sdf

        if isinstance(value, Sdf.AssetPath):
            return value.path
        if isinstance(value, (bool, int, str)):
            return value
        if isinstance(value, float):
            return _number(value, where, self.path)
        if hasattr(value, "__len__"):
            items = list(value)
            if all(isinstance(v, str) for v in items):
                return items
            return [_number(float(v), where, self.path) for v in items]
        return str(value)

    def _coverage_mips(self, fields: dict, where: str) -> dict:
        """A ``coverageMips`` entry (:mod:`baker.texels.alpha_mips`) from the writer's ``file`` (the KTX2), ``image``
        (its level 0, one of the material's textures), ``alphaCutoff`` and ``levelCount``: the KTX2 becomes an
        accessor again and the coverage is measured on its level 0."""
        from baker.texels.alpha_mips import alpha_coverage, read_coverage_mips

        image, ktx2 = fields.get("image"), fields.get("file")
        if image is None or ktx2 is None:
            raise BakerError(self.path, f"{where}: a coverage mip chain needs its file and image")
        source = self.images.get(image.resolvedPath or image.path)
        texture = next((t for t, tex in enumerate(self.doc.json.get("textures") or []) if tex.get("source") == source),
                       None)
        if source is None or texture is None:
            raise BakerError(self.path, f"{where}: image {image.path} is none of the material's textures")
        data = self._asset_bytes(ktx2.resolvedPath or ktx2.path, f"{where}:file")
        accessor = self.doc.add_accessor(np.frombuffer(data, np.uint8), target=None,
                                         name=f"coverage mips of texture {texture} (KTX2)")
        cutoff = float(fields.get("alphaCutoff", 0.5))
        entry = {"texture": texture, "accessor": accessor, "mimeType": "image/ktx2", "alphaCutoff": cutoff}
        if "levelCount" in fields:
            entry["levelCount"] = int(fields["levelCount"])
        try:
            entry["coverage"] = alpha_coverage(read_coverage_mips(self.doc, entry)[0][..., 3], cutoff)
        except ValueError:  # not a KTX2 chain: `baker validate` says why
            pass
        return entry

    def _texture_info(self, output, short: str, extensions: dict) -> dict | None:
        from pxr import UsdShade

        if not output.HasConnectedSource():
            return None
        source = output.GetConnectedSources()[0][0]
        shader = UsdShade.Shader(source.source.GetPrim())
        params = extensions.get(short) if isinstance(extensions.get(short), dict) else {}
        default = _texcoord(params.get("texCoordPrimvar")) if isinstance(params.get("texCoordPrimvar"), str) else 0
        return self._shader_texture(shader, default)

    def _shader_texture(self, shader, default_texcoord: int) -> dict | None:
        """``{"index": n[, "texCoord": k]}`` for a ``UsdUVTexture`` (its image read once per file)."""
        if not shader or shader.GetIdAttr().Get() != "UsdUVTexture":
            return None
        file_input = shader.GetInput("file")
        asset = file_input.Get() if file_input else None
        if asset is None or not asset.path:
            return None
        resolved = asset.resolvedPath or asset.path
        if resolved not in self.images:
            data = self._asset_bytes(resolved, f"{shader.GetPath()}.inputs:file")
            mime = sniff_mime(data)
            images = self.doc.json.setdefault("images", [])
            images.append({"name": Path(asset.path).stem, "mimeType": mime})
            self.images[resolved] = len(images) - 1
            self.doc.new_images[len(images) - 1] = (data, mime, Path(asset.path).stem)
        sampler = {}
        for field, key in (("wrapS", "wrapS"), ("wrapT", "wrapT")):
            i = shader.GetInput(field)
            sampler[key] = WRAP_CODES.get(str(i.Get()) if i and i.Get() else "repeat", 10497)
        texture = self.doc.add_texture(self.images[resolved], sampler)
        texcoord = default_texcoord
        st = shader.GetInput("st")
        if st and st.HasConnectedSource():
            from pxr import UsdShade

            reader = UsdShade.Shader(st.GetConnectedSources()[0][0].source.GetPrim())
            varname = reader.GetInput("varname").Get() if reader and reader.GetInput("varname") else None
            if isinstance(varname, str) and ST_NAME.fullmatch(varname):
                texcoord = _texcoord(varname)
        info = {"index": texture}
        if texcoord != default_texcoord:
            info["texCoord"] = texcoord
        return info

    def _asset_bytes(self, resolved: str, where: str) -> bytes:
        """An image's bytes: a file inside the stage's folder, or an entry of the ``.usdz`` package."""
        package, _, inner = resolved.partition("[")
        file = Path(package).resolve()
        if not file.is_relative_to(self.folder):
            raise BakerError(self.path, f"{where}: {resolved} lies outside the stage's folder")
        try:
            if inner:
                with zipfile.ZipFile(file) as archive:
                    return archive.read(inner.rstrip("]"))
            return file.read_bytes()
        except (OSError, KeyError, zipfile.BadZipFile) as exc:
            raise BakerError(self.path, f"{where}: cannot read {resolved}: {exc}") from None


def _number(value: float, where: str, path: Path) -> float:
    if not np.isfinite(value):
        raise BakerError(path, f"{where}: {value} is not a finite number")
    return value


def _texcoord(varname: str) -> int:
    match = ST_NAME.fullmatch(varname or "")
    return int(match.group(1) or 0) if match else 0


def _put(tree: dict, parts: list, value) -> None:
    for part in parts[:-1]:
        node = tree.get(part)
        if not isinstance(node, dict):
            node = tree[part] = {}
        tree = node
    tree[parts[-1]] = value


def _get(tree: dict, parts: list):
    for part in parts:
        if not isinstance(tree, dict) or part not in tree:
            return None
        tree = tree[part]
    return tree


def _with_lists(node):
    """Objects whose keys are all ``_<i>`` (the writer's list items) back into lists; ``texCoordPrimvar`` back to
    ``texCoord``, primvar names back to attribute names."""
    if not isinstance(node, dict):
        if isinstance(node, str) and node.startswith("primvars:baker:"):
            return "_" + node[len("primvars:baker:"):].upper()
        return node
    if node and all(LIST_ITEM.fullmatch(k) for k in node):
        return [_with_lists(node[k]) for k in sorted(node, key=lambda k: int(k[1:]))]
    out = {}
    for key, value in node.items():
        if key == "texCoordPrimvar" and isinstance(value, str):
            out["texCoord"] = _texcoord(value)
        else:
            out[key] = _with_lists(value)
    return out


def _values(value, width: int) -> np.ndarray:
    if value is None:
        return np.zeros((0, width) if width > 1 else 0)
    out = np.asarray(value, np.float64)
    return out.reshape(-1, width) if width > 1 else out.reshape(-1)
