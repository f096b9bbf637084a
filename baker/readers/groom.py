"""A groom read from a file: dense hair curves as one ragged set of polylines in world space, checked before use.
Each format's reader (``read_groom`` of :mod:`baker.readers.usd` for ``BasisCurves``, :mod:`baker.readers.gltf` for
``LINES``/``LINE_STRIP`` and ``BAKER_hair``, :mod:`baker.readers.tfx` for TressFX) returns one;
:func:`baker.readers.read_groom` picks the reader by suffix.

A :class:`Groom` is ``points`` (P, 3) + ``counts`` (S,) (vertices per curve, root first) + optional per-vertex
``widths`` (P,). Cubic USD curves are read as their control polylines (for Catmull-Rom and B-spline hair the control
points lie on or next to the curve; resampling to a fixed vertex count follows them by arc length).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from baker.errors import BakerError


@dataclass
class Groom:
    points: np.ndarray  # (P, 3) float64, world space, curve after curve, root first
    counts: np.ndarray  # (S,) int64 vertices per curve
    widths: np.ndarray | None = None  # (P,) float64 per-vertex width, world units, or None
    skipped: dict | None = None  # reason -> number of curves dropped by :func:`clean_groom`

    @property
    def count(self) -> int:
        return len(self.counts)


def concat_curves(parts: list, path) -> Groom:
    """One groom of the ``(points, counts, widths)`` parts a file holds (its prims or primitives), in order."""
    if not parts:
        raise BakerError(path, "no hair curves found (USD BasisCurves, glTF LINES/LINE_STRIP or TressFX strands)")
    points = np.concatenate([p for p, _, _ in parts]).astype(np.float64)
    counts = np.concatenate([c for _, c, _ in parts]).astype(np.int64)
    widths = None  # one width model per groom: when some curves have none, none are kept
    if all(w is not None for _, _, w in parts):
        widths = np.concatenate([w for _, _, w in parts]).astype(np.float64)
    return Groom(points, counts, widths)


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
