"""Hair as USD: one ``UsdGeom.BasisCurves`` per strand set, beside the emitter written by :mod:`baker.gltf.usd`.

Per strand set (``/Root/Hair/guides``, ``/Root/Hair/children``):

- ``curveVertexCounts`` (all ``verticesPerStrand``), ``points`` (root first), ``extent``;
- ``type`` ``linear``, or ``cubic`` with ``basis`` ``catmullRom`` or ``bspline`` and ``wrap`` ``pinned`` (the
  curve starts at the root and ends at the tip, USD >= 21.11);
- ``widths`` per vertex (``vertex`` interpolation): ``mix(rootWidth, tipWidth, param) * widthScale``;
- primvars ``baker:strandParam`` (float, vertex: 0 root .. 1 tip), ``baker:widthScale`` (float, uniform),
  and for children ``baker:guideIds`` (int3, uniform: indices of curves in ``guides``) and ``baker:guideWeights``
  (float3, uniform, >= 0, summing to 1);
- custom attributes ``baker:hair:*`` on ``/Root/Hair`` (length, widths, counts), as for material extensions.

``/Root/Hair`` carries the world transform of the first node that draws the emitter mesh, so the curves sit on it.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from baker.techniques.hair.kernel import HairResult, StrandSet
from baker.errors import BakerError


def emitter_world_matrix(gltf: dict, emitter_mesh: int) -> np.ndarray:
    """World matrix of the first node drawing ``emitter_mesh`` (the one the hair node hangs under), else identity."""
    from baker.gltf.document import node_matrix

    nodes = gltf.get("nodes", [])
    parent = {c: i for i, n in enumerate(nodes) for c in n.get("children", [])}
    for i, n in enumerate(nodes):
        if n.get("mesh") == emitter_mesh:
            m, j, depth = np.eye(4), i, 0
            while j is not None and depth <= len(nodes):
                m = node_matrix(nodes[j]) @ m
                j, depth = parent.get(j), depth + 1
            return m
    return np.eye(4)


def _curves(stage, path: str, strands: StrandSet, result: HairResult, curve_type: str):
    from pxr import Gf, Sdf, UsdGeom, Vt

    s, v = strands.count, strands.vertices
    curves = UsdGeom.BasisCurves.Define(stage, path)
    if curve_type == "linear":
        curves.CreateTypeAttr(UsdGeom.Tokens.linear)
    else:
        curves.CreateTypeAttr(UsdGeom.Tokens.cubic)
        curves.CreateBasisAttr(UsdGeom.Tokens.catmullRom if curve_type == "catmullRom" else UsdGeom.Tokens.bspline)
        curves.CreateWrapAttr(UsdGeom.Tokens.pinned)
    points = strands.positions.reshape(-1, 3).astype(np.float32)
    curves.CreateCurveVertexCountsAttr(Vt.IntArray([int(v)] * s))
    curves.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(points))
    param = np.tile(np.linspace(0.0, 1.0, v, dtype=np.float32), s)
    widths = ((result.root_width + (result.tip_width - result.root_width) * param)
              * np.repeat(strands.width_scale, v)).astype(np.float32)
    curves.CreateWidthsAttr(Vt.FloatArray.FromNumpy(widths))
    curves.SetWidthsInterpolation(UsdGeom.Tokens.vertex)
    half = float(widths.max()) / 2 if len(widths) else 0.0
    lo, hi = points.min(0) - half, points.max(0) + half
    curves.CreateExtentAttr(Vt.Vec3fArray([Gf.Vec3f(*map(float, lo)), Gf.Vec3f(*map(float, hi))]))
    api = UsdGeom.PrimvarsAPI(curves.GetPrim())
    api.CreatePrimvar("baker:strandParam", Sdf.ValueTypeNames.FloatArray, UsdGeom.Tokens.vertex).Set(
        Vt.FloatArray.FromNumpy(param))
    api.CreatePrimvar("baker:widthScale", Sdf.ValueTypeNames.FloatArray, UsdGeom.Tokens.uniform).Set(
        Vt.FloatArray.FromNumpy(strands.width_scale.astype(np.float32)))
    if strands.guide_ids is not None:
        api.CreatePrimvar("baker:guideIds", Sdf.ValueTypeNames.Int3Array, UsdGeom.Tokens.uniform).Set(
            Vt.Vec3iArray.FromNumpy(strands.guide_ids.astype(np.int32)))
        api.CreatePrimvar("baker:guideWeights", Sdf.ValueTypeNames.Float3Array, UsdGeom.Tokens.uniform).Set(
            Vt.Vec3fArray.FromNumpy(strands.guide_weights.astype(np.float32)))
    return curves


def write_hair_usd(doc, result: HairResult, emitter_mesh: int, path, curve_type: str = "linear",
                   primitive_hooks=None, hair_hook=None) -> None:
    """Write the emitter asset (as :func:`baker.gltf.usd.write_usd` does, with the same ``primitive_hooks``) plus the
    hair curves, atomically; ``hair_hook(stage)``, when given, adds to the hair prims before the file is written."""
    from pxr import Gf, UsdGeom

    from baker.gltf.usd import build_stage, custom_attributes, write_stage_and_textures

    path = Path(path)
    if path.suffix.lower() not in (".usda", ".usdc", ".usd"):
        raise BakerError(path, "hair USD output must end in .usda, .usdc or .usd")
    folder = f"{path.stem}_textures"
    from baker.registry import usd_primitive_accessors, usd_texture_color_spaces, vertex_attribute_widths

    stage, images = build_stage(doc, folder, primitive_hooks, vertex_attribute_widths(),
                                 usd_texture_color_spaces(), usd_primitive_accessors())
    hair = UsdGeom.Xform.Define(stage, "/Root/Hair")
    matrix = emitter_world_matrix(doc.json, emitter_mesh)
    if not np.array_equal(matrix, np.eye(4)):
        hair.AddTransformOp().Set(Gf.Matrix4d(matrix.T.tolist()))
    custom_attributes(hair.GetPrim(), "baker:hair", {
        "length": float(result.length), "rootWidth": float(result.root_width), "tipWidth": float(result.tip_width),
        "guideCount": int(result.guides.count), "childCount": int(result.children.count),
        "verticesPerStrand": int(result.guides.vertices)})
    _curves(stage, "/Root/Hair/guides", result.guides, result, curve_type)
    if result.children.count:
        _curves(stage, "/Root/Hair/children", result.children, result, curve_type)
    if hair_hook is not None:
        hair_hook(stage)
    write_stage_and_textures(stage, path, [(path.parent / folder / name, data) for name, data in images])
