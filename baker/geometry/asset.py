"""An :class:`Asset`: a lossless glTF document plus the geometry decoded from it, cached. :mod:`baker.readers`
makes one from any input file."""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from baker.errors import BakerError, NothingToBake
from baker.gltf.document import GltfDocument
from baker.gltf.accessors import MODE_FAN, MODE_STRIP, MODE_TRIANGLES, faces_from_indices, is_derived_fins, to_float

UNLIT = "KHR_materials_unlit"


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
    # baking from another mesh (``--from``): a baker.texels.transfer.TransferRequest the texel layer traces through
    transfer: object = field(default=None, repr=False, compare=False)

    def note(self, text: str) -> None:
        """Something the user should know about the result (a Khronos field left out, materials skipped); each
        distinct note is printed once when the bakes are done."""
        if text not in self.notes:
            self.notes.append(text)

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

    # ------------------------------------------------------------------ materials
    def is_unlit(self, material: int) -> bool:
        """Whether material ``material`` is ``KHR_materials_unlit`` (no lighting model to bake data for)."""
        materials = self.doc.json.get("materials") or []
        return 0 <= material < len(materials) and UNLIT in (materials[material].get("extensions") or {})

    def material_label(self, material: int) -> str:
        """How a note or error names a material: its index and, when it has one, its name."""
        name = self.doc.json["materials"][material].get("name")
        return f"{material} {name!r}" if name else str(material)

    def material_groups(self) -> dict[int, list[tuple[int, int]]]:
        """Triangle primitives ``(mesh, primitive)`` by material index; primitives without one get a new default
        material (same look).

        ``KHR_materials_unlit`` materials are left out: the material bakes are lighting models (translucency, skin,
        toon, hatching, fur shading) that an unlit material does not evaluate, and the Khronos validator warns
        (MULTIPLE_EXTENSIONS) about any other extension beside KHR_materials_unlit. The asset notes which; when
        every material is unlit the bake has nothing to cover (:class:`baker.errors.NothingToBake`)."""
        groups: dict[int, list] = {}
        default = None
        unlit = set()
        for m in range(len(self.meshes())):
            for p in self.triangle_primitives(m):
                prim = self.meshes()[m]["primitives"][p]
                if "material" in prim and self.is_unlit(prim["material"]):
                    unlit.add(prim["material"])
                    continue
                if "material" not in prim:
                    if default is None:
                        mats = self.doc.json.setdefault("materials", [])
                        mats.append({"name": "baker_default"})  # all-default material == glTF's implicit default
                        default = len(mats) - 1
                    self.assign_material(m, p, default)
                groups.setdefault(prim["material"], []).append((m, p))
        if unlit:
            names = ", ".join(self.material_label(i) for i in sorted(unlit))
            if not groups:
                raise NothingToBake(f"every material is unlit (KHR_materials_unlit): {names}")
            self.note(f"unlit (KHR_materials_unlit) materials get no baked material data: {names}")
        return dict(sorted(groups.items()))


def _read_only(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array
