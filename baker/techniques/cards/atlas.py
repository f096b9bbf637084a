"""The strand atlas: every card's region packed into one texture (shelf packing with padding), its clump's strands
projected onto the card (orthographic along the card normal: each point's closest point on the ribbon) and drawn
as anti-aliased lines of the strand's width into the region (RTR4 14.7.1: textures of strands on alpha-tested
cards).

Per texel the rasteriser keeps the coverage (alpha = 1 - prod(1 - c) over strands; a strand counts once, at its
largest coverage of the texel), the coverage-weighted depth offset from the card plane, root-to-tip parameter and
flow direction, and the strand covering the texel most (its random value).
"""
from __future__ import annotations

import math

import numba
import numpy as np


# ------------------------------------------------------------------------------------------------------- packing
def shelf_pack(sizes: np.ndarray, atlas_size: int, padding: int, scale: float):
    """Rectangles (K, 4) int64 x, y, width, height (padding included) of regions whose inside is ``sizes`` (K, 2:
    width, height in world units) x ``scale`` texels, packed in rows, tallest first; None when they overflow."""
    inner = np.maximum(np.rint(sizes * scale).astype(np.int64), 2)
    outer = inner + 2 * padding
    if (outer > atlas_size).any():
        return None
    order = np.lexsort((np.arange(len(sizes)), -outer[:, 0], -outer[:, 1]))
    rects = np.zeros((len(sizes), 4), np.int64)
    x = y = row = 0
    for k in order.tolist():
        w, h = int(outer[k, 0]), int(outer[k, 1])
        if x + w > atlas_size:
            x, y, row = 0, y + row, 0
        if y + h > atlas_size:
            return None
        rects[k] = (x, y, w, h)
        x += w
        row = max(row, h)
    return rects


def pack_regions(sizes: np.ndarray, atlas_size: int, padding: int) -> tuple[np.ndarray, float]:
    """The largest uniform texel density (texels per world unit, found by bisection) at which the regions fit;
    returns (rectangles, density)."""
    sizes = np.maximum(np.asarray(sizes, np.float64), 1e-12)
    lo = 0.0
    hi = (atlas_size - 2 * padding) / sizes.max()
    for _ in range(48):
        mid = 0.5 * (lo + hi)
        if shelf_pack(sizes, atlas_size, padding, mid) is None:
            hi = mid
        else:
            lo = mid
    rects = shelf_pack(sizes, atlas_size, padding, lo)
    if rects is None:
        raise ValueError(f"{len(sizes)} cards do not fit a {atlas_size}² atlas with {padding}-texel padding "
                         "(raise --atlas-size or lower --padding or --cards)")
    return rects, lo


# ---------------------------------------------------------------------------------------------------- projection
@numba.njit(cache=True, nogil=True, inline="always")
def _dot3(ax, ay, az, bx, by, bz):
    return ax * bx + ay * by + az * bz


@numba.njit(cache=True, nogil=True)
def _closest_on_triangle(p, tri):
    """Closest point of triangle ``tri`` (3, 3) to p as barycentrics (Ericson, Real-Time Collision Detection,
    5.1.5), in scalars: no temporary arrays in the inner loop."""
    ax, ay, az = tri[0, 0], tri[0, 1], tri[0, 2]
    abx, aby, abz = tri[1, 0] - ax, tri[1, 1] - ay, tri[1, 2] - az
    acx, acy, acz = tri[2, 0] - ax, tri[2, 1] - ay, tri[2, 2] - az
    apx, apy, apz = p[0] - ax, p[1] - ay, p[2] - az
    d1, d2 = _dot3(abx, aby, abz, apx, apy, apz), _dot3(acx, acy, acz, apx, apy, apz)
    if d1 <= 0.0 and d2 <= 0.0:
        return 1.0, 0.0, 0.0
    bpx, bpy, bpz = p[0] - tri[1, 0], p[1] - tri[1, 1], p[2] - tri[1, 2]
    d3, d4 = _dot3(abx, aby, abz, bpx, bpy, bpz), _dot3(acx, acy, acz, bpx, bpy, bpz)
    if d3 >= 0.0 and d4 <= d3:
        return 0.0, 1.0, 0.0
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        v = d1 / (d1 - d3)
        return 1.0 - v, v, 0.0
    cpx, cpy, cpz = p[0] - tri[2, 0], p[1] - tri[2, 1], p[2] - tri[2, 2]
    d5, d6 = _dot3(abx, aby, abz, cpx, cpy, cpz), _dot3(acx, acy, acz, cpx, cpy, cpz)
    if d6 >= 0.0 and d5 <= d6:
        return 0.0, 0.0, 1.0
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        w = d2 / (d2 - d6)
        return 1.0 - w, 0.0, w
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return 0.0, 1.0 - w, w
    denom = 1.0 / (va + vb + vc)
    v, w = vb * denom, vc * denom
    return 1.0 - v - w, v, w


@numba.njit(cache=True, nogil=True, parallel=True)
def closest_on_cards(points, card_of_point, tri_start, tri_count, corners):
    """For each point, the closest point on its card's triangles: (triangle (P,), barycentrics (P, 3), distance (P,)).
    ``corners`` (T, 3, 3) triangle corner positions; card c owns triangles tri_start[c] .. + tri_count[c]."""
    n = len(points)
    tri = np.empty(n, np.int64)
    bary = np.empty((n, 3))
    dist = np.empty(n)
    for i in numba.prange(n):
        c = card_of_point[i]
        best = np.inf
        p = points[i]
        for t in range(tri_start[c], tri_start[c] + tri_count[c]):
            k = corners[t]
            u, v, w = _closest_on_triangle(p, k)
            dx = p[0] - (u * k[0, 0] + v * k[1, 0] + w * k[2, 0])
            dy = p[1] - (u * k[0, 1] + v * k[1, 1] + w * k[2, 1])
            dz = p[2] - (u * k[0, 2] + v * k[1, 2] + w * k[2, 2])
            d = dx * dx + dy * dy + dz * dz
            if d < best:
                best = d
                tri[i] = t
                bary[i, 0], bary[i, 1], bary[i, 2] = u, v, w
        dist[i] = math.sqrt(best)
    return tri, bary, dist


# ------------------------------------------------------------------------------------------------- rasterisation
@numba.njit(cache=True, nogil=True)
def _segment_texels(x0, y0, x1, y1, radius, clip, stamp, cov, attr, a0, a1, pass_two, strand, alpha, sums, weight,
                    top, top_cov):
    """Visit the texels a segment of half-width ``radius`` (texels) touches inside ``clip``. Pass one keeps the
    strand's largest coverage of each texel and the attributes where it was reached; pass two composites each
    touched texel once (``stamp`` marks the strand that last wrote it)."""
    xa = max(int(math.floor(min(x0, x1) - radius - 1.0)), clip[0])
    xb = min(int(math.ceil(max(x0, x1) + radius + 1.0)), clip[2] - 1)
    ya = max(int(math.floor(min(y0, y1) - radius - 1.0)), clip[1])
    yb = min(int(math.ceil(max(y0, y1) + radius + 1.0)), clip[3] - 1)
    dx, dy = x1 - x0, y1 - y0
    ll = dx * dx + dy * dy
    n_attr = attr.shape[2]
    for y in range(ya, yb + 1):
        for x in range(xa, xb + 1):
            if pass_two:
                if stamp[y, x] == strand or cov[y, x] <= 0.0:
                    continue
                stamp[y, x] = strand
                c = cov[y, x]
                alpha[y, x] = 1.0 - (1.0 - alpha[y, x]) * (1.0 - c)
                weight[y, x] += c
                for k in range(n_attr):
                    sums[y, x, k] += c * attr[y, x, k]
                if c > top_cov[y, x]:
                    top_cov[y, x] = c
                    top[y, x] = strand
                cov[y, x] = 0.0
                continue
            px, py = x + 0.5 - x0, y + 0.5 - y0
            t = 0.0
            if ll > 0.0:
                t = min(max((px * dx + py * dy) / ll, 0.0), 1.0)
            ex, ey = px - t * dx, py - t * dy
            d = math.sqrt(ex * ex + ey * ey)
            # box-filtered edge: a line of half-width r covers a texel at distance d by about r + 1/2 - d
            c = min(max(radius + 0.5 - d, 0.0), 1.0)
            if radius < 0.5:
                c *= 2.0 * radius  # thinner than a texel: its area, not more
            if c > cov[y, x]:
                cov[y, x] = c
                for k in range(n_attr):
                    attr[y, x, k] = a0[k] + t * (a1[k] - a0[k])


@numba.njit(cache=True, nogil=True)
def rasterize_strands(xy, attributes, radius, clip, height, width):
    """Draw strands (S, V, 2 texel coordinates) with per-vertex ``attributes`` (S, V, A) and half-widths ``radius``
    (S, V, texels), each inside its ``clip`` rectangle (S, 4: x0, y0, x1, y1, exclusive ends).
    Returns alpha (H, W), coverage-weighted attribute sums (H, W, A), weights (H, W), top strand (H, W; -1: none).
    Per-texel arrays are float32 / int32 (about 16 x 4 bytes per texel at A = 5: 1 GB for a 4096² atlas)."""
    s, v, _ = xy.shape
    n_attr = attributes.shape[2]
    alpha = np.zeros((height, width), np.float32)
    sums = np.zeros((height, width, n_attr), np.float32)
    weight = np.zeros((height, width), np.float32)
    top = np.full((height, width), -1, np.int32)
    top_cov = np.zeros((height, width), np.float32)
    stamp = np.full((height, width), -1, np.int32)
    cov = np.zeros((height, width), np.float32)
    attr = np.zeros((height, width, n_attr), np.float32)
    for i in range(s):
        for pass_two in (False, True):
            for j in range(v - 1):
                r = 0.5 * (radius[i, j] + radius[i, j + 1])
                _segment_texels(xy[i, j, 0], xy[i, j, 1], xy[i, j + 1, 0], xy[i, j + 1, 1], r, clip[i], stamp, cov,
                                attr, attributes[i, j], attributes[i, j + 1], pass_two, i, alpha, sums, weight, top,
                                top_cov)
    return alpha, sums, weight, top


@numba.njit(cache=True, nogil=True, parallel=True)
def points_held(strands, candidates, tri_start, tri_count, corners, tri_first, tri_last, window, tolerance):
    """(S, C) for each strand (S, V, 3) and candidate card (``candidates`` (S, C)): how many of its points lie within
    ``tolerance`` of the card, and (second array) the mean of min(distance / tolerance, 4) over its points. Point j
    is measured against the card's triangles spanning stations within ``window`` of j only (``tri_first`` /
    ``tri_last``: the station numbers a triangle's quad spans): a strand runs beside its card station by station,
    and a farther triangle would only be nearer for a strand that does not follow the card."""
    s, v, _ = strands.shape
    c = candidates.shape[1]
    held = np.zeros((s, c), np.int64)
    spread = np.zeros((s, c))
    for i in numba.prange(s):
        for k in range(c):
            card = candidates[i, k]
            count = 0
            total = 0.0
            for j in range(v):
                p = strands[i, j]
                best = np.inf
                reach = np.inf  # sqrt(best): a triangle whose bounding sphere lies farther cannot be nearer
                for t in range(tri_start[card], tri_start[card] + tri_count[card]):
                    if tri_last[t] < j - window or tri_first[t] > j + window:
                        continue
                    q = corners[t]
                    cx = (q[0, 0] + q[1, 0] + q[2, 0]) / 3.0 - p[0]
                    cy = (q[0, 1] + q[1, 1] + q[2, 1]) / 3.0 - p[1]
                    cz = (q[0, 2] + q[1, 2] + q[2, 2]) / 3.0 - p[2]
                    r = 0.0
                    for m in range(3):
                        ex, ey, ez = q[m, 0] - p[0] - cx, q[m, 1] - p[1] - cy, q[m, 2] - p[2] - cz
                        r = max(r, ex * ex + ey * ey + ez * ez)
                    if math.sqrt(cx * cx + cy * cy + cz * cz) - math.sqrt(r) >= reach:
                        continue
                    a, b, w = _closest_on_triangle(p, q)
                    dx = p[0] - (a * q[0, 0] + b * q[1, 0] + w * q[2, 0])
                    dy = p[1] - (a * q[0, 1] + b * q[1, 1] + w * q[2, 1])
                    dz = p[2] - (a * q[0, 2] + b * q[1, 2] + w * q[2, 2])
                    d = dx * dx + dy * dy + dz * dz
                    if d < best:
                        best = d
                        reach = math.sqrt(d)
                d = reach / tolerance
                if d <= 1.0:
                    count += 1
                total += min(d, 4.0)
            held[i, k] = count
            spread[i, k] = total / v
    return held, spread
