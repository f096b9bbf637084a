"""A glyph's shape as arrays: segments grouped into closed contours, normalized and oriented for the distance kernels.

``Shape`` holds the outline in font units. :func:`prepare` makes it ready for the fields:

1. drop degenerate segments (all control points equal);
2. split the segments of contours with fewer than three edges in thirds, so every contour has enough edges for
   three colors (a one-edge teardrop or a two-edge circle would otherwise be one color);
3. orient every contour so the filled side, under the **nonzero** rule of the whole shape, is on its left. The
   winding number just left and right of an edge decides: an edge between filled (w != 0) and empty (w = 0) space
   points the contour's way; a contour drawn the other way round is reversed. Contours that lie wholly inside
   others (overlaps, common in variable fonts) have no such edge and are left as they are: their pseudo-distances
   are corrected later against the true, winding-based sign.
4. mark *interior* segments, whose two sides have the same fill all along them (inside an overlap, or where windings cancel):
   they bound nothing, so the distance kernels ignore them. The fill itself (winding numbers) always comes from
   the original contours, so orientation fixes never change what is inside.

Winding numbers are computed exactly by a ray to +x against **y-monotone pieces** of the segments (Beziers split
where dy/dt = 0): a piece is crossed at most once, with the half-open rule y0 <= y < y1, so joints between pieces
are never counted twice.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from baker.techniques.glyphs.segments import direction_at, point_at, solve_quadratic, sub_segment


@dataclass
class Shape:
    """Closed contours of lines and Beziers.

    Attributes
    ----------
    points : (n, 4, 2) float64
        Control points of each segment (first ``degree + 1`` rows used), in font units, y up.
    degree : (n,) int8
        1 line, 2 quadratic, 3 cubic Bezier.
    contour_start : (c + 1,) int64
        Segments of contour k are ``contour_start[k]:contour_start[k + 1]``, in order, each ending where the next
        begins, the last ending where the first begins.
    """

    points: np.ndarray
    degree: np.ndarray
    contour_start: np.ndarray
    # set by prepare(): the y-monotone pieces of the ORIGINAL contours (the fill is theirs, whatever orientation
    # fixes did to the segments), and segments that bound no filled region (both sides filled or both empty)
    fill_pieces: np.ndarray | None = None
    fill_piece_degree: np.ndarray | None = None
    interior: np.ndarray | None = None

    @classmethod
    def empty(cls) -> "Shape":
        return cls(np.zeros((0, 4, 2)), np.zeros(0, np.int8), np.zeros(1, np.int64))

    @property
    def segment_count(self) -> int:
        return len(self.degree)

    @property
    def contour_count(self) -> int:
        return len(self.contour_start) - 1

    def contour_of_segment(self) -> np.ndarray:
        return np.repeat(np.arange(self.contour_count), np.diff(self.contour_start))

    def bounds(self) -> tuple[float, float, float, float]:
        """Exact (left, bottom, right, top) of the outline (curve extrema, not control points)."""
        if not self.segment_count:
            return (0.0, 0.0, 0.0, 0.0)
        out = np.empty(4)
        _exact_bounds(self.points, self.degree, out)
        return tuple(float(v) for v in out)

    def transformed(self, scale: float, dx: float, dy: float) -> "Shape":
        """The same shape under p -> p * scale + (dx, dy) (Beziers are affine invariant)."""
        def move(p):
            if p is None:
                return None
            p = p * scale
            p[:, :, 0] += dx
            p[:, :, 1] += dy
            return p

        return Shape(move(self.points), self.degree.copy(), self.contour_start.copy(), move(self.fill_pieces),
                     self.fill_piece_degree, self.interior)


# ---------------------------------------------------------------------------------------------------- building
def from_contours(contours: list) -> Shape:
    """Build a Shape from a list of contours, each a list of (degree, [(x, y), ...]) segments."""
    pts, deg, starts = [], [], [0]
    for contour in contours:
        for d, p in contour:
            row = np.zeros((4, 2))
            row[: d + 1] = p
            pts.append(row)
            deg.append(d)
        starts.append(len(deg))
    if not deg:
        return Shape.empty()
    return Shape(np.array(pts, np.float64), np.array(deg, np.int8), np.array(starts, np.int64))


def prepare(shape: Shape) -> Shape:
    """Normalize (no degenerate segments, >= 3 edges per contour) and orient every contour (filled side on the left)."""
    shape = _drop_degenerate(shape)
    shape = _split_short_contours(shape)
    if not shape.segment_count:
        return shape
    pieces, piece_degree = monotone_pieces(shape.points, shape.degree)
    flip = np.zeros(shape.contour_count, np.bool_)
    _orientation_flips(shape.points, shape.degree, shape.contour_start, pieces, piece_degree, flip)
    oriented = reverse_contours(shape, flip) if flip.any() else shape
    interior = np.zeros(oriented.segment_count, np.bool_)
    _interior_segments(oriented.points, oriented.degree, pieces, piece_degree, interior)
    return Shape(oriented.points, oriented.degree, oriented.contour_start, pieces, piece_degree, interior)


def _drop_degenerate(shape: Shape) -> Shape:
    if not shape.segment_count:
        return shape
    idx = np.arange(4)[None, :] <= shape.degree[:, None]
    spread = np.where(idx[..., None], np.abs(shape.points - shape.points[:, :1, :]), 0.0).max(axis=(1, 2))
    keep = spread > 0.0
    if keep.all():
        return shape
    contour = shape.contour_of_segment()[keep]
    counts = np.bincount(contour, minlength=shape.contour_count)
    counts = counts[counts > 0]
    return Shape(shape.points[keep], shape.degree[keep], np.concatenate([[0], np.cumsum(counts)]).astype(np.int64))


def _split_short_contours(shape: Shape) -> Shape:
    counts = np.diff(shape.contour_start)
    short = np.repeat(counts < 3, counts)
    if not short.any():
        return shape
    times = np.where(short, 3, 1)
    index = np.repeat(np.arange(shape.segment_count), times)
    # the k-th third of a split segment is t in [k/3, (k+1)/3]; unsplit segments keep [0, 1]
    first = np.concatenate([[0], np.cumsum(times)[:-1]])
    k = np.arange(len(index)) - np.repeat(first, times)
    t0 = np.where(np.repeat(short, times), k / 3.0, 0.0)
    t1 = np.where(np.repeat(short, times), (k + 1) / 3.0, 1.0)
    pts = np.empty((len(index), 4, 2))
    _sub_segments(shape.points, shape.degree, index, t0, t1, pts)
    new_counts = counts * np.where(counts < 3, 3, 1)
    return Shape(pts, shape.degree[index], np.concatenate([[0], np.cumsum(new_counts)]).astype(np.int64))


@numba.njit(cache=True)
def _sub_segments(points, degree, index, t0, t1, out):
    for i in range(len(index)):
        s = index[i]
        if t0[i] == 0.0 and t1[i] == 1.0:
            out[i] = points[s]
        else:
            sub_segment(points[s], degree[s], t0[i], t1[i], out[i])


def reverse_contours(shape: Shape, flip: np.ndarray) -> Shape:
    """Reverse the direction of travel of the contours where ``flip`` is true (segment order and control points)."""
    contour = shape.contour_of_segment()
    start, end = shape.contour_start[:-1][contour], shape.contour_start[1:][contour]
    pos = np.arange(shape.segment_count)
    order = np.where(flip[contour], start + end - 1 - pos, pos)
    pts = shape.points[order].copy()
    deg = shape.degree[order]
    rev = flip[contour]
    # reverse the first degree + 1 control points of each flipped segment
    for d in (1, 2, 3):
        rows = rev & (deg == d)
        pts[rows, : d + 1] = pts[rows, d::-1]
    return Shape(pts, deg, shape.contour_start.copy())


# ---------------------------------------------------------------------------------------------------- geometry
@numba.njit(cache=True)
def _extrema_params(P, deg, axis, out):
    """Parameters in (0, 1) where the coordinate ``axis`` of the segment has zero derivative; returns the count."""
    if deg == 1:
        return 0
    roots = np.empty(3)
    if deg == 2:
        den = P[0, axis] - 2.0 * P[1, axis] + P[2, axis]
        if den == 0.0:
            return 0
        t = (P[0, axis] - P[1, axis]) / den
        if 0.0 < t < 1.0:
            out[0] = t
            return 1
        return 0
    # B'(t) / 3 = a t^2 + b t + c
    p0, p1, p2, p3 = P[0, axis], P[1, axis], P[2, axis], P[3, axis]
    a = -p0 + 3.0 * p1 - 3.0 * p2 + p3
    b = 2.0 * (p0 - 2.0 * p1 + p2)
    c = p1 - p0
    n = solve_quadratic(a, b, c, roots)
    m = 0
    for k in range(max(n, 0)):
        if 0.0 < roots[k] < 1.0:
            out[m] = roots[k]
            m += 1
    if m == 2 and out[0] > out[1]:
        out[0], out[1] = out[1], out[0]
    if m == 2 and out[0] == out[1]:
        m = 1
    return m


@numba.njit(cache=True)
def _exact_bounds(points, degree, out):
    out[0], out[1], out[2], out[3] = np.inf, np.inf, -np.inf, -np.inf
    ts = np.empty(2)
    for s in range(len(degree)):
        P, d = points[s], degree[s]
        for axis in range(2):
            for t in (0.0, 1.0):
                x, y = point_at(P, d, t)
                v = x if axis == 0 else y
                out[axis] = min(out[axis], v)
                out[axis + 2] = max(out[axis + 2], v)
            n = _extrema_params(P, d, axis, ts)
            for k in range(n):
                x, y = point_at(P, d, ts[k])
                v = x if axis == 0 else y
                out[axis] = min(out[axis], v)
                out[axis + 2] = max(out[axis + 2], v)


def monotone_pieces(points: np.ndarray, degree: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Split every segment where dy/dt = 0: (pieces (k, 4, 2), degrees (k,)), each piece monotonic in y."""
    out = np.empty((3 * len(degree), 4, 2))
    out_deg = np.empty(3 * len(degree), np.int8)
    k = _monotone_pieces(points, degree, out, out_deg)
    return out[:k], out_deg[:k]


@numba.njit(cache=True, nogil=True)  # bake_atlas prepares glyphs on several threads
def _monotone_pieces(points, degree, out, out_deg):
    k = 0
    ts = np.empty(2)
    cuts = np.empty(4)
    for s in range(len(degree)):
        n = _extrema_params(points[s], degree[s], 1, ts)
        cuts[0] = 0.0
        for i in range(n):
            cuts[i + 1] = ts[i]
        cuts[n + 1] = 1.0
        for i in range(n + 1):
            if n == 0:
                out[k] = points[s]
            else:
                sub_segment(points[s], degree[s], cuts[i], cuts[i + 1], out[k])
            out_deg[k] = degree[s]
            k += 1
    return k


@numba.njit(cache=True)
def crossing_x(P, deg, y):
    """x where the y-monotone piece P reaches height y (y within its range)."""
    y0, y1 = P[0, 1], P[deg, 1]
    if deg == 1:
        t = (y - y0) / (y1 - y0)
    elif deg == 2:
        a = P[0, 1] - 2.0 * P[1, 1] + P[2, 1]
        b = 2.0 * (P[1, 1] - P[0, 1])
        c = P[0, 1] - y
        roots = np.empty(3)
        n = solve_quadratic(a, b, c, roots)
        t = 0.5
        best = np.inf
        for i in range(max(n, 0)):
            # the root inside [0, 1] (the piece is monotone: there is exactly one, up to rounding)
            r = roots[i]
            off = max(0.0 - r, r - 1.0, 0.0)
            if off < best:
                best, t = off, min(1.0, max(0.0, r))
    else:
        lo, hi = 0.0, 1.0
        rising = y1 > y0
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            _, ym = point_at(P, 3, mid)
            if (ym < y) == rising:
                lo = mid
            else:
                hi = mid
        t = 0.5 * (lo + hi)
    x, _ = point_at(P, deg, t)
    return x


@numba.njit(cache=True)
def winding_at(pieces, piece_degree, start, stop, px, py):
    """Winding number of the closed outline (its y-monotone pieces ``start:stop``) around p: a ray to +x."""
    w = 0
    for k in range(start, stop):
        P, d = pieces[k], piece_degree[k]
        y0, y1 = P[0, 1], P[d, 1]
        if y0 <= py < y1:
            if crossing_x(P, d, py) > px:
                w += 1
        elif y1 <= py < y0:
            if crossing_x(P, d, py) > px:
                w -= 1
    return w


@numba.njit(cache=True)
def _probe_eps(points, degree):
    lo_x, lo_y, hi_x, hi_y = np.inf, np.inf, -np.inf, -np.inf
    for s in range(len(degree)):
        for i in range(degree[s] + 1):
            lo_x, hi_x = min(lo_x, points[s, i, 0]), max(hi_x, points[s, i, 0])
            lo_y, hi_y = min(lo_y, points[s, i, 1]), max(hi_y, points[s, i, 1])
    return 1e-5 * max(hi_x - lo_x, hi_y - lo_y, 1e-12)


@numba.njit(cache=True, nogil=True)  # bake_atlas prepares glyphs on several threads
def _interior_segments(points, degree, pieces, piece_degree, out):
    """Mark segments with the same fill on both sides at 16 points along them (inside an overlap, or cancelled).
    Segments are not split where contours cross: one that is partly a boundary keeps counting (a boundary part
    shorter than 1/16 of a segment can be missed)."""
    eps = _probe_eps(points, degree)
    n_pieces = len(piece_degree)
    for s in range(len(degree)):
        boundary = False
        for k in range(16):
            t = (k + 0.5) / 16.0
            x, y = point_at(points[s], degree[s], t)
            dx, dy = direction_at(points[s], degree[s], t)
            dl = math.sqrt(dx * dx + dy * dy)
            if dl == 0.0:
                boundary = True
                break
            nx, ny = -dy / dl * eps, dx / dl * eps
            left = winding_at(pieces, piece_degree, 0, n_pieces, x + nx, y + ny)
            right = winding_at(pieces, piece_degree, 0, n_pieces, x - nx, y - ny)
            if (left != 0) != (right != 0):
                boundary = True
                break
        out[s] = not boundary


@numba.njit(cache=True, nogil=True)  # bake_atlas prepares glyphs on several threads
def _orientation_flips(points, degree, contour_start, pieces, piece_degree, flip):
    """Decide for each contour whether it must be reversed to have the nonzero-filled side on its left."""
    # probe offset: tiny against the outline, large against rounding (font units or pixels alike)
    eps = _probe_eps(points, degree)
    n_pieces = len(piece_degree)
    for c in range(len(contour_start) - 1):
        decided = False
        for s in range(contour_start[c], contour_start[c + 1]):
            for t in (0.5, 0.25, 0.75):
                x, y = point_at(points[s], degree[s], t)
                dx, dy = direction_at(points[s], degree[s], t)
                dl = math.sqrt(dx * dx + dy * dy)
                if dl == 0.0:
                    continue
                nx, ny = -dy / dl * eps, dx / dl * eps  # left normal
                left = winding_at(pieces, piece_degree, 0, n_pieces, x + nx, y + ny)
                right = winding_at(pieces, piece_degree, 0, n_pieces, x - nx, y - ny)
                if (left != 0) != (right != 0):
                    flip[c] = left == 0
                    decided = True
                    break
            if decided:
                break
