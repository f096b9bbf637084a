"""MSDF error correction: texels whose bilinear interpolation puts the median's edge in the wrong place.

Between texel centres a renderer interpolates each channel bilinearly and then takes the median. Where neighbouring
texels' channels come from different edges (thin stems, edges of one color passing near another contour, the
inside of overlapping contours) the median of the interpolated channels can cross 0.5 far from any real edge:
a spurious dent, hole or blob (Chlumsky, Sloup, Šimeček, *Improved Corners with Multi-Channel Signed Distance
Fields*, Computer Graphics Forum 2018, section 4).

The default, :func:`correct_edge_priority`, is msdfgen's edge-priority error correction reimplemented (the method of
its ``MSDFErrorCorrection``): texels around colored corners and texels whose non-median channels draw an edge
between them and a neighbour are *protected*; every texel is then tested against its 8 neighbours at the points
where two channels cross (where the interpolated median has its extremes, solved exactly: linear along rows and
columns, quadratic along diagonals); a crossing whose median leaves the range allowed by its distance from the two
texels (1 px of distance per px, with 1/0.9 slack) is an artifact, and for protected texels only a median that
inverts the sign of both ends counts. Flagged texels take their median (single-channel there, texel-centre value
unchanged). msdfgen's optional second stage (``distance_check``: with every texel protected, flag also texels whose
flattening brings the interpolated median closer to the exact field) is available but off: it cost wrong pixels on
every font measured (benchmarks/RESULTS.md, "glyphs": the note on `distance_check`).

:func:`correct_errors` is the former check (a 5 x 5 grid per cell against the interpolated exact distance), kept for
comparison in the tests.
"""
from __future__ import annotations

import math

import numba
import numpy as np

from baker.techniques.glyphs.sdf import point_distance
from baker.techniques.glyphs.segments import solve_quadratic

TOLERANCE_PX = 0.5  # how far from the outline (true distance, pixels) a sign disagreement counts as an artifact
SAMPLES = 5  # per cell and axis, at (k + .5) / 5: odd, so the cell midpoint (where clashes peak) is one


@numba.njit(cache=True)
def _median3(a, b, c):
    return max(min(a, b), min(max(a, b), c))


@numba.njit(cache=True)
def _bilinear(v00, v01, v10, v11, u, v):
    return (1.0 - v) * ((1.0 - u) * v00 + u * v01) + v * ((1.0 - u) * v10 + u * v11)


@numba.njit(cache=True)
def _protect_corners(flags, w, h, corners, c0, c1, mark):
    """Mark (|=) the 4 texels around each corner point ``corners[c0:c1]`` (box pixel space) in row-major ``flags``."""
    for k in range(c0, c1):
        j0 = int(math.floor(corners[k, 0] - 0.5))
        i0 = int(math.floor(corners[k, 1] - 0.5))
        for di in range(2):
            for dj in range(2):
                i, j = i0 + di, j0 + dj
                if 0 <= i < h and 0 <= j < w:
                    flags[i * w + j] |= mark


@numba.njit(cache=True)
def _correct_glyph(values, true, base, w, h, corners, c0, c1, distance_range, tolerance, passes):
    protected = np.zeros((h, w), np.bool_)
    _protect_corners(protected.reshape(-1), w, h, corners, c0, c1, True)
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


# ------------------------------------------------------------------------------------------ edge-priority correction
# The method of msdfgen's MSDFErrorCorrection (Chlumsky, msdfgen 1.9+: ErrorCorrectionConfig EDGE_PRIORITY with the
# distance check at edges), reimplemented: protect texels at colored corners and texels whose extreme channels make
# an edge between them and a neighbour; flag a texel when interpolating it with any of its 8 neighbours puts the
# median outside the range its distance allows (where two channels cross, the median has its extremes); then, with
# every texel protected, flag the remaining texels whose flattening brings the interpolated median closer to the
# exact field at an inverted candidate point; flattened texels take their median.
PROTECTED = 1
ERROR = 2
CANDIDATE = 1
ARTIFACT = 2
T_EPSILON = 0.01  # crossings this close to a texel centre are the texel's own (two channels are often equal there)
PROTECTION_RADIUS_TOLERANCE = 1.001
MIN_DEVIATION_RATIO = 10.0 / 9.0  # how much faster than 1 px / px the median may change before it is an artifact
MIN_IMPROVE_RATIO = 10.0 / 9.0  # how much closer to the exact field a flattened texel must bring the median


@numba.njit(cache=True, inline="always")
def _mix(a, b, t):
    return a + (b - a) * t


@numba.njit(cache=True)
def _channel_makes_edge(values, a, b, ch):
    """Channel ``ch`` crosses 0.5 between texels a and b where it is the median: it draws an edge there."""
    da = values[a, ch] - values[b, ch]
    if da == 0.0:
        return False
    t = (values[a, ch] - 0.5) / da
    if 0.0 < t < 1.0:
        c0 = _mix(values[a, 0], values[b, 0], t)
        c1 = _mix(values[a, 1], values[b, 1], t)
        c2 = _mix(values[a, 2], values[b, 2], t)
        c = c0 if ch == 0 else (c1 if ch == 1 else c2)
        return _median3(c0, c1, c2) == c
    return False


@numba.njit(cache=True)
def _protect_pair(values, stencil, a, b, radius):
    ma = _median3(values[a, 0], values[a, 1], values[a, 2])
    mb = _median3(values[b, 0], values[b, 1], values[b, 2])
    if abs(ma - 0.5) + abs(mb - 0.5) >= radius:
        return
    mask = 0
    for ch in range(3):
        if _channel_makes_edge(values, a, b, ch):
            mask |= 1 << ch
    for t, m in ((a, ma), (b, mb)):
        for ch in range(3):
            if (mask >> ch) & 1 and values[t, ch] != m:
                stencil[t] |= PROTECTED


@numba.njit(cache=True)
def _range_test(at, bt, xt, am, bm, xm, span, protected):
    """Flags for the median xm interpolated at xt between medians am (at xt = at) and bm (at bt)."""
    if (am > 0.5 and bm > 0.5 and xm <= 0.5) or (am < 0.5 and bm < 0.5 and xm >= 0.5) or \
            (not protected and _median3(am, bm, xm) != xm):
        ax, bx = (xt - at) * span, (bt - xt) * span
        if not (am - ax <= xm <= am + ax and bm - bx <= xm <= bm + bx):
            return CANDIDATE | ARTIFACT
        return CANDIDATE
    return 0


@numba.njit(cache=True)
def _sample(values, base, w, h, x, y, out):
    """Bilinear sample of the glyph's 3 channels at box point (x, y), clamped at the box edge."""
    px, py = x - 0.5, y - 0.5
    l, b = int(math.floor(px)), int(math.floor(py))
    fx, fy = px - l, py - b
    r, t = min(max(l + 1, 0), w - 1), min(max(b + 1, 0), h - 1)
    l, b = min(max(l, 0), w - 1), min(max(b, 0), h - 1)
    for c in range(3):
        lo = _mix(values[base + b * w + l, c], values[base + b * w + r, c], fx)
        hi = _mix(values[base + t * w + l, c], values[base + t * w + r, c], fx)
        out[c] = _mix(lo, hi, fy)


@numba.njit(cache=True)
def _evaluate(flags, t, dx, dy, ctx, values, batch_arrays, scratch):
    """Is the candidate at parameter t along direction (dx, dy) from the current texel an artifact?"""
    if ctx[0] == 0.0:  # no distance check: the range test decides
        return (flags & ARTIFACT) != 0
    if (flags & CANDIDATE) == 0:
        return False
    if (flags & ARTIFACT) != 0:
        return True
    (points, degree, colors, pieces, piece_degree, s0, s1, p0, p1, base, w, h, cx, cy, ct, distance_range) = \
        batch_arrays
    tx, ty = t * dx, t * dy
    _sample(values, base, w, h, cx + tx, cy + ty, scratch)
    weight = (1.0 - abs(tx)) * (1.0 - abs(ty))
    m = _median3(values[ct, 0], values[ct, 1], values[ct, 2])
    old = _median3(scratch[0], scratch[1], scratch[2])
    new = _median3(scratch[0] + weight * (m - values[ct, 0]), scratch[1] + weight * (m - values[ct, 1]),
                   scratch[2] + weight * (m - values[ct, 2]))
    ref = 0.5 + point_distance(points, degree, colors, s0, s1, pieces, piece_degree, p0, p1, cx + tx, cy + ty) \
        / distance_range
    return MIN_IMPROVE_RATIO * abs(new - ref) < abs(old - ref)


@numba.njit(cache=True)
def _linear_artifact(values, a, b, span, protected, dx, dy, ctx, batch_arrays, scratch):
    am = _median3(values[a, 0], values[a, 1], values[a, 2])
    bm = _median3(values[b, 0], values[b, 1], values[b, 2])
    # of the pair, only the texel farther from the edge is reported (fewer side effects)
    if abs(am - 0.5) < abs(bm - 0.5):
        return False
    for c0, c1 in ((0, 1), (1, 2), (2, 0)):
        da = values[a, c1] - values[a, c0]
        db = values[b, c1] - values[b, c0]
        if da == db:
            continue
        t = da / (da - db)
        if T_EPSILON < t < 1.0 - T_EPSILON:
            xm = _median3(_mix(values[a, 0], values[b, 0], t), _mix(values[a, 1], values[b, 1], t),
                          _mix(values[a, 2], values[b, 2], t))
            if _evaluate(_range_test(0.0, 1.0, t, am, bm, xm, span, protected), t, dx, dy, ctx, values,
                         batch_arrays, scratch):
                return True
    return False


@numba.njit(cache=True, inline="always")
def _quad_median(a, lin, q, t):
    return _median3(t * (t * q[0] + lin[0]) + a[0], t * (t * q[1] + lin[1]) + a[1], t * (t * q[2] + lin[2]) + a[2])


@numba.njit(cache=True)
def _diagonal_artifact(values, a, b, c, d, span, protected, dx, dy, ctx, batch_arrays, scratch, roots, work):
    """Bilinear interpolation along the diagonal a -> d (b, c the other two texels of the cell): per channel
    a + t (b + c - 2a) + t^2 (a - b - c + d)."""
    am = _median3(values[a, 0], values[a, 1], values[a, 2])
    dm = _median3(values[d, 0], values[d, 1], values[d, 2])
    if abs(am - 0.5) < abs(dm - 0.5):
        return False
    av, lin, q, tex = work[0], work[1], work[2], work[3]
    for ch in range(3):
        av[ch] = values[a, ch]
        lin[ch] = values[b, ch] + values[c, ch] - 2.0 * values[a, ch]
        q[ch] = values[a, ch] - values[b, ch] - values[c, ch] + values[d, ch]
        tex[ch] = -0.5 * lin[ch] / q[ch] if q[ch] != 0.0 else -1.0  # each channel's extreme
    for c0, c1 in ((0, 1), (1, 2), (2, 0)):
        da = values[a, c1] - values[a, c0]
        dbc = values[b, c1] - values[b, c0] + values[c, c1] - values[c, c0]
        dd = values[d, c1] - values[d, c0]
        n = solve_quadratic(dd - dbc + da, dbc - 2.0 * da, da, roots)
        for k in range(max(n, 0)):
            t = roots[k]
            if not (T_EPSILON < t < 1.0 - T_EPSILON):
                continue
            xm = _quad_median(av, lin, q, t)
            flags = _range_test(0.0, 1.0, t, am, dm, xm, span, protected)
            # also against the interpolated medians at the two channels' extremes on the near side of t
            for te in (tex[c0], tex[c1]):
                if 0.0 < te < 1.0:
                    em = _quad_median(av, lin, q, te)
                    if te > t:
                        flags |= _range_test(0.0, te, t, am, em, xm, span, protected)
                    else:
                        flags |= _range_test(te, 1.0, t, em, dm, xm, span, protected)
            if _evaluate(flags, t, dx, dy, ctx, values, batch_arrays, scratch):
                return True
    return False


@numba.njit(cache=True)
def _edge_priority_glyph(values, points, degree, colors, seg_start, pieces, piece_degree, piece_start, base, w, h,
                         corners, c0, c1, distance_range, distance_check, g):
    n = w * h
    stencil = np.zeros(n, np.uint8)
    _protect_corners(stencil, w, h, corners, c0, c1, PROTECTED)
    unit = 1.0 / distance_range  # a change of 1 px of distance in normalized values
    radius = PROTECTION_RADIUS_TOLERANCE * unit
    sv = values[base:base + n]
    for i in range(h):
        for j in range(w - 1):
            _protect_pair(sv, stencil, i * w + j, i * w + j + 1, radius)
    for i in range(h - 1):
        for j in range(w):
            _protect_pair(sv, stencil, i * w + j, (i + 1) * w + j, radius)
    dradius = radius * math.sqrt(2.0)
    for i in range(h - 1):
        for j in range(w - 1):
            _protect_pair(sv, stencil, i * w + j, (i + 1) * w + j + 1, dradius)
            _protect_pair(sv, stencil, i * w + j + 1, (i + 1) * w + j, dradius)
    span = MIN_DEVIATION_RATIO * unit
    dspan = span * math.sqrt(2.0)
    scratch = np.empty(3)
    roots = np.empty(2)
    work = np.empty((4, 3))  # per-channel terms of the diagonal interpolation, reused
    s0, s1, p0, p1 = seg_start[g], seg_start[g + 1], piece_start[g], piece_start[g + 1]
    for stage in range(2 if distance_check else 1):
        ctx = np.array([float(stage)])
        for i in range(h):
            for j in range(w):
                t = i * w + j
                if stencil[t] & ERROR:
                    continue
                prot = stage == 1 or (stencil[t] & PROTECTED) != 0
                arrays = (points, degree, colors, pieces, piece_degree, s0, s1, p0, p1, 0, w, h, j + 0.5, i + 0.5,
                          t, distance_range)
                bad = False
                for dj, di in ((-1, 0), (0, -1), (1, 0), (0, 1)):
                    jj, ii = j + dj, i + di
                    if 0 <= jj < w and 0 <= ii < h and _linear_artifact(
                            sv, t, ii * w + jj, span, prot, dj, di, ctx, arrays, scratch):
                        bad = True
                        break
                if not bad:
                    for dj, di in ((-1, -1), (1, -1), (-1, 1), (1, 1)):
                        jj, ii = j + dj, i + di
                        if 0 <= jj < w and 0 <= ii < h and _diagonal_artifact(
                                sv, t, i * w + jj, ii * w + j, ii * w + jj, dspan, prot, dj, di, ctx, arrays,
                                scratch, roots, work):
                            bad = True
                            break
                if bad:
                    stencil[t] |= ERROR
    for t in range(n):
        if stencil[t] & ERROR:
            m = _median3(sv[t, 0], sv[t, 1], sv[t, 2])
            sv[t, 0] = m
            sv[t, 1] = m
            sv[t, 2] = m


@numba.njit(cache=True, parallel=True)
def _edge_priority_all(values, points, degree, colors, seg_start, pieces, piece_degree, piece_start, texel_start,
                       box_w, box_h, corners, corner_start, distance_range, distance_check):
    for g in numba.prange(len(box_w)):
        _edge_priority_glyph(values, points, degree, colors, seg_start, pieces, piece_degree, piece_start,
                             texel_start[g], box_w[g], box_h[g], corners, corner_start[g], corner_start[g + 1],
                             distance_range, distance_check, g)


@numba.njit(cache=True, parallel=True)
def _correct_all(values, true, texel_start, box_w, box_h, corners, corner_start, distance_range, tolerance, passes):
    for g in numba.prange(len(box_w)):
        _correct_glyph(values, true, texel_start[g], box_w[g], box_h[g], corners, corner_start[g],
                       corner_start[g + 1], distance_range, tolerance, passes)


def _flat_corners(corners: list) -> tuple[np.ndarray, np.ndarray]:
    """Every glyph's (m, 2) corner points in one array, and where each glyph's run starts (len(corners) + 1)."""
    counts = np.array([len(c) for c in corners], np.int64)
    corner_start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    all_corners = np.concatenate([np.asarray(c, np.float64).reshape(-1, 2) for c in corners]) if len(corners) \
        else np.zeros((0, 2))
    return all_corners, corner_start


def correct_errors(batch, corners: list, values: np.ndarray, true_values: np.ndarray, distance_range: float,
                   tolerance: float = TOLERANCE_PX, passes: int = 1) -> None:
    """Fix interpolation artifacts of the 3 MSDF channels of ``values`` (T, 3) in place (see the module docstring).

    ``true_values`` are the normalized true distances (T,); ``corners`` per glyph an (m, 2) array of protected
    corner points in box pixel space.
    """
    all_corners, corner_start = _flat_corners(corners)
    _correct_all(values, true_values, batch.texel_start.astype(np.int64), batch.box_w.astype(np.int64),
                 batch.box_h.astype(np.int64), all_corners, corner_start, float(distance_range), float(tolerance),
                 int(passes))


def correct_edge_priority(batch, corners: list, values: np.ndarray, distance_range: float,
                          distance_check: bool = False) -> None:
    """msdfgen's edge-priority error correction (see the comment above ``PROTECTED``) of the 3 MSDF channels of
    ``values`` (T, 3), normalized but not clamped, in place; ``corners`` per glyph an (m, 2) array of colored corner
    points in box pixel space. ``distance_check`` adds the second stage that compares with the exact field."""
    all_corners, corner_start = _flat_corners(corners)
    _edge_priority_all(values, batch.points, batch.degree, batch.colors, batch.seg_start.astype(np.int64),
                       batch.pieces, batch.piece_degree, batch.piece_start.astype(np.int64),
                       batch.texel_start.astype(np.int64), batch.box_w.astype(np.int64),
                       batch.box_h.astype(np.int64), all_corners, corner_start, float(distance_range),
                       bool(distance_check))
