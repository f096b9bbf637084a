"""Rest-pose precomputes per strand vertex (RTR4 14.7.2: "pre-integrated ambient occlusion computed from the hair at
its rest position"; Zinke et al. 2008's global transmittance needs the number of fibres between a point and the
light, which an engine without deep opacity maps can take from here):

- **occlusion**: the fraction of directions (uniform over the sphere) along which a ray from the vertex travels
  ``distance`` without meeting another strand, each strand a tube of its width (segment by segment: the capsule of
  radius max(width at its two ends) / 2), or the scalp (Embree, :class:`baker.geometry.raycast.RayScene`);
- **fibre counts**: along the same rays, the number of other strands crossed before the ray leaves the groom (or
  ``count_distance``, or the scalp), reduced to an ambient cube (McTaggart 2004): per axis and sign, the mean
  count over the hemisphere around it weighted by cos^2; a shader reads n(l) = sum_i l_i^2 c(sign l_i, i).

The strands are binned into a uniform grid of cells (about a segment long); each ray walks it (3D DDA,
Amanatides & Woo 1987) and counts a strand where its closest approach to the ray lies inside the cell being
visited, so a capsule spanning several cells counts once. The own strand is skipped (a fibre does not occlude
itself: its own shading is the BSDF's). Directions: a spherical Fibonacci set, rotated at random per vertex
(deterministic from the vertex index), so neighbouring vertices do not share the same aliasing.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange


CELL_SEGMENTS = 0.75  # cell width in median segment lengths


def fibonacci_sphere(n: int) -> np.ndarray:
    """(n, 3) unit directions, nearly uniform over the sphere (equal-area rings of a golden-angle spiral)."""
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    r = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    phi = math.pi * (3.0 - math.sqrt(5.0)) * i
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], -1)


def random_rotations(count: int, seed: int) -> np.ndarray:
    """(count, 3, 3) rotation matrices uniform over SO(3) (unit quaternions from normals), deterministic."""
    q = np.random.default_rng(seed).normal(size=(count, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
        np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
        np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1)], 1)


@njit(cache=True)
def bin_segments(a, b, radius, lo, cell, dims):
    """CSR (start, items) of the segments overlapping each cell (their AABB grown by the radius)."""
    n = a.shape[0]
    nx, ny, nz = dims[0], dims[1], dims[2]
    counts = np.zeros(nx * ny * nz + 1, np.int64)
    boxes = np.empty((n, 6), np.int64)
    for k in range(n):
        for ax in range(3):
            mn = min(a[k, ax], b[k, ax]) - radius[k]
            mx = max(a[k, ax], b[k, ax]) + radius[k]
            hi = dims[ax] - 1
            boxes[k, ax] = min(hi, max(0, int((mn - lo[ax]) / cell)))
            boxes[k, 3 + ax] = min(hi, max(0, int((mx - lo[ax]) / cell)))
        for i in range(boxes[k, 0], boxes[k, 3] + 1):
            for j in range(boxes[k, 1], boxes[k, 4] + 1):
                for m in range(boxes[k, 2], boxes[k, 5] + 1):
                    counts[(i * ny + j) * nz + m + 1] += 1
    for c in range(1, counts.shape[0]):
        counts[c] += counts[c - 1]
    items = np.empty(counts[-1], np.int64)
    fill = counts[:-1].copy()
    for k in range(n):
        for i in range(boxes[k, 0], boxes[k, 3] + 1):
            for j in range(boxes[k, 1], boxes[k, 4] + 1):
                for m in range(boxes[k, 2], boxes[k, 5] + 1):
                    c = (i * ny + j) * nz + m
                    items[fill[c]] = k
                    fill[c] += 1
    return counts, items


@njit(cache=True, inline="always")
def closest_approach(ox, oy, oz, dx, dy, dz, ax, ay, az, ex, ey, ez):
    """(t along the ray, squared distance) of the closest approach of the line o + t d (unit d) and the segment
    a + s e, s in [0, 1]: the convex quadratic's minimum over s clamped to the segment."""
    wx, wy, wz = ox - ax, oy - ay, oz - az
    b = dx * ex + dy * ey + dz * ez
    c = ex * ex + ey * ey + ez * ez
    dw = dx * wx + dy * wy + dz * wz
    ew = ex * wx + ey * wy + ez * wz
    denom = c - b * b
    s = (ew - b * dw) / denom if denom > 1e-12 * c else 0.5
    s = min(1.0, max(0.0, s))
    t = s * b - dw
    px = wx + t * dx - s * ex
    py = wy + t * dy - s * ey
    pz = wz + t * dz - s * ez
    return t, px * px + py * py + pz * pz


@njit(cache=True)
def walk(ox, oy, oz, dx, dy, dz, t_max, own, a, e, radius2, strand, starts, items, lo, cell, dims):
    """(first hit distance or inf, strands crossed before t_max) of one ray through the grid."""
    nx, ny, nz = dims[0], dims[1], dims[2]
    # enter the grid's box
    t0, t1 = 0.0, t_max
    o = (ox, oy, oz)
    d = (dx, dy, dz)
    for ax in range(3):
        lo_ax = lo[ax]
        hi_ax = lo[ax] + dims[ax] * cell
        if abs(d[ax]) < 1e-12:
            if o[ax] < lo_ax or o[ax] > hi_ax:
                return np.inf, 0
        else:
            ta = (lo_ax - o[ax]) / d[ax]
            tb = (hi_ax - o[ax]) / d[ax]
            if ta > tb:
                ta, tb = tb, ta
            t0 = max(t0, ta)
            t1 = min(t1, tb)
    if t0 > t1:
        return np.inf, 0
    px, py, pz = ox + t0 * dx, oy + t0 * dy, oz + t0 * dz
    ix = min(nx - 1, max(0, int((px - lo[0]) / cell)))
    iy = min(ny - 1, max(0, int((py - lo[1]) / cell)))
    iz = min(nz - 1, max(0, int((pz - lo[2]) / cell)))
    step_x = 1 if dx > 0 else -1
    step_y = 1 if dy > 0 else -1
    step_z = 1 if dz > 0 else -1
    inf = np.inf
    next_x = ((lo[0] + (ix + (step_x > 0)) * cell) - ox) / dx if abs(dx) > 1e-12 else inf
    next_y = ((lo[1] + (iy + (step_y > 0)) * cell) - oy) / dy if abs(dy) > 1e-12 else inf
    next_z = ((lo[2] + (iz + (step_z > 0)) * cell) - oz) / dz if abs(dz) > 1e-12 else inf
    delta_x = cell / abs(dx) if abs(dx) > 1e-12 else inf
    delta_y = cell / abs(dy) if abs(dy) > 1e-12 else inf
    delta_z = cell / abs(dz) if abs(dz) > 1e-12 else inf
    first = inf
    count = 0
    t_enter = t0
    while True:
        t_exit = min(next_x, next_y, next_z, t1)
        c = (ix * ny + iy) * nz + iz
        for q in range(starts[c], starts[c + 1]):
            k = items[q]
            if strand[k] == own:
                continue
            t, dist2 = closest_approach(ox, oy, oz, dx, dy, dz, a[k, 0], a[k, 1], a[k, 2], e[k, 0], e[k, 1], e[k, 2])
            if dist2 < radius2[k] and t > 0.0 and t <= t1 and t_enter <= t < t_exit:
                count += 1
                if t < first:
                    first = t
        if t_exit >= t1:
            break
        t_enter = t_exit
        if next_x <= next_y and next_x <= next_z:
            ix += step_x
            if ix < 0 or ix >= nx:
                break
            next_x += delta_x
        elif next_y <= next_z:
            iy += step_y
            if iy < 0 or iy >= ny:
                break
            next_y += delta_y
        else:
            iz += step_z
            if iz < 0 or iz >= nz:
                break
            next_z += delta_z
    return first, count


@njit(cache=True, parallel=True)
def trace_vertices(points, own, directions, scalp_t, distance, count_distance, a, e, radius2, strand, starts, items,
                   lo, cell, dims):
    """Per vertex: visibility (share of open rays), and the cos^2-weighted mean counts per axis and sign."""
    n, rays = directions.shape[0], directions.shape[1]
    visibility = np.zeros(n, np.float32)
    positive = np.zeros((n, 3), np.float32)
    negative = np.zeros((n, 3), np.float32)
    for v in prange(n):
        open_rays = 0
        sum_p = np.zeros(3)
        sum_n = np.zeros(3)
        weight_p = np.zeros(3)
        weight_n = np.zeros(3)
        for r in range(rays):
            dx, dy, dz = directions[v, r, 0], directions[v, r, 1], directions[v, r, 2]
            t_scalp = scalp_t[v, r]
            first, count = walk(points[v, 0], points[v, 1], points[v, 2], dx, dy, dz,
                                min(t_scalp, count_distance), own[v], a, e, radius2, strand, starts, items, lo,
                                cell, dims)
            if first > distance and t_scalp > distance:
                open_rays += 1
            for ax in range(3):
                w = directions[v, r, ax] ** 2
                if directions[v, r, ax] > 0:
                    sum_p[ax] += w * count
                    weight_p[ax] += w
                else:
                    sum_n[ax] += w * count
                    weight_n[ax] += w
        visibility[v] = open_rays / rays
        for ax in range(3):
            positive[v, ax] = sum_p[ax] / weight_p[ax] if weight_p[ax] > 0 else 0.0
            negative[v, ax] = sum_n[ax] / weight_n[ax] if weight_n[ax] > 0 else 0.0
    return visibility, positive, negative


def ray_directions(count: int, rays: int, seed: int = 0) -> np.ndarray:
    """(count, rays, 3): the Fibonacci set rotated at random per vertex."""
    return np.einsum("vij,rj->vri", random_rotations(count, seed), fibonacci_sphere(rays)).astype(np.float64)


def strand_occlusion(positions: np.ndarray, widths: np.ndarray, *, rays: int = 32, distance: float | None = None,
                     count_distance: float | None = None, scalp: tuple | None = None, seed: int = 0):
    """(visibility (S V,), counts along +x +y +z (S V, 3), along -x -y -z (S V, 3), info) of strands ``positions``
    (S, V, 3) of per-vertex ``widths`` (S, V); ``scalp``: (vertices, faces) of the emitter that occludes too.
    ``distance`` (default: the mean strand length) bounds the occlusion rays, ``count_distance`` (default: the
    same) the fibre counts. ``info``: what the extension records."""
    positions = np.asarray(positions, np.float64)
    s, v = positions.shape[:2]
    lengths = np.linalg.norm(np.diff(positions, axis=1), axis=2).sum(axis=1)
    mean_length = float(lengths.mean()) if s else 1.0
    distance = float(distance if distance is not None else mean_length)
    count_distance = float(count_distance if count_distance is not None else distance)
    radius = np.maximum(np.asarray(widths, np.float64)[:, :-1], np.asarray(widths, np.float64)[:, 1:]) / 2.0
    a = np.ascontiguousarray(positions[:, :-1].reshape(-1, 3))
    e = np.ascontiguousarray((positions[:, 1:] - positions[:, :-1]).reshape(-1, 3))
    radius = radius.reshape(-1)
    strand = np.repeat(np.arange(s, dtype=np.int64), v - 1)
    points = np.ascontiguousarray(positions.reshape(-1, 3))
    own = np.repeat(np.arange(s, dtype=np.int64), v)
    # cells about a segment long (measured on the bunny's default groom: the fastest of 0.7-2), at most 256 per axis
    seg = float(np.median(np.linalg.norm(e, axis=1))) if len(e) else 1.0
    lo = points.min(0) - radius.max(initial=0.0) - 1e-6
    hi = points.max(0) + radius.max(initial=0.0) + 1e-6
    cell = max(CELL_SEGMENTS * seg, float((hi - lo).max()) / 256.0, 1e-9)
    dims = np.maximum(1, np.ceil((hi - lo) / cell).astype(np.int64))
    starts, items = bin_segments(a, a + e, radius, lo, cell, dims)
    directions = ray_directions(len(points), int(rays), seed)
    scalp_t = np.full((len(points), int(rays)), np.inf)
    if scalp is not None and len(scalp[1]):
        from baker.geometry.raycast import RayScene

        scene = RayScene(np.asarray(scalp[0], np.float32), np.asarray(scalp[1], np.int32))
        origins = np.repeat(points, rays, axis=0)
        hit = scene.distances(origins, directions.reshape(-1, 3)).astype(np.float64)
        scalp_t = np.where(hit >= RayScene.MISS * 0.5, np.inf, hit).reshape(len(points), int(rays))
    visibility, positive, negative = trace_vertices(points, own, directions, scalp_t, distance, count_distance, a,
                                                    e, radius * radius, strand, starts, items, lo, cell, dims)
    info = {"rays": int(rays), "distance": distance, "countDistance": count_distance,
            "scalp": scalp is not None and bool(len(scalp[1]))}
    return visibility, positive, negative, info
