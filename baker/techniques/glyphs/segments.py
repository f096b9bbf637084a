"""Edge segments of an outline: lines, quadratic and cubic Beziers, and the exact distance from a point to one.

A segment is a row of a ``(n, 4, 2)`` float64 array of control points plus its degree (1, 2 or 3); unused rows are
ignored. Everything here is ``numba.njit``: the distance-field kernels call these functions once per texel and
segment.

Distance (Chlumsky, *Shape Decomposition for Multi-channel Distance Fields*, MSc thesis, 2015, section 2.2):
the closest point of a Bezier B(t) to p is at an endpoint or where (B(t) - p) . B'(t) = 0. For a quadratic this is a
cubic in t, solved in closed form; for a cubic it is a quintic, solved by Newton iterations from evenly spaced starts
(the standard approach of msdfgen). The sign is + when p lies to the LEFT of the segment's direction: contours are
oriented so the filled side is on the left (counter-clockwise outer contours, y up), so + means inside.

Ties at a shared endpoint (a corner) are broken by how far p is from the segment's tangent there (``dot``: |cos| of
the angle between the tangent and p - endpoint, smaller wins), which makes the nearest edge of a corner the one whose
pseudo-distance is valid.
"""
from __future__ import annotations

import math

import numba
import numpy as np

LINE, QUADRATIC, CUBIC = 1, 2, 3


@numba.njit(cache=True, inline="always")
def point_at(P, deg, t):
    """B(t) as (x, y)."""
    if deg == 1:
        return P[0, 0] + t * (P[1, 0] - P[0, 0]), P[0, 1] + t * (P[1, 1] - P[0, 1])
    s = 1.0 - t
    if deg == 2:
        a, b, c = s * s, 2.0 * s * t, t * t
        return a * P[0, 0] + b * P[1, 0] + c * P[2, 0], a * P[0, 1] + b * P[1, 1] + c * P[2, 1]
    a, b, c, d = s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t
    return (a * P[0, 0] + b * P[1, 0] + c * P[2, 0] + d * P[3, 0],
            a * P[0, 1] + b * P[1, 1] + c * P[2, 1] + d * P[3, 1])


@numba.njit(cache=True)
def direction_at(P, deg, t):
    """A tangent vector at t (not normalized). At an endpoint whose derivative vanishes (a control point on top of
    the endpoint) the next control point gives the limit direction."""
    if deg == 1:
        return P[1, 0] - P[0, 0], P[1, 1] - P[0, 1]
    s = 1.0 - t
    if deg == 2:
        dx = s * (P[1, 0] - P[0, 0]) + t * (P[2, 0] - P[1, 0])
        dy = s * (P[1, 1] - P[0, 1]) + t * (P[2, 1] - P[1, 1])
        if dx == 0.0 and dy == 0.0:
            return P[2, 0] - P[0, 0], P[2, 1] - P[0, 1]
        return dx, dy
    dx = (s * s * (P[1, 0] - P[0, 0]) + 2.0 * s * t * (P[2, 0] - P[1, 0]) + t * t * (P[3, 0] - P[2, 0]))
    dy = (s * s * (P[1, 1] - P[0, 1]) + 2.0 * s * t * (P[2, 1] - P[1, 1]) + t * t * (P[3, 1] - P[2, 1]))
    if dx == 0.0 and dy == 0.0:
        if t <= 0.5:
            dx, dy = P[2, 0] - P[0, 0], P[2, 1] - P[0, 1]
        else:
            dx, dy = P[3, 0] - P[1, 0], P[3, 1] - P[1, 1]
        if dx == 0.0 and dy == 0.0:
            dx, dy = P[3, 0] - P[0, 0], P[3, 1] - P[0, 1]
    return dx, dy


@numba.njit(cache=True)
def solve_quadratic(a, b, c, roots):
    """Real roots of a t^2 + b t + c into ``roots``; returns their count (-1: every t is a root)."""
    if a == 0.0 or abs(b) > 1e12 * abs(a):
        if b == 0.0:
            return -1 if c == 0.0 else 0
        roots[0] = -c / b
        return 1
    disc = b * b - 4.0 * a * c
    if disc > 0.0:
        # the numerically stable pair: no cancellation between -b and sqrt(disc)
        q = -0.5 * (b + math.copysign(math.sqrt(disc), b))
        roots[0] = q / a
        roots[1] = c / q if q != 0.0 else -b / a - roots[0]
        return 2
    if disc == 0.0:
        roots[0] = -0.5 * b / a
        return 1
    return 0


@numba.njit(cache=True)
def solve_cubic(a, b, c, d, roots):
    """Real roots of a t^3 + b t^2 + c t + d into ``roots`` (size >= 3); returns their count."""
    if a != 0.0:
        bn = b / a
        if abs(bn) < 1e6:  # otherwise the cubic term is noise: treat as a quadratic
            cn, dn = c / a, d / a
            a3 = bn / 3.0
            q = (a3 * a3) - cn / 3.0           # depressed cubic x^3 - 3 q x + 2 r = 0 with t = x - a3
            r = (a3 * a3 * a3) - 0.5 * a3 * cn + 0.5 * dn
            r2, q3 = r * r, q * q * q
            if r2 < q3:  # three real roots: trigonometric form
                ratio = max(-1.0, min(1.0, r / math.sqrt(q3)))
                theta = math.acos(ratio)
                m = -2.0 * math.sqrt(q)
                roots[0] = m * math.cos(theta / 3.0) - a3
                roots[1] = m * math.cos((theta + 2.0 * math.pi) / 3.0) - a3
                roots[2] = m * math.cos((theta - 2.0 * math.pi) / 3.0) - a3
                return 3
            big = -math.copysign(math.pow(abs(r) + math.sqrt(r2 - q3), 1.0 / 3.0), r)
            small = q / big if big != 0.0 else 0.0
            roots[0] = (big + small) - a3
            if big == small or abs(big - small) < 1e-12 * abs(big + small):
                roots[1] = -0.5 * (big + small) - a3
                return 2
            return 1
    return solve_quadratic(b, c, d, roots)


@numba.njit(cache=True)
def _endpoint_candidate(P, deg, t, px, py):
    """Distance (unsigned), sign and tie-break value of p against the endpoint at t in {0, 1}."""
    ex, ey = point_at(P, deg, t)
    dx, dy = direction_at(P, deg, t)
    qx, qy = px - ex, py - ey
    dist = math.sqrt(qx * qx + qy * qy)
    cross = dx * qy - dy * qx
    dl = math.sqrt(dx * dx + dy * dy)
    dot = abs(dx * qx + dy * qy) / (dl * dist) if dl > 0.0 and dist > 0.0 else 0.0
    return dist, (1.0 if cross >= 0.0 else -1.0), dot


@numba.njit(cache=True)
def signed_distance(P, deg, px, py):
    """Exact distance from p to the segment: (signed distance, tie-break dot, parameter t of the closest point).

    ``t`` is 0 or 1 when the closest point is an endpoint; the sign is + on the left of the direction of travel.
    """
    d0, s0, dot0 = _endpoint_candidate(P, deg, 0.0, px, py)
    d1, s1, dot1 = _endpoint_candidate(P, deg, 1.0, px, py)
    if d1 < d0 or (d1 == d0 and dot1 < dot0):
        best, sign, dot, best_t = d1, s1, dot1, 1.0
    else:
        best, sign, dot, best_t = d0, s0, dot0, 0.0
    if deg == 1:
        abx, aby = P[1, 0] - P[0, 0], P[1, 1] - P[0, 1]
        l2 = abx * abx + aby * aby
        if l2 > 0.0:
            t = ((px - P[0, 0]) * abx + (py - P[0, 1]) * aby) / l2
            if 0.0 < t < 1.0:
                cross = abx * (py - P[0, 1]) - aby * (px - P[0, 0])
                d = abs(cross) / math.sqrt(l2)
                if d < best:
                    return (d if cross >= 0.0 else -d), 0.0, t
        return sign * best, dot, best_t
    roots = np.empty(3)
    if deg == 2:
        # (q + 2 t a + t^2 b) . (a + t b) = 0 with q = p0 - p, a = p1 - p0, b = p2 - 2 p1 + p0
        qx, qy = P[0, 0] - px, P[0, 1] - py
        ax, ay = P[1, 0] - P[0, 0], P[1, 1] - P[0, 1]
        bx, by = P[2, 0] - 2.0 * P[1, 0] + P[0, 0], P[2, 1] - 2.0 * P[1, 1] + P[0, 1]
        n = solve_cubic(bx * bx + by * by, 3.0 * (ax * bx + ay * by), 2.0 * (ax * ax + ay * ay) + qx * bx + qy * by,
                        qx * ax + qy * ay, roots)
        for k in range(max(n, 0)):
            t = roots[k]
            if 0.0 < t < 1.0:
                x, y = point_at(P, 2, t)
                d = math.sqrt((px - x) ** 2 + (py - y) ** 2)
                if d < best:
                    tx, ty = ax + t * bx, ay + t * by
                    cross = tx * (py - y) - ty * (px - x)
                    best, sign, dot, best_t = d, (1.0 if cross >= 0.0 else -1.0), 0.0, t
        return sign * best, dot, best_t
    # cubic: B(t) = p0 + t A1 + t^2 A2 + t^3 A3; Newton on g(t) = (B - p) . B'
    a1x, a1y = 3.0 * (P[1, 0] - P[0, 0]), 3.0 * (P[1, 1] - P[0, 1])
    a2x = 3.0 * (P[2, 0] - 2.0 * P[1, 0] + P[0, 0])
    a2y = 3.0 * (P[2, 1] - 2.0 * P[1, 1] + P[0, 1])
    a3x = P[3, 0] - 3.0 * P[2, 0] + 3.0 * P[1, 0] - P[0, 0]
    a3y = P[3, 1] - 3.0 * P[2, 1] + 3.0 * P[1, 1] - P[0, 1]
    # starts: one per ~6 units of control-polygon length (texels in the kernels), 3..8: the closest-point function of
    # a short segment has at most a couple of basins, a long one may have more; Newton stops once the step is tiny
    poly = 0.0
    for k in range(3):
        poly += math.sqrt((P[k + 1, 0] - P[k, 0]) ** 2 + (P[k + 1, 1] - P[k, 1]) ** 2)
    starts = min(8, max(3, int(math.ceil(poly / 6.0))))
    for k in range(starts + 1):
        t = k / starts
        for _ in range(8):
            bx = P[0, 0] + t * (a1x + t * (a2x + t * a3x)) - px
            by = P[0, 1] + t * (a1y + t * (a2y + t * a3y)) - py
            d1x, d1y = a1x + t * (2.0 * a2x + 3.0 * t * a3x), a1y + t * (2.0 * a2y + 3.0 * t * a3y)
            d2x, d2y = 2.0 * a2x + 6.0 * t * a3x, 2.0 * a2y + 6.0 * t * a3y
            g = bx * d1x + by * d1y
            h = d1x * d1x + d1y * d1y + bx * d2x + by * d2y
            if h == 0.0:
                break
            step = g / h
            t -= step
            if not (0.0 < t < 1.0) or abs(step) < 1e-12:
                break
        if 0.0 < t < 1.0:
            x, y = point_at(P, 3, t)
            d = math.sqrt((px - x) ** 2 + (py - y) ** 2)
            if d < best:
                tx, ty = direction_at(P, 3, t)
                cross = tx * (py - y) - ty * (px - x)
                best, sign, dot, best_t = d, (1.0 if cross >= 0.0 else -1.0), 0.0, t
    return sign * best, dot, best_t


@numba.njit(cache=True)
def pseudo_distance(P, deg, t, distance, px, py):
    """Chlumsky's pseudo-distance: when the closest point is an endpoint and p lies beyond it along the tangent,
    the signed distance to the tangent line extended there, if that is closer; else ``distance`` unchanged."""
    if t <= 0.0:
        ex, ey = point_at(P, deg, 0.0)
        dx, dy = direction_at(P, deg, 0.0)
        qx, qy = px - ex, py - ey
        if dx * qx + dy * qy < 0.0:
            dl = math.sqrt(dx * dx + dy * dy)
            if dl > 0.0:
                pd = (dx * qy - dy * qx) / dl
                if abs(pd) <= abs(distance):
                    return pd
    elif t >= 1.0:
        ex, ey = point_at(P, deg, 1.0)
        dx, dy = direction_at(P, deg, 1.0)
        qx, qy = px - ex, py - ey
        if dx * qx + dy * qy > 0.0:
            dl = math.sqrt(dx * dx + dy * dy)
            if dl > 0.0:
                pd = (dx * qy - dy * qx) / dl
                if abs(pd) <= abs(distance):
                    return pd
    return distance


@numba.njit(cache=True)
def blossom(P, deg, u, v, w):
    """The polar form of the segment at (u, v, w) (only the first ``deg`` arguments are used)."""
    params = (u, v, w)
    buf = np.empty((4, 2))
    for i in range(deg + 1):
        buf[i, 0], buf[i, 1] = P[i, 0], P[i, 1]
    for level in range(deg):
        t = params[level]
        for i in range(deg - level):
            buf[i, 0] = (1.0 - t) * buf[i, 0] + t * buf[i + 1, 0]
            buf[i, 1] = (1.0 - t) * buf[i, 1] + t * buf[i + 1, 1]
    return buf[0, 0], buf[0, 1]


@numba.njit(cache=True)
def sub_segment(P, deg, t0, t1, out):
    """Write the control points of the piece t in [t0, t1] of the segment into ``out`` (4, 2)."""
    out[:] = 0.0
    for k in range(deg + 1):
        # control point k = blossom(t0 x (deg - k), t1 x k)
        a = t0 if 0 < deg - k else t1
        b = t0 if 1 < deg - k else t1
        c = t0 if 2 < deg - k else t1
        out[k, 0], out[k, 1] = blossom(P, deg, a, b, c)
    out[0, 0], out[0, 1] = point_at(P, deg, t0)
    out[deg, 0], out[deg, 1] = point_at(P, deg, t1)
