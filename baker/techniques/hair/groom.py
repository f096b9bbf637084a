"""Grooms in: dense hair curves from USD ``BasisCurves``, glTF ``LINES``/``LINE_STRIP`` (incl. ``BAKER_hair``) or
TressFX ``.tfx``, as one ragged set of polylines in world space, checked before use.

A :class:`Groom` is ``points`` (P, 3) + ``counts`` (S,) (vertices per curve, root first) + optional per-vertex
``widths`` (P,). Cubic USD curves are read as their control polylines (for Catmull-Rom and B-spline hair the control
points lie on or next to the curve; resampling to a fixed vertex count follows them by arc length).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from baker.errors import BakerError

GROOM_SUFFIXES = (".usd", ".usda", ".usdc", ".usdz", ".gltf", ".glb", ".tfx")
MODE_LINES, MODE_LINE_STRIP = 1, 3


@dataclass
class Groom:
    points: np.ndarray  # (P, 3) float64, world space, curve after curve, root first
    counts: np.ndarray  # (S,) int64 vertices per curve
    widths: np.ndarray | None = None  # (P,) float64 per-vertex width, world units, or None
    skipped: dict | None = None  # reason -> number of curves dropped by :func:`clean_groom`

    @property
    def count(self) -> int:
        return len(self.counts)


def _concat(parts: list, path) -> Groom:
    if not parts:
        raise BakerError(path, "no hair curves found (USD BasisCurves, glTF LINES/LINE_STRIP or TressFX strands)")
    points = np.concatenate([p for p, _, _ in parts]).astype(np.float64)
    counts = np.concatenate([c for _, c, _ in parts]).astype(np.int64)
    widths = None  # one width model per groom: when some curves have none, none are kept
    if all(w is not None for _, _, w in parts):
        widths = np.concatenate([w for _, _, w in parts]).astype(np.float64)
    return Groom(points, counts, widths)


# ------------------------------------------------------------------------------------------------------------ USD
def read_usd_groom(path) -> Groom:
    """Every visible ``UsdGeom.BasisCurves`` of the stage (instance proxies included), points moved by the prim's local-to-world transform, widths
    (constant, uniform, vertex or varying when it has one value per point) scaled by the transform's mean scale."""
    from pxr import Usd, UsdGeom

    try:
        stage = Usd.Stage.Open(str(path))
    except Exception as exc:  # pxr raises Tf.ErrorException with a multi-line message: keep its first commentary
        text = next((str(getattr(a, "commentary", "")).strip() for a in exc.args
                     if str(getattr(a, "commentary", "")).strip()), str(exc))
        raise BakerError(path, f"cannot open USD stage: {' '.join(text.split())[:300]}") from None
    if stage is None:
        raise BakerError(path, "cannot open USD stage")
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
    return _concat(parts, path)


# ----------------------------------------------------------------------------------------------------------- glTF
def line_chains(segments: np.ndarray, vertex_count: int) -> list[np.ndarray]:
    """Polylines (vertex index arrays, first vertex = the one no segment enters) of a LINES segment list in which
    every vertex starts at most one segment and ends at most one; raises ValueError otherwise."""
    a, b = segments[:, 0], segments[:, 1]
    if len(a) == 0:
        return []
    if (np.bincount(a, minlength=vertex_count) > 1).any() or (np.bincount(b, minlength=vertex_count) > 1).any():
        raise ValueError("LINES segments branch (a vertex starts or ends two segments): not a set of strands")
    following = np.full(vertex_count, -1, np.int64)
    following[a] = b
    entered = np.zeros(vertex_count, bool)
    entered[b] = True
    roots = np.flatnonzero((following >= 0) & ~entered)
    chains = [[r] for r in roots.tolist()]
    current = roots.copy()
    alive = np.arange(len(roots))
    steps = 0
    while len(alive):
        current = following[current]
        keep = current >= 0
        alive, current = alive[keep], current[keep]
        for i, c in zip(alive.tolist(), current.tolist()):
            chains[i].append(c)
        steps += 1
        if steps > vertex_count:
            raise ValueError("LINES segments form a cycle")
    return [np.asarray(c, np.int64) for c in chains]


def read_gltf_groom(path) -> Groom:
    """The strands of every ``LINES``/``LINE_STRIP`` primitive drawn by a node of the default scene, in world space.
    A mesh with ``BAKER_hair`` children contributes its children only (its guides are a subset of what they show)."""
    from baker.gltf.document import GltfDocument, world_nodes

    doc = GltfDocument.load(path)
    gltf = doc.json
    meshes = gltf.get("meshes") or []
    parts = []
    for node, matrix in world_nodes(gltf):
        m = (gltf["nodes"][node]).get("mesh")
        if m is None or not (0 <= m < len(meshes)):
            continue
        prims = meshes[m].get("primitives") or []
        hair = [(prim.get("extensions") or {}).get("BAKER_hair") for prim in prims]
        has_children = any(isinstance(h, dict) and h.get("strandSet") == "children" for h in hair)
        scale = abs(float(np.linalg.det(matrix[:3, :3]))) ** (1.0 / 3.0)
        for p, prim in enumerate(prims):
            mode = prim.get("mode", 4)
            if mode not in (MODE_LINES, MODE_LINE_STRIP):
                continue
            ext = hair[p] if isinstance(hair[p], dict) else None
            if ext is not None and has_children and ext.get("strandSet") != "children":
                continue
            where = f"/meshes/{m}/primitives/{p}"
            if "POSITION" not in prim.get("attributes", {}):
                raise BakerError(path, f"{where}/attributes: a line primitive without POSITION")
            positions = np.asarray(doc.accessor(prim["attributes"]["POSITION"]), np.float64).reshape(-1, 3)
            positions = positions @ matrix[:3, :3].T + matrix[:3, 3]
            n = len(positions)
            if ext is not None:
                s, v = ext.get("strandCount"), ext.get("verticesPerStrand")
                if not (isinstance(s, int) and isinstance(v, int)) or s < 1 or v < 1 or s * v != n:
                    raise BakerError(path, f"{where}/extensions/BAKER_hair: strandCount x verticesPerStrand does "
                                           f"not match POSITION count {n}")
                scales = np.ones(s)
                if isinstance(ext.get("widthScale"), int) and 0 <= ext["widthScale"] < len(gltf["accessors"]):
                    scales = np.asarray(doc.accessor(ext["widthScale"]), np.float64).reshape(-1)
                    if len(scales) != s:
                        raise BakerError(path, f"{where}/extensions/BAKER_hair/widthScale: {len(scales)} values "
                                               f"for {s} strands")
                t = np.tile(np.linspace(0.0, 1.0, v), s)
                root, tip = float(ext.get("rootWidth", 0.0)), float(ext.get("tipWidth", 0.0))
                widths = (root + (tip - root) * t) * np.repeat(scales, v) * scale
                parts.append((positions, np.full(s, v, np.int64), widths))
                continue
            if "indices" in prim:
                index = np.asarray(doc.accessor(prim["indices"]), np.int64).reshape(-1)
                if len(index) and (index.min() < 0 or index.max() >= n):
                    raise BakerError(path, f"{where}/indices: index out of range of POSITION ({n})")
            else:
                index = np.arange(n, dtype=np.int64)
            if mode == MODE_LINE_STRIP:
                chains = [index] if len(index) else []
            else:
                try:
                    chains = line_chains(index[: len(index) // 2 * 2].reshape(-1, 2), n)
                except ValueError as exc:
                    raise BakerError(path, f"{where}/indices: {exc}") from None
            if chains:
                order = np.concatenate(chains)
                parts.append((positions[order], np.array([len(c) for c in chains], np.int64), None))
    return _concat(parts, path)


# -------------------------------------------------------------------------------------------------------- TressFX
def read_tfx_groom(path) -> Groom:
    """TressFX strands (sizes checked against the file length by :func:`baker.techniques.hair.tfx.decode_tfx`);
    the per-strand thickness becomes a constant per-vertex width."""
    from baker.techniques.hair.tfx import decode_tfx

    try:
        tfx = decode_tfx(Path(path).read_bytes())
    except ValueError as exc:
        raise BakerError(path, str(exc)) from None
    s, v = tfx.positions.shape[:2]
    widths = np.repeat(tfx.thickness.astype(np.float64), v) if tfx.thickness is not None else None
    return Groom(tfx.positions[..., :3].reshape(-1, 3).astype(np.float64), np.full(s, v, np.int64), widths)


def read_groom(path) -> Groom:
    path = Path(path)
    if not path.is_file():
        raise BakerError(path, "file not found")
    suffix = path.suffix.lower()
    if suffix in (".usd", ".usda", ".usdc", ".usdz"):
        return read_usd_groom(path)
    if suffix in (".gltf", ".glb"):
        return read_gltf_groom(path)
    if suffix == ".tfx":
        return read_tfx_groom(path)
    raise BakerError(path, f"unsupported groom type (use one of {' '.join(GROOM_SUFFIXES)})")


# ----------------------------------------------------------------------------------------------------------- clean
def clean_groom(groom: Groom, path, bad_curves: str = "skip") -> Groom:
    """Drop (or, with ``bad_curves='error'``, refuse) curves with fewer than 2 vertices, non-finite points or
    widths, or zero length; the counts per reason land in ``Groom.skipped``."""
    counts = groom.counts
    curve_of_point = np.repeat(np.arange(len(counts)), counts)
    finite = np.isfinite(groom.points).all(axis=1)
    if groom.widths is not None:
        finite &= np.isfinite(groom.widths)
    curve_finite = np.ones(len(counts), bool)
    np.logical_and.at(curve_finite, curve_of_point, finite)
    seg = np.linalg.norm(np.diff(groom.points, axis=0), axis=1)
    same_curve = curve_of_point[1:] == curve_of_point[:-1]
    seg = np.where(same_curve & np.isfinite(seg), seg, 0.0)
    length = np.zeros(len(counts))
    np.add.at(length, curve_of_point[1:][same_curve], seg[same_curve])
    reasons = {
        "fewer than 2 vertices": counts < 2,
        "non-finite points": (counts >= 2) & ~curve_finite,
    }
    reasons["zero length"] = (counts >= 2) & curve_finite & ~(length > 1e-12 * max(1.0, float(np.abs(
        groom.points[finite]).max()) if finite.any() else 1.0))
    bad = np.zeros(len(counts), bool)
    skipped = {}
    for reason, mask in reasons.items():
        if mask.any():
            if bad_curves == "error":
                first = int(np.flatnonzero(mask)[0])
                raise BakerError(path, f"curve {first}: {reason} ({int(mask.sum())} such curves; "
                                       "--bad-curves skip drops them)")
            skipped[reason] = int(mask.sum())
            bad |= mask
    keep_curve = ~bad
    if not keep_curve.any():
        raise BakerError(path, f"no usable curve: {', '.join(f'{n} {r}' for r, n in skipped.items())}")
    keep_point = keep_curve[curve_of_point]
    return Groom(groom.points[keep_point], counts[keep_curve],
                 None if groom.widths is None else groom.widths[keep_point], skipped)
