"""Edge coloring for multi-channel distance fields (Chlumsky 2015, section 3.1).

Each edge gets a subset of the channels {R, G, B} (a bitmask: 1 R, 2 G, 4 B). At every *corner* — where the
direction turns by more than the angle threshold, i.e. the unit tangents a, b meet with a . b <= 0 or
|a x b| > sin(threshold) — the two edges must share exactly one channel; along a smooth spline the color stays. The
median of the three channels then reproduces the sharp corner under bilinear interpolation.

Strategies:
- ``simple``: walk the corners of each contour and rotate through cyan/magenta/yellow, never letting the last
  spline share two channels with the first; a contour with one corner (a teardrop) is split into three color
  zones around it; a contour without corners is white (all channels).
- ``inktrap``: as simple, but on contours with more than three corners the corner that ends an unusually short
  spline (shorter than both its neighbours: the notch of an ink trap) is *minor*: the colors of the major corners
  are chosen first, then each minor corner gets the one channel its neighbours do not share, so the short spline
  does not force a two-channel clash onto its long neighbours. Removing every such short spline leaves a valid
  coloring of the rest. The default, as in msdf-atlas-gen: serif and sans fonts are full of such notches (the
  short flat end of a serif, the cut where a bowl meets its stem), and with it the mean coverage error is below
  msdfgen's ``edgeColoringSimple`` on every font measured (benchmarks/RESULTS.md, issue 19 edge colouring);
  ``simple`` left Noto Serif above it (its ``b``, ``d`` and ``u``).

Deterministic: the color sequence depends only on the contour order (``seed`` 0 unless asked).
"""
from __future__ import annotations

import math

import numba
import numpy as np

from baker.techniques.glyphs.segments import direction_at, point_at

BLACK, RED, GREEN, YELLOW, BLUE, MAGENTA, CYAN, WHITE = 0, 1, 2, 3, 4, 5, 6, 7
STRATEGIES = {"simple": 0, "inktrap": 1}


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
def color_edges(points, degree, contour_start, angle_threshold, strategy, seed, colors):
    """Fill ``colors`` (uint8 per segment); contours must already have >= 3 segments when they have one corner."""
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
        # corners: segment i starts at a corner when the previous segment's end tangent turns into its start tangent
        count = 0
        length = 0.0
        px, py = direction_at(points[s1 - 1], degree[s1 - 1], 1.0)
        for i in range(m):
            s = s0 + i
            dx, dy = direction_at(points[s], degree[s], 0.0)
            if _is_corner(px, py, dx, dy, cross_threshold):
                corners[count] = i
                spline_len[count] = length  # length of the spline that ends at this corner
                minor[count] = False
                count += 1
                length = 0.0
            length += _length(points[s], degree[s])
            px, py = direction_at(points[s], degree[s], 1.0)
        if count == 0:
            for i in range(m):
                colors[s0 + i] = WHITE
        elif count == 1:
            # teardrop: three zones around the single corner (the first and last share one channel each side)
            zone0, seed = _switch_color(WHITE, seed, BLACK)
            zone2, seed = _switch_color(zone0, seed, BLACK)
            for i in range(m):
                k = int(3.0 + 2.875 * i / (m - 1) - 1.4375 + 0.5) - 3 if m > 1 else 0
                colors[s0 + (corners[0] + i) % m] = zone0 if k < 0 else (WHITE if k == 0 else zone2)
        else:
            if strategy == 1 and count > 3:
                spline_len[0] += length  # the spline wrapping around the contour's start
                major = count
                for i in range(count):
                    if (spline_len[i] > spline_len[(i + 1) % count]
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
                strategy: str = "inktrap", seed: int = 0) -> np.ndarray:
    """Channel bitmask per segment (see the module docstring)."""
    if strategy not in STRATEGIES:
        raise ValueError(f"unknown edge-coloring strategy {strategy!r} (known: {', '.join(STRATEGIES)})")
    colors = np.full(len(degree), WHITE, np.uint8)
    if len(degree):
        color_edges(points, degree, contour_start, float(angle_threshold), STRATEGIES[strategy], int(seed), colors)
    return colors
