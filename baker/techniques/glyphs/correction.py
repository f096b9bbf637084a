"""MSDF error correction: texels whose bilinear interpolation puts the median's edge in the wrong place.

Between texel centres a renderer interpolates each channel bilinearly and then takes the median. Where neighbouring
texels' channels come from different edges (thin stems, edges of one color passing near another contour, the
inside of overlapping contours) the median of the interpolated channels can cross 0.5 far from any real edge:
a spurious dent, hole or blob (Chlumsky, Sloup, Šimeček, *Improved Corners with Multi-Channel Signed Distance
Fields*, Computer Graphics Forum 2018, section 4; msdfgen's distance-checked error correction).

The check uses the exact distance field the kernel already computed at every texel (``true``), which interpolates
almost exactly away from corners: for every cell of four texel centres, the median of the interpolated channels is
compared with the interpolated true distance on a 5 x 5 grid of points. A cell where they disagree in sign while
the true distance says the point is farther than ``tolerance`` pixels from the outline holds an artifact. Its
texels that carry real multi-channel information (channel spread) and are not *protected* become single-channel:
their channels take their own median, so the texel-centre value is unchanged and interpolation around it behaves
like a pseudo-SDF. Texels of the cell around every colored corner are protected: there the true field is rounded
and the MSDF is right. By default (``passes=1``) protected texels are never changed, as in msdfgen's edge-priority
mode; a second pass that also flattened them (``passes=2``) rounded more corners than it removed artifacts (2% more
wrong pixels on Noto Sans CJK, benchmarks/RESULTS.md, issue 19 fidelity).
"""
from __future__ import annotations

import math

import numba
import numpy as np

TOLERANCE_PX = 0.5  # how far from the outline (true distance, pixels) a sign disagreement counts as an artifact
SAMPLES = 5  # per cell and axis, at (k + .5) / 5: odd, so the cell midpoint (where clashes peak) is one


@numba.njit(cache=True)
def _median3(a, b, c):
    return max(min(a, b), min(max(a, b), c))


@numba.njit(cache=True)
def _bilinear(v00, v01, v10, v11, u, v):
    return (1.0 - v) * ((1.0 - u) * v00 + u * v01) + v * ((1.0 - u) * v10 + u * v11)


@numba.njit(cache=True)
def _correct_glyph(values, true, base, w, h, corners, c0, c1, distance_range, tolerance, passes):
    protected = np.zeros((h, w), np.bool_)
    for k in range(c0, c1):
        j0 = int(math.floor(corners[k, 0] - 0.5))
        i0 = int(math.floor(corners[k, 1] - 0.5))
        for di in range(2):
            for dj in range(2):
                i, j = i0 + di, j0 + dj
                if 0 <= i < h and 0 <= j < w:
                    protected[i, j] = True
    tol = tolerance / distance_range
    fix = np.zeros((h, w), np.bool_)
    for pass_ in range(passes):
        # the last pass may also fix protected texels: a hole or blob is worse than a slightly rounder corner
        ignore_protection = pass_ == passes - 1 and passes > 1
        fix[:] = False
        any_fix = False
        for i in range(h - 1):
            for j in range(w - 1):
                t00, t01 = base + i * w + j, base + i * w + j + 1
                t10, t11 = t00 + w, t01 + w
                bad = False
                for a in range(SAMPLES):
                    v = (a + 0.5) / SAMPLES
                    for b in range(SAMPLES):
                        u = (b + 0.5) / SAMPLES
                        tt = _bilinear(true[t00], true[t01], true[t10], true[t11], u, v) - 0.5
                        if abs(tt) <= tol:
                            continue
                        m = _median3(_bilinear(values[t00, 0], values[t01, 0], values[t10, 0], values[t11, 0], u, v),
                                     _bilinear(values[t00, 1], values[t01, 1], values[t10, 1], values[t11, 1], u, v),
                                     _bilinear(values[t00, 2], values[t01, 2], values[t10, 2], values[t11, 2], u, v))
                        if (m - 0.5 > 0.0) != (tt > 0.0):
                            bad = True
                            break
                    if bad:
                        break
                if bad:
                    for di in range(2):
                        for dj in range(2):
                            if ignore_protection or not protected[i + di, j + dj]:
                                fix[i + di, j + dj] = True
                                any_fix = True
        if not any_fix:
            continue
        for i in range(h):
            for j in range(w):
                if fix[i, j]:
                    t = base + i * w + j
                    m = _median3(values[t, 0], values[t, 1], values[t, 2])
                    if values[t, 0] != m or values[t, 1] != m or values[t, 2] != m:
                        values[t, 0] = m
                        values[t, 1] = m
                        values[t, 2] = m


@numba.njit(cache=True, parallel=True)
def _correct_all(values, true, texel_start, box_w, box_h, corners, corner_start, distance_range, tolerance, passes):
    for g in numba.prange(len(box_w)):
        _correct_glyph(values, true, texel_start[g], box_w[g], box_h[g], corners, corner_start[g],
                       corner_start[g + 1], distance_range, tolerance, passes)


def correct_errors(batch, corners: list, values: np.ndarray, true_values: np.ndarray, distance_range: float,
                   tolerance: float = TOLERANCE_PX, passes: int = 1) -> None:
    """Fix interpolation artifacts of the 3 MSDF channels of ``values`` (T, 3) in place (see the module docstring).

    ``true_values`` are the normalized true distances (T,); ``corners`` per glyph an (m, 2) array of protected
    corner points in box pixel space.
    """
    counts = np.array([len(c) for c in corners], np.int64)
    corner_start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    all_corners = np.concatenate([np.asarray(c, np.float64).reshape(-1, 2) for c in corners]) if len(corners) \
        else np.zeros((0, 2))
    _correct_all(values, true_values, batch.texel_start.astype(np.int64), batch.box_w.astype(np.int64),
                 batch.box_h.astype(np.int64), all_corners, corner_start, float(distance_range), float(tolerance),
                 int(passes))
