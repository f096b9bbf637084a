"""Edge coloring for multi-channel distance fields (Chlumsky 2015, section 3.1).

Each edge gets a subset of the channels {R, G, B} (a bitmask: 1 R, 2 G, 4 B). At every *corner* — where the
direction turns by more than the angle threshold, i.e. the unit tangents a, b meet with a . b <= 0 or
|a x b| > sin(threshold) — the two edges must share exactly one channel; along a smooth spline the color stays. The
median of the three channels then reproduces the sharp corner under bilinear interpolation.

Strategies:
- ``simple``: walk the corners of each contour and rotate through cyan/magenta/yellow, never letting the last
  spline share two channels with the first; a contour with one corner (a teardrop) is split into three color
  zones around it; a contour without corners is white (all channels).
- ``inktrap``: as simple, but on contours with more than three corners the corner that starts an unusually short
  spline (shorter than both its neighbours: the notch of an ink trap) is *minor*: the colors of the major corners
  are chosen first, then each minor corner gets the one channel its neighbours do not share, so the short spline
  does not force a two-channel clash onto its long neighbours. Removing every such short spline leaves a valid
  coloring of the rest. msdf-atlas-gen's default.
- ``notch`` (the default): the ink-trap rule for notches shorter than one texel only, longer splines rotate as in
  ``simple``. Why: a notch the texel grid cannot resolve (the flat tip of a serif, 0.1-0.3 px at 48 px/em; the cut
  where a bowl meets its stem) leaves its two neighbours meeting as at one corner, and at a corner two edges must
  share only one channel; a notch of a texel or more is drawn as an edge of its own, and treating it as minor only
  moves the clash elsewhere (measured: Liberation Serif and Noto Sans CJK lose with ``inktrap``'s unbounded rule and
  gain with the texel bound). With it the mean coverage error is at or below msdfgen's ``edgeColoringSimple`` on
  every font measured, serif, sans and CJK (benchmarks/RESULTS.md, "glyphs", the fidelity table); ``simple``
  left Noto Serif above it (its ``b``, ``d`` and ``u``).
- ``distance``: msdfgen's ``edgeColoringByDistance`` (experimental there): splines are the vertices of a graph,
  touching splines must differ, then closest pairs first, splines nearer than a cutoff (``range / 2`` in an atlas:
  the half-width of the encoded band) are made to differ where a 3-coloring allows, so the two sides of a
  hairline or parallel strokes take different channel pairs. About as good as ``inktrap`` on Latin fonts, worse
  on CJK (benchmarks/RESULTS.md, "glyphs": its `distance` column), so not the default.

Deterministic: the color sequence depends only on the contour order (``seed`` 0 unless asked).
"""
from __future__ import annotations

import math

import numba
import numpy as np

from baker.techniques.glyphs.segments import direction_at, point_at, signed_distance

BLACK, RED, GREEN, YELLOW, BLUE, MAGENTA, CYAN, WHITE = 0, 1, 2, 3, 4, 5, 6, 7
STRATEGIES = {"simple": 0, "inktrap": 1, "distance": 2, "notch": 3}


@numba.njit(cache=True)
def _switch_color(color, seed, banned):
    """The next color of the rotation (two channels), avoiding a single shared channel ``banned``."""
    combined = color & banned
    if combined == RED or combined == GREEN or combined == BLUE:
        return combined ^ WHITE, seed
    if color == BLACK or color == WHITE:
        starts = (CYAN, MAGENTA, YELLOW)
        return starts[seed % 3], seed // 3
    shifted = color << (1 + (seed & 1))
    return (shifted | (shifted >> 3)) & WHITE, seed >> 1


@numba.njit(cache=True)
def _is_corner(ax, ay, bx, by, cross_threshold):
    la, lb = math.sqrt(ax * ax + ay * ay), math.sqrt(bx * bx + by * by)
    if la == 0.0 or lb == 0.0:
        return False
    ax, ay, bx, by = ax / la, ay / la, bx / lb, by / lb
    return ax * bx + ay * by <= 0.0 or abs(ax * by - ay * bx) > cross_threshold


@numba.njit(cache=True)
def _length(P, deg):
    total = 0.0
    x0, y0 = point_at(P, deg, 0.0)
    for i in range(1, 17):
        x, y = point_at(P, deg, i / 16.0)
        total += math.sqrt((x - x0) ** 2 + (y - y0) ** 2)
        x0, y0 = x, y
    return total


@numba.njit(cache=True)
def _contour_corners(points, degree, s0, s1, cross_threshold, corners, spline_len):
    """Corners of contour s0:s1 (segment i, relative to s0, starts at a corner when the previous segment's end
    tangent turns into its start tangent), the length of the spline ending at each, and their count plus the length
    of the part after the last corner (the spline wrapping around the contour's start)."""
    count = 0
    length = 0.0
    px, py = direction_at(points[s1 - 1], degree[s1 - 1], 1.0)
    for i in range(s1 - s0):
        s = s0 + i
        dx, dy = direction_at(points[s], degree[s], 0.0)
        if _is_corner(px, py, dx, dy, cross_threshold):
            corners[count] = i
            spline_len[count] = length
            count += 1
            length = 0.0
        length += _length(points[s], degree[s])
        px, py = direction_at(points[s], degree[s], 1.0)
    return count, length


@numba.njit(cache=True)
def _teardrop_zone(i, m):
    """-1, 0 or 1: the first, middle (white) or last of three balanced zones of edge i of m after a lone corner."""
    return int(3.0 + 2.875 * i / (m - 1) - 1.4375 + 0.5) - 3 if m > 1 else 0


@numba.njit(cache=True)
def color_edges(points, degree, contour_start, angle_threshold, strategy, seed, colors, max_notch):
    """Fill ``colors`` (uint8 per segment); contours must already have >= 3 segments when they have one corner.
    ``max_notch``: with the ink-trap rules, only splines shorter than this can be notches."""
    cross_threshold = math.sin(angle_threshold)
    n_max = len(degree)
    corners = np.empty(n_max, np.int64)
    spline_len = np.empty(n_max)
    minor = np.zeros(n_max, np.bool_)
    corner_color = np.zeros(n_max, np.int64)
    for c in range(len(contour_start) - 1):
        s0, s1 = contour_start[c], contour_start[c + 1]
        m = s1 - s0
        if m == 0:
            continue
        count, length = _contour_corners(points, degree, s0, s1, cross_threshold, corners, spline_len)
        minor[:count] = False
        if count == 0:
            for i in range(m):
                colors[s0 + i] = WHITE
        elif count == 1:
            # teardrop: three zones around the single corner (the first and last share one channel each side)
            zone0, seed = _switch_color(WHITE, seed, BLACK)
            zone2, seed = _switch_color(zone0, seed, BLACK)
            for i in range(m):
                k = _teardrop_zone(i, m)
                colors[s0 + (corners[0] + i) % m] = zone0 if k < 0 else (WHITE if k == 0 else zone2)
        else:
            if (strategy == 1 or strategy == 3) and count > 3:
                spline_len[0] += length  # the spline wrapping around the contour's start
                major = count
                for i in range(count):
                    if (spline_len[(i + 1) % count] < max_notch and spline_len[i] > spline_len[(i + 1) % count]
                            and spline_len[(i + 1) % count] < spline_len[(i + 2) % count]):
                        minor[i] = True
                        major -= 1
                color = WHITE
                initial = BLACK
                remaining = major
                for i in range(count):
                    if not minor[i]:
                        remaining -= 1
                        color, seed = _switch_color(color, seed, initial if remaining == 0 else BLACK)
                        corner_color[i] = color
                        if initial == BLACK:
                            initial = color
                for i in range(count):
                    if minor[i]:
                        corner_color[i] = (color & corner_color[(i + 1) % count]) ^ WHITE
                    else:
                        color = corner_color[i]
            else:
                color, seed = _switch_color(WHITE, seed, BLACK)
                initial = color
                corner_color[0] = color
                for k in range(1, count):
                    color, seed = _switch_color(color, seed, initial if k == count - 1 else BLACK)
                    corner_color[k] = color
            spline = 0
            color = corner_color[0]
            for i in range(m):
                index = (corners[0] + i) % m
                if spline + 1 < count and corners[spline + 1] == index:
                    spline += 1
                    color = corner_color[spline]
                colors[s0 + index] = color
    return seed


MAX_RECOLOR_STEPS = 16  # msdfgen's bound on the recoloring search when a new constraint conflicts
MAX_GRAPH_SPLINES = 1024  # larger glyphs (none in real fonts; a hostile one could hold 10^5) fall back to simple:
# the graph is a dense splines x splines matrix
DISTANCE_SAMPLES = 16  # points per segment at which the distance to the other segment is taken
SPLINE_COLORS = (YELLOW, CYAN, MAGENTA)  # any two share exactly one channel


@numba.njit(cache=True)
def _segment_gap(P, dp, Q, dq):
    """Distance between two segments, 0 when they share an endpoint: the least distance from DISTANCE_SAMPLES + 1
    points of each to the other (exact point-to-segment distances)."""
    for ei in range(2):
        i = dp if ei else 0
        for ej in range(2):
            j = dq if ej else 0
            if P[i, 0] == Q[j, 0] and P[i, 1] == Q[j, 1]:
                return 0.0
    best = math.sqrt((P[0, 0] - Q[0, 0]) ** 2 + (P[0, 1] - Q[0, 1]) ** 2)
    for i in range(DISTANCE_SAMPLES + 1):
        t = i / DISTANCE_SAMPLES
        x, y = point_at(Q, dq, t)
        d, _, _ = signed_distance(P, dp, x, y)
        best = min(best, abs(d))
        x, y = point_at(P, dp, t)
        d, _, _ = signed_distance(Q, dq, x, y)
        best = min(best, abs(d))
    return best


@numba.njit(cache=True)
def _free_colors(coloring, adjacent, v):
    """Bitmask of the spline colors (bit k: color k) no colored neighbour of spline v uses."""
    used = 0
    for j in range(len(coloring)):
        if adjacent[v, j] and coloring[j] >= 0:
            used |= 1 << coloring[j]
    return 7 & ~used


@numba.njit(cache=True)
def _first_color(mask):
    for k in range(3):
        if mask & (1 << k):
            return k
    return -1


@numba.njit(cache=True)
def _uncolor_same(queue, tail, coloring, adjacent, v):
    for j in range(len(coloring)):
        if j != v and adjacent[v, j] and coloring[j] == coloring[v]:
            coloring[j] = -1
            queue[tail] = j
            tail += 1
    return tail


@numba.njit(cache=True)
def _try_constraint(coloring, adjacent, a, b, trial, queue):
    """Add "splines a and b differ" to the graph if a 3-coloring can keep it: b takes a free color, else a short
    breadth-first recoloring from b (at most MAX_RECOLOR_STEPS forced choices) must end with no spline uncolored.
    On failure the constraint is dropped and the coloring is unchanged."""
    adjacent[a, b] = adjacent[b, a] = True
    if coloring[a] != coloring[b]:
        return True
    free = _free_colors(coloring, adjacent, b)
    if free:
        coloring[b] = _first_color(free)
        return True
    trial[:] = coloring
    trial[b] = _first_color(7 & ~(1 << trial[a]))
    head, tail = 0, _uncolor_same(queue, 0, trial, adjacent, b)
    step = 0
    while head < tail and step < MAX_RECOLOR_STEPS:
        v = queue[head]
        head += 1
        free = _free_colors(trial, adjacent, v)
        if free:
            trial[v] = _first_color(free)
            continue
        while True:
            trial[v] = step % 3
            step += 1
            if not (adjacent[v, a] and trial[v] == trial[a]):
                break
        tail = _uncolor_same(queue, tail, trial, adjacent, v)
    if head < tail:
        adjacent[a, b] = adjacent[b, a] = False
        return False
    coloring[:] = trial
    return True


@numba.njit(cache=True)
def color_edges_by_distance(points, degree, contour_start, angle_threshold, cutoff, seed, colors):
    """Edge coloring by distance (msdfgen's ``edgeColoringByDistance``): every spline (the edges between two corners;
    the two outer zones of a teardrop) is a vertex of a graph; splines that touch must differ, then, closest pairs
    first, any two splines nearer than ``cutoff`` should differ too when a 3-coloring allows it. Close but
    non-adjacent splines (the two sides of a hairline, a serif and the stem beside it, parallel CJK strokes) thus
    get different channel pairs, so one channel's nearest edge does not jump between them. Smooth contours and the
    middle zone of a teardrop stay white, as in ``simple``. Returns the seed left, or -1 (colors not set) when the
    glyph has more than MAX_GRAPH_SPLINES splines."""
    cross_threshold = math.sin(angle_threshold)
    n = len(degree)
    walk = np.empty(n, np.int64)  # segment indices in spline order
    spline_start = np.empty(n + 1, np.int64)
    corners = np.empty(n, np.int64)
    spline_len = np.empty(n)
    count = 0
    splines = 0
    for c in range(len(contour_start) - 1):
        s0, s1 = contour_start[c], contour_start[c + 1]
        m = s1 - s0
        if m == 0:
            continue
        corner_count, _ = _contour_corners(points, degree, s0, s1, cross_threshold, corners, spline_len)
        if corner_count == 0:
            for i in range(m):
                colors[s0 + i] = WHITE
        elif corner_count == 1:
            spline_start[splines] = count
            splines += 1
            for i in range(m):
                if i == m // 2:
                    spline_start[splines] = count
                    splines += 1
                s = s0 + (corners[0] + i) % m
                if _teardrop_zone(i, m) == 0:
                    colors[s] = WHITE
                else:
                    walk[count] = s
                    count += 1
        else:
            spline = 0
            for i in range(m):
                index = (corners[0] + i) % m
                if i == 0 or (spline + 1 < corner_count and corners[spline + 1] == index):
                    if i > 0:
                        spline += 1
                    spline_start[splines] = count
                    splines += 1
                walk[count] = s0 + index
                count += 1
    spline_start[splines] = count
    if splines == 0:
        return seed
    if splines > MAX_GRAPH_SPLINES:
        return -1
    lo = np.full((splines, 2), np.inf)
    hi = np.full((splines, 2), -np.inf)
    for v in range(splines):
        for k in range(spline_start[v], spline_start[v + 1]):
            s = walk[k]
            for r in range(degree[s] + 1):
                for axis in range(2):
                    lo[v, axis] = min(lo[v, axis], points[s, r, axis])
                    hi[v, axis] = max(hi[v, axis], points[s, r, axis])
    # pairwise spline distances below the cutoff (control-point boxes bound the curves: farther boxes are skipped)
    pair_a = np.empty(splines * (splines - 1) // 2, np.int64)
    pair_b = np.empty_like(pair_a)
    pair_d = np.empty(len(pair_a))
    pairs = 0
    adjacent = np.zeros((splines, splines), np.bool_)
    for a in range(splines):
        for b in range(a + 1, splines):
            gx = max(0.0, max(lo[b, 0] - hi[a, 0], lo[a, 0] - hi[b, 0]))
            gy = max(0.0, max(lo[b, 1] - hi[a, 1], lo[a, 1] - hi[b, 1]))
            if gx * gx + gy * gy > cutoff * cutoff:
                continue
            best = np.inf
            for i in range(spline_start[a], spline_start[a + 1]):
                for j in range(spline_start[b], spline_start[b + 1]):
                    if best > 0.0:
                        best = min(best, _segment_gap(points[walk[i]], degree[walk[i]], points[walk[j]],
                                                      degree[walk[j]]))
            if best == 0.0:
                adjacent[a, b] = adjacent[b, a] = True
            elif best <= cutoff:
                pair_a[pairs], pair_b[pairs], pair_d[pairs] = a, b, best
                pairs += 1
    # greedy coloring of the touching graph (a contour's splines form a cycle: always 3-colorable), in spline order
    coloring = np.full(splines, -1, np.int64)
    for v in range(splines):
        free = _free_colors(coloring, adjacent, v)
        options = (free & 1) + ((free >> 1) & 1) + ((free >> 2) & 1)
        if options == 0:
            coloring[v] = 0
        elif options == 3:
            coloring[v] = (seed % 3 + v) % 3
            seed //= 3
        elif options == 2:
            first = _first_color(free)
            second = _first_color(free & ~(1 << first))
            coloring[v] = second if seed & 1 else first
            seed >>= 1
        else:
            coloring[v] = _first_color(free)
    order = np.argsort(pair_d[:pairs], kind="mergesort")
    trial = np.empty(splines, np.int64)
    queue = np.empty(splines * (MAX_RECOLOR_STEPS + 2), np.int64)
    for k in order:
        _try_constraint(coloring, adjacent, pair_a[k], pair_b[k], trial, queue)
    for v in range(splines):
        for k in range(spline_start[v], spline_start[v + 1]):
            colors[walk[k]] = SPLINE_COLORS[coloring[v]]
    return seed


@numba.njit(cache=True)
def corner_points(points, degree, contour_start, colors, out):
    """Points where two edges meet that share at most one channel (the corners MSDF keeps sharp); returns count."""
    n = 0
    for c in range(len(contour_start) - 1):
        s0, s1 = contour_start[c], contour_start[c + 1]
        for s in range(s0, s1):
            prev = s1 - 1 if s == s0 else s - 1
            common = colors[prev] & colors[s]
            if (common & (common - 1)) == 0:
                out[n, 0], out[n, 1] = points[s, 0, 0], points[s, 0, 1]
                n += 1
    return n


def edge_colors(points: np.ndarray, degree: np.ndarray, contour_start: np.ndarray, angle_threshold: float = 3.0,
                strategy: str = "notch", seed: int = 0, cutoff: float = math.inf, texel: float = 1.0) -> np.ndarray:
    """Channel bitmask per segment (see the module docstring). ``cutoff``: the ``distance`` strategy's largest
    spline-to-spline distance that asks for different colors (unbounded as in msdfgen unless given); ``texel``: the
    size of one field texel in the points' units (``notch``: shorter splines can be notches)."""
    if strategy not in STRATEGIES:
        raise ValueError(f"unknown edge-coloring strategy {strategy!r} (known: {', '.join(STRATEGIES)})")
    colors = np.full(len(degree), WHITE, np.uint8)
    if not len(degree):
        return colors
    if strategy == "distance":
        if color_edges_by_distance(points, degree, contour_start, float(angle_threshold), float(cutoff), int(seed),
                                   colors) >= 0:
            return colors
        strategy = "simple"  # more splines than the graph may hold (MAX_GRAPH_SPLINES): the rotation
    max_notch = float(texel) if strategy == "notch" else math.inf
    color_edges(points, degree, contour_start, float(angle_threshold), STRATEGIES[strategy], int(seed), colors,
                max_notch)
    return colors
