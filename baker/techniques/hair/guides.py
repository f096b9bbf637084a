"""``baker guides GROOM -o OUT`` (run by :func:`baker.techniques.hair.step.run_guides`): read a dense groom, choose
guides, solve child weights, order LODs, write.

Outputs by suffix (see ``schemas/BAKER_hair/README.md``):

- ``.glb``/``.gltf``: a ``hair`` mesh with two ``BAKER_hair`` LINES primitives, as ``baker hair`` writes them:
  ``guides`` (the chosen strands) and ``children`` (every groom strand, in blue-noise LOD order, with 3 guide ids
  and weights, ``guides.interpolation = "offset"`` and ``lods``); with ``--scalp`` the scalp asset comes first and
  both primitives carry ``rootBinding`` (primitive, triangle, barycentrics of each root on the scalp mesh);
- ``.usda``/``.usdc``/``.usd``: ``/Root/Hair/guides`` and ``/Root/Hair/children`` BasisCurves with primvars
  ``baker:guideIds``/``baker:guideWeights`` and the LODs as ``baker:hair:lod:*`` attributes;
- ``.tfx``: the guides as TressFX 4 (the format holds guide strands only: TressFX makes its follow hairs itself),
  plus ``<stem>.children.tfx`` (the children) and ``<stem>.weights`` (ids + weights, layout in the README).
"""
from __future__ import annotations

import struct
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from baker.errors import BakerError
from baker.progress import QUIET, Progress
from baker.readers import read_groom
from baker.readers.groom import clean_groom
from baker.techniques.hair.guide_solver import (GuideSolution, lod_counts, progressive_order, resample_strands,
                                                 solve_guides)
from baker.techniques.hair.options import GuidesOptions
from baker.techniques.hair.kernel import HairResult, StrandSet

WEIGHTS_MAGIC = b"BKHW"
WEIGHTS_HEADER = struct.Struct("<4s3I")  # magic, version 1, strand count, guide count


@dataclass
class RootBinding:
    """Where each root sits on the scalp: glTF primitive (of ``mesh``), triangle in it, barycentrics."""

    mesh: int
    primitive: np.ndarray  # (S,) int
    triangle: np.ndarray  # (S,) int
    barycentrics: np.ndarray  # (S, 3) float


@dataclass
class GuidesBake:
    result: HairResult
    solution: GuideSolution
    lods: list  # [{"strandCount", "widthScale"}]
    skipped: dict
    asset: object = None  # the scalp Asset, or None
    child_binding: RootBinding | None = None
    guide_binding: RootBinding | None = None
    stats: dict = field(default_factory=dict)


# ------------------------------------------------------------------------------------------------------------ widths
def width_model(widths: np.ndarray | None, lengths: np.ndarray):
    """(rootWidth, tipWidth, per-strand widthScale in (0, 1]) of BAKER_hair's linear taper fitted to per-vertex
    widths (S, V): root width per strand, one tip/root ratio (the median); defaults length / 150 and / 10."""
    s = len(lengths)
    if widths is None or not (widths.max(initial=0.0) > 0):
        root = float(np.median(lengths)) / 150.0
        return root, root / 10.0, np.ones(s)
    root_s, tip_s = widths[:, 0], widths[:, -1]
    root = float(root_s.max()) if root_s.max() > 0 else float(widths.max())
    ratio = tip_s[root_s > 0] / root_s[root_s > 0]
    tip = root * float(np.median(ratio)) if len(ratio) else root
    scale = np.clip(np.where(root_s > 0, root_s, widths.max(axis=1)) / root, 1e-6, 1.0)
    return root, min(tip, root), scale


# ------------------------------------------------------------------------------------------------------------- scalp
def bind_to_scalp(asset, strands: np.ndarray, seed: int):
    """Move each strand so its root lies on the closest point of the scalp's mesh 0 and push the strands out of
    the scalp (segment lengths kept); returns (RootBinding, pushed strands, root normals, vertices still inside)."""
    from baker.techniques.hair.grow import emitter_from_asset
    from baker.techniques.hair.kernel import InsideTest, SurfaceLookup, barycentric_weights, push_out
    from baker.techniques.hair.options import HairOptions

    emitter = emitter_from_asset(asset, HairOptions())
    surface = SurfaceLookup(emitter.vertices, emitter.colliders, rng_seed=seed)
    closest, _, _, face = surface.closest_faces(strands[:, 0])
    tri = emitter.vertices[emitter.colliders[face]]
    bary = barycentric_weights(closest, tri[:, 0], tri[:, 1], tri[:, 2])
    moved = strands + (closest - strands[:, 0])[:, None, :]
    # face normals point outwards for a consistently wound mesh; the smooth normals are what grow.py uses
    smooth = np.einsum("sk,skd->sd", bary, emitter.normals[emitter.colliders[face]])
    smooth /= np.maximum(np.linalg.norm(smooth, axis=1, keepdims=True), 1e-30)
    rest = np.linalg.norm(np.diff(moved, axis=1), axis=2).mean(axis=1)
    diag = float(np.linalg.norm(emitter.vertices.max(0) - emitter.vertices.min(0))) or 1.0
    inside = push_out(moved, rest, InsideTest(emitter.vertices, emitter.colliders), surface, 1e-4 * diag,
                      root_normals=smooth)
    # triangle numbers of the welded emitter -> (primitive, triangle within it): emitter_from_asset concatenates
    # the triangle primitives of mesh 0 in order
    prims = list(asset.triangle_primitives(0))
    sizes = [len(asset.primitive(0, p).faces) for p in prims]
    offsets = np.cumsum([0] + [n for n in sizes if n])
    prims = [p for p, n in zip(prims, sizes) if n]
    which = np.searchsorted(offsets, face, side="right") - 1
    binding = RootBinding(0, np.asarray(prims, np.int64)[which], face - offsets[which], bary)
    return binding, moved, smooth, inside


# ------------------------------------------------------------------------------------------------------------- bake
def make_guides(groom_path, options: GuidesOptions, progress: Progress = QUIET,
                max_memory: int | None = None) -> GuidesBake:
    """Guides, child weights and LODs of a groom; ``max_memory``: bytes the ``scalp`` mesh may need (None: no
    limit)."""
    timings = {}
    start = time.perf_counter()
    groom = clean_groom(read_groom(groom_path), groom_path, options.bad_curves)
    strands, _, widths = resample_strands(groom.points, groom.counts, options.vertices_per_strand, groom.widths)
    lengths = np.linalg.norm(np.diff(strands, axis=1), axis=2).sum(axis=1)  # errors are relative to these
    timings["read"] = time.perf_counter() - start
    asset, binding, inside, normals = None, None, 0, np.zeros((len(strands), 3))
    scalp = options.scalp
    if scalp:
        from baker import readers

        asset = readers.read(scalp, max_memory=max_memory)
    else:  # the groom file's own emitter mesh (a ``baker hair`` output holds it), when it has one
        from baker.geometry.asset import Asset
        from baker.readers.scalp import read_scalp

        doc = read_scalp(groom_path, max_memory=max_memory)
        asset, scalp = (Asset(doc=doc, source=Path(groom_path)), groom_path) if doc is not None else (None, None)
    if asset is not None:
        from baker.memory import check_bake

        check_bake(asset, (), None, max_memory, "binding roots to this scalp")
        # the hair is written under the scalp's node (glTF) or with its transform (USD): work in its mesh space
        from baker.techniques.hair.usd import emitter_world_matrix

        matrix = emitter_world_matrix(asset.doc.json, 0)
        if abs(np.linalg.det(matrix[:3, :3])) < 1e-300:
            raise BakerError(scalp, "the node drawing the scalp mesh has a singular transform")
        inverse = np.linalg.inv(matrix)
        strands = strands @ inverse[:3, :3].T + inverse[:3, 3]
        binding, strands, normals, inside = bind_to_scalp(asset, strands, options.seed)
        lengths = np.linalg.norm(np.diff(strands, axis=1), axis=2).sum(axis=1)
    with progress.task("guides", 3) as advance:
        t = time.perf_counter()
        solution = solve_guides(strands, lengths, options.guides, candidates=options.candidates,
                                locality=options.locality, iterations=options.iterations, seed=options.seed)
        timings["solve"] = time.perf_counter() - t
        advance(2)
        t = time.perf_counter()
        counts = lod_counts(len(strands), options.lods)
        order = progressive_order(strands[:, 0], counts, options.seed)
        timings["lods"] = time.perf_counter() - t
        advance(1)
    root_width, tip_width, width_scale = width_model(widths, lengths)
    v = options.vertices_per_strand
    g = solution.guides
    rest = lengths / (v - 1)
    guide_set = StrandSet(strands[g], width_scale[g], rest[g], normals[g])
    child_set = StrandSet(strands[order], width_scale[order], rest[order], normals[order],
                          guide_ids=solution.ids[order], guide_weights=solution.weights[order])
    length = float(np.median(lengths))
    result = HairResult(guide_set, child_set, length, root_width, tip_width, 0.0)
    lods = [{"strandCount": int(n), "widthScale": float(len(strands) / n)} for n in counts]
    stats = dict(solution.stats, seconds=timings, stillInside=int(inside))
    bake = GuidesBake(result, solution, lods, groom.skipped or {}, asset, stats=stats)
    if binding is not None:
        pick = lambda b, idx: RootBinding(b.mesh, b.primitive[idx], b.triangle[idx], b.barycentrics[idx])  # noqa
        bake.child_binding, bake.guide_binding = pick(binding, order), pick(binding, g)
    return bake


# ------------------------------------------------------------------------------------------------------------ write
def _binding_json(doc, binding: RootBinding) -> dict:
    return {"mesh": int(binding.mesh),
            "primitives": doc.add_accessor(binding.primitive.astype(np.uint32), target=None),
            "triangles": doc.add_accessor(binding.triangle.astype(np.uint32), target=None),
            "barycentrics": doc.add_accessor(binding.barycentrics.astype(np.float32), target=None)}


def groom_attributes(doc, result, shading, has_scalp: bool):
    """(guide attributes, child attributes, material keywords): the children are every strand of the groom, so the
    precomputes are theirs and each guide, one of them, takes its own strand's values (tracing both sets would
    let a guide occlude its own copy)."""
    from baker.techniques.hair.extension import mesh_triangles
    from baker.techniques.hair_shading.strands import strand_attributes

    (child_extra,), kwargs = strand_attributes(shading, [result.children], result.root_width, result.tip_width,
                                               scalp=mesh_triangles(doc, 0) if has_scalp else None)
    s, v = result.children.positions.shape[:2]
    rows = {result.children.positions[i].tobytes(): i for i in range(s)}
    pick = np.array([rows[g.tobytes()] for g in result.guides.positions], np.int64)
    guide_extra = {}
    for name, values in child_extra.items():
        per_strand = values.reshape(s, v, *values.shape[1:])
        guide_extra[name] = per_strand[pick].reshape(len(pick) * v, *values.shape[1:])
    return guide_extra, child_extra, kwargs


def write_gltf(bake: GuidesBake, output, shading=None) -> None:
    from baker.gltf.document import GltfDocument
    from baker.techniques.hair.extension import NAME, add_hair_node, write_strand_primitive
    from baker.techniques.hair_shading.extension import add_hair_material
    from baker.techniques.hair_shading.options import HairMaterialOptions

    doc = bake.asset.doc if bake.asset is not None else GltfDocument()
    result = bake.result
    shading = shading or HairMaterialOptions()
    guide_extra, child_extra, kwargs = groom_attributes(doc, result, shading, bake.asset is not None)
    fibre_count = kwargs.pop("fibreCount", None)
    material = add_hair_material(doc, shading, fibre_count=fibre_count, **kwargs)
    guides = write_strand_primitive(doc, result.guides, strand_set="guides", result=result, material=material,
                                    extra_attributes=guide_extra)
    children = write_strand_primitive(doc, result.children, strand_set="children", result=result,
                                      material=material, guide_primitive=0, extra_attributes=child_extra)
    gext, cext = guides["extensions"][NAME], children["extensions"][NAME]
    gext["order"] = "none"
    cext["order"] = "lodPrefix"
    cext["guides"]["interpolation"] = "offset"
    cext["lods"] = bake.lods
    if bake.child_binding is not None:
        gext["rootBinding"] = _binding_json(doc, bake.guide_binding)
        cext["rootBinding"] = _binding_json(doc, bake.child_binding)
    meshes = doc.json.setdefault("meshes", [])
    meshes.append({"name": "hair", "primitives": [guides, children]})
    add_hair_node(doc, len(meshes) - 1, 0 if bake.asset is not None else None, "hair")
    doc.use_extension(NAME)
    doc.save(output)


def write_usd(bake: GuidesBake, output, curve_type: str, shading=None) -> None:
    from baker.gltf.document import GltfDocument
    from baker.registry import usd_primitive_hooks
    from baker.techniques.hair.usd import write_hair_usd

    def annotate(stage):
        from pxr import Sdf, UsdGeom, Vt

        hair = stage.GetPrimAtPath("/Root/Hair")
        hair.CreateAttribute("baker:hair:interpolation", Sdf.ValueTypeNames.String, custom=True).Set("offset")
        hair.CreateAttribute("baker:hair:lod:strandCounts", Sdf.ValueTypeNames.IntArray, custom=True).Set(
            Vt.IntArray([lod["strandCount"] for lod in bake.lods]))
        hair.CreateAttribute("baker:hair:lod:widthScales", Sdf.ValueTypeNames.FloatArray, custom=True).Set(
            Vt.FloatArray([lod["widthScale"] for lod in bake.lods]))
        for name, binding in (("guides", bake.guide_binding), ("children", bake.child_binding)):
            if binding is None:
                continue
            api = UsdGeom.PrimvarsAPI(stage.GetPrimAtPath(f"/Root/Hair/{name}"))
            api.CreatePrimvar("baker:rootPrimitive", Sdf.ValueTypeNames.IntArray, UsdGeom.Tokens.uniform).Set(
                Vt.IntArray.FromNumpy(binding.primitive.astype(np.int32)))
            api.CreatePrimvar("baker:rootTriangle", Sdf.ValueTypeNames.IntArray, UsdGeom.Tokens.uniform).Set(
                Vt.IntArray.FromNumpy(binding.triangle.astype(np.int32)))
            api.CreatePrimvar("baker:rootBarycentrics", Sdf.ValueTypeNames.Float3Array, UsdGeom.Tokens.uniform).Set(
                Vt.Vec3fArray.FromNumpy(binding.barycentrics.astype(np.float32)))

    doc = bake.asset.doc if bake.asset is not None else GltfDocument()
    material = usd_groom_material(bake, doc, shading)

    def hook(stage):
        annotate(stage)
        material(stage)

    write_hair_usd(doc, bake.result, 0, output, curve_type, usd_primitive_hooks(), hair_hook=hook)


def usd_groom_material(bake: GuidesBake, doc, shading):
    """The hook binding the hair material to the guides and children curves, with their precomputes (the
    children's, each guide its own strand's, as :func:`groom_attributes`)."""
    from baker.techniques.hair_shading.options import HairMaterialOptions
    from baker.techniques.hair_shading.usd import write_strand_material

    shading = shading or HairMaterialOptions()
    guide_extra, child_extra, kwargs = groom_attributes(doc, bake.result, shading, bake.asset is not None)
    return lambda stage: write_strand_material(stage, ["/Root/Hair/guides", "/Root/Hair/children"], shading,
                                               [guide_extra, child_extra], kwargs)


def sidecar_paths(output) -> tuple[Path, Path]:
    """The children ``.tfx`` and the ``.weights`` file written beside a ``.tfx`` guides file."""
    output = Path(output)
    return output.with_name(output.stem + ".children.tfx"), output.with_name(output.stem + ".weights")


def encode_weights(ids: np.ndarray, weights: np.ndarray, guide_count: int) -> bytes:
    """``<stem>.weights``: header (magic "BKHW", uint32 version 1, strand count S, guide count N), then
    uint32[S][3] guide ids, then float32[S][3] weights, little-endian."""
    head = WEIGHTS_HEADER.pack(WEIGHTS_MAGIC, 1, len(ids), int(guide_count))
    return head + np.asarray(ids, "<u4").tobytes() + np.asarray(weights, "<f4").tobytes()


def write_tfx_files(bake: GuidesBake, output) -> None:
    from baker.gltf.atomic import write_files_atomic
    from baker.techniques.hair.tfx import encode_tfx

    children_path, weights_path = sidecar_paths(output)
    g, c = bake.result.guides, bake.result.children
    write_files_atomic([
        (children_path, encode_tfx(c.positions, thickness=c.width_scale)),
        (weights_path, encode_weights(c.guide_ids, c.guide_weights, g.count)),
        (Path(output), encode_tfx(g.positions, thickness=g.width_scale))])


def write_output(bake: GuidesBake, output, options: GuidesOptions, shading=None) -> None:
    """Write the guides as ``output``'s suffix says; ``shading``: the hair material's options
    (:class:`~baker.techniques.hair_shading.options.HairMaterialOptions`, default when None)."""
    suffix = Path(output).suffix.lower()
    if suffix in (".glb", ".gltf"):
        write_gltf(bake, output, shading)
    elif suffix in (".usda", ".usdc", ".usd"):
        write_usd(bake, output, options.curve_type, shading)
    else:
        write_tfx_files(bake, output)


def summary(bake: GuidesBake, input_path, output) -> dict:
    r = bake.result
    return {"input": str(input_path), "output": str(output), "strands": int(r.children.count),
            "skipped": dict(bake.skipped), "guides": int(r.guides.count),
            "verticesPerStrand": int(r.guides.vertices), "rmsError": bake.stats["rmsError"],
            "maxError": bake.stats["maxError"], "lods": bake.lods,
            "seconds": {k: round(v, 3) for k, v in bake.stats["seconds"].items()}}
