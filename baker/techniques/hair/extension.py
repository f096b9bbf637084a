"""``BAKER_hair``: strand sets -> a LINES mesh with strand attributes and the ribbon/guide data a runtime needs.

Where the data goes (see ``schemas/BAKER_hair/README.md``):
- one ``LINES`` primitive per strand set (guides, children), vertices strand by strand from root to tip, strands
  ordered nearest-the-emitter first (RTR4 14.7.1: a pre-sorted buffer limits alpha-blending errors); plain viewers
  draw the lines;
- vertex attributes ``_STRAND_TANGENT`` (FLOAT VEC3, unit) and ``_STRAND_PARAM`` (0 at the root, 1 at the tip: FLOAT
  SCALAR in the ``native`` layout, x of a FLOAT VEC3 in the ``blender`` one, :mod:`baker.gltf.vertex_attributes`);
- ``BAKER_hair`` on the primitive: counts, widths, the per-strand width scale, the ribbon index buffer (6 indices
  per segment over ``2 x vertex count`` ribbon vertices), and for children the guide ids + weights.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from baker.gltf.document import TARGET_ELEMENT_ARRAY_BUFFER, GltfDocument
from baker.gltf.vertex_attributes import add_vertex_attribute, unpadded

if TYPE_CHECKING:  # validation and read() must not import the kernel (numba)
    from baker.techniques.hair.kernel import HairResult, StrandSet

NAME = "BAKER_hair"
TANGENT = "_STRAND_TANGENT"
PARAM = "_STRAND_PARAM"
VERTEX_ATTRIBUTES = {TANGENT: 3, PARAM: 1}  # name -> the data's width (baker.registry)
MODE_LINES = 1


def add_hair_node(doc: GltfDocument, mesh: int, emitter_mesh: int | None, name: str) -> int:
    """A node drawing ``mesh``, child of the first node that draws ``emitter_mesh`` (so it shares its transform),
    else (or when ``emitter_mesh`` is None) a root of the default scene."""
    gltf = doc.json
    nodes = gltf.setdefault("nodes", [])
    nodes.append({"name": name, "mesh": mesh})
    node = len(nodes) - 1
    for i, n in enumerate(nodes[:-1]):
        if emitter_mesh is not None and n.get("mesh") == emitter_mesh:
            n.setdefault("children", []).append(node)
            return node
    scenes = gltf.setdefault("scenes", [{"nodes": []}])
    scenes[gltf.get("scene", 0)].setdefault("nodes", []).append(node)
    gltf.setdefault("scene", 0)
    return node


def write_strand_primitive(doc: GltfDocument, strands: StrandSet, *, strand_set: str, result: HairResult,
                           material: int, guide_primitive: int | None = None, extra_attributes: dict | None = None
                           ) -> dict:
    """The primitive dict (not yet attached to a mesh) for one strand set; ``extra_attributes``: more per-vertex
    custom attributes ({name: values}, the hair material's, :mod:`baker.techniques.hair_shading.strands`)."""
    from baker.techniques.hair.kernel import ribbon_indices, strand_tangents

    s, v = strands.count, strands.vertices
    positions = strands.positions.reshape(-1, 3).astype(np.float32)
    tangents = strand_tangents(strands.positions).reshape(-1, 3).astype(np.float32)
    param = np.tile(np.linspace(0.0, 1.0, v, dtype=np.float32), s)
    seg = (np.arange(s)[:, None] * v + np.arange(v - 1)[None, :]).reshape(-1)
    lines = np.stack([seg, seg + 1], axis=1).reshape(-1).astype(np.uint32)
    attributes = {"POSITION": doc.add_accessor(positions, min_max=True)}
    add_vertex_attribute(doc, None, attributes, TANGENT, tangents)  # a mesh of its own: the strands' widths only
    add_vertex_attribute(doc, None, attributes, PARAM, param)
    for name, values in (extra_attributes or {}).items():
        add_vertex_attribute(doc, None, attributes, name, values)
    prim = {
        "attributes": attributes,
        "indices": doc.add_accessor(lines, target=TARGET_ELEMENT_ARRAY_BUFFER),
        "mode": MODE_LINES,
        "material": material,
    }
    ext = {
        "strandSet": strand_set,
        "strandCount": int(s),
        "verticesPerStrand": int(v),
        "length": float(result.length),
        "rootWidth": float(result.root_width),
        "tipWidth": float(result.tip_width),
        "widthScale": doc.add_accessor(strands.width_scale.astype(np.float32), target=None),
        "ribbonIndices": doc.add_accessor(ribbon_indices(s, v).astype(np.uint32), target=None),
        "order": "nearestFirst",
        "tangentAttribute": TANGENT,
        "paramAttribute": PARAM,
    }
    if strands.guide_ids is not None:
        ext["guides"] = {
            "primitive": int(guide_primitive),
            "ids": doc.add_accessor(strands.guide_ids.astype(np.uint32), target=None),
            "weights": doc.add_accessor(strands.guide_weights.astype(np.float32), target=None),
        }
    prim["extensions"] = {NAME: ext}
    return prim


def write_hair(doc: GltfDocument, result: HairResult, emitter_mesh: int, shading=None, seed: int = 0) -> int:
    """Add the hair mesh (guides, then children when there are any), its hair material (``BAKER_hair_shading``
    from ``shading``, a :class:`~baker.techniques.hair_shading.options.HairMaterialOptions`, default when None;
    the emitter mesh occludes the strands) and its node; returns the mesh index."""
    from baker.techniques.hair_shading.options import HairMaterialOptions
    from baker.techniques.hair_shading.strands import hair_material

    sets = [result.guides] + ([result.children] if result.children.count else [])
    material, extra = hair_material(doc, shading or HairMaterialOptions(), sets, result.root_width,
                                    result.tip_width, scalp=mesh_triangles(doc, emitter_mesh), seed=seed)
    prims = [write_strand_primitive(doc, result.guides, strand_set="guides", result=result, material=material,
                                    extra_attributes=extra[0])]
    if result.children.count:
        prims.append(write_strand_primitive(doc, result.children, strand_set="children", result=result,
                                            material=material, guide_primitive=0, extra_attributes=extra[1]))
    meshes = doc.json.setdefault("meshes", [])
    meshes.append({"name": "hair", "primitives": prims})
    mesh = len(meshes) - 1
    add_hair_node(doc, mesh, emitter_mesh, "hair")
    doc.use_extension(NAME)
    return mesh


def mesh_triangles(doc: GltfDocument, mesh: int | None):
    """(vertices, faces) of every triangle primitive of ``mesh`` in its own space (the hair node's, which hangs
    under the emitter's node), or None: what occludes the strands besides the strands."""
    meshes = doc.json.get("meshes") or []
    if mesh is None or not 0 <= mesh < len(meshes):
        return None
    vertices, faces, offset = [], [], 0
    for prim in meshes[mesh].get("primitives") or []:
        if prim.get("mode", 4) != 4 or "POSITION" not in prim.get("attributes", {}):
            continue
        p = np.asarray(doc.accessor(prim["attributes"]["POSITION"]), np.float64).reshape(-1, 3)
        f = (np.asarray(doc.accessor(prim["indices"]), np.int64).reshape(-1, 3) if "indices" in prim
             else np.arange(len(p) - len(p) % 3).reshape(-1, 3))
        vertices.append(p)
        faces.append(f + offset)
        offset += len(p)
    return (np.concatenate(vertices), np.concatenate(faces)) if vertices else None


def read_strands(doc: GltfDocument, mesh: int, primitive: int) -> dict:
    """The strand data of one BAKER_hair primitive as arrays (positions (s, v, 3), param, tangents, guides...)."""
    prim = doc.json["meshes"][mesh]["primitives"][primitive]
    ext = prim["extensions"][NAME]
    s, v = ext["strandCount"], ext["verticesPerStrand"]
    out = {
        "positions": doc.accessor(prim["attributes"]["POSITION"]).reshape(s, v, 3),
        "tangents": unpadded(doc.accessor(prim["attributes"][ext.get("tangentAttribute", TANGENT)]), 3).reshape(s, v, 3),
        "param": unpadded(doc.accessor(prim["attributes"][ext.get("paramAttribute", PARAM)]), 1).reshape(s, v),
        "width_scale": doc.accessor(ext["widthScale"]),
        "ribbon": doc.accessor(ext["ribbonIndices"]),
        "ext": ext,
    }
    if "guides" in ext:
        out["guide_ids"] = doc.accessor(ext["guides"]["ids"])
        out["guide_weights"] = doc.accessor(ext["guides"]["weights"])
    return out


def check(doc: GltfDocument, places: list, issues) -> None:
    """Semantic rules of BAKER_hair (``baker validate``): counts agree with the accessors, strands run root to tip,
    tangents are unit, the ribbon buffer addresses the ribbon vertices, guide references resolve and weights are a
    partition of unity."""
    from baker.checks import is_index, check_vertex_attribute, pointer

    gltf = doc.json
    accessors = gltf.get("accessors") or []
    for parts, ext in places:
        if len(parts) != 4 or parts[0] != "meshes" or parts[2] != "primitives" or not isinstance(ext, dict):
            continue  # misplaced or malformed: reported by the schema pass
        m, p = parts[1], parts[3]
        prim = gltf["meshes"][m]["primitives"][p]
        ptr = pointer("meshes", m, "primitives", p, "extensions", NAME)
        s, v = ext.get("strandCount"), ext.get("verticesPerStrand")
        if not (isinstance(s, int) and isinstance(v, int)) or s < 1 or v < 2:
            continue
        if prim.get("mode", 4) != MODE_LINES:
            issues.error("BAKER_HAIR_MODE", f"a BAKER_hair primitive must be LINES (mode 1), not {prim.get('mode', 4)}",
                         pointer("meshes", m, "primitives", p, "mode"))
        attrs = prim.get("attributes") or {}
        pos = attrs.get("POSITION")
        if is_index(pos, accessors) and accessors[pos].get("count") != s * v:
            issues.error("BAKER_HAIR_VERTEX_COUNT", f"POSITION has {accessors[pos].get('count')} vertices, expected "
                         f"strandCount x verticesPerStrand = {s * v}", pointer("accessors", pos))
            continue
        if "indices" in prim and is_index(prim["indices"], accessors):
            lines = doc.accessor(prim["indices"]).astype(np.int64)
            if len(lines) != 2 * s * (v - 1):
                issues.error("BAKER_HAIR_LINE_COUNT", f"{len(lines)} line indices, expected 2 x strandCount x "
                             f"(verticesPerStrand - 1) = {2 * s * (v - 1)}", pointer("accessors", prim["indices"]))
        tangent = check_vertex_attribute(doc, m, p, ext.get("tangentAttribute", TANGENT), issues,
                                         code="BAKER_HAIR_TANGENT", width=3)
        if tangent is not None and len(tangent):
            bad = np.abs(np.linalg.norm(tangent, axis=1) - 1.0) > 1e-3
            if bad.any():
                issues.error("BAKER_HAIR_TANGENT_NOT_UNIT", f"{int(bad.sum())} tangents are not unit length",
                             pointer("accessors", attrs[ext.get("tangentAttribute", TANGENT)]))
        param = check_vertex_attribute(doc, m, p, ext.get("paramAttribute", PARAM), issues, code="BAKER_HAIR_PARAM")
        if param is not None and len(param) == s * v:
            strands = param.reshape(s, v)
            if (np.abs(strands[:, 0]) > 1e-6).any() or (np.abs(strands[:, -1] - 1.0) > 1e-6).any() \
                    or (np.diff(strands, axis=1) <= 0).any():
                issues.error("BAKER_HAIR_PARAM_ORDER", "every strand's parameter must rise from 0 at the root to 1 "
                             "at the tip", pointer("accessors", attrs[ext.get("paramAttribute", PARAM)]))
        for key, count, kind in (("widthScale", s, "SCALAR"), ("ribbonIndices", 6 * s * (v - 1), "SCALAR")):
            a = ext.get(key)
            if not is_index(a, accessors):
                issues.error("UNRESOLVED_REFERENCE", f"accessor {a!r} does not exist", ptr + "/" + key)
                continue
            if accessors[a].get("count") != count or accessors[a].get("type") != kind:
                issues.error("BAKER_HAIR_ACCESSOR_COUNT", f"'{key}' must be {count} {kind} values, not "
                             f"{accessors[a].get('count')} {accessors[a].get('type')}", pointer("accessors", a))
                continue
            values = doc.accessor(a)
            if key == "widthScale" and ((values <= 0) | (values > 1) | ~np.isfinite(values)).any():
                issues.error("BAKER_HAIR_WIDTH_SCALE", "width scales must be in (0, 1]", pointer("accessors", a))
            if key == "ribbonIndices" and len(values) and int(values.max()) >= 2 * s * v:
                issues.error("BAKER_HAIR_RIBBON_INDEX_OOB", f"ribbon indices must be < 2 x vertex count = {2 * s * v}",
                             pointer("accessors", a))
        if (ext.get("tipWidth") or 0) > (ext.get("rootWidth") or 0) * 1.000001:
            issues.warning("BAKER_HAIR_WIDTH_ORDER", "tipWidth is larger than rootWidth", ptr)
        check_lods_and_binding(doc, ext, s, ptr, issues)
        guides = ext.get("guides")
        if isinstance(guides, dict):
            gp = guides.get("primitive")
            mesh_prims = gltf["meshes"][m]["primitives"]
            gext = (mesh_prims[gp].get("extensions") or {}).get(NAME) if is_index(gp, mesh_prims) else None
            if not isinstance(gext, dict) or gp == p:
                issues.error("BAKER_HAIR_GUIDES_MISSING", f"guides.primitive {gp!r} is not another BAKER_hair "
                             "primitive of this mesh", ptr + "/guides/primitive")
                continue
            n_guides = gext.get("strandCount", 0)
            ids_a, w_a = guides.get("ids"), guides.get("weights")
            if not (is_index(ids_a, accessors) and is_index(w_a, accessors)):
                continue
            ids, weights = doc.accessor(ids_a), doc.accessor(w_a)
            if ids.shape != (s, 3) or weights.shape != (s, 3):
                issues.error("BAKER_HAIR_GUIDE_ACCESSORS", "guides.ids and guides.weights must hold one VEC3 per "
                             "strand", ptr + "/guides")
                continue
            if int(ids.max()) >= n_guides:
                issues.error("BAKER_HAIR_GUIDE_ID_OOB", f"guide ids must be < the guide strand count {n_guides}",
                             pointer("accessors", ids_a))
            w = weights.astype(np.float64)
            if (w < 0).any() or (np.abs(w.sum(axis=1) - 1.0) > 1e-4).any():
                issues.error("BAKER_HAIR_GUIDE_WEIGHTS", "guide weights must be >= 0 and sum to 1 per strand",
                             pointer("accessors", w_a))


def check_lods_and_binding(doc: GltfDocument, ext: dict, strand_count: int, ptr: str, issues) -> None:
    """``lods``: the first level holds every strand, counts never grow, widthScale > 0; ``rootBinding``: one
    primitive/triangle/barycentric per strand, naming triangles that exist, barycentrics a partition of unity."""
    from baker.checks import is_index, pointer

    lods = ext.get("lods")
    if isinstance(lods, list) and lods and all(isinstance(x, dict) for x in lods):
        counts = [x.get("strandCount") for x in lods]
        if all(isinstance(c, int) for c in counts):
            if counts[0] != strand_count:
                issues.error("BAKER_HAIR_LOD_COUNT", f"lods[0].strandCount must be strandCount {strand_count}, not "
                             f"{counts[0]}", ptr + "/lods/0/strandCount")
            if any(b > a for a, b in zip(counts, counts[1:])):
                issues.error("BAKER_HAIR_LOD_ORDER", "lods must go from the most strands to the fewest",
                             ptr + "/lods")
        if ext.get("order") != "lodPrefix" and len(lods) > 1:
            issues.warning("BAKER_HAIR_LOD_ORDER", "lods on a primitive whose order is not 'lodPrefix': a prefix "
                           "may not cover the scalp evenly", ptr + "/order")
    binding = ext.get("rootBinding")
    if not isinstance(binding, dict):
        return
    gltf = doc.json
    accessors = gltf.get("accessors") or []
    meshes = gltf.get("meshes") or []
    m = binding.get("mesh")
    if not is_index(m, meshes):
        issues.error("UNRESOLVED_REFERENCE", f"mesh {m!r} does not exist", ptr + "/rootBinding/mesh")
        return
    arrays = {}
    for key, kind in (("primitives", "SCALAR"), ("triangles", "SCALAR"), ("barycentrics", "VEC3")):
        a = binding.get(key)
        if not is_index(a, accessors):
            issues.error("UNRESOLVED_REFERENCE", f"accessor {a!r} does not exist", ptr + "/rootBinding/" + key)
            return
        if accessors[a].get("count") != strand_count or accessors[a].get("type") != kind:
            issues.error("BAKER_HAIR_BINDING", f"rootBinding.{key} must be {strand_count} {kind} values",
                         pointer("accessors", a))
            return
        arrays[key] = doc.accessor(a)
    prims = meshes[m].get("primitives") or []
    primitive = arrays["primitives"].astype(np.int64)
    if len(primitive) and int(primitive.max()) >= len(prims):
        issues.error("BAKER_HAIR_BINDING", f"rootBinding.primitives must be < {len(prims)} (primitives of mesh {m})",
                     pointer("accessors", binding["primitives"]))
        return
    for p in np.unique(primitive).tolist():
        prim = prims[p]
        if prim.get("mode", 4) != 4:
            continue
        source = prim.get("indices", (prim.get("attributes") or {}).get("POSITION"))
        n_tri = (accessors[source].get("count", 0) // 3) if is_index(source, accessors) else 0
        if int(arrays["triangles"][primitive == p].max()) >= n_tri:
            issues.error("BAKER_HAIR_BINDING", f"rootBinding.triangles names a triangle past the {n_tri} of mesh {m} "
                         f"primitive {p}", pointer("accessors", binding["triangles"]))
    bary = arrays["barycentrics"].astype(np.float64)
    if (bary < -1e-6).any() or (np.abs(bary.sum(axis=1) - 1.0) > 1e-4).any() or not np.isfinite(bary).all():
        issues.error("BAKER_HAIR_BINDING", "rootBinding.barycentrics must be >= 0 and sum to 1 per strand",
                     pointer("accessors", binding["barycentrics"]))


@dataclass(frozen=True, eq=False)  # holds arrays: compared by identity
class HairStrands:
    """One ``BAKER_hair`` primitive as read back: strands of ``vertices_per_strand`` vertices, root first."""

    strand_count: int
    vertices_per_strand: int
    positions: np.ndarray  # (strand_count * vertices_per_strand, 3), as stored
    tangents: np.ndarray  # unit, per vertex
    param: np.ndarray  # 0 at the root, 1 at the tip, per vertex
    ribbon_indices: np.ndarray  # triangles of the view-facing ribbon (ribbon vertex r = line vertex r // 2)
    root_width: float
    tip_width: float
    width_scale: np.ndarray | None = None  # per strand
    guides_primitive: int | None = None  # children: the guide primitive they follow
    guide_ids: np.ndarray | None = None
    guide_weights: np.ndarray | None = None
    material: int | None = None
    interpolation: str | None = None  # children: "offset"
    lods: tuple = ()  # ((strandCount, widthScale), ...), finest first
    root_binding: dict | None = None  # {"mesh", "primitives", "triangles", "barycentrics"} (arrays), or None


def read(doc: GltfDocument, mesh: int, primitive: int) -> HairStrands | None:
    """What :func:`write_strand_primitive` wrote, accessors read; None when the primitive has no ``BAKER_hair``."""
    prim = doc.json["meshes"][mesh]["primitives"][primitive]
    ext = (prim.get("extensions") or {}).get(NAME)
    if ext is None:
        return None
    attrs = prim["attributes"]
    guides = ext.get("guides") or {}
    return HairStrands(
        strand_count=int(ext["strandCount"]), vertices_per_strand=int(ext["verticesPerStrand"]),
        positions=doc.accessor(attrs["POSITION"]),
        tangents=unpadded(doc.accessor(attrs[ext.get("tangentAttribute", TANGENT)]), 3),
        param=unpadded(doc.accessor(attrs[ext.get("paramAttribute", PARAM)]), 1).reshape(-1),
        ribbon_indices=doc.accessor(ext["ribbonIndices"]).reshape(-1),
        root_width=float(ext["rootWidth"]), tip_width=float(ext["tipWidth"]),
        width_scale=doc.accessor(ext["widthScale"]).reshape(-1) if "widthScale" in ext else None,
        guides_primitive=int(guides["primitive"]) if "primitive" in guides else None,
        guide_ids=doc.accessor(guides["ids"]) if "ids" in guides else None,
        guide_weights=doc.accessor(guides["weights"]) if "weights" in guides else None,
        material=prim.get("material"),
        interpolation=guides.get("interpolation", "offset") if guides else None,
        lods=tuple((int(x["strandCount"]), float(x["widthScale"])) for x in ext.get("lods", ())),
        root_binding=None if "rootBinding" not in ext else {
            "mesh": int(ext["rootBinding"]["mesh"]),
            **{k: doc.accessor(ext["rootBinding"][k]) for k in ("primitives", "triangles", "barycentrics")}})


def summary(doc: GltfDocument, mesh: int, primitive: int) -> dict | None:
    """What ``baker inspect`` shows of one ``BAKER_hair`` primitive (from :func:`read`): the strand set, counts,
    widths, the mean strand length (in mesh units, from the positions), guides, LODs and the root binding."""
    hair = read(doc, mesh, primitive)
    if hair is None:
        return None
    ext = doc.json["meshes"][mesh]["primitives"][primitive]["extensions"][NAME]
    strands = np.asarray(hair.positions, np.float64).reshape(hair.strand_count, hair.vertices_per_strand, 3)
    lengths = np.linalg.norm(np.diff(strands, axis=1), axis=2).sum(axis=1)
    out = {"strandSet": ext.get("strandSet", ""), "strands": hair.strand_count,
           "verticesPerStrand": hair.vertices_per_strand, "rootWidth": hair.root_width, "tipWidth": hair.tip_width,
           "meanLength": float(lengths.mean()) if len(lengths) else 0.0}
    if hair.guides_primitive is not None:
        out["guidesPrimitive"] = hair.guides_primitive
    if hair.lods:
        out["lodStrands"] = [count for count, _ in hair.lods]
    if hair.root_binding is not None:
        out["rootBindingMesh"] = hair.root_binding["mesh"]
    return out


def from_usd_curves(doc: GltfDocument, prim, matrix: np.ndarray) -> dict | None:
    """A ``BasisCurves`` prim :mod:`baker.techniques.hair.usd` wrote, as the ``BAKER_hair`` LINES primitive it was
    written from (world transform baked into the points; ``primvars:baker:<name>`` of vertex interpolation as
    ``_<NAME>`` attributes); None for other curves. Children name primitive 0 (the guides, written first) as their
    guides. What :mod:`baker.readers.usd_baked` asks through the registry's ``curve_readers``."""
    from pxr import UsdGeom

    from baker.errors import BakerError
    from baker.techniques.hair.kernel import ribbon_indices, strand_tangents

    curves = UsdGeom.BasisCurves(prim)
    api = UsdGeom.PrimvarsAPI(prim)
    if not api.HasPrimvar("baker:strandParam"):
        return None
    counts = np.asarray(curves.GetCurveVertexCountsAttr().Get() or [], np.int64)
    points = np.asarray(curves.GetPointsAttr().Get() or [], np.float64).reshape(-1, 3)
    if not len(counts) or (counts != counts[0]).any() or counts[0] < 2 or counts.sum() != len(points):
        raise BakerError(None, f"{prim.GetPath()}: hair curves must all have the same vertex count >= 2")
    s, v = len(counts), int(counts[0])
    points = points @ matrix[:3, :3] + matrix[3, :3]  # USD's row vectors
    if not np.isfinite(points).all():
        raise BakerError(None, f"{prim.GetPath()}.points: NaN or infinite values")
    hair = prim.GetParent()

    def hair_attribute(name, default):
        attr = hair.GetAttribute(f"baker:hair:{name}")
        return attr.Get() if attr and attr.HasAuthoredValue() else default

    positions = points.astype(np.float32)
    attributes = {"POSITION": doc.add_accessor(positions, min_max=True)}
    tangents = strand_tangents(points.reshape(s, v, 3)).reshape(-1, 3).astype(np.float32)
    attributes[TANGENT] = doc.add_accessor(tangents)
    for primvar in api.GetPrimvars():
        name = primvar.GetPrimvarName()
        if not name.startswith("baker:") or primvar.GetInterpolation() != UsdGeom.Tokens.vertex:
            continue
        values = np.asarray(primvar.Get(), np.float32)
        if len(values) != s * v or not np.isfinite(values).all():
            raise BakerError(None, f"{prim.GetPath()}.primvars:{name}: {len(values)} values (expected {s * v}), "
                             "finite")
        attribute = PARAM if name == "baker:strandParam" else "_" + name[len("baker:"):].upper()
        attributes[attribute] = doc.add_accessor(values)
    lines = (np.arange(s)[:, None] * v + np.arange(v - 1)[None, :]).reshape(-1)
    width_scale = api.GetPrimvar("baker:widthScale")
    scale = np.asarray(width_scale.Get(), np.float32) if width_scale else np.ones(s, np.float32)
    ext = {"strandSet": prim.GetName(), "strandCount": s, "verticesPerStrand": v,
           "length": float(hair_attribute("length", 0.0)), "rootWidth": float(hair_attribute("rootWidth", 0.0)),
           "tipWidth": float(hair_attribute("tipWidth", 0.0)),
           "widthScale": doc.add_accessor(scale, target=None),
           "ribbonIndices": doc.add_accessor(ribbon_indices(s, v).astype(np.uint32), target=None),
           "order": "nearestFirst", "tangentAttribute": TANGENT, "paramAttribute": PARAM}
    ids, weights = api.GetPrimvar("baker:guideIds"), api.GetPrimvar("baker:guideWeights")
    if ids and weights:
        ext["guides"] = {"primitive": 0, "ids": doc.add_accessor(np.asarray(ids.Get(), np.uint32), target=None),
                         "weights": doc.add_accessor(np.asarray(weights.Get(), np.float32), target=None)}
        interpolation = hair_attribute("interpolation", None)
        if interpolation:
            ext["guides"]["interpolation"] = str(interpolation)
            ext["order"] = "lodPrefix"
        lods = hair_attribute("lod:strandCounts", None)
        scales = hair_attribute("lod:widthScales", None)
        if lods is not None and scales is not None:
            ext["lods"] = [{"strandCount": int(n), "widthScale": float(w)} for n, w in zip(lods, scales)]
    elif hair_attribute("interpolation", None):
        ext["order"] = "none"
    doc.use_extension(NAME)
    return {"attributes": attributes, "mode": MODE_LINES,
            "indices": doc.add_accessor(np.stack([lines, lines + 1], 1).reshape(-1).astype(np.uint32),
                                        target=TARGET_ELEMENT_ARRAY_BUFFER),
            "extensions": {NAME: ext}}
