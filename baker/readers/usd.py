"""USD stages in: ``read_usd`` (any ``UsdGeom.Mesh`` -> a trimesh scene), converted to a glTF document by
:mod:`baker.readers.trimesh_scene`; ``read_groom`` (every ``UsdGeom.BasisCurves`` -> a groom); :mod:`baker.gltf.usd`
writes stages.

Every ``UsdGeom.Mesh`` that would be drawn in a final render is read: instance proxies are included, meshes that
are invisible or whose purpose is ``guide`` or ``proxy`` are skipped (``render`` and ``default`` are kept, so a
proxy/render pair is not read twice). Values are read at the earliest authored time (the default value when the
attribute has no time samples). Polygons are triangulated as fans, ``holeIndices`` and faces with fewer than three
corners are dropped, subdivision is not applied (the control cage is read as is). The world transform is baked
into the points (and normals), so every mesh comes back in stage space; a left-handed mesh, or one under a
mirroring transform, has its winding flipped so front faces stay counter-clockwise. The stage's ``upAxis`` and
``metersPerUnit`` are left as they are: a Z-up stage stays Z-up (glTF viewers will show it lying down).

UVs come from ``primvars:st`` (else ``uv``, ``st0``, ``UVMap``, else the first ``texCoord2f`` primvar), normals
from ``primvars:normals`` or ``normals``. Vertex/varying data stays per point; face-varying, uniform (per face)
or constant data splits points per face corner, and identical corners are merged again, so the result has one UV
and one normal per vertex. USD's ``t`` axis points up the image and glTF's ``v`` down: ``v = 1 - t`` (trimesh
uses USD's convention and applies the flip when :mod:`baker.readers.trimesh_scene` converts the scene to glTF). A mesh without
normals gets them as a USD renderer would draw it: flat per face when ``subdivisionScheme`` is ``none``, smooth
(area-weighted per point) otherwise. USD materials are not read (meshes get glTF's default material).
"""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from baker.errors import BakerError
from baker.gltf.document import GltfDocument
from baker.readers.groom import Groom, concat_curves

UV_NAMES = ("st", "uv", "st0", "UVMap")


def read(path: Path, allow_outside=None, max_memory: int | None = None) -> GltfDocument:
    """A USD stage's meshes as a glTF document (usd-core reads the stage: no memory estimate before it). A stage
    baker wrote comes back with its baked data (:mod:`baker.readers.usd_baked`), any other through trimesh."""
    from baker.readers.trimesh_scene import doc_from_trimesh_scene
    from baker.readers.usd_baked import is_baked_stage, read_baked_stage

    path = Path(path)
    stage = open_stage(path)
    if is_baked_stage(stage):
        doc = read_baked_stage(path, stage, list(renderable_meshes(stage)))
        from baker.checks import Issues
        from baker.gltf.structure import check_data, first_error

        issues = Issues()
        check_data(doc, issues)
        problem = first_error(issues)
        if problem:
            raise BakerError(path, problem)
        return doc
    return doc_from_trimesh_scene(path, read_usd(path, stage))


def renderable_meshes(stage):
    """(UsdGeom.Mesh, local-to-world matrix) of every mesh a final render draws (see the module docstring)."""
    from pxr import Usd, UsdGeom

    time = Usd.TimeCode.EarliestTime()
    xform_cache = UsdGeom.XformCache(time)
    for prim in stage.Traverse(Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)):
        if not prim.IsA(UsdGeom.Mesh):
            continue
        imageable = UsdGeom.Imageable(prim)
        if imageable.ComputeVisibility(time) == UsdGeom.Tokens.invisible:
            continue
        if imageable.ComputePurpose() in (UsdGeom.Tokens.guide, UsdGeom.Tokens.proxy):
            continue
        yield UsdGeom.Mesh(prim), np.array(xform_cache.GetLocalToWorldTransform(prim), dtype=np.float64)


def read_usd(path, stage=None) -> "trimesh.Scene":
    """Read every renderable ``UsdGeom.Mesh`` of a stage into a ``trimesh.Scene`` in world space.

    One ``trimesh.Trimesh`` per mesh prim, named by its prim path (geometry and node). A stage without meshes
    gives an empty scene. Raises :class:`BakerError` when the stage cannot be opened.
    """
    import trimesh
    from pxr import Usd, UsdGeom

    path = Path(path)
    stage = open_stage(path) if stage is None else stage  # the caller may have opened it already
    time = Usd.TimeCode.EarliestTime()
    scene = trimesh.Scene()
    for usd_mesh, matrix in renderable_meshes(stage):
        mesh = _read_mesh(usd_mesh, matrix, time, path)
        if mesh is not None:
            name = str(usd_mesh.GetPath())
            scene.add_geometry(mesh, geom_name=name, node_name=name)
    return scene


def open_stage(path: Path) -> "Usd.Stage":
    """The stage, or :class:`BakerError` with the commentary of pxr's first Tf error (where parsing failed), without
    its C++ source locations."""
    from pxr import Usd

    try:
        stage = Usd.Stage.Open(str(path))
    except Exception as exc:  # pxr raises Tf.ErrorException with a multi-line message
        messages = [str(getattr(a, "commentary", "")).strip() for a in exc.args]
        text = next((m for m in messages if m), str(exc))
        text = re.sub(r"pxrInternal_\w+?__pxrReserved__::", "", " ".join(text.split()))  # pxr's namespace
        raise BakerError(path, f"cannot open USD stage: {text[:300]}") from None
    if stage is None:
        raise BakerError(path, "cannot open USD stage")
    return stage


def _read_mesh(mesh, matrix: np.ndarray, time, path: Path):
    """One mesh prim -> ``trimesh.Trimesh`` (world space) or None when it has no faces; broken topology raises."""
    import trimesh
    from pxr import UsdGeom

    points = _array(mesh.GetPointsAttr().Get(time), np.float64, 3)
    counts = _array(mesh.GetFaceVertexCountsAttr().Get(time), np.int64)
    indices = _array(mesh.GetFaceVertexIndicesAttr().Get(time), np.int64)
    if len(points) == 0 or len(counts) == 0:
        return None
    where = mesh.GetPath()
    if counts.min() < 0 or counts.sum() != len(indices):
        raise BakerError(path, f"mesh {where}: faceVertexCounts add up to {counts.sum()}, "
                               f"but there are {len(indices)} faceVertexIndices")
    if len(indices) and (indices.min() < 0 or indices.max() >= len(points)):
        raise BakerError(path, f"mesh {where}: faceVertexIndices out of range (>= {len(points)} points)")
    holes = _array(mesh.GetHoleIndicesAttr().Get(time), np.int64)

    # fan triangulation, all faces at once: triangle k of face f is (s, s + k, s + k + 1), s = first corner of f
    starts = np.cumsum(counts) - counts
    keep = counts >= 3
    if len(holes):
        keep[holes[(holes >= 0) & (holes < len(counts))]] = False
    tris_per_face = np.where(keep, counts - 2, 0)
    face_of_tri = np.repeat(np.arange(len(counts)), tris_per_face)
    k = np.arange(len(face_of_tri)) - np.repeat(np.cumsum(tris_per_face) - tris_per_face, tris_per_face) + 1
    s = starts[face_of_tri]
    corner_tris = np.stack([s, s + k, s + k + 1], axis=1)  # indices into the face-corner arrays
    if len(corner_tris) == 0:
        return None

    mirrored = np.linalg.det(matrix[:3, :3]) < 0
    left = mesh.GetOrientationAttr().Get(time) == UsdGeom.Tokens.leftHanded
    if mirrored != left:
        corner_tris = corner_tris[:, [0, 2, 1]]

    points = points @ matrix[:3, :3] + matrix[3, :3]  # to world space; USD matrices act on row vectors
    face_of_corner = np.repeat(np.arange(len(counts)), counts)
    uv = _corner_values(_find_uv_primvar(mesh), time, indices, face_of_corner, 2, len(points))
    normals = _read_normals(mesh, time, indices, face_of_corner, len(points))
    if normals is None:
        normals = _default_normals(points, indices, corner_tris, face_of_tri, face_of_corner, len(counts),
                                   mesh.GetSubdivisionSchemeAttr().Get(time) == UsdGeom.Tokens.none)
    else:
        values, is_corner, per_point = normals
        inverse_transpose = np.linalg.inv(matrix[:3, :3]).T  # normals of row-vector points: n' = n A^-T
        normals = (values @ inverse_transpose, is_corner, None if per_point is None else per_point @ inverse_transpose)

    # split points per corner where any attribute is per corner, then merge identical corners again
    per_corner = [a for a in (uv, normals) if a is not None and a[1]]
    if per_corner:
        key = np.concatenate([indices[:, None].astype(np.float64)] + [a[0] for a in per_corner], axis=1)
        _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
        inverse = inverse.reshape(-1)
        order = np.argsort(first, kind="stable")  # number vertices by first use: deterministic, file order
        rank = np.empty_like(order)
        rank[order] = np.arange(len(order))
        vertex_corner = first[order]  # one representative corner per output vertex
        faces = rank[inverse][corner_tris]
        vertex_point = indices[vertex_corner]
    else:
        vertex_corner = None
        faces = indices[corner_tris]
        vertex_point = np.arange(len(points))

    def per_vertex(item):
        if item is None:
            return None
        values, is_corner, per_point = item
        return values[vertex_corner] if is_corner else per_point[vertex_point]

    vertices = points[vertex_point]
    n = per_vertex(normals)
    kwargs = {"vertex_normals": n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-20)}
    t = per_vertex(uv)
    if t is not None:
        # trimesh keeps UVs v-up like USD and flips them into glTF's v-down when it writes the glTF document
        kwargs["visual"] = trimesh.visual.TextureVisuals(uv=t)
    return trimesh.Trimesh(vertices=vertices, faces=faces, process=False, **kwargs)


def _default_normals(points, indices, corner_tris, face_of_tri, face_of_corner, n_faces, flat: bool):
    """Normals as a USD renderer draws a mesh without any: flat per face when ``subdivisionScheme`` is ``none``,
    else smooth (area-weighted over the faces around each point), as the limit surface of a subdivided cage is.
    """
    tri = points[indices[corner_tris]]
    tri_normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])  # length = 2 x area: area weighting
    face_normals = np.zeros((n_faces, 3))
    np.add.at(face_normals, face_of_tri, tri_normals)
    if flat:
        face_normals /= np.maximum(np.linalg.norm(face_normals, axis=1, keepdims=True), 1e-300)
        return face_normals[face_of_corner], True, None
    per_point = np.zeros_like(points)
    np.add.at(per_point, indices, face_normals[face_of_corner])
    return per_point[indices], False, per_point


def _array(value, dtype, width: int | None = None) -> np.ndarray:
    if value is None:
        return np.zeros((0, width) if width else 0, dtype)
    out = np.asarray(value, dtype=dtype)
    return out.reshape(-1, width) if width else out.reshape(-1)


def _find_uv_primvar(mesh):
    from pxr import Sdf, UsdGeom

    two = (Sdf.ValueTypeNames.Float2.type, Sdf.ValueTypeNames.Double2.type)
    primvars = [p for p in UsdGeom.PrimvarsAPI(mesh.GetPrim()).GetPrimvarsWithValues()
                if p.GetTypeName().isArray and p.GetTypeName().scalarType.type in two]
    by_name = {str(p.GetPrimvarName()): p for p in primvars}
    for name in UV_NAMES:
        if name in by_name:
            return by_name[name]
    for p in sorted(primvars, key=lambda p: str(p.GetPrimvarName())):
        if p.GetTypeName().role == Sdf.ValueTypeNames.TexCoord2f.role:
            return p
    return None


def _read_normals(mesh, time, indices, face_of_corner, n_points):
    from pxr import UsdGeom

    primvar = UsdGeom.PrimvarsAPI(mesh.GetPrim()).GetPrimvar("normals")
    if primvar and primvar.HasValue():
        return _corner_values(primvar, time, indices, face_of_corner, 3, n_points)
    attr = mesh.GetNormalsAttr()
    if attr.HasValue():
        return _interpolate(_array(attr.Get(time), np.float64, 3), mesh.GetNormalsInterpolation(), indices,
                            face_of_corner, n_points)
    return None


def _corner_values(primvar, time, indices, face_of_corner, width, n_points):
    """(values, per_corner, per_point): per-corner values, or per-point values when ``per_corner`` is False."""
    if primvar is None:
        return None
    value = primvar.ComputeFlattened(time)  # resolves indexed primvars
    if value is None:
        return None
    return _interpolate(_array(value, np.float64, width), primvar.GetInterpolation(), indices, face_of_corner,
                        n_points)


def _interpolate(values, interpolation, indices, face_of_corner, n_points):
    """Spread values of any interpolation over face corners; data of the wrong length is ignored (None)."""
    from pxr import UsdGeom

    if interpolation in (UsdGeom.Tokens.vertex, UsdGeom.Tokens.varying):
        if len(values) < n_points:
            return None
        return values[indices], False, values
    if interpolation == UsdGeom.Tokens.faceVarying:
        return (values, True, None) if len(values) == len(indices) else None
    if interpolation == UsdGeom.Tokens.uniform:
        return (values[face_of_corner], True, None) if len(values) > face_of_corner.max(initial=-1) else None
    if interpolation == UsdGeom.Tokens.constant and len(values):
        return np.repeat(values[:1], len(indices), axis=0), True, None
    return None


# ====================================================================== writing


def read_groom(path) -> Groom:
    """Every visible ``UsdGeom.BasisCurves`` of the stage as a groom (instance proxies included), points moved by
    the prim's local-to-world transform, widths (constant, uniform, vertex or varying when it has one value per
    point) scaled by the transform's mean scale; every layer the stage uses must lie inside the groom's folder."""
    from pxr import Usd, UsdGeom

    stage = open_stage(path)
    folder = Path(path).resolve().parent
    for layer in stage.GetUsedLayers():  # sublayers and references must stay inside the groom's folder
        real = layer.realPath.split("[", 1)[0]  # a layer inside a .usdz: "file.usdz[inner.usdc]"
        if real and not Path(real).resolve().is_relative_to(folder):
            raise BakerError(path, f"layer {layer.identifier} lies outside the groom's folder")
    parts = []
    for prim in stage.Traverse(Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)):
        if not prim.IsA(UsdGeom.BasisCurves):
            continue
        if UsdGeom.Imageable(prim).ComputeVisibility(Usd.TimeCode.Default()) == UsdGeom.Tokens.invisible:
            continue
        curves = UsdGeom.BasisCurves(prim)
        where = f"{prim.GetPath()}"
        points = curves.GetPointsAttr().Get()
        counts = curves.GetCurveVertexCountsAttr().Get()
        if points is None or counts is None or len(counts) == 0:
            continue
        points = np.asarray(points, np.float64).reshape(-1, 3)
        counts = np.asarray(counts, np.int64).reshape(-1)
        if (counts < 0).any() or int(counts.sum()) != len(points):
            raise BakerError(path, f"{where}: curveVertexCounts sum to {int(counts.sum())} but there are "
                                   f"{len(points)} points")
        matrix = np.asarray(curves.ComputeLocalToWorldTransform(Usd.TimeCode.Default()), np.float64)
        # USD matrices act on row vectors: p' = p M
        points = points @ matrix[:3, :3] + matrix[3, :3]
        scale = abs(float(np.linalg.det(matrix[:3, :3]))) ** (1.0 / 3.0)
        widths = None
        raw = curves.GetWidthsAttr().Get()
        if raw is not None and len(raw):
            raw = np.asarray(raw, np.float64).reshape(-1) * scale
            if len(raw) == len(points):
                widths = raw
            elif len(raw) == len(counts):
                widths = np.repeat(raw, counts)
            elif len(raw) == 1:
                widths = np.full(len(points), raw[0])
        parts.append((points, counts, widths))
    return concat_curves(parts, path)
