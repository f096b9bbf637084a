"""``BAKER_edges`` and ``EXT_mesh_primitive_edge_visibility``: per-primitive edge data -> glTF JSON/accessors, + USD.

Where the data goes (see ``schemas/BAKER_edges/README.md``):
- ``EXT_mesh_primitive_edge_visibility`` on the triangle primitive (Bentley's vendor extension, Khronos registry):
  ``visibility`` (2 bits per triangle edge, LSB first, ceil(6N/8) bytes) and ``silhouetteMates``;
- ``BAKER_edges`` on the primitive: accessors for the edge list, flags, dihedral angles and the wireframe mask
  (opposite vertices and dihedral angles only with the ``opposite_vertices`` and ``dihedral_angles`` options: the
  triangles, positions and the edge list give them), the
  settings, per-class counts, and the index of the optional fin primitive;
- the vertex attribute ``_OUTLINE_NORMAL`` (FLOAT VEC3): one averaged unit normal per welded position, zero at
  positions on a boundary or non-manifold edge (the shell outline is pinned to open boundaries);
- optionally a fin primitive in the same mesh (4 vertices, 2 degenerate triangles per edge) whose ``BAKER_edges``
  names its source primitive; a viewer that ignores the extensions rasterizes nothing from it. Its attributes
  ``_FIN_V0.._FIN_V3`` (VEC3), ``_FIN_CORNER`` and ``_FIN_FLAGS`` (scalars) are laid out as
  :mod:`baker.gltf.vertex_attributes` says (``blender``: all FLOAT VEC3, scalars in x; ``native``: SCALAR).
"""
from __future__ import annotations

import math

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from baker.geometry import edge_codes
from baker.gltf.document import TARGET_ELEMENT_ARRAY_BUFFER, GltfDocument
from baker.gltf.derived import copy_skinning, match_morph_targets
from baker.gltf.vertex_attributes import add_vertex_attribute, unpadded

if TYPE_CHECKING:  # the writers take the kernel's results; validation must not import the numba kernels
    from baker.geometry.edges import PrimitiveEdges

NAME = "BAKER_edges"
EXT_VISIBILITY = "EXT_mesh_primitive_edge_visibility"
# other extensions this module's ``check`` validates, with their accessor-valued properties (for baker validate)
ALSO_CHECKS = {EXT_VISIBILITY: ("visibility", "silhouetteMates")}
# primitive extension -> its accessors of vertex indices (the maximum of their type: no vertex), renumbered when a
# bake splits the vertices (baker.registry.vertex_index_members)
VERTEX_INDEX_MEMBERS = {NAME: ("edges", "oppositeVertices"), EXT_VISIBILITY: ("silhouetteMates",)}
OUTLINE_NORMAL = "_OUTLINE_NORMAL"
FIN_ATTRIBUTES = ("_FIN_V0", "_FIN_V1", "_FIN_V2", "_FIN_V3", "_FIN_CORNER", "_FIN_FLAGS")
# name -> the data's width (baker.registry); the fur fins share the _FIN_ names
VERTEX_ATTRIBUTES = {OUTLINE_NORMAL: 3, **dict(zip(FIN_ATTRIBUTES, (3, 3, 3, 3, 1, 1)))}
# extension name -> its accessor members: the USD writer keeps them on the mesh prim (baker.registry)
USD_PRIMITIVE_ACCESSORS = {NAME: ("edges", "oppositeVertices", "flags", "dihedralAngles", "wireframeMask"),
                           EXT_VISIBILITY: ("visibility", "silhouetteMates")}
FLOAT, UBYTE, USHORT, UINT = 5126, 5121, 5123, 5125
INDEX_MAX = {UBYTE: 0xFF, USHORT: 0xFFFF, UINT: 0xFFFFFFFF}


def index_dtype(vertex_count: int):
    """Smallest unsigned type whose maximum (the 'no vertex' sentinel) is not a vertex index."""
    return np.uint16 if vertex_count < 0xFFFF else np.uint32


def write_edge_visibility(doc: GltfDocument, mesh: int, primitive: int, codes: np.ndarray,
                          mates: np.ndarray, vertex_count: int) -> dict | None:
    """Write ``EXT_mesh_primitive_edge_visibility``; None (nothing written) when every code is 0, which the
    extension forbids."""
    if not np.any(codes):
        return None
    packed = edge_codes.pack_visibility(codes)
    ext = {"visibility": doc.add_accessor(packed, target=None, name="edge visibility")}
    if len(mates):
        ext["silhouetteMates"] = doc.add_accessor(mates.astype(index_dtype(vertex_count)), target=None,
                                                  name="silhouette mates")
    return doc.set_primitive_extension(mesh, primitive, EXT_VISIBILITY, ext)


def write_outline_normals(doc: GltfDocument, mesh: int, primitive: int, normals: np.ndarray) -> int:
    attributes = doc.json["meshes"][mesh]["primitives"][primitive]["attributes"]
    return add_vertex_attribute(doc, mesh, attributes, OUTLINE_NORMAL, normals, min_max=True,
                                leave_out="--edges-outline-normals false")


def write_fin_primitive(doc: GltfDocument, mesh: int, primitive: int, pe: PrimitiveEdges) -> int:
    """Append the fin primitive of ``primitive``: per edge a degenerate quad (v0, v1, v1, v0) whose vertices all
    carry the edge's four positions, their corner number (0-3) and the edge flags. Returns its index."""
    prims = doc.json["meshes"][mesh]["primitives"]
    n = len(pe.edges)
    corners = pe.fin_corners.astype(np.float32)  # (n, 4, 3)
    corner = np.tile(np.arange(4, dtype=np.float32), n)
    at_v1 = np.array([0, 1, 1, 0])
    position = corners[np.repeat(np.arange(n), 4), np.tile(at_v1, n)]
    quad = np.array([0, 1, 2, 0, 2, 3], np.int64)
    indices = (np.arange(n)[:, None] * 4 + quad[None, :]).reshape(-1)
    attributes = {"POSITION": doc.add_accessor(position, min_max=True)}
    columns = [np.repeat(corners[:, j], 4, axis=0) for j in range(4)] + [corner, np.repeat(pe.flags.astype(np.float32), 4)]
    for name, values in zip(FIN_ATTRIBUTES, columns):
        add_vertex_attribute(doc, mesh, attributes, name, values, leave_out="--edges-fins false")
    fin = {
        "attributes": attributes,
        "indices": doc.add_accessor(indices.astype(np.uint16 if 4 * n <= 0xFFFF else np.uint32),
                                    target=TARGET_ELEMENT_ARRAY_BUFFER),
        "mode": 4,
        "extensions": {NAME: {"finsOf": primitive}},
    }
    # no material: fins are drawn by baker_edges.glsl with the source primitive's material (found through finsOf);
    # copying it would bind its textures to a primitive without their TEXCOORD sets (invalid glTF)
    match_morph_targets(doc, mesh, fin, len(position))
    copy_skinning(doc, mesh, primitive, fin, pe.edges[np.repeat(np.arange(n), 4), np.tile(at_v1, n)])
    prims.append(fin)
    return len(prims) - 1


def write_primitive_edges(doc: GltfDocument, mesh: int, primitive: int, pe: PrimitiveEdges, *, options,
                          vertex_count: int, fins: int | None, outline: bool,
                          visibility: bool) -> dict:
    """Write ``BAKER_edges`` on a triangle primitive (accessors only when ``options.edge_list``)."""
    counts = {"edges": int(len(pe.flags))}
    for bit, name in edge_codes.FLAG_NAMES.items():
        counts[name] = int(np.count_nonzero(pe.flags & bit))
    ext = {
        "creaseAngle": math.radians(options.crease_angle),
        "planarAngle": math.radians(options.planar_angle),
        "weldTolerance": float(options.weld_tolerance),
        "counts": counts,
        "edgeVisibility": bool(visibility),
    }
    if options.edge_list:
        dtype = index_dtype(vertex_count)
        ext["edges"] = doc.add_accessor(pe.edges.astype(dtype), target=None, name="edges v0 v1")
        if options.opposite_vertices:  # derivable from the triangles and the edge list: only on request
            opposite = np.where(pe.opposite < 0, np.iinfo(dtype).max, pe.opposite)
            ext["oppositeVertices"] = doc.add_accessor(opposite.astype(dtype), target=None, name="edges v2 v3")
        ext["flags"] = doc.add_accessor(pe.flags.astype(np.uint16), target=None, name="edge flags")
        if options.dihedral_angles:  # derivable from the positions and the triangles: only on request
            ext["dihedralAngles"] = doc.add_accessor(pe.angle.astype(np.float32), target=None, min_max=True,
                                                     name="edge dihedral angles")
    if options.wireframe != "off":
        ext["wireframeMask"] = doc.add_accessor(pe.wireframe_mask.astype(np.uint8), target=None,
                                                name="wireframe edge mask")
        ext["wireframeHides"] = options.wireframe
    if outline:
        ext["outlineNormal"] = OUTLINE_NORMAL
    if fins is not None:
        ext["fins"] = fins
    return doc.set_primitive_extension(mesh, primitive, NAME, ext)


# =========================================================================================================== USD
def usd_basis_curves(stage, path: str, doc: GltfDocument, mesh: int, primitive: int,
                     mask: int = edge_codes.CREASE | edge_codes.BOUNDARY | edge_codes.MATERIAL
                     | edge_codes.NON_MANIFOLD):
    """Define a linear ``UsdGeom.BasisCurves`` at ``path`` holding the primitive's edges whose flags match ``mask``
    (crease, boundary, material, non-manifold by default), one 2-point curve per edge, with the uniform primvars
    ``baker:edgeFlags`` (int) and ``baker:dihedralAngle`` (float, radians). Returns the prim, or None when the
    primitive has no BAKER_edges edge list or no such edge."""
    from pxr import Gf, UsdGeom, Vt

    prim = doc.json["meshes"][mesh]["primitives"][primitive]
    ext = (prim.get("extensions") or {}).get(NAME) or {}
    if "edges" not in ext or "flags" not in ext:
        return None
    positions = doc.accessor(prim["attributes"]["POSITION"]).astype(np.float32)
    edges = doc.accessor(ext["edges"]).astype(np.int64).reshape(-1, 2)
    flags = doc.accessor(ext["flags"]).astype(np.int64)
    if "dihedralAngles" in ext:
        angles = doc.accessor(ext["dihedralAngles"]).astype(np.float32)
    else:  # not stored by default: the triangles give them
        from baker.geometry.edges import dihedral_angles_of

        faces = doc.accessor(prim["indices"]).astype(np.int64).reshape(-1, 3) if "indices" in prim else \
            np.arange(len(positions)).reshape(-1, 3)
        angles = dihedral_angles_of(positions, faces, edges).astype(np.float32)
    keep = (flags & mask) != 0
    if not keep.any():
        return None
    points = positions[edges[keep]].reshape(-1, 3)
    curves = UsdGeom.BasisCurves.Define(stage, path)
    curves.CreateTypeAttr(UsdGeom.Tokens.linear)
    curves.CreateCurveVertexCountsAttr(Vt.IntArray([2] * int(keep.sum())))
    curves.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(np.ascontiguousarray(points)))
    curves.CreateWidthsAttr(Vt.FloatArray([0.0]))  # 0: the renderer's hairline
    curves.SetWidthsInterpolation(UsdGeom.Tokens.constant)
    lo, hi = points.min(0), points.max(0)
    curves.CreateExtentAttr(Vt.Vec3fArray([Gf.Vec3f(*map(float, lo)), Gf.Vec3f(*map(float, hi))]))
    primvars = UsdGeom.PrimvarsAPI(curves.GetPrim())
    from pxr import Sdf

    primvars.CreatePrimvar("baker:edgeFlags", Sdf.ValueTypeNames.IntArray, UsdGeom.Tokens.uniform).Set(
        Vt.IntArray.FromNumpy(np.ascontiguousarray(flags[keep].astype(np.int32))))
    primvars.CreatePrimvar("baker:dihedralAngle", Sdf.ValueTypeNames.FloatArray, UsdGeom.Tokens.uniform).Set(
        Vt.FloatArray.FromNumpy(np.ascontiguousarray(angles[keep])))
    return curves


# =========================================================================================================== validation
def _accessor_info(gltf, index):
    accessors = gltf.get("accessors") or []
    if not (isinstance(index, int) and not isinstance(index, bool) and 0 <= index < len(accessors)):
        return None
    return accessors[index]


def _triangle_count(doc: GltfDocument, prim: dict) -> int | None:
    attrs = prim.get("attributes") or {}
    acc = _accessor_info(doc.json, attrs.get("POSITION"))
    if acc is None:
        return None
    if "indices" in prim:
        indices = doc.accessor(prim["indices"]).astype(np.int64)
    else:
        indices = np.arange(acc.get("count", 0))
    mode = prim.get("mode", 4)
    # EXT_mesh_primitive_edge_visibility counts every triangle of the primitive (degenerate ones too)
    if mode == 4:
        return len(indices) // 3
    return max(len(indices) - 2, 0)


def _want(issues, code, cond, message, ptr) -> bool:
    if not cond:
        issues.error(code, message, ptr)
    return cond


def check_edge_visibility(doc: GltfDocument, mesh: int, primitive: int, issues) -> None:
    """The rules of EXT_mesh_primitive_edge_visibility that baker writes: an UNSIGNED_BYTE SCALAR ``visibility`` of
    exactly ceil(6N/8) bytes with zero padding bits and at least one non-zero value; ``silhouetteMates`` present if
    and only if some edge is 1, one valid vertex index per 1; every edge encoded as 2 at most once."""
    from baker.checks import pointer

    gltf = doc.json
    prim = gltf["meshes"][mesh]["primitives"][primitive]
    ext = prim["extensions"][EXT_VISIBILITY]
    ptr = pointer("meshes", mesh, "primitives", primitive, "extensions", EXT_VISIBILITY)
    if not isinstance(ext, dict):
        issues.error("EDGE_VISIBILITY_INVALID", "the extension must be an object", ptr)
        return
    if prim.get("mode", 4) not in (4, 5, 6):
        issues.error("EDGE_VISIBILITY_MODE", "the extension applies to triangle primitives only", ptr)
        return
    if "visibility" not in ext:
        if "lineStrings" not in ext:
            issues.error("EDGE_VISIBILITY_EMPTY", "neither visibility nor lineStrings is defined", ptr)
        return
    acc = _accessor_info(gltf, ext["visibility"])
    if not _want(issues, "EDGE_VISIBILITY_ACCESSOR", acc is not None, "visibility is not an accessor index",
                 ptr + "/visibility"):
        return
    acc_ptr = pointer("accessors", ext["visibility"])
    if not _want(issues, "EDGE_VISIBILITY_ACCESSOR_FORMAT",
                 acc.get("componentType") == UBYTE and acc.get("type") == "SCALAR" and not acc.get("normalized"),
                 f"visibility must be UNSIGNED_BYTE SCALAR, not {acc.get('componentType')} {acc.get('type')}",
                 acc_ptr):
        return
    n_tris = _triangle_count(doc, prim)
    if n_tris is None:
        return
    expected = (6 * n_tris + 7) // 8
    if not _want(issues, "EDGE_VISIBILITY_BIT_COUNT", acc.get("count") == expected,
                 f"visibility has {acc.get('count')} bytes; {n_tris} triangles need ceil(6 x {n_tris} / 8) = "
                 f"{expected}", acc_ptr):
        return
    data = doc.accessor(ext["visibility"]).astype(np.uint8)
    used_bits = 6 * n_tris
    if used_bits % 8:
        last = int(data[-1]) >> (used_bits % 8)
        _want(issues, "EDGE_VISIBILITY_PADDING", last == 0, "unused bits of the last visibility byte are not zero",
              acc_ptr)
    codes = edge_codes.unpack_visibility(data, n_tris)
    _want(issues, "EDGE_VISIBILITY_ALL_HIDDEN", bool(codes.any()), "every edge is hidden (0): the bitfield must "
          "contain at least one non-zero value", acc_ptr)
    n_sil = int(np.count_nonzero(codes == edge_codes.VIS_SILHOUETTE))
    mates = ext.get("silhouetteMates")
    if n_sil == 0:
        _want(issues, "EDGE_VISIBILITY_MATES_UNEXPECTED", mates is None,
              "silhouetteMates is defined but no edge is a silhouette (1)", ptr + "/silhouetteMates")
    elif _want(issues, "EDGE_VISIBILITY_MATES_MISSING", mates is not None,
               f"{n_sil} silhouette edges (1) but no silhouetteMates", ptr):
        macc = _accessor_info(gltf, mates)
        mptr = pointer("accessors", mates) if macc is not None else ptr + "/silhouetteMates"
        if (_want(issues, "EDGE_VISIBILITY_ACCESSOR", macc is not None, "silhouetteMates is not an accessor index",
                  mptr)
                and _want(issues, "EDGE_VISIBILITY_ACCESSOR_FORMAT",
                          macc.get("componentType") in (UBYTE, USHORT, UINT) and macc.get("type") == "SCALAR",
                          "silhouetteMates must be an unsigned integer SCALAR accessor", mptr)
                and _want(issues, "EDGE_VISIBILITY_MATES_COUNT", macc.get("count") == n_sil,
                          f"silhouetteMates has {macc.get('count')} entries for {n_sil} silhouette edges", mptr)):
            values = doc.accessor(mates).astype(np.int64)
            vertex_count = gltf["accessors"][prim["attributes"]["POSITION"]]["count"]
            _want(issues, "EDGE_VISIBILITY_MATES_OOB", not len(values) or int(values.max()) < vertex_count,
                  f"silhouetteMates indices must be < the vertex count {vertex_count}", mptr)
    # "a hard edge MUST be encoded as 2 exactly once": edges identified by their welded endpoint positions
    positions = doc.accessor(prim["attributes"]["POSITION"]).astype(np.float64)
    indices = doc.accessor(prim["indices"]).astype(np.int64) if "indices" in prim else np.arange(len(positions))
    faces = all_triangles(indices, prim.get("mode", 4))
    if len(faces) != n_tris:
        return
    tolerance = ((prim.get("extensions") or {}).get(NAME) or {}).get("weldTolerance", 1e-6)
    _, inverse = edge_codes.weld_positions(positions, float(tolerance) if isinstance(tolerance, (int, float)) else 1e-6)
    w = inverse[faces]
    a = w.reshape(-1)
    b = w[:, [1, 2, 0]].reshape(-1)
    key = np.minimum(a, b) * (int(inverse.max(initial=0)) + 1) + np.maximum(a, b)
    flat = codes.reshape(-1)
    for value, name in ((edge_codes.VIS_HARD, "hard (2)"), (edge_codes.VIS_SILHOUETTE, "silhouette (1)")):
        k = key[flat == value]
        dup = len(k) - len(np.unique(k))
        _want(issues, "EDGE_VISIBILITY_REPEATED", dup == 0, f"{dup} edges are encoded as {name} more than once",
              acc_ptr)
    hard_keys = np.unique(key[flat == edge_codes.VIS_HARD])
    repeated = np.unique(key[flat == edge_codes.VIS_REPEATED_HARD])
    orphans = int(np.count_nonzero(~np.isin(repeated, hard_keys)))
    _want(issues, "EDGE_VISIBILITY_REPEATED_WITHOUT_HARD", orphans == 0,
          f"{orphans} edges are encoded as repeated hard (3) but never as hard (2)", acc_ptr)


def all_triangles(indices: np.ndarray, mode: int) -> np.ndarray:
    """Every triangle of a primitive in glTF's order and vertex order (section 3.7.2.1), degenerate ones included:
    the order EXT_mesh_primitive_edge_visibility's bitfield follows. Strips: (i, i+1, i+2) for even i and
    (i, i+2, i+1) for odd i; fans: (i+1, i+2, 0)."""
    indices = np.asarray(indices, np.int64)
    if mode == 4:
        return indices[: len(indices) // 3 * 3].reshape(-1, 3)
    if len(indices) < 3:
        return np.zeros((0, 3), np.int64)
    k = np.arange(len(indices) - 2)
    if mode == 5:
        even = (k % 2) == 0
        return np.stack([indices[k], np.where(even, indices[k + 1], indices[k + 2]),
                         np.where(even, indices[k + 2], indices[k + 1])], axis=1)
    return np.stack([indices[k + 1], indices[k + 2], np.full_like(k, indices[0])], axis=1)


def _check_edge_accessor(doc, ext, key, ptr, issues, *, types, component_types, count, code="BAKER_EDGES"):
    from baker.checks import pointer

    if key not in ext:
        return None
    acc = _accessor_info(doc.json, ext[key])
    if acc is None:
        issues.error(f"{code}_ACCESSOR", f"{key} is not an accessor index", ptr + "/" + key)
        return None
    acc_ptr = pointer("accessors", ext[key])
    if acc.get("type") not in types or acc.get("componentType") not in component_types or acc.get("normalized"):
        issues.error(f"{code}_ACCESSOR_FORMAT", f"{key} must be {' or '.join(types)} of component type "
                     f"{' or '.join(map(str, component_types))}, not {acc.get('componentType')} {acc.get('type')}",
                     acc_ptr)
        return None
    if count is not None and acc.get("count") != count:
        issues.error(f"{code}_ACCESSOR_COUNT", f"{key} has {acc.get('count')} elements, expected {count}", acc_ptr)
        return None
    return doc.accessor(ext[key])


def check(doc: GltfDocument, places: list, issues) -> None:
    """Semantic rules of BAKER_edges (``baker validate``), and of EXT_mesh_primitive_edge_visibility on the same
    primitives (the schema pass only visits BAKER_* extensions)."""
    from baker.checks import check_vertex_attribute, pointer, stored_resolution

    gltf = doc.json
    for parts, ext in places:
        if len(parts) != 4 or parts[0] != "meshes" or parts[2] != "primitives" or not isinstance(ext, dict):
            continue  # misplaced or malformed: reported by the schema pass
        m, p = parts[1], parts[3]
        prims = gltf["meshes"][m]["primitives"]
        prim = prims[p]
        ptr = pointer("meshes", m, "primitives", p, "extensions", NAME)
        attrs = prim.get("attributes") or {}
        pos = _accessor_info(gltf, attrs.get("POSITION"))
        if pos is None:
            continue
        vertex_count = pos.get("count", 0)
        if "finsOf" in ext:
            source = ext["finsOf"]
            if not (isinstance(source, int) and 0 <= source < len(prims)):
                issues.error("BAKER_EDGES_FIN_SOURCE", f"finsOf {source!r} is not a primitive of this mesh",
                             ptr + "/finsOf")
            for name in FIN_ATTRIBUTES:
                check_vertex_attribute(doc, m, p, name, issues, code="BAKER_EDGES_FIN",
                                       width=3 if name.startswith("_FIN_V") else 1)
            if vertex_count % 4:
                issues.error("BAKER_EDGES_FIN_COUNT", f"a fin primitive has 4 vertices per edge, not {vertex_count}",
                             pointer("meshes", m, "primitives", p))
            continue
        if prim.get("mode", 4) not in (4, 5, 6):
            issues.error("BAKER_EDGES_MODE", "BAKER_edges applies to triangle primitives only", ptr)
            continue
        n_edges = (ext.get("counts") or {}).get("edges")
        n_edges = n_edges if isinstance(n_edges, int) else None
        index_types = (USHORT, UINT)
        edges = _check_edge_accessor(doc, ext, "edges", ptr, issues, types=("VEC2",), component_types=index_types,
                                     count=n_edges)
        if edges is not None:
            n_edges = len(edges)
            if len(edges) and int(edges.max()) >= vertex_count:
                issues.error("BAKER_EDGES_INDEX_OOB", f"edge vertex indices must be < the vertex count {vertex_count}",
                             pointer("accessors", ext["edges"]))
            if len(edges) and np.any(edges[:, 0] == edges[:, 1]):
                issues.error("BAKER_EDGES_DEGENERATE", "an edge joins a vertex to itself",
                             pointer("accessors", ext["edges"]))
        opposite = _check_edge_accessor(doc, ext, "oppositeVertices", ptr, issues, types=("VEC2",),
                                        component_types=index_types, count=n_edges)
        if opposite is not None:
            sentinel = INDEX_MAX[gltf["accessors"][ext["oppositeVertices"]]["componentType"]]
            bad = (opposite >= vertex_count) & (opposite != sentinel)
            if bad.any():
                issues.error("BAKER_EDGES_INDEX_OOB", f"{int(bad.sum())} opposite vertices are neither < the vertex "
                             f"count {vertex_count} nor the 'none' value {sentinel}",
                             pointer("accessors", ext["oppositeVertices"]))
            if len(opposite) and np.any(opposite[:, 0] == sentinel):
                issues.error("BAKER_EDGES_OPPOSITE_MISSING", "every edge has a face, so v2 is never 'none'",
                             pointer("accessors", ext["oppositeVertices"]))
        flags = _check_edge_accessor(doc, ext, "flags", ptr, issues, types=("SCALAR",), component_types=(USHORT,),
                                     count=n_edges)
        if flags is not None and len(flags) and int(flags.max()) >= (1 << len(edge_codes.FLAG_NAMES)):
            issues.error("BAKER_EDGES_FLAGS", "flags use undefined bits", pointer("accessors", ext["flags"]))
        angles = _check_edge_accessor(doc, ext, "dihedralAngles", ptr, issues, types=("SCALAR",),
                                      component_types=(FLOAT,), count=n_edges)
        if angles is not None and len(angles) and (not np.all(np.isfinite(angles))
                                                    or np.abs(angles).max() > math.pi + 1e-5):
            issues.error("BAKER_EDGES_ANGLE_RANGE", "dihedral angles must be finite and within [-pi, pi]",
                         pointer("accessors", ext["dihedralAngles"]))
        if flags is not None and angles is not None and opposite is not None and "creaseAngle" in ext:
            crease = (flags & edge_codes.CREASE) != 0
            if np.any(np.abs(angles[crease]) < float(ext["creaseAngle"]) - 1e-4):
                issues.warning("BAKER_EDGES_CREASE_ANGLE", "some crease edges have a dihedral angle below "
                               "creaseAngle", pointer("accessors", ext["flags"]))
        n_tris = _triangle_count(doc, prim)
        mask = _check_edge_accessor(doc, ext, "wireframeMask", ptr, issues, types=("SCALAR",),
                                    component_types=(UBYTE,), count=n_tris)
        if mask is not None and len(mask) and int(mask.max()) > 7:
            issues.error("BAKER_EDGES_WIREFRAME_MASK", "wireframe mask values use bits above the three edges",
                         pointer("accessors", ext["wireframeMask"]))
        name = ext.get("outlineNormal")
        if isinstance(name, str):
            values = check_vertex_attribute(doc, m, p, name, issues, code="BAKER_EDGES_OUTLINE", width=3)
            if values is not None and len(values):
                length = np.linalg.norm(values, axis=1)
                # zero at vertices on an open boundary (the shell is pinned there), unit everywhere else; a quantized
                # form (KHR_mesh_quantization, Draco) moves each component by half its step
                step = stored_resolution(doc, m, p, name, values)
                if np.minimum(np.abs(length - 1.0), length).max() > 1e-3 + math.sqrt(3.0) * step:
                    issues.error("BAKER_EDGES_OUTLINE_NOT_UNIT", "outline normals must be unit vectors (or zero at "
                                 "vertices on a boundary or non-manifold edge)", pointer("accessors", attrs[name]))
        fins = ext.get("fins")
        if fins is not None:
            ok = isinstance(fins, int) and 0 <= fins < len(prims)
            fin_ext = ((prims[fins].get("extensions") or {}).get(NAME) or {}) if ok else {}
            if not ok or fin_ext.get("finsOf") != p:
                issues.error("BAKER_EDGES_FIN_REFERENCE", f"fins {fins!r} is not a fin primitive of this one",
                             ptr + "/fins")
            elif n_edges is not None:
                fin_pos = _accessor_info(gltf, (prims[fins].get("attributes") or {}).get("POSITION"))
                if fin_pos is not None and fin_pos.get("count") != 4 * n_edges:
                    issues.error("BAKER_EDGES_FIN_COUNT", f"the fin primitive has {fin_pos.get('count')} vertices "
                                 f"for {n_edges} edges (4 each)", ptr + "/fins")
        if ext.get("edgeVisibility") is True and EXT_VISIBILITY not in (prim.get("extensions") or {}):
            issues.error("BAKER_EDGES_VISIBILITY_MISSING", "edgeVisibility is true but the primitive has no "
                         "EXT_mesh_primitive_edge_visibility", ptr)
    # EXT_mesh_primitive_edge_visibility wherever it is (validate.py collects only BAKER_* extensions)
    for m, mesh in enumerate(gltf.get("meshes") or []):
        for p, prim in enumerate(mesh.get("primitives") or []):
            if EXT_VISIBILITY in (prim.get("extensions") or {}):
                check_edge_visibility(doc, m, p, issues)
                if EXT_VISIBILITY not in (gltf.get("extensionsUsed") or []):
                    issues.warning("BAKER_EXTENSION_NOT_DECLARED", f"{EXT_VISIBILITY} is used but missing from "
                                   "extensionsUsed", "/extensionsUsed")


def to_usd_primitive(stage, name: str, parent: str, doc: GltfDocument, mesh: int, primitive: int) -> None:
    """USD hook (called by baker.gltf.usd for primitives carrying BAKER_edges): the crease, boundary, material and
    non-manifold edges as a linear BasisCurves prim ``<parent>/<name>`` beside the mesh."""
    usd_basis_curves(stage, f"{parent}/{name}", doc, mesh, primitive)


# =========================================================================================================== reading back
@dataclass(frozen=True, eq=False)  # holds arrays: compared by identity
class EdgesPrimitive:
    """``BAKER_edges`` of one primitive as read back: on a triangle primitive its settings, counts and accessors;
    on a fin primitive (``fins_of`` set) the fin attributes and indices."""

    fins_of: int | None = None  # a fin primitive: its source triangle primitive
    crease_angle: float | None = None  # radians
    planar_angle: float | None = None
    weld_tolerance: float | None = None
    counts: dict = field(default_factory=dict)
    edge_visibility: bool = False
    outline_normal: str | None = None  # the attribute (``_OUTLINE_NORMAL``)
    fins: int | None = None  # the fin primitive's index
    wireframe_mask: np.ndarray | None = None  # one 3-bit mask per triangle (bit k: edge k is drawn)
    wireframe_hides: str | None = None
    edges: np.ndarray | None = None  # (e, 2) vertex indices (``edge_list``)
    opposite_vertices: np.ndarray | None = None
    flags: np.ndarray | None = None
    dihedral_angles: np.ndarray | None = None
    fin_attributes: dict = field(default_factory=dict)  # fin primitive: _FIN_V0.._FIN_V3, _FIN_CORNER, _FIN_FLAGS
    fin_indices: np.ndarray | None = None  # fin primitive: (2 e, 3) triangles


def read(doc: GltfDocument, mesh: int, primitive: int) -> EdgesPrimitive | None:
    """What :func:`write_primitive_edges` (or :func:`write_fin_primitive`) wrote on a primitive, accessors read;
    None when the primitive has no ``BAKER_edges``."""
    prim = doc.json["meshes"][mesh]["primitives"][primitive]
    ext = (prim.get("extensions") or {}).get(NAME)
    if ext is None:
        return None
    accessor = lambda key: doc.accessor(ext[key]) if key in ext else None  # noqa: E731
    if "finsOf" in ext:
        return EdgesPrimitive(
            fins_of=int(ext["finsOf"]),
            fin_attributes={k: unpadded(doc.accessor(a), 3 if k.startswith("_FIN_V") else 1)
                            for k, a in prim["attributes"].items() if k.startswith("_FIN_")},
            fin_indices=doc.accessor(prim["indices"]).reshape(-1, 3))
    return EdgesPrimitive(
        crease_angle=float(ext["creaseAngle"]) if "creaseAngle" in ext else None,
        planar_angle=float(ext["planarAngle"]) if "planarAngle" in ext else None,
        weld_tolerance=float(ext["weldTolerance"]) if "weldTolerance" in ext else None,
        counts=dict(ext.get("counts", {})), edge_visibility=bool(ext.get("edgeVisibility", False)),
        outline_normal=ext.get("outlineNormal"), fins=int(ext["fins"]) if "fins" in ext else None,
        wireframe_mask=accessor("wireframeMask"), wireframe_hides=ext.get("wireframeHides"),
        edges=accessor("edges"), opposite_vertices=accessor("oppositeVertices"), flags=accessor("flags"),
        dihedral_angles=accessor("dihedralAngles"))


def summary(doc: GltfDocument, mesh: int, primitive: int) -> dict | None:
    """What ``baker inspect`` shows of a ``BAKER_edges`` primitive. A triangle primitive: its edge count and the
    number of edges of each class present (counted from the stored flags when the edge list was written, else the
    extension's ``counts``), the crease angle in degrees, the fin primitive and what the wireframe mask hides. A fin
    primitive: its source primitive and fin count (two triangles per edge). None when the extension cannot be read
    (inspect shows "-"; ``baker validate`` says why)."""
    from baker.errors import BakerError

    try:
        edges = read(doc, mesh, primitive)
    except (BakerError, ValueError, TypeError, KeyError, IndexError, AttributeError):
        return None
    if edges is None:
        return None
    if edges.fins_of is not None:
        return {"finsOf": edges.fins_of, "fins": len(edges.fin_indices) // 2}
    if edges.flags is not None:
        flags = np.asarray(edges.flags).reshape(-1).astype(np.int64)
        counts = {"edges": int(len(flags)), **{name: int(np.count_nonzero(flags & bit))
                                               for bit, name in edge_codes.FLAG_NAMES.items()}}
    else:
        counts = {k: int(v) for k, v in edges.counts.items() if isinstance(v, (int, float))}
    out = {"edges": counts.get("edges", 0)}
    out.update({name: n for name, n in counts.items() if name != "edges" and n})  # the classes present
    if edges.crease_angle is not None:
        out["creaseAngleDeg"] = round(math.degrees(edges.crease_angle), 6)
    if edges.fins is not None:
        out["finPrimitive"] = edges.fins
    if edges.wireframe_hides:
        out["wireframeHides"] = edges.wireframe_hides
    return out


def visibility_summary(doc: GltfDocument, mesh: int, primitive: int) -> dict | None:
    """What ``baker inspect`` shows of ``EXT_mesh_primitive_edge_visibility``: the edges each code marks, counted
    from the packed ``visibility`` (a hard edge is counted once: its second triangle's code is "repeated"), and the
    silhouette mates. None when it cannot be read."""
    prim = doc.json["meshes"][mesh]["primitives"][primitive]
    ext = (prim.get("extensions") or {}).get(EXT_VISIBILITY)
    try:
        triangles = doc.json["accessors"][prim["indices"]]["count"] // 3 if "indices" in prim else \
            doc.json["accessors"][prim["attributes"]["POSITION"]]["count"] // 3
        codes = np.bincount(edge_codes.unpack_visibility(doc.accessor(ext["visibility"]), triangles).reshape(-1),
                            minlength=4)
        mates = doc.json["accessors"][ext["silhouetteMates"]]["count"] if "silhouetteMates" in ext else 0
    except (ValueError, TypeError, KeyError, IndexError, AttributeError):
        return None
    return {"silhouette": int(codes[edge_codes.VIS_SILHOUETTE]), "hard": int(codes[edge_codes.VIS_HARD]),
            "silhouetteMates": int(mates)}


# inspect's summaries of the other extensions this module writes
ALSO_SUMMARIES = {EXT_VISIBILITY: visibility_summary}
