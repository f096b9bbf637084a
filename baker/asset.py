"""Load any supported input into an :class:`Asset`: a lossless glTF document plus geometry accessors.

glTF/GLB are read as they are (see :mod:`baker.io.gltf`). OBJ, PLY and STL are read with trimesh and USD with
usd-core, then converted to a glTF document, so every bake and writer deals with one representation.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .errors import BakerError
from .io.gltf import GltfDocument

GLTF_SUFFIXES = {".gltf", ".glb"}
TRIMESH_SUFFIXES = {".obj", ".ply", ".stl"}
USD_SUFFIXES = {".usd", ".usda", ".usdc", ".usdz"}
INPUT_SUFFIXES = GLTF_SUFFIXES | TRIMESH_SUFFIXES | USD_SUFFIXES

MODE_TRIANGLES, MODE_STRIP, MODE_FAN = 4, 5, 6


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
class Asset:
    doc: GltfDocument
    source: Path

    @classmethod
    def load(cls, path) -> "Asset":
        path = Path(path)
        suffix = path.suffix.lower()
        if not path.exists():
            raise BakerError(path, "file not found")
        if suffix not in INPUT_SUFFIXES:
            raise BakerError(path, f"unsupported input type '{suffix}' (use one of {', '.join(sorted(INPUT_SUFFIXES))})")
        if suffix in GLTF_SUFFIXES:
            doc = GltfDocument.load(path)
        elif suffix in USD_SUFFIXES:
            from .io.usd import read_usd

            doc = _doc_from_trimesh_scene(path, read_usd(path))
        else:
            doc = _doc_from_trimesh_scene(path, _load_trimesh(path))
        asset = cls(doc=doc, source=path)
        asset.check_supported()
        asset.check_has_triangles()
        return asset

    # compressed geometry keeps its vertices inside the extension: reading the accessors would give zeros
    UNSUPPORTED = {"KHR_draco_mesh_compression": "Draco-compressed", "EXT_meshopt_compression": "meshopt-compressed"}

    def check_supported(self) -> None:
        for name, what in self.UNSUPPORTED.items():
            if name in self.doc.json.get("extensionsUsed", []):
                raise BakerError(self.source, f"{what} geometry ({name}) is not supported: decompress it first "
                                              "(e.g. gltf-transform copy --decompress) and bake the result")

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
                and not _derived_fins(prim)]

    def primitive(self, mesh: int, primitive: int) -> PrimitiveGeometry:
        prim = self.meshes()[mesh]["primitives"][primitive]
        attrs = prim.get("attributes", {})
        if "POSITION" not in attrs:
            raise BakerError(self.source, f"mesh {mesh} primitive {primitive} has no POSITION attribute")
        # _to_float honours normalized integers (KHR_mesh_quantization stores positions and normals that way)
        positions = _to_float(self.doc, attrs["POSITION"])
        n = len(positions)
        if "indices" in prim:
            indices = self.doc.accessor(prim["indices"]).astype(np.int64)
        else:
            indices = np.arange(n, dtype=np.int64)
        if len(indices) and (indices.max() >= n or indices.min() < 0):
            raise BakerError(self.source, f"mesh {mesh} primitive {primitive} has indices out of range (>= {n} vertices)")
        faces = _faces_from_indices(indices, prim.get("mode", MODE_TRIANGLES))
        normals = None
        if "NORMAL" in attrs:
            normals = _to_float(self.doc, attrs["NORMAL"])
            normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-20)
        texcoords = {}
        for key, acc in attrs.items():
            if key.startswith("TEXCOORD_"):
                texcoords[int(key[9:])] = _to_float(self.doc, acc)
        return PrimitiveGeometry(mesh, primitive, positions, faces, normals, texcoords, prim.get("material"))

    def mesh_triangles(self, mesh: int) -> tuple[np.ndarray, np.ndarray]:
        """All triangles of ``mesh`` (every triangle primitive) as (vertices, faces) in mesh space."""
        verts, faces, base = [], [], 0
        for p in self.triangle_primitives(mesh):
            g = self.primitive(mesh, p)
            verts.append(g.positions)
            faces.append(g.faces + base)
            base += len(g.positions)
        if not verts:
            return np.zeros((0, 3)), np.zeros((0, 3), np.int64)
        return np.concatenate(verts), np.concatenate(faces)


def _derived_fins(prim: dict) -> bool:
    """True for fin primitives baker derives from a mesh (BAKER_edges / BAKER_fur ``finsOf``): zero-area quads that
    bakes must not sample."""
    exts = prim.get("extensions") or {}
    return any("finsOf" in (exts.get(name) or {}) for name in ("BAKER_edges", "BAKER_fur"))


def _to_float(doc: GltfDocument, accessor: int) -> np.ndarray:
    data = doc.accessor(accessor)
    acc = doc.json["accessors"][accessor]
    if acc.get("normalized") and data.dtype.kind in "iu":
        info = np.iinfo(data.dtype)
        out = data.astype(np.float64) / info.max
        return np.maximum(out, -1.0) if data.dtype.kind == "i" else out
    return data.astype(np.float64)


def _faces_from_indices(indices: np.ndarray, mode: int) -> np.ndarray:
    """Triangles of a primitive in glTF's order (spec 3.7.2.1), degenerate ones included: per-triangle data such
    as EXT_mesh_primitive_edge_visibility counts them, and they carry no area for the bakes that sample surfaces."""
    n = len(indices)
    if mode == MODE_TRIANGLES:
        return indices[: n // 3 * 3].reshape(-1, 3)
    if n < 3 or mode not in (MODE_STRIP, MODE_FAN):
        return np.zeros((0, 3), np.int64)
    k = np.arange(n - 2)
    if mode == MODE_STRIP:
        even = (k % 2) == 0
        a = indices[k]
        b = np.where(even, indices[k + 1], indices[k + 2])
        c = np.where(even, indices[k + 2], indices[k + 1])
        return np.stack([a, b, c], axis=1)
    # fan: triangle i is (v[i+1], v[i+2], v[0])
    return np.stack([indices[k + 1], indices[k + 2], np.full_like(k, indices[0])], axis=1)


def _load_trimesh(path: Path):
    import trimesh

    try:
        # process=False keeps the file's vertices (no merging); OBJ vertices are split where UVs differ
        loaded = trimesh.load(str(path), process=False)
    except Exception as exc:  # trimesh raises many types for malformed files
        raise BakerError(path, f"cannot read mesh: {exc}") from None
    if path.suffix.lower() == ".obj" and b"mtllib" not in path.read_bytes():
        # without a .mtl trimesh invents a material with a 2x2 grey image; keep the glTF default material instead
        geoms = [loaded] if isinstance(loaded, trimesh.Trimesh) else list(getattr(loaded, "geometry", {}).values())
        for g in geoms:
            if getattr(g.visual, "kind", None) == "texture":
                g.visual.material = trimesh.visual.material.PBRMaterial()
    return loaded


def _doc_from_trimesh_scene(path: Path, loaded) -> GltfDocument:
    """Convert what trimesh (or our USD reader) loaded into a glTF document."""
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
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        glb = Path(d) / "converted.glb"
        # trimesh writes vertex normals only when it has them; keep what the file had
        glb.write_bytes(trimesh.exchange.gltf.export_glb(scene, include_normals=True))
        doc = GltfDocument.load(glb)
    doc.path = path
    # trimesh leaves bufferView.target unset; say which views are vertex data and which are indices
    for mesh in doc.json.get("meshes", []):
        for prim in mesh.get("primitives", []):
            for acc in prim.get("attributes", {}).values():
                _set_view_target(doc, acc, 34962)
            if "indices" in prim:
                _set_view_target(doc, prim["indices"], 34963)
    doc.json["asset"]["generator"] = "baker (converted from " + path.suffix.lower().lstrip(".") + ")"
    return doc


def _set_view_target(doc: GltfDocument, accessor: int, target: int) -> None:
    view = doc.json["accessors"][accessor].get("bufferView")
    if view is not None:
        doc.json["bufferViews"][view].setdefault("target", target)


def weld(positions: np.ndarray, tolerance: float = 1e-6) -> tuple[np.ndarray, np.ndarray]:
    """Merge vertices closer than ``tolerance`` x the bounding-box diagonal.

    Returns (welded positions, inverse) with ``welded[inverse] ~= positions``. Deterministic: welded vertices are
    ordered by first occurrence.
    """
    if len(positions) == 0:
        return positions.copy(), np.zeros(0, np.int64)
    diag = float(np.linalg.norm(positions.max(0) - positions.min(0))) or 1.0
    keys = np.round(positions / (diag * tolerance)).astype(np.int64)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    # renumber by first occurrence so the order does not depend on coordinates' sort order
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    return positions[first[order]], rank[inverse]


def vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Area-weighted vertex normals (unit length; zero-area neighbourhoods get +Z)."""
    fn = np.cross(vertices[faces[:, 1]] - vertices[faces[:, 0]], vertices[faces[:, 2]] - vertices[faces[:, 0]])
    out = np.zeros_like(vertices)
    for k in range(3):
        np.add.at(out, faces[:, k], fn)
    length = np.linalg.norm(out, axis=1, keepdims=True)
    out = np.where(length > 1e-30, out / np.maximum(length, 1e-30), np.array([0.0, 0.0, 1.0]))
    return out
