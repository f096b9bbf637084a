"""Load any supported input into an :class:`Asset`: a lossless glTF document plus geometry accessors.

glTF/GLB are read as they are (see :mod:`baker.gltf.document`). OBJ, PLY and STL are read with trimesh and USD with
usd-core, then converted to a glTF document, so every bake and writer deals with one representation. Plain OBJs
(:mod:`baker.geometry.obj_files`) and binary triangle PLYs are read directly with numpy, without importing trimesh.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from baker.errors import BakerError
from baker.gltf.compression import decompress
from baker.gltf.document import GltfDocument
from baker.gltf.accessors import MODE_FAN, MODE_STRIP, MODE_TRIANGLES, faces_from_indices, is_derived_fins, to_float

GLTF_SUFFIXES = {".gltf", ".glb"}
TRIMESH_SUFFIXES = {".obj", ".ply", ".stl"}
USD_SUFFIXES = {".usd", ".usda", ".usdc", ".usdz"}
INPUT_SUFFIXES = GLTF_SUFFIXES | TRIMESH_SUFFIXES | USD_SUFFIXES



@dataclass
class PrimitiveGeometry:
    """One triangle primitive in mesh space. ``faces`` index ``positions`` (the primitive's own vertices)."""

    mesh: int
    primitive: int
    positions: np.ndarray  # (n, 3) float64
    faces: np.ndarray  # (m, 3) int64
    normals: np.ndarray | None  # (n, 3) float64, unit, or None when the primitive has none
    texcoords: dict  # set index -> (n, 2) float64 (normalized integers converted to [0, 1])
    material: int | None


@dataclass
class WeldedMesh:
    """Several primitives of one mesh as one welded triangle mesh: one vertex per position, so the split copies of a
    vertex (UV, normal or primitive seams) get one value. ``positions[inverse[offsets[i] + k]]`` is vertex ``k`` of
    ``geometries[i]``."""

    geometries: list  # PrimitiveGeometry per primitive, in the order asked for
    positions: np.ndarray  # (n, 3) welded positions
    inverse: np.ndarray  # (sum of primitive vertex counts,) index into ``positions``
    offsets: np.ndarray  # (len(geometries) + 1,) start of each primitive's vertices in ``inverse``
    faces: np.ndarray  # (m, 3) every primitive's triangles on the welded vertices (degenerate ones kept)


@dataclass
class Asset:
    """A glTF document plus geometry decoded from it. Decoded primitives and welded meshes are cached (as trimesh
    caches ``face_adjacency``), keyed by the accessors they were read from: accessors are never rewritten, so a bake
    that re-indexes a primitive (a new texture layout) gets a new key, and every other bake reuses the arrays. Cached
    arrays are read-only."""

    doc: GltfDocument
    source: Path
    cache: dict = field(default_factory=dict, repr=False, compare=False)
    notes: list = field(default_factory=list, repr=False, compare=False)  # said once on stderr after the bakes

    def note(self, text: str) -> None:
        """Something the user should know about the result (a Khronos field left out, materials skipped); each
        distinct note is printed once when the bakes are done."""
        if text not in self.notes:
            self.notes.append(text)

    @classmethod
    def load(cls, path, allow_outside=None, require_triangles: bool = True) -> "Asset":
        """Read any input; ``require_triangles=False`` also takes a glTF of lines or points only (a groom), which
        ``baker inspect`` lists but no bake can use."""
        path = Path(path)
        suffix = path.suffix.lower()
        if not path.exists():
            raise BakerError(path, "file not found")
        if suffix not in INPUT_SUFFIXES:
            raise BakerError(path, f"unsupported input type '{suffix}' (use one of {', '.join(sorted(INPUT_SUFFIXES))})")
        if suffix in GLTF_SUFFIXES:
            doc = GltfDocument.load(path, allow_outside=allow_outside)
            decompress(doc)  # Draco / meshopt geometry into plain accessors (asset.extras.baker.decompressed)
        elif suffix in USD_SUFFIXES:
            from baker.gltf.usd import read_usd

            doc = _doc_from_trimesh_scene(path, read_usd(path))
        else:
            # an OBJ's MTL files are read once for both readers (a missing one is one warning)
            libraries = None
            if suffix == ".obj":
                from baker.geometry.mtl import read_obj_materials

                libraries = read_obj_materials(path, allow_outside)
            doc = (_read_direct(path, allow_outside, libraries)
                   or _doc_from_trimesh_scene(path, *_load_trimesh(path, allow_outside, libraries)))
        asset = cls(doc=doc, source=path)
        if require_triangles:
            asset.check_has_triangles()
        return asset

    # ------------------------------------------------------------------ geometry
    def meshes(self) -> list:
        return self.doc.json.get("meshes", [])

    def check_has_triangles(self) -> None:
        found = False
        for m, mesh in enumerate(self.meshes()):
            for p, prim in enumerate(mesh.get("primitives", [])):
                if prim.get("mode", MODE_TRIANGLES) in (MODE_TRIANGLES, MODE_STRIP, MODE_FAN):
                    if len(self.primitive(m, p).faces):
                        found = True
        if not self.meshes():
            raise BakerError(self.source, "no meshes in the asset")
        if not found:
            raise BakerError(self.source, "no triangle faces (points or lines only, or empty meshes)")

    def triangle_primitives(self, mesh: int) -> list[int]:
        """Triangle primitives of ``mesh``, without baker's own derived geometry (edge fins)."""
        prims = self.meshes()[mesh].get("primitives", [])
        return [p for p, prim in enumerate(prims)
                if prim.get("mode", MODE_TRIANGLES) in (MODE_TRIANGLES, MODE_STRIP, MODE_FAN)
                and not is_derived_fins(prim)]

    def primitive_key(self, mesh: int, primitive: int) -> tuple:
        """What a decoded primitive depends on: its mode, material and the accessors of its indices, positions,
        normals and texture coordinates."""
        prim = self.meshes()[mesh]["primitives"][primitive]
        read = tuple(sorted((k, v) for k, v in prim.get("attributes", {}).items()
                            if k in ("POSITION", "NORMAL") or k.startswith("TEXCOORD_")))
        return (mesh, primitive, prim.get("mode", MODE_TRIANGLES), prim.get("indices"), prim.get("material"), read)

    def assign_material(self, mesh: int, primitive: int, material: int) -> None:
        """Give a primitive a material. Its decoded geometry does not depend on the material, so the cached arrays
        move to the new key (a 4.4M-triangle PLY is not decoded twice when a bake adds the default material after
        another step read it); welded meshes that included it are dropped and welded again when asked for."""
        old = self.primitive_key(mesh, primitive)
        self.meshes()[mesh]["primitives"][primitive]["material"] = material
        new = self.primitive_key(mesh, primitive)
        decoded = self.cache.pop(("primitive", old), None)
        if decoded is not None:
            self.cache[("primitive", new)] = replace(decoded, material=material)
        for key in [k for k in self.cache if k[0] == "welded" and old in k[1]]:
            del self.cache[key]

    def primitive(self, mesh: int, primitive: int) -> PrimitiveGeometry:
        """Primitive ``primitive`` of ``mesh`` decoded to float64 arrays (cached; see the class docstring)."""
        key = ("primitive", self.primitive_key(mesh, primitive))
        if key not in self.cache:
            self.cache[key] = self._decode_primitive(mesh, primitive)
        return self.cache[key]

    def welded(self, mesh: int, primitives: list[int]) -> WeldedMesh:
        """Primitives ``primitives`` of ``mesh`` welded into one mesh (cached)."""
        key = ("welded", tuple(self.primitive_key(mesh, p) for p in primitives))
        if key not in self.cache:
            from baker.geometry.welding import weld  # numba: not loaded by validate/inspect, which never weld

            geoms = [self.primitive(mesh, p) for p in primitives]
            positions = geoms[0].positions if len(geoms) == 1 else np.concatenate([g.positions for g in geoms])
            welded, inverse = weld(positions)
            offsets = np.cumsum([0] + [len(g.positions) for g in geoms])
            if len(welded) == len(positions):  # nothing merged (a scan, a subdivided mesh): the faces stand as they are
                faces = geoms[0].faces if len(geoms) == 1 else np.concatenate([g.faces + offsets[i]
                                                                                for i, g in enumerate(geoms)])
            else:
                faces = np.concatenate([inverse[g.faces + offsets[i]] for i, g in enumerate(geoms)])
            self.cache[key] = WeldedMesh(geoms, _read_only(welded), _read_only(inverse), _read_only(offsets),
                                         _read_only(faces))
        return self.cache[key]

    def _decode_primitive(self, mesh: int, primitive: int) -> PrimitiveGeometry:
        prim = self.meshes()[mesh]["primitives"][primitive]
        attrs = prim.get("attributes", {})
        if "POSITION" not in attrs:
            raise BakerError(self.source, f"mesh {mesh} primitive {primitive} has no POSITION attribute")
        # to_float honours normalized integers (KHR_mesh_quantization stores positions and normals that way)
        positions = to_float(self.doc, attrs["POSITION"])
        n = len(positions)
        if "indices" in prim:
            stored = self.doc.accessor(prim["indices"], copy=False)  # checked in its own type, then widened once
            if len(stored) and (int(stored.max()) >= n or int(stored.min()) < 0):
                raise BakerError(self.source, f"mesh {mesh} primitive {primitive} has indices out of range (>= {n} vertices)")
            indices = stored.astype(np.int64)
            del stored
        else:
            indices = np.arange(n, dtype=np.int64)
        faces = faces_from_indices(indices, prim.get("mode", MODE_TRIANGLES))
        normals = None
        if "NORMAL" in attrs:
            normals = to_float(self.doc, attrs["NORMAL"])
            normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-20)
        texcoords = {}
        for key, acc in attrs.items():
            if key.startswith("TEXCOORD_"):
                texcoords[int(key[9:])] = to_float(self.doc, acc)
        return PrimitiveGeometry(mesh, primitive, _read_only(positions), _read_only(faces),
                                 None if normals is None else _read_only(normals),
                                 {k: _read_only(v) for k, v in texcoords.items()}, prim.get("material"))

    def mesh_triangles(self, mesh: int) -> tuple[np.ndarray, np.ndarray]:
        """All triangles of ``mesh`` (every triangle primitive) as (vertices, faces) in mesh space."""
        prims = self.triangle_primitives(mesh)
        if len(prims) == 1:  # the cached (read-only) arrays themselves: no copy of a 4.4M-triangle mesh
            g = self.primitive(mesh, prims[0])
            return g.positions, g.faces
        verts, faces, base = [], [], 0
        for p in prims:
            g = self.primitive(mesh, p)
            verts.append(g.positions)
            faces.append(g.faces + base)
            base += len(g.positions)
        if not verts:
            return np.zeros((0, 3)), np.zeros((0, 3), np.int64)
        return np.concatenate(verts), np.concatenate(faces)








def _read_only(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array


def _read_direct(path: Path, allow_outside=None, libraries: tuple | None = None) -> GltfDocument | None:
    """A binary PLY of triangles (:func:`baker.geometry.mesh_files.read_ply_triangles`) or a plain OBJ
    (:func:`baker.geometry.obj_files.read_obj_groups`) read straight into a document without trimesh; None for
    every other file (trimesh reads it). A PLY keeps the positions, normals and UVs it has as float32, no normals
    are computed; an OBJ gives the document the trimesh path gives. ``libraries``: an OBJ's
    :func:`baker.geometry.mtl.read_obj_materials`, when already read."""
    from baker.geometry.mesh_files import check_mesh_file, non_finite_location, read_ply_triangles

    if path.suffix.lower() == ".obj":
        return _read_obj(path, allow_outside, libraries)
    if path.suffix.lower() != ".ply":
        return None
    check_mesh_file(path)  # header counts against the file size, before anything is allocated
    arrays = read_ply_triangles(path)
    if arrays is None:
        return None
    indices = arrays.pop("indices")
    for name, values in arrays.items():
        if not np.isfinite(values).all():  # float32 already: a double beyond float32 became an infinity
            where = non_finite_location(path) or f"{name}: NaN, infinite or beyond float32"
            raise BakerError(path, f"{where} (NaN and infinite coordinates, normals and UVs are refused)")
    doc = GltfDocument.from_triangles(path, path.name, arrays, indices, "baker (converted from ply)")
    assign_materials(doc, {})
    return doc


def _read_obj(path: Path, allow_outside=None, libraries: tuple | None = None) -> GltfDocument | None:
    """An OBJ the direct reader takes, as the document :func:`_doc_from_trimesh_scene` makes of trimesh's reading:
    one mesh and node per usemtl group, accessors laid out as trimesh's glTF exporter lays them out (identical
    arrays share a bufferView or an accessor), vertex normals made unit by :func:`unit_normals`, then as trimesh's
    exporter does. ``libraries``: :func:`baker.geometry.mtl.read_obj_materials` of the file, when already read."""
    from baker.geometry.mtl import read_obj_materials
    from baker.geometry.obj_files import check_finite, read_obj_groups, seamless_vertex_normals, unitize

    materials, _ = libraries or read_obj_materials(path, allow_outside)
    groups = read_obj_groups(path, materials)
    if groups is None:
        return None
    doc = GltfDocument(json={"scene": 0, "scenes": [{"nodes": list(range(len(groups)))}],
                             "asset": {"version": "2.0", "generator": "baker (converted from obj)"}}, path=path)
    views: dict = {}
    accessors: dict = {}

    def add(array, role: str) -> int:
        data = array.tobytes()
        target = 34963 if role == "indices" else 34962
        if (data, target) not in views:
            views[data, target] = doc.add_buffer_view(data, target=target)
        if (data, role) not in accessors:
            blob = {"componentType": 5125 if role == "indices" else 5126}
            if role == "normal":
                blob["count"] = len(array)
            blob["type"] = {"indices": "SCALAR", "uv": "VEC2"}.get(role, "VEC3")
            if role != "indices":
                blob["byteOffset"] = 0
            blob["bufferView"] = views[data, target]
            blob["count"] = len(array)
            flat = array.reshape(len(array), -1)
            blob["max"] = flat.max(axis=0).tolist()
            blob["min"] = flat.min(axis=0).tolist()
            doc.json.setdefault("accessors", []).append(blob)
            accessors[data, role] = len(doc.json["accessors"]) - 1
        return accessors[data, role]

    for group in groups:
        check_finite(path, group)
    computed = {}
    without_normals = [i for i, group in enumerate(groups) if group.normals is None]
    if without_normals:  # the file has no normals: one smooth surface across its material groups and UV seams
        with np.errstate(all="ignore"):
            parts = [(groups[i].positions, groups[i].faces, groups[i].smoothing) for i in without_normals]
            computed = dict(zip(without_normals, seamless_vertex_normals(parts)))
    meshes, by_mesh = [], {}
    for index, group in enumerate(groups):
        normals = group.normals if group.normals is not None else computed[index]
        primitive = {"attributes": {}, "indices": add(group.faces.astype(np.uint32).reshape(-1), "indices"),
                     "mode": MODE_TRIANGLES}
        primitive["attributes"]["POSITION"] = add(group.positions.astype(np.float32), "position")
        mtl = materials.get(group.material)
        if group.texcoords is not None:
            uv = group.texcoords.copy()
            uv[:, 1] = 1.0 - uv[:, 1]  # OBJ's v runs up, glTF's down
            primitive["attributes"]["TEXCOORD_0"] = add(uv.astype(np.float32), "uv")
        # trimesh's exporter unitizes the normals once more (a last-bit change on some)
        primitive["attributes"]["NORMAL"] = add(unitize(unit_normals(normals)).astype(np.float32), "normal")
        by_mesh[len(meshes)] = mtl
        meshes.append({"name": group.name, "extras": {}, "primitives": [primitive]})
    doc.json["meshes"] = meshes
    doc.json["nodes"] = [{"name": m["name"], "mesh": i} for i, m in enumerate(meshes)]
    # the converted GLB's key order, so the output's bytes are the trimesh path's
    layout = ("scene", "scenes", "asset", "accessors", "meshes", "nodes", "buffers", "bufferViews")
    ordered = {key: doc.json.pop(key) for key in layout}
    doc.json.update(ordered)
    assign_materials(doc, by_mesh)
    return doc


class _LibraryResolver:
    """What trimesh's OBJ reader may open: the OBJ's MTL files (already checked under the URI policy), served as
    one text so every material is known by name. Texture images are refused: baker reads them itself
    (:mod:`baker.geometry.mtl`), under the same policy."""

    def __init__(self, libraries: list):
        self.text = b"\n".join(p.read_bytes() for p in libraries)

    def __getitem__(self, name: str) -> bytes:  # trimesh asks for the mtllib this way
        return self.text

    def get(self, name: str) -> bytes:  # ... and for texture images this way
        raise OSError(f"{name}: read by baker.geometry.mtl")


def _load_trimesh(path: Path, allow_outside=None, libraries: tuple | None = None) -> tuple:
    """The mesh file read by trimesh, and the MTL materials by name (empty without ``mtllib``). ``libraries``: an
    OBJ's :func:`baker.geometry.mtl.read_obj_materials`, when already read."""
    import trimesh

    from baker.geometry.mesh_files import check_mesh_file

    check_mesh_file(path)  # header counts against the file size, before trimesh allocates anything
    materials, kwargs = {}, {}
    if path.suffix.lower() == ".obj":
        from baker.geometry.mtl import read_obj_materials

        materials, files = libraries or read_obj_materials(path, allow_outside)
        kwargs["resolver"] = _LibraryResolver(files)
    try:
        # process=False keeps the file's vertices (no merging); OBJ vertices are split where UVs differ
        loaded = trimesh.load(str(path), process=False, **kwargs)
    except Exception as exc:  # trimesh raises many types for malformed files
        raise BakerError(path, f"cannot read mesh: {exc}") from None
    if isinstance(loaded, trimesh.PointCloud) and path.suffix.lower() == ".ply":
        loaded = _mesh_from_ply_strips(path, loaded)
    return loaded, materials


def _mesh_from_ply_strips(path: Path, cloud):
    """A PLY whose surface is a ``tristrips`` element (Stanford scans such as igea.ply): trimesh reads only its
    vertices; build the triangles from the strips. Other point clouds are returned as they are."""
    import trimesh

    from baker.geometry.strips import ply_strip_indices, triangles_from_strips

    elements = cloud.metadata.get("_ply_raw") or {}
    strips = ply_strip_indices(elements)
    if strips is None:
        return cloud
    vertices = np.asarray(cloud.vertices, dtype=np.float64)
    valid = strips[strips >= 0]
    if len(valid) and valid.max() >= len(vertices):
        raise BakerError(path, f"tristrips: vertex index {int(valid.max())} out of range ({len(vertices)} vertices)")
    if (strips < -1).any():
        raise BakerError(path, "tristrips: negative vertex index other than the -1 restart")
    faces = triangles_from_strips(strips)
    kwargs = {}
    data = elements["vertex"]["data"]
    names = data.keys() if isinstance(data, dict) else (data.dtype.names or ())
    if all(name in names for name in ("nx", "ny", "nz")):
        kwargs["vertex_normals"] = np.column_stack([data[name] for name in ("nx", "ny", "nz")])
    return trimesh.Trimesh(vertices=vertices, faces=faces, process=False, **kwargs)


def unit_normals(normals: np.ndarray) -> np.ndarray:
    """Vertex normals as glTF requires them (unit length): the file's, or those trimesh computes when it has none,
    are zero where every adjacent triangle is degenerate (a mesh collapsed to a point or a line), which Khronos'
    validator reports as ACCESSOR_VECTOR3_NON_UNIT. Those get +Z (any unit vector: such a vertex shades nothing);
    the others are renormalised only where float rounding left them off unit length."""
    normals = np.array(normals, np.float64)
    length = np.linalg.norm(normals, axis=1) if len(normals) else np.zeros(0)
    off = np.abs(length - 1.0) > 1e-4
    usable = off & (length > 1e-12)
    normals[usable] /= length[usable, None]
    normals[off & ~usable] = (0.0, 0.0, 1.0)
    return normals


def _doc_from_trimesh_scene(path: Path, loaded, materials: dict | None = None) -> GltfDocument:
    """Convert what trimesh (or our USD reader) loaded into a glTF document; each mesh gets the MTL material
    ``materials`` holds under its trimesh material's name, or the explicit dielectric."""
    import trimesh

    if isinstance(loaded, trimesh.Trimesh):
        scene = trimesh.Scene(loaded)
    elif isinstance(loaded, trimesh.Scene):
        scene = loaded
    else:
        raise BakerError(path, "no triangle faces (the file holds points or lines only)")
    meshes = [g for g in scene.geometry.values() if isinstance(g, trimesh.Trimesh)]
    if not meshes or sum(len(g.faces) for g in meshes) == 0:
        raise BakerError(path, "no triangle faces")
    # trimesh's own material (an MTL's, or a 2x2 grey image it invents without one) is replaced by baker's: its
    # export would re-encode images and write a metallic default. UVs stay
    material_of = {}
    for key, g in scene.geometry.items():
        if getattr(g.visual, "kind", None) == "texture":
            material_of[key] = (materials or {}).get(getattr(g.visual.material, "name", None))
            g.visual.material = trimesh.visual.material.PBRMaterial()
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        glb = Path(d) / "converted.glb"
        # NaN or float32 overflow in the input would warn here: _check_finite refuses such a file first
        _check_finite(path, meshes)
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            computed = {}
            if path.suffix.lower() in (".obj", ".ply"):  # an STL's facets carry their normals: it stays faceted
                from baker.geometry.obj_files import seamless_vertex_normals

                # meshes the file gave no normals: smooth across UV and material seams, as the direct OBJ reader
                without_normals = [i for i, g in enumerate(meshes)
                                   if "vertex_normals" not in getattr(getattr(g, "_cache", None), "cache", {})]
                if without_normals:
                    parts = [(np.asarray(meshes[i].vertices), np.asarray(meshes[i].faces), None)
                             for i in without_normals]
                    computed = dict(zip(without_normals, seamless_vertex_normals(parts)))
            for i, g in enumerate(meshes):
                g.vertex_normals = unit_normals(computed[i] if i in computed else g.vertex_normals)
            glb.write_bytes(trimesh.exchange.gltf.export_glb(scene, include_normals=True))
        try:
            doc = GltfDocument.load(glb)
        except BakerError as exc:  # name the input, not the converted file
            raise BakerError(path, exc.message) from None
    doc.path = path
    # trimesh leaves bufferView.target unset; say which views are vertex data and which are indices
    for mesh in doc.json.get("meshes", []):
        for prim in mesh.get("primitives", []):
            for acc in prim.get("attributes", {}).values():
                _set_view_target(doc, acc, 34962)
            if "indices" in prim:
                _set_view_target(doc, prim["indices"], 34963)
    doc.json["asset"]["generator"] = "baker (converted from " + path.suffix.lower().lstrip(".") + ")"
    for key in ("materials", "textures", "images", "samplers"):
        doc.json.pop(key, None)  # only the (image-less) PBRMaterial placeholders were written
    assign_materials(doc, {m: material_of.get(mesh.get("name")) for m, mesh in enumerate(doc.json.get("meshes", []))})
    return doc


def assign_materials(doc: GltfDocument, mtl_by_mesh: dict) -> None:
    """Give every primitive of a converted document its material: ``mtl_by_mesh`` maps a mesh index to its
    :class:`baker.geometry.mtl.MtlMaterial` (absent or None: the explicit dielectric). A material's textures are
    kept when every primitive using it has TEXCOORD_0."""
    from baker.geometry.mtl import MaterialWriter

    meshes = doc.json.get("meshes", [])
    textured: dict = {}
    for m, mesh in enumerate(meshes):
        mtl = mtl_by_mesh.get(m)
        key = None if mtl is None else mtl.name
        textured[key] = textured.get(key, True) and all("TEXCOORD_0" in prim.get("attributes", {})
                                                          for prim in mesh.get("primitives", []))
    writer = MaterialWriter(doc)
    materials = doc.json["materials"] = []
    index_of: dict = {}
    for m, mesh in enumerate(meshes):
        mtl = mtl_by_mesh.get(m)
        key = None if mtl is None else mtl.name
        if key not in index_of:
            materials.append(writer.material(mtl, textured[key]))
            index_of[key] = len(materials) - 1
        for prim in mesh.get("primitives", []):
            prim["material"] = index_of[key]


def _check_finite(path: Path, meshes: list) -> None:
    """Refuse NaN, infinite (or beyond float32, which glTF stores) positions, normals or UVs read from a mesh file,
    naming the OBJ line / PLY element / STL triangle where it can. Normals are checked only when the file had them
    (trimesh keeps them in its cache; computing them here would cost time)."""
    for m, g in enumerate(meshes):
        named = {"POSITION": g.vertices, "TEXCOORD_0": getattr(g.visual, "uv", None)}
        cache = getattr(getattr(g, "_cache", None), "cache", {})
        named["NORMAL"] = cache.get("vertex_normals")
        for name, values in named.items():
            if values is None:
                continue
            values = np.asarray(values)
            if values.dtype.kind != "f":
                continue
            with np.errstate(invalid="ignore"):
                bad = not np.isfinite(values).all() or bool((np.abs(values) > 3.4028234663852886e38).any())
            if bad:
                from baker.geometry.mesh_files import non_finite_location

                where = non_finite_location(path) or f"mesh {m} {name}: NaN, infinite or beyond float32"
                raise BakerError(path, f"{where} (NaN and infinite coordinates, normals and UVs are refused)")


def _set_view_target(doc: GltfDocument, accessor: int, target: int) -> None:
    view = doc.json["accessors"][accessor].get("bufferView")
    if view is not None:
        doc.json["bufferViews"][view].setdefault("target", target)




