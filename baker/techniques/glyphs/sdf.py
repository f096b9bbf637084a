"""Signed distance fields from vector outlines: the exact distance and per-channel pseudo-distances per texel.

One compiled kernel serves every field type (Green 2007 SDF, pseudo-SDF, Chlumsky's MSDF/MTSDF): for each texel
centre p it finds

- the **true signed distance**: the exact distance to the nearest segment (lines, quadratic and cubic Beziers, see
  :mod:`.segments`), with the sign of the **nonzero winding number** of the whole outline at p, so overlapping
  and reversed contours are inside exactly when the font's renderer fills them;
Segments of color 0 (interior edges of overlapping contours, see :func:`.shape.prepare`) are ignored.

- for each requested channel (a bitmask of edge colors), the nearest edge among the edges of that color (ties broken
  by the tangent criterion, then by segment index, so the result does not depend on visiting order) and its
  signed **pseudo-distance** (distance to the edge's tangent line extended beyond its endpoints).

Winding numbers come per texel row from the crossings of the row with the outline's y-monotone pieces (exact
roots), so each costs O(crossings), not O(segments). The segment loop skips a segment when the distance to its
control-point bounding box (a lower bound, by the convex-hull property) cannot beat the current nearest edge of any
channel it could update; the nearest edges of the previous texel are tried first to make that bound tight.

Rows of all glyphs are independent tasks run in parallel (numba ``prange``, both cores); each texel's value depends
only on its own inputs, so results are byte-identical whatever the thread count.
"""
from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from baker.techniques.glyphs.segments import pseudo_distance, signed_distance
from baker.techniques.glyphs.shape import crossing_x, winding_at


@dataclass
class GlyphBatch:
    """Segments of many glyphs in their boxes' pixel space (y up; texel (row i, col j) centre at (j + .5, i + .5)).

    ``*_start`` arrays have one entry per glyph plus one: glyph g owns segments ``seg_start[g]:seg_start[g + 1]``,
    winding pieces ``piece_start[g]:...`` and texels ``texel_start[g]:...`` (row-major, bottom row first, width
    ``box_w[g]``).
    """

    points: np.ndarray  # (n, 4, 2) float64
    degree: np.ndarray  # (n,) int8
    colors: np.ndarray  # (n,) uint8 channel bitmask (1 R, 2 G, 4 B)
    seg_start: np.ndarray
    pieces: np.ndarray  # (k, 4, 2) y-monotone pieces
    piece_degree: np.ndarray
    piece_start: np.ndarray
    box_w: np.ndarray  # (g,) int64
    box_h: np.ndarray
    texel_start: np.ndarray

    @property
    def texel_count(self) -> int:
        return int(self.texel_start[-1])


def segment_bounds(points: np.ndarray, degree: np.ndarray) -> np.ndarray:
    """(n, 4) control-point bounding boxes (x0, y0, x1, y1): each Bezier lies inside its control polygon."""
    used = (np.arange(4)[None, :] <= degree[:, None])[..., None]
    lo = np.where(used, points, np.inf).min(axis=1)
    hi = np.where(used, points, -np.inf).max(axis=1)
    return np.concatenate([lo, hi], axis=1)


@numba.njit(cache=True, inline="always")
def _better(ad, dot, idx, best_ad, best_dot, best_idx):
    if ad != best_ad:
        return ad < best_ad
    if dot != best_dot:
        return dot < best_dot
    return idx < best_idx


@numba.njit(cache=True)
def _row(points, degree, colors, bounds, s0, s1, pieces, piece_degree, p0, p1, width, y, masks,
         out_true, out_channels, base):
    """One texel row: true signed distances into ``out_true[base:base + width]`` and channel pseudo-distances."""
    nch = len(masks)
    # crossings of the row with the outline: winding(x) = sum of directions of crossings right of x
    xs = np.empty(max(p1 - p0, 1))
    dirs = np.empty(max(p1 - p0, 1), np.int64)
    nc = 0
    for k in range(p0, p1):
        P, d = pieces[k], piece_degree[k]
        a, b = P[0, 1], P[d, 1]
        if a <= y < b:
            xs[nc], dirs[nc] = crossing_x(P, d, y), 1
            nc += 1
        elif b <= y < a:
            xs[nc], dirs[nc] = crossing_x(P, d, y), -1
            nc += 1
    best_ad = np.empty(nch + 1)
    best_dot = np.empty(nch + 1)
    best_idx = np.empty(nch + 1, np.int64)
    best_d = np.empty(nch + 1)
    best_t = np.empty(nch + 1)
    prev_idx = np.full(nch + 1, -1, np.int64)
    for j in range(width):
        x = j + 0.5
        winding = 0
        for k in range(nc):
            if xs[k] > x:
                winding += dirs[k]
        for c in range(nch + 1):
            best_ad[c], best_dot[c], best_idx[c], best_d[c], best_t[c] = np.inf, np.inf, s1, 0.0, 0.0
        # slot nch is the true distance over all edges; slots 0..nch-1 the channels
        for pass_ in range(2):
            count = nch + 1 if pass_ == 0 else s1 - s0
            for q in range(count):
                if pass_ == 0:
                    s = prev_idx[q]
                    if s < 0:
                        continue
                else:
                    s = s0 + q
                col = colors[s]
                if col == 0:  # an interior edge: bounds no filled region
                    continue
                limit = best_ad[nch]
                for c in range(nch):
                    if (col & masks[c]) != 0 and best_ad[c] > limit:
                        limit = best_ad[c]
                bx = max(bounds[s, 0] - x, 0.0, x - bounds[s, 2])
                by = max(bounds[s, 1] - y, 0.0, y - bounds[s, 3])
                if bx * bx + by * by > limit * limit:
                    continue
                d, dot, t = signed_distance(points[s], degree[s], x, y)
                ad = abs(d)
                if _better(ad, dot, s, best_ad[nch], best_dot[nch], best_idx[nch]):
                    best_ad[nch], best_dot[nch], best_idx[nch], best_d[nch], best_t[nch] = ad, dot, s, d, t
                for c in range(nch):
                    if (col & masks[c]) != 0 and _better(ad, dot, s, best_ad[c], best_dot[c], best_idx[c]):
                        best_ad[c], best_dot[c], best_idx[c], best_d[c], best_t[c] = ad, dot, s, d, t
        for c in range(nch + 1):
            prev_idx[c] = best_idx[c] if best_idx[c] < s1 else -1
        true = best_ad[nch] if winding != 0 else -best_ad[nch]
        out_true[base + j] = true
        for c in range(nch):
            s = best_idx[c]
            if s >= s1:  # no edge of this color: the channel follows the true distance
                out_channels[base + j, c] = true
            else:
                out_channels[base + j, c] = pseudo_distance(points[s], degree[s], best_t[c], best_d[c], x, y)


@numba.njit(cache=True, parallel=True)
def _fields(points, degree, colors, bounds, seg_start, pieces, piece_degree, piece_start, box_w, texel_start,
            row_glyph, row_index, masks, out_true, out_channels):
    for r in numba.prange(len(row_glyph)):
        g = row_glyph[r]
        i = row_index[r]
        _row(points, degree, colors, bounds, seg_start[g], seg_start[g + 1], pieces, piece_degree, piece_start[g],
             piece_start[g + 1], box_w[g], i + 0.5, masks, out_true, out_channels, texel_start[g] + i * box_w[g])


def distance_fields(batch: GlyphBatch, masks=()) -> tuple[np.ndarray, np.ndarray]:
    """True signed distances (T,) and channel pseudo-distances (T, len(masks)), in pixels, for every texel of
    every glyph of ``batch`` (+ inside). ``masks`` are edge-color bitmasks, one per channel (e.g. (7,) for a
    single-channel pseudo-SDF, (1, 2, 4) for MSDF)."""
    masks = np.asarray(masks, np.uint8).reshape(-1)
    total = batch.texel_count
    out_true = np.empty(total, np.float64)
    out_channels = np.empty((total, len(masks)), np.float64)
    if total == 0:
        return out_true, out_channels
    row_glyph = np.repeat(np.arange(len(batch.box_h)), batch.box_h)
    first = np.repeat(np.concatenate([[0], np.cumsum(batch.box_h)[:-1]]), batch.box_h)
    row_index = np.arange(len(row_glyph)) - first
    bounds = segment_bounds(batch.points, batch.degree) if len(batch.degree) else np.zeros((0, 4))
    _fields(batch.points, batch.degree, batch.colors, bounds, batch.seg_start.astype(np.int64), batch.pieces,
            batch.piece_degree, batch.piece_start.astype(np.int64), batch.box_w.astype(np.int64),
            batch.texel_start.astype(np.int64), row_glyph.astype(np.int64), row_index.astype(np.int64), masks,
            out_true, out_channels)
    return out_true, out_channels


def true_distance_field(shape, width: int, height: int) -> np.ndarray:
    """The (height, width) exact signed distance of one prepared :class:`~.shape.Shape` already in pixel space,
    row 0 at the bottom (y up)."""
    from baker.techniques.glyphs.shape import monotone_pieces

    if shape.fill_pieces is not None:
        pieces, piece_degree = shape.fill_pieces, shape.fill_piece_degree
    else:
        pieces, piece_degree = monotone_pieces(shape.points, shape.degree)
    colors = np.full(shape.segment_count, 7, np.uint8)
    if shape.interior is not None:
        colors[shape.interior] = 0
    batch = GlyphBatch(shape.points, shape.degree, colors, np.array([0, shape.segment_count]), pieces, piece_degree,
                       np.array([0, len(piece_degree)]), np.array([width]), np.array([height]),
                       np.array([0, width * height]))
    true, _ = distance_fields(batch)
    return true.reshape(height, width)


@numba.njit(cache=True)
def point_distance(points, degree, colors, s0, s1, pieces, piece_degree, p0, p1, x, y):
    """The single-channel field at one point (x, y) of a glyph's box: the pseudo-distance of the nearest edge (Chlumsky
    2015, section 2.3), or the exact distance where the pseudo-distance's sign disagrees with the nonzero winding
    number (the kernel's sign correction), in pixels, + inside. Brute force over the glyph's segments; for the
    distance check of :mod:`.correction`, which evaluates it at a few points between texel centres."""
    winding = winding_at(pieces, piece_degree, p0, p1, x, y)
    best_ad, best_dot, best_idx, best_d, best_t = np.inf, np.inf, s1, 0.0, 0.0
    for s in range(s0, s1):
        if colors[s] == 0:
            continue
        d, dot, t = signed_distance(points[s], degree[s], x, y)
        ad = abs(d)
        if _better(ad, dot, s, best_ad, best_dot, best_idx):
            best_ad, best_dot, best_idx, best_d, best_t = ad, dot, s, d, t
    if best_idx >= s1:
        return -np.inf if winding == 0 else np.inf
    pd = pseudo_distance(points[best_idx], degree[best_idx], best_t, best_d, x, y)
    if (pd > 0.0) != (winding != 0):
        return best_ad if winding != 0 else -best_ad
    return pd
