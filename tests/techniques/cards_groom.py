"""An independent dense groom for the hair-card tests and benchmark: written as USD BasisCurves by pxr directly
(not by baker's grower). A head (sphere of radius 0.1 m) with clumps of strands leaving the scalp at a shallow
angle, falling under gravity, tips pulled together per clump, some clumps curly (a helix around the clump's path,
each strand with its own phase jitter), lengths varying per clump and per strand, 20..48 vertices per curve,
per-vertex widths tapering to the tip, split over two prims (one with a transform)."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

HEAD_RADIUS = 0.1


def _unit(v):
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-300)


def clump_paths(centres: np.ndarray, lengths: np.ndarray, steps: int, rng) -> np.ndarray:
    """(C, steps, 3) paths from each clump centre on the head: out at a shallow angle, bending down, kept outside
    the head."""
    n = _unit(centres)
    down = np.array([0.0, -1.0, -0.35])
    direction = _unit(0.3 * n + (down - np.einsum("ci,i->c", n, down)[:, None] * n) + 0.2 * rng.normal(size=n.shape))
    paths = np.empty((len(centres), steps, 3))
    p = centres.copy()
    h = lengths / (steps - 1)
    for j in range(steps):
        paths[:, j] = p
        direction = _unit(direction + np.array([0.0, -0.09, 0.0]))
        p = p + direction * h[:, None]
        r = np.linalg.norm(p, axis=1)
        outside = np.maximum(r, HEAD_RADIUS * 1.02)
        p = p * (outside / r)[:, None]
    return paths


def make_groom(strands: int = 4000, clumps: int = 120, seed: int = 11):
    """(curves: list of (n_i, 3) arrays, widths: list of (n_i,) arrays)."""
    rng = np.random.default_rng(seed)
    # clump centres on the scalp: the upper and back part of the head
    z = rng.uniform(-0.35, 1.0, 4 * clumps)
    phi = rng.uniform(0, 2 * math.pi, 4 * clumps)
    pts = np.stack([np.sqrt(1 - z ** 2) * np.cos(phi), z, np.sqrt(1 - z ** 2) * np.sin(phi)], axis=1)
    pts = pts[(pts[:, 2] < 0.55) | (pts[:, 1] > 0.6)][:clumps]  # no hair on the face
    centres = pts * HEAD_RADIUS
    c = len(centres)
    steps = 64
    clump_length = rng.uniform(0.16, 0.26, c)
    paths = clump_paths(centres, clump_length, steps, rng)
    tangents = _unit(np.gradient(paths, axis=1))
    side = _unit(np.cross(tangents, _unit(paths)))
    up = np.cross(side, tangents)
    curl_amp = np.where(rng.random(c) < 0.4, rng.uniform(0.003, 0.008, c), 0.0)
    curl_turns = rng.uniform(3.0, 6.0, c)
    tighten = rng.uniform(0.4, 0.8, c)
    owner = rng.integers(0, c, strands)
    curves, widths = [], []
    t = np.linspace(0.0, 1.0, steps)
    for i in range(strands):
        k = owner[i]
        spread = rng.normal(0.0, 0.005, 2)
        offset0 = spread[0] * side[k, 0] + spread[1] * up[k, 0] * 0.3  # roots on the scalp, near the clump centre
        taper = 1.0 - tighten[k] * t ** 0.7
        phase = 2 * math.pi * curl_turns[k] * t + rng.normal(0.0, 0.4)
        curl = curl_amp[k] * (np.cos(phase)[:, None] * side[k] + np.sin(phase)[:, None] * up[k])
        jitter = np.cumsum(rng.normal(0.0, 0.0004, (steps, 3)), axis=0) * t[:, None]
        curve = paths[k] + offset0[None] * taper[:, None] + curl * np.minimum(1.0, 8 * t)[:, None] + jitter
        stretch = rng.uniform(0.85, 1.05)  # strands of a clump differ in length: cut at a fraction
        keep = max(8, int(round(steps * stretch)))
        curve = curve[: min(keep, steps)]
        n = int(rng.integers(20, 49))
        seg = np.linalg.norm(np.diff(curve, axis=0), axis=1)
        arc = np.concatenate([[0.0], np.cumsum(seg)])
        s = np.linspace(0.0, arc[-1], n)
        curves.append(np.stack([np.interp(s, arc, curve[:, d]) for d in range(3)], axis=1))
        widths.append(np.linspace(8e-5, 3e-5, n))
    return curves, widths


def write_groom_usd(path: Path, curves, widths, offset=(0.05, 0.0, 0.0)) -> Path:
    """Two BasisCurves prims by pxr; the second translated by ``offset`` (its points stored minus it)."""
    from pxr import Gf, Usd, UsdGeom, Vt

    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    half = len(curves) // 2
    for k, (part, part_w) in enumerate(((curves[:half], widths[:half]), (curves[half:], widths[half:]))):
        prim = UsdGeom.BasisCurves.Define(stage, f"/Groom/part{k}")
        prim.CreateTypeAttr(UsdGeom.Tokens.linear)
        points = np.concatenate(part)
        if k == 1:
            points = points - np.asarray(offset)
            UsdGeom.Xformable(prim).AddTranslateOp().Set(Gf.Vec3d(*offset))
        prim.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(points.astype(np.float32)))
        prim.CreateCurveVertexCountsAttr(Vt.IntArray([len(c) for c in part]))
        prim.CreateWidthsAttr(Vt.FloatArray.FromNumpy(np.concatenate(part_w).astype(np.float32)))
        prim.SetWidthsInterpolation(UsdGeom.Tokens.vertex)
    stage.GetRootLayer().Save()
    return Path(path)
