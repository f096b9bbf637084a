"""Hair strands: guide curves grown on an emitter mesh, and child strands interpolated from them.

RTR4 section 14.7.1: hair is drawn as ribbons extruded around curves; a few *guide* strands carry the shape (and,
in an engine, the simulation) and many *children* are interpolated from the guides around them (Yuksel & Tariq,
SIGGRAPH 2010 course; TressFX "follow hairs"). This module is the offline half: pure arrays in, arrays out.

Steps (each a function below):

1. **Roots** (:func:`sample_roots`): area-weighted random candidates on the emitter triangles (optionally thinned
   by a density mask), reduced to a blue-noise set by weighted sample elimination (Yuksel, "Sample Elimination for
   Generating Poisson Disk Sample Sets", Eurographics 2015): exactly ``n`` samples, no dart-throwing radius to tune.
2. **Rest shape** (:func:`grow_guides`): straight along the smooth root normal, with an optional helical curl
   (amplitude, turns per strand) that fades in from the root.
3. **Relaxation** (:func:`relax`): a few iterations of position-based dynamics (Mueller et al. 2007) for the static
   pose under gravity: an external displacement, a global shape-matching pull towards the rest shape (TressFX's
   global shape constraint, stronger at the root), then one follow-the-leader pass (Mueller et al., "Fast
   Simulation of Inextensible Hair and Fur", VRIPHYS 2012) that makes every segment its rest length again, exactly.
4. **Collision** (:func:`push_out`): vertices inside the emitter (ray parity on closed meshes, generalized winding
   number on open ones) are moved to the closest surface point plus a margin and slid along the tangent plane so
   their segment keeps its length; repeated until no vertex is inside.
5. **Children** (:func:`interpolate_children`): roots sampled on the surface; each child takes the 3 nearest guide
   roots, barycentric weights of its root in their triangle (clamped to >= 0 and renormalized, inverse distance
   when the triangle is degenerate), the weighted guide shapes relative to their roots, a TressFX-style follow
   offset that grows towards the tip, clumping towards its dominant guide, random tip thinning (shorter strands),
   then the same follow-the-leader length restoration and collision.

Everything is vectorized over strands (numpy) or compiled loops (numba, GIL-free); randomness comes from one
``numpy.random.Generator`` seeded by ``seed``, consumed in a fixed order, so the same input gives the same bytes.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numba
import numpy as np
from scipy.spatial import cKDTree

from baker import interruptible
from baker.techniques.hair.options import HairOptions
from baker.geometry.frames import orthonormal_basis




# ---------------------------------------------------------------------------------------------------- data
@dataclass
class Emitter:
    """The surface strands grow from, and the closed (or open) mesh they must not enter."""

    vertices: np.ndarray  # (n, 3) float64, welded
    faces: np.ndarray  # (m, 3) int64 emitting triangles (index vertices)
    normals: np.ndarray  # (n, 3) smooth unit vertex normals
    density: "SurfaceField | None" = None  # mask in [0, 1] over the emitting triangles, or None
    length_scale: "SurfaceField | None" = None  # multiplies the strand length, or None
    collider_faces: np.ndarray | None = None  # (k, 3) triangles of the whole mesh (default: faces)
    texcoords: np.ndarray | None = None  # (m, 3, 2) per-corner UV (for TressFX strand UVs), or None

    @property
    def colliders(self) -> np.ndarray:
        return self.faces if self.collider_faces is None else self.collider_faces


@dataclass
class StrandSet:
    """``count`` strands of ``vertices`` points each, root first."""

    positions: np.ndarray  # (s, v, 3) float64
    width_scale: np.ndarray  # (s,) float64 in (0, 1]: multiplies rootWidth/tipWidth
    rest_lengths: np.ndarray  # (s,) float64 segment rest length of each strand (segments are uniform per strand)
    root_normals: np.ndarray  # (s, 3)
    root_uv: np.ndarray | None = None  # (s, 2)
    guide_ids: np.ndarray | None = None  # (s, 3) int64 (children only)
    guide_weights: np.ndarray | None = None  # (s, 3) float64, >= 0, rows sum to 1 (children only)

    @property
    def count(self) -> int:
        return self.positions.shape[0]

    @property
    def vertices(self) -> int:
        return self.positions.shape[1]

    def take(self, order: np.ndarray) -> "StrandSet":
        pick = lambda a: None if a is None else a[order]  # noqa: E731
        return StrandSet(self.positions[order], self.width_scale[order], self.rest_lengths[order],
                         self.root_normals[order], pick(self.root_uv), pick(self.guide_ids), pick(self.guide_weights))


@dataclass
class HairResult:
    guides: StrandSet
    children: StrandSet
    length: float
    root_width: float
    tip_width: float
    spacing: float  # mean guide root spacing (mesh units)
    stats: dict = field(default_factory=dict)


class SurfaceField:
    """A scalar over the emitting triangles, evaluated at (triangle ids, barycentrics): per-corner values
    (e.g. vertex colours), or an image sampled bilinearly (repeat wrap) at per-corner texture coordinates."""

    def __init__(self, corner_values: np.ndarray | None = None, corner_uv: np.ndarray | None = None,
                 image: np.ndarray | None = None):
        self.corner_values, self.corner_uv, self.image = corner_values, corner_uv, image

    def __call__(self, tri: np.ndarray, bary: np.ndarray) -> np.ndarray:
        if self.image is None:
            return corner_interpolate(self.corner_values, tri, bary)
        uv = corner_interpolate(self.corner_uv, tri, bary)
        return bilinear(self.image, uv)


def bilinear(image: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """Sample a (H, W) float image at glTF UVs (v down, texel centres at (i + 0.5) / size, repeat wrap)."""
    h, w = image.shape
    x = uv[:, 0] * w - 0.5
    y = uv[:, 1] * h - 0.5
    x0, y0 = np.floor(x).astype(np.int64), np.floor(y).astype(np.int64)
    fx, fy = x - x0, y - y0
    x0, y0, x1, y1 = x0 % w, y0 % h, (x0 + 1) % w, (y0 + 1) % h
    return ((image[y0, x0] * (1 - fx) + image[y0, x1] * fx) * (1 - fy)
            + (image[y1, x0] * (1 - fx) + image[y1, x1] * fx) * fy)


# ---------------------------------------------------------------------------------------------------- roots
def triangle_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    v = vertices[faces]
    return 0.5 * np.linalg.norm(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), axis=1)


def random_surface_points(vertices, faces, count: int, rng: np.random.Generator, weights=None):
    """``count`` points uniform over the area (times ``weights`` per triangle): (triangle ids, barycentrics)."""
    area = triangle_areas(vertices, faces)
    if weights is not None:
        area = area * weights
    cdf = np.cumsum(area)
    if cdf[-1] <= 0:
        raise ValueError("the emitter has no area (or the density mask is zero everywhere)")
    tri = np.minimum(np.searchsorted(cdf, rng.random(count) * cdf[-1], side="right"), len(faces) - 1)
    u, v = rng.random(count), rng.random(count)
    flip = u + v > 1.0
    u, v = np.where(flip, 1.0 - u, u), np.where(flip, 1.0 - v, v)
    bary = np.stack([1.0 - u - v, u, v], axis=1)
    return tri, bary


def corner_interpolate(values: np.ndarray, tri: np.ndarray, bary: np.ndarray) -> np.ndarray:
    """Interpolate per-corner ``values`` (m, 3, ...) at (triangle, barycentric) samples."""
    v = values[tri]
    return np.einsum("sk,sk...->s...", bary, v)




@numba.njit(cache=True, nogil=True)
def _heap_sift_down(heap, pos, key, i, size):
    while True:
        left = 2 * i + 1
        best = i
        for c in (left, left + 1):
            if c < size:
                x, y = heap[c], heap[best]
                if key[x] > key[y] or (key[x] == key[y] and x < y):
                    best = c
        if best == i:
            break
        a, b = heap[i], heap[best]
        heap[i], heap[best] = b, a
        pos[b], pos[a] = i, best
        i = best


@numba.njit(cache=True, nogil=True)
def _sample_elimination(n_keep, indptr, indices, dist, rmax, alpha):
    """Yuksel 2015: repeatedly remove the sample with the largest crowding weight until ``n_keep`` remain."""
    n = indptr.shape[0] - 1
    weight = np.zeros(n)
    for i in range(n):
        for e in range(indptr[i], indptr[i + 1]):
            weight[i] += (1.0 - min(dist[e], 2.0 * rmax) / (2.0 * rmax)) ** alpha
    heap = np.arange(n)
    pos = np.arange(n)
    for i in range(n // 2 - 1, -1, -1):
        _heap_sift_down(heap, pos, weight, i, n)
    alive = np.ones(n, np.bool_)
    size = n
    while size > n_keep:
        top = heap[0]
        size -= 1
        last = heap[size]
        heap[0] = last
        pos[last] = 0
        _heap_sift_down(heap, pos, weight, 0, size)
        alive[top] = False
        for e in range(indptr[top], indptr[top + 1]):
            j = indices[e]
            if alive[j]:
                weight[j] -= (1.0 - min(dist[e], 2.0 * rmax) / (2.0 * rmax)) ** alpha
                _heap_sift_down(heap, pos, weight, pos[j], size)
    return alive


def _neighbour_graph(points: np.ndarray, radius: float):
    """Symmetric CSR graph of point pairs closer than ``radius`` (deterministic order)."""
    pairs = cKDTree(points).query_pairs(radius, output_type="ndarray")
    i = np.concatenate([pairs[:, 0], pairs[:, 1]]).astype(np.int64)
    j = np.concatenate([pairs[:, 1], pairs[:, 0]]).astype(np.int64)
    order = np.lexsort((j, i))
    i, j = i[order], j[order]
    dist = np.linalg.norm(points[i] - points[j], axis=1)
    indptr = np.zeros(len(points) + 1, np.int64)
    np.add.at(indptr, i + 1, 1)
    return np.cumsum(indptr), j, dist


def eliminate_samples(points: np.ndarray, keep: int, rmax: float, alpha: float = 8.0) -> np.ndarray:
    """Boolean mask of the ``keep`` points weighted sample elimination (Yuksel 2015) keeps, for a Poisson radius
    ``rmax`` of the kept set."""
    indptr, indices, dist = _neighbour_graph(points, 2.0 * rmax)
    return _sample_elimination(keep, indptr, indices, dist, rmax, alpha)


def masked_surface_points(emitter: Emitter, count: int, rng: np.random.Generator, oversample: int = 1):
    """``count * oversample`` points, uniform over the area times the density mask (rejection sampling in
    batches; deterministic). Returns (triangle ids, barycentrics, mean mask value)."""
    v, f = emitter.vertices, emitter.faces
    want = count * oversample
    if emitter.density is None:
        tri, bary = random_surface_points(v, f, want, rng)
        return tri, bary, 1.0
    tris, barys, tried, kept = [], [], 0, 0
    while kept < want:
        tri, bary = random_surface_points(v, f, max(want, 1024), rng)
        keep = rng.random(len(tri)) < np.clip(emitter.density(tri, bary), 0.0, 1.0)
        tried += len(tri)
        kept += int(keep.sum())
        tris.append(tri[keep])
        barys.append(bary[keep])
        if tried > 200 * max(want, 1024) and kept < want:
            raise ValueError("the density mask is (almost) zero everywhere")
    return np.concatenate(tris)[:want], np.concatenate(barys)[:want], kept / tried


def sample_roots(emitter: Emitter, count: int, rng: np.random.Generator, oversample: int = 5):
    """``count`` blue-noise roots: (triangle ids, barycentrics, positions, Poisson radius), by weighted sample
    elimination over ``oversample * count`` candidates."""
    faces = emitter.faces
    tri, bary, mask_mean = masked_surface_points(emitter, count, rng, oversample)
    effective_area = float(triangle_areas(emitter.vertices, faces).sum()) * mask_mean
    points = np.einsum("sk,skd->sd", bary, emitter.vertices[faces[tri]])
    rmax = math.sqrt(effective_area / (2.0 * math.sqrt(3.0) * count))
    alive = eliminate_samples(points, count, rmax)
    return tri[alive], bary[alive], points[alive], rmax




def grow_guides(roots: np.ndarray, normals: np.ndarray, lengths: np.ndarray, segments: int,
                curl_amplitude: float, curl_frequency: float, phases: np.ndarray) -> np.ndarray:
    """Rest shapes (s, segments + 1, 3): along the normal, plus a helix whose radius fades in from the root.

    The curl only bends the rest shape; :func:`follow_the_leader` afterwards gives every segment its exact length.
    """
    t = np.linspace(0.0, 1.0, segments + 1)
    tangent, bitangent = orthonormal_basis(normals)
    along = t[None, :, None] * lengths[:, None, None] * normals[:, None, :]
    angle = 2.0 * math.pi * curl_frequency * t[None, :] + phases[:, None]
    radius = curl_amplitude * lengths[:, None] * np.minimum(1.0, 4.0 * t)[None, :]  # reach full radius at 1/4
    curl = radius[..., None] * (np.cos(angle)[..., None] * tangent[:, None, :]
                                + np.sin(angle)[..., None] * bitangent[:, None, :])
    curl -= curl[:, :1]  # the root stays on the surface
    return roots[:, None, :] + along + curl


@numba.njit(cache=True, nogil=True, parallel=True)
def follow_the_leader(positions, rest_lengths):
    """In place: walk each strand from its root and put vertex k at ``rest_length`` from vertex k - 1, along the
    current direction (Mueller et al. 2012). Lengths are then exact up to rounding."""
    s, v = positions.shape[0], positions.shape[1]
    for i in numba.prange(s):
        length = rest_lengths[i]
        for k in range(1, v):
            dx = positions[i, k, 0] - positions[i, k - 1, 0]
            dy = positions[i, k, 1] - positions[i, k - 1, 1]
            dz = positions[i, k, 2] - positions[i, k - 1, 2]
            d = math.sqrt(dx * dx + dy * dy + dz * dz)
            if d < 1e-30:
                dx, dy, dz, d = 0.0, 0.0, 1.0, 1.0
            scale = length / d
            positions[i, k, 0] = positions[i, k - 1, 0] + dx * scale
            positions[i, k, 1] = positions[i, k - 1, 1] + dy * scale
            positions[i, k, 2] = positions[i, k - 1, 2] + dz * scale


def relax(rest: np.ndarray, rest_lengths: np.ndarray, gravity: float, gravity_direction, stiffness: float,
          iterations: int) -> np.ndarray:
    """Static pose under gravity by position-based relaxation; returns new positions (s, v, 3).

    Per iteration: every free vertex moves ``gravity * length / iterations`` along ``gravity_direction`` (so
    ``gravity`` is the total fall, in strand lengths, of an unresisting strand), is pulled back towards its rest
    position by ``1 - (1 - k)^(1 / iterations)`` with ``k = stiffness * (1 - t / 2)`` (t = 0 at the root, 1 at the
    tip; the per-iteration form makes the result nearly independent of the iteration count, as in PBD), then
    follow-the-leader restores every segment's rest length. Roots never move.
    """
    x = rest.copy()
    if iterations == 0:
        follow_the_leader(x, rest_lengths)
        return x
    g = np.asarray(gravity_direction, np.float64)
    g = g / max(np.linalg.norm(g), 1e-30)
    v = rest.shape[1]
    t = np.linspace(0.0, 1.0, v)
    k = np.clip(stiffness * (1.0 - 0.5 * t), 0.0, 1.0)
    pull = (1.0 - (1.0 - k) ** (1.0 / iterations))[None, :, None]
    step = (gravity * rest_lengths * (v - 1) / iterations)[:, None, None] * g[None, None, :]
    for _ in range(iterations):
        x[:, 1:] += step
        x[:, 1:] += pull[:, 1:] * (rest[:, 1:] - x[:, 1:])
        follow_the_leader(x, rest_lengths)
    return x


# ---------------------------------------------------------------------------------------------------- collision
def boundary_edge_count(faces: np.ndarray) -> int:
    """Edges used by exactly one triangle (0 for a closed, i.e. watertight, mesh)."""
    e = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    _, counts = np.unique(e, axis=0, return_counts=True)
    return int((counts == 1).sum())


@numba.njit(cache=True, nogil=True, parallel=True)
def winding_numbers(points, vertices, faces):
    """Generalized winding number (Jacobson et al. 2013) of each point: the signed solid angle of all triangles
    over 4 pi (van Oosterom & Strackee 1983). Brute force, O(points x triangles): the reference that
    :class:`WindingTree` is tested against."""
    triangles = np.empty((faces.shape[0], 9))
    for f in range(faces.shape[0]):
        for k in range(3):
            for c in range(3):
                triangles[f, 3 * k + c] = vertices[faces[f, k], c]
    out = np.zeros(points.shape[0])
    for p in numba.prange(points.shape[0]):
        total = 0.0
        for f in range(faces.shape[0]):
            total += _solid_angle(points[p, 0], points[p, 1], points[p, 2], triangles[f])
        out[p] = total / (4.0 * math.pi)
    return out


class WindingTree:
    """Fast generalized winding numbers (Barill, Dickson, Schmidt, Levin & Jacobson, "Fast Winding Numbers for
    Soups and Clouds", SIGGRAPH 2018), first order: a tree over the triangles, each node summarised by its
    area-weighted centre and summed area vector (a dipole); a node farther from the query point than ``beta``
    times its radius contributes its dipole's solid angle, A . (c - q) / |c - q|^3, a nearer one is opened, and the
    leaves are summed exactly (van Oosterom & Strackee). Near the surface, where the 0.5 threshold is decided, the
    sum is exact; far from it the error of a node is O((r / d)^2) of its share.

    The tree is implicit and balanced: node n = 2^l + k covers the sorted triangles [k F / 2^l, (k + 1) F / 2^l),
    and its two halves are its children."""

    LEAF = 8
    BETA = 2.0

    def __init__(self, vertices: np.ndarray, faces: np.ndarray):
        v = np.asarray(vertices, np.float64)[np.asarray(faces, np.int64)]  # (F, 3, 3)
        count = len(v)
        centroids = v.mean(axis=1)
        self.depth = max(0, int(math.ceil(math.log2(max(count, 1) / self.LEAF))))
        # median splits along each node's longest axis: every level sorts each node's range by that coordinate
        # (one stable lexsort per level), so the halves by index are the halves in space
        order = np.arange(count)
        for level in range(self.depth):
            width = 2 ** level
            starts = (np.arange(width, dtype=np.int64) * count) // width
            owner = np.repeat(np.arange(width), np.diff(np.append(starts, count)))
            c = centroids[order]
            lo, hi = np.minimum.reduceat(c, starts), np.maximum.reduceat(c, starts)
            axis = (hi - lo).argmax(axis=1)
            extent = np.maximum((hi - lo)[np.arange(width), axis], 1e-300)
            along = (c[np.arange(count), axis[owner]] - lo[owner, axis[owner]]) / extent[owner]  # 0..1 in its node
            order = order[np.argsort(owner + 0.5 * along, kind="stable")]
        v, centroids = v[order], centroids[order]
        area_vectors = 0.5 * np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
        areas = np.linalg.norm(area_vectors, axis=1)
        nodes = 2 ** (self.depth + 1)
        self.centre = np.zeros((nodes, 3))
        self.area_vector = np.zeros((nodes, 3))
        self.radius = np.zeros(nodes)
        for level in range(self.depth + 1):
            width = 2 ** level
            starts = (np.arange(width, dtype=np.int64) * count) // width
            ends = (np.arange(1, width + 1, dtype=np.int64) * count) // width
            filled = ends > starts
            starts, ends, ids = starts[filled], ends[filled], width + np.flatnonzero(filled)
            size = ends - starts
            weight = np.add.reduceat(areas, starts)
            centre = np.add.reduceat(areas[:, None] * centroids, starts) / np.maximum(weight, 1e-300)[:, None]
            plain = np.add.reduceat(centroids, starts) / size[:, None]
            centre = np.where((weight > 0)[:, None], centre, plain)  # all-degenerate node: the plain mean
            owner = np.repeat(np.arange(len(starts)), size)
            offsets = v - centre[owner][:, None, :]
            reach = np.sqrt(np.einsum("fvd,fvd->fv", offsets, offsets).max(axis=1))
            self.centre[ids] = centre
            self.area_vector[ids] = np.add.reduceat(area_vectors, starts)
            self.radius[ids] = np.maximum.reduceat(reach, starts)
        self.triangles = np.ascontiguousarray(v.reshape(count, 9))
        self.count = count

    def __call__(self, points: np.ndarray, beta: float | None = None) -> np.ndarray:
        """Winding numbers at ``points``; a larger ``beta`` opens more nodes (error ~ 1 / beta^2, cost ~ beta^2)."""
        points = np.ascontiguousarray(points, np.float64)
        if self.count == 0 or len(points) == 0:
            return np.zeros(len(points))
        return interruptible.call(_fast_winding_numbers, points, self.triangles, self.centre, self.area_vector,
                                  self.radius, self.depth, self.BETA if beta is None else beta)


@numba.njit(cache=True, nogil=True, inline="always")
def _solid_angle(px, py, pz, t):
    """Signed solid angle of triangle ``t`` (9 coordinates) seen from (px, py, pz) (van Oosterom & Strackee)."""
    ax, ay, az = t[0] - px, t[1] - py, t[2] - pz
    bx, by, bz = t[3] - px, t[4] - py, t[5] - pz
    cx, cy, cz = t[6] - px, t[7] - py, t[8] - pz
    la = math.sqrt(ax * ax + ay * ay + az * az)
    lb = math.sqrt(bx * bx + by * by + bz * bz)
    lc = math.sqrt(cx * cx + cy * cy + cz * cz)
    det = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)
    div = la * lb * lc + (ax * bx + ay * by + az * bz) * lc + (bx * cx + by * cy + bz * cz) * la \
        + (cx * ax + cy * ay + cz * az) * lb
    return 2.0 * math.atan2(det, div)


@numba.njit(cache=True, nogil=True, parallel=True)
def _fast_winding_numbers(points, triangles, centre, area_vector, radius, depth, beta):
    count = triangles.shape[0]
    first_leaf = 1 << depth
    out = np.zeros(points.shape[0])
    for p in numba.prange(points.shape[0]):
        px, py, pz = points[p, 0], points[p, 1], points[p, 2]
        stack = np.empty(2 * depth + 4, np.int64)
        top = 0
        stack[0] = 1
        total = 0.0
        while top >= 0:
            node = stack[top]
            top -= 1
            dx, dy, dz = centre[node, 0] - px, centre[node, 1] - py, centre[node, 2] - pz
            d2 = dx * dx + dy * dy + dz * dz
            r = beta * radius[node]
            if d2 > r * r:
                total += (dx * area_vector[node, 0] + dy * area_vector[node, 1] + dz * area_vector[node, 2]) \
                    / (d2 * math.sqrt(d2))
            elif node >= first_leaf:
                k = node - first_leaf
                for f in range((k * count) >> depth, ((k + 1) * count) >> depth):
                    total += _solid_angle(px, py, pz, triangles[f])
            else:
                stack[top + 1] = 2 * node
                stack[top + 2] = 2 * node + 1
                top += 2
        out[p] = total / (4.0 * math.pi)
    return out


# three fixed, irrational-looking directions: a ray grazing an edge along one rarely grazes along all three
_PARITY_DIRECTIONS = np.array([[0.5773502, 0.5773503, 0.5773502], [-0.6712, 0.2183, 0.7083],
                               [0.1236, -0.8944, -0.4298]])


class InsideTest:
    """Which points are inside the emitter: ray parity (majority of 3 rays, Embree) for a closed mesh, the
    generalized winding number (> 0.5, :class:`WindingTree`) for an open one, where parity is meaningless.

    Points go to the winding-number kernel in blocks, so the main thread returns to Python (where signal handlers
    run) every fraction of a second: a compiled call cannot be interrupted."""

    BLOCK = 4096
    AMBIGUOUS = 0.15

    def __init__(self, vertices: np.ndarray, faces: np.ndarray):
        from baker.geometry.raycast import RayScene

        self.vertices = np.ascontiguousarray(vertices, np.float64)
        self.faces = np.ascontiguousarray(faces, np.int64)
        self.closed = boundary_edge_count(self.faces) == 0
        self.diag = float(np.linalg.norm(vertices.max(0) - vertices.min(0))) or 1.0
        self.scene = RayScene(vertices, faces) if self.closed else None
        self.winding = None if self.closed else WindingTree(self.vertices, self.faces)

    def __call__(self, points: np.ndarray) -> np.ndarray:
        if len(points) == 0:
            return np.zeros(0, bool)
        points = np.ascontiguousarray(points, np.float64)
        if not self.closed:
            return np.concatenate([self._winding_inside(points[i:i + self.BLOCK])
                                   for i in range(0, len(points), self.BLOCK)])
        # one ray per point; only the (rare) odd ones get two more rays and a majority vote, which guards against a
        # ray grazing an edge and counting it twice or not at all
        odd = self._parity(points, _PARITY_DIRECTIONS[0])
        suspects = np.flatnonzero(odd)
        if len(suspects):
            votes = 1 + self._parity(points[suspects], _PARITY_DIRECTIONS[1]) \
                + self._parity(points[suspects], _PARITY_DIRECTIONS[2])
            odd[suspects] = votes >= 2
        return odd

    def _winding_inside(self, points: np.ndarray) -> np.ndarray:
        """Winding number > 0.5: the tree's estimate (beta 2), again with beta 8 where it is within
        ``AMBIGUOUS`` of the threshold, and the exact sum where that one is within ``AMBIGUOUS / 8``. The error of
        the beta-2 estimate was at most 0.071 on the Stanford bunny (4000 points in and around it, the largest deep
        inside, where w is near 1) and 0.05 on the test's open dome, and it falls as 1 / beta^2; only points near a
        hole's rim, where w passes 0.5 away from the surface, come to the later steps."""
        w = self.winding(points)
        near = np.flatnonzero(np.abs(w - 0.5) < self.AMBIGUOUS)
        w[near] = self.winding(points[near], 4.0 * self.winding.BETA)
        near = near[np.abs(w[near] - 0.5) < self.AMBIGUOUS / 8.0]
        for i in range(0, len(near), 64):  # brute force: a block of 64 takes ~0.05 s on the bunny
            part = near[i:i + 64]
            w[part] = interruptible.call(winding_numbers, points[part], self.vertices, self.faces)
        return w > 0.5

    def _parity(self, points: np.ndarray, direction: np.ndarray) -> np.ndarray:
        d = (direction / np.linalg.norm(direction)).astype(np.float32)
        step = np.float32(1e-6 * self.diag)
        chunks = np.array_split(np.arange(len(points)), max(1, min(8, len(points) // 65536)))

        def run(idx):
            origins = points[idx].astype(np.float32)
            directions = np.broadcast_to(d, origins.shape).copy()
            crossings = np.zeros(len(idx), np.int64)
            active = np.arange(len(idx))
            for _ in range(64):  # one batched Embree call per round; rays leave the loop when they miss
                t = self.scene.distances(origins[active], directions[active])
                hit = t < 1e30
                active = active[hit]
                if not len(active):
                    break
                crossings[active] += 1
                origins[active] += directions[active] * (t[hit][:, None] + step)
            return crossings % 2 == 1

        
        with interruptible.thread_pool(2) as pool:  # Embree's numba loop releases the GIL
            parts = list(pool.map(run, chunks))
        return np.concatenate(parts) if parts else np.zeros(0, bool)


class SurfaceLookup:
    """Closest point on a triangle mesh, approximately: the triangles of the k nearest of dense surface samples."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray, rng_seed: int = 0, k: int = 8):
        self.vertices, self.faces, self.k = vertices, faces, k
        v = vertices[faces]
        n = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
        self.face_normals = n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)
        rng = np.random.default_rng(rng_seed)
        tri, bary = random_surface_points(vertices, faces, max(8 * len(faces), 20000), rng)
        samples = np.concatenate([v.mean(axis=1), np.einsum("sk,skd->sd", bary, v[tri])])
        self.sample_triangle = np.concatenate([np.arange(len(faces)), tri])
        self.tree = cKDTree(samples)
        # a coarse tree for distances far from the surface (sorting strands): a KD query costs about the number of
        # samples within the distance, so a dense tree is slow away from the surface
        coarse = samples[rng.permutation(len(samples))[:4096]]
        self.coarse_tree = cKDTree(coarse)

    def closest(self, points: np.ndarray):
        """(closest points, unit face normals there, distances) for each point."""
        k = min(self.k, self.tree.n)
        _, idx = self.tree.query(points, k=k, workers=2)
        idx = idx.reshape(len(points), k)
        tris = self.sample_triangle[idx]
        best_p, best_n, best_d, _ = _closest_on_triangles(np.ascontiguousarray(points, np.float64), tris,
                                                         self.vertices, self.faces, self.face_normals)
        return best_p, best_n, best_d

    def closest_faces(self, points: np.ndarray):
        """(closest points, unit face normals, distances, triangle indices) for each point."""
        k = min(self.k, self.tree.n)
        _, idx = self.tree.query(points, k=k, workers=2)
        tris = self.sample_triangle[idx.reshape(len(points), k)]
        return _closest_on_triangles(np.ascontiguousarray(points, np.float64), tris, self.vertices, self.faces,
                                     self.face_normals)

    def distance(self, points: np.ndarray) -> np.ndarray:
        return self.closest(points)[2]

    def approximate_distance(self, points: np.ndarray) -> np.ndarray:
        """Distance to the nearest of 4096 surface samples (an upper bound, within their spacing)."""
        return self.coarse_tree.query(points, k=1, workers=2)[0]


@numba.njit(cache=True, nogil=True, parallel=True)
def _closest_on_triangles(points, tris, vertices, faces, face_normals):
    n = points.shape[0]
    out_p = np.empty((n, 3))
    out_n = np.empty((n, 3))
    out_d = np.empty(n)
    out_f = np.empty(n, np.int64)
    for i in numba.prange(n):
        best = 1e300
        for j in range(tris.shape[1]):
            f = tris[i, j]
            q = _closest_point_triangle(points[i], vertices[faces[f, 0]], vertices[faces[f, 1]], vertices[faces[f, 2]])
            d = (q[0] - points[i, 0]) ** 2 + (q[1] - points[i, 1]) ** 2 + (q[2] - points[i, 2]) ** 2
            if d < best:
                best = d
                out_p[i] = q
                out_n[i] = face_normals[f]
                out_f[i] = f
        out_d[i] = math.sqrt(best)
    return out_p, out_n, out_d, out_f


@numba.njit(cache=True, nogil=True, inline="always")
def _dot3(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@numba.njit(cache=True, nogil=True, inline="always")
def _closest_point_triangle(p, a, b, c):
    """Ericson, Real-Time Collision Detection, 5.1.5."""
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = _dot3(ab, ap), _dot3(ac, ap)
    if d1 <= 0.0 and d2 <= 0.0:
        return a.copy()
    bp = p - b
    d3, d4 = _dot3(ab, bp), _dot3(ac, bp)
    if d3 >= 0.0 and d4 <= d3:
        return b.copy()
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        return a + ab * (d1 / (d1 - d3))
    cp = p - c
    d5, d6 = _dot3(ab, cp), _dot3(ac, cp)
    if d6 >= 0.0 and d5 <= d6:
        return c.copy()
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        return a + ac * (d2 / (d2 - d6))
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))
    denom = 1.0 / (va + vb + vc)
    return a + ab * (vb * denom) + ac * (vc * denom)


@numba.njit(cache=True, nogil=True)
def _slide_out(positions, strand, vertex, targets, normals, rest_lengths):
    """Move flagged vertices to their surface target and slide them along the tangent plane until their segment
    from the previous vertex has its rest length again; the rest of each strand follows the leader."""
    for e in range(strand.shape[0]):
        i, k = strand[e], vertex[e]
        prev = positions[i, k - 1]
        length = rest_lengths[i]
        q = targets[e]
        nrm = normals[e]
        d = positions[i, k] - prev
        tang = d - (_dot3(d, nrm)) * nrm
        tl = math.sqrt(_dot3(tang, tang))
        if tl < 1e-30:
            tang = np.zeros(3)
            # any tangent: the one completing the normal
            if abs(nrm[0]) < 0.9:
                tang[0] = 1.0
            else:
                tang[1] = 1.0
            tang = tang - (_dot3(tang, nrm)) * nrm
            tl = math.sqrt(_dot3(tang, tang))
        tang = tang / tl
        # |q + s tang - prev| = length, s >= 0
        w = q - prev
        b = _dot3(w, tang)
        c = _dot3(w, w) - length * length
        disc = b * b - c
        if disc >= 0.0:
            s = -b + math.sqrt(disc)
            positions[i, k] = q + s * tang
        else:  # the target is farther than one segment: point at it
            dd = w / math.sqrt(_dot3(w, w))
            positions[i, k] = prev + dd * length
        for j in range(k + 1, positions.shape[1]):
            dv = positions[i, j] - positions[i, j - 1]
            dl = math.sqrt(_dot3(dv, dv))
            if dl < 1e-30:
                dv = nrm.copy()
                dl = 1.0
            positions[i, j] = positions[i, j - 1] + dv * (length / dl)


def push_out(positions: np.ndarray, rest_lengths: np.ndarray, inside: InsideTest, surface: SurfaceLookup,
             margin: float, rounds: int | None = None, root_normals: np.ndarray | None = None) -> int:
    """In place: move strand vertices out of the emitter, keeping segment lengths; returns how many remain inside.

    Each round flags the inside vertices (roots excluded: they lie on the surface) of the strands still in
    question; per strand only the first flagged vertex is fixed (the ones after it move with it, follow-the-leader),
    so a round never works against itself. Only strands changed in a round are tested again.
    """
    s, v, _ = positions.shape
    rounds = rounds if rounds is not None else 3 * v
    active = np.arange(s)
    last_fixed = np.zeros(s, np.int64)
    boost = np.ones(s)
    for _ in range(rounds):
        if not len(active):
            return 0
        flags = inside(positions[active, 1:].reshape(-1, 3)).reshape(len(active), v - 1)
        hit = flags.any(axis=1)
        active, flags = active[hit], flags[hit]
        if not len(active):
            return 0
        first = flags.argmax(axis=1) + 1
        # the same vertex again (a concave spot: the slide went back in): double its clearance each time
        again = last_fixed[active] == first
        boost[active] = np.where(again, boost[active] * 2.0, 1.0)
        last_fixed[active] = first
        points = positions[active, first]
        closest, normals, _ = surface.closest(points)
        # outward: the face normal oriented away from the inside point
        side = np.einsum("ij,ij->i", points - closest, normals)
        normals = np.where((side > 0)[:, None], -normals, normals)
        targets = closest + normals * (margin * boost[active])[:, None]
        _slide_out(positions, active.astype(np.int64), first.astype(np.int64), targets, normals, rest_lengths)
    if not len(active):
        return 0
    if root_normals is not None:
        # last resort for the rare strand caught in a crevice: straighten it along its root normal from the first
        # vertex still inside, then (if that fails too) from the root
        for whole in (False, True):
            flags = inside(positions[active, 1:].reshape(-1, 3)).reshape(len(active), v - 1)
            hit = flags.any(axis=1)
            active, flags = active[hit], flags[hit]
            if not len(active):
                return 0
            first = np.ones(len(active), np.int64) if whole else flags.argmax(axis=1) + 1
            k = np.arange(v)[None, :]
            steps = np.clip(k - first[:, None] + 1, 0, None)  # 0 before the first bad vertex, then 1, 2, ...
            base = positions[active, first - 1]
            straight = base[:, None, :] + (steps * rest_lengths[active][:, None])[..., None] \
                * root_normals[active][:, None, :]
            positions[active] = np.where((steps > 0)[..., None], straight, positions[active])
    return int(inside(positions[active, 1:].reshape(-1, 3)).sum()) if len(active) else 0


# ---------------------------------------------------------------------------------------------------- children
def barycentric_weights(points: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Barycentric coordinates of ``points`` projected on triangles (a, b, c), clamped to >= 0 and renormalized;
    inverse-distance weights where a triangle is degenerate."""
    v0, v1, v2 = b - a, c - a, points - a
    d00 = np.einsum("ij,ij->i", v0, v0)
    d01 = np.einsum("ij,ij->i", v0, v1)
    d11 = np.einsum("ij,ij->i", v1, v1)
    d20 = np.einsum("ij,ij->i", v2, v0)
    d21 = np.einsum("ij,ij->i", v2, v1)
    denom = d00 * d11 - d01 * d01
    scale = np.maximum(d00 * d11, 1e-300)
    ok = denom > 1e-6 * scale
    safe = np.where(ok, denom, 1.0)
    v = (d11 * d20 - d01 * d21) / safe
    w = (d00 * d21 - d01 * d20) / safe
    bary = np.clip(np.stack([1.0 - v - w, v, w], axis=1), 0.0, None)
    dist = np.stack([np.linalg.norm(points - p, axis=1) for p in (a, b, c)], axis=1)
    idw = 1.0 / np.maximum(dist, 1e-12) ** 2
    bary = np.where(ok[:, None] & (bary.sum(axis=1, keepdims=True) > 1e-12), bary, idw)
    return bary / bary.sum(axis=1, keepdims=True)


def interpolate_children(guides: np.ndarray, guide_rest: np.ndarray, guide_roots: np.ndarray, child_roots,
                         child_normals, spacing: float, *, spread: float, clump: float, thinning: float,
                         rng: np.random.Generator):
    """Child strands (c, v, 3) from guide strands (g, v, 3); returns (positions, rest lengths, ids, weights).

    child(t) = root_c + sum_i w_i (guide_i(t) - guide_i(0))                           shape transfer
             + spread * spacing * t * (cos phi T + sin phi B) * r                       TressFX follow offset
    then lerp towards the dominant guide's curve (offset to the child's root) by clump * t, and random
    thinning scales a strand's length by U(0.3, 1). Segment lengths are restored by follow-the-leader.
    """
    c = len(child_roots)
    k = min(3, len(guide_roots))
    _, ids = cKDTree(guide_roots).query(child_roots, k=k)
    ids = ids.reshape(c, k).astype(np.int64)
    if k < 3:
        ids = np.concatenate([ids, np.repeat(ids[:, :1], 3 - k, axis=1)], axis=1)
    weights = barycentric_weights(child_roots, guide_roots[ids[:, 0]], guide_roots[ids[:, 1]],
                                  guide_roots[ids[:, 2]])
    shapes = guides - guides[:, :1]
    t = np.linspace(0.0, 1.0, guides.shape[1])
    pos = child_roots[:, None, :] + np.einsum("ck,ckvd->cvd", weights, shapes[ids])
    # follow offset: a random direction in the child's tangent plane, radius sqrt(U) (uniform in the disc)
    tangent, bitangent = orthonormal_basis(child_normals)
    phi = rng.random(c) * 2.0 * math.pi
    radius = np.sqrt(rng.random(c)) * spread * spacing
    offset = (np.cos(phi)[:, None] * tangent + np.sin(phi)[:, None] * bitangent) * radius[:, None]
    pos += t[None, :, None] * offset[:, None, :]
    if clump > 0:
        dominant = ids[np.arange(c), weights.argmax(axis=1)]
        target = child_roots[:, None, :] + shapes[dominant] * 1.0
        target = target + (guides[dominant, :1] - child_roots[:, None, :]) * t[None, :, None]
        pos += (clump * t)[None, :, None] * (target - pos)
    rest = np.einsum("ck,ck->c", weights, guide_rest[ids])
    shorten = rng.random(c) < thinning
    scale = np.where(shorten, 0.3 + 0.7 * rng.random(c), 1.0)
    rest = rest * scale
    pos = np.ascontiguousarray(pos)
    follow_the_leader(pos, rest)
    return pos, rest, ids, weights


# ---------------------------------------------------------------------------------------------------- driver
def generate_hair(emitter: Emitter, options: HairOptions, seed: int = 0) -> HairResult:
    """Guides + children on ``emitter`` for ``options``; deterministic for a given ``seed``."""
    rng = np.random.default_rng(seed)
    v, f = emitter.vertices, emitter.faces
    diag = float(np.linalg.norm(v.max(0) - v.min(0))) or 1.0
    length = options.length if options.length else 0.15 * diag
    margin = options.margin if options.margin is not None else 1e-3 * length
    segments = options.segments

    # guides
    tri, bary, roots, rmax = sample_roots(emitter, options.guides, rng)
    normals = _unit(corner_interpolate(emitter.normals[f], tri, bary))
    scale = np.ones(len(roots))
    if emitter.length_scale is not None:
        scale = np.clip(emitter.length_scale(tri, bary), 0.0, None)
    lengths = np.maximum(length * scale, 1e-9 * diag)
    rest_len = lengths / segments
    rest = grow_guides(roots, normals, lengths, segments, options.curl_amplitude, options.curl_frequency,
                       rng.random(len(roots)) * 2.0 * math.pi)
    guides = relax(rest, rest_len, options.gravity, options.gravity_direction, options.stiffness, options.iterations)
    inside = InsideTest(v, emitter.colliders)
    surface = SurfaceLookup(v, emitter.colliders, rng_seed=seed)
    guides_inside = push_out(guides, rest_len, inside, surface, margin, root_normals=normals)
    guide_uv = corner_interpolate(emitter.texcoords, tri, bary) if emitter.texcoords is not None else None
    guide_width = 1.0 - options.width_variation * rng.random(len(roots))
    guide_set = StrandSet(guides, guide_width, rest_len, normals, guide_uv)

    # children
    n_children = options.children * len(roots)
    ctri, cbary, _ = masked_surface_points(emitter, n_children, rng)
    croots = np.einsum("sk,skd->sd", cbary, v[f[ctri]])
    cnormals = _unit(corner_interpolate(emitter.normals[f], ctri, cbary))
    spacing = 2.0 * rmax
    cpos, crest, ids, w = interpolate_children(guides, rest_len, roots, croots, cnormals, spacing,
                                               spread=options.spread, clump=options.clump,
                                               thinning=options.thinning, rng=rng)
    children_inside = push_out(cpos, crest, inside, surface, margin, root_normals=cnormals)
    child_uv = corner_interpolate(emitter.texcoords, ctri, cbary) if emitter.texcoords is not None else None
    child_width = 1.0 - options.width_variation * rng.random(n_children)
    child_set = StrandSet(cpos, child_width, crest, cnormals, child_uv, ids, w)

    # blending order (RTR4 14.7.1): strands nearest the emitter first, outer ones last
    guide_order = depth_order(guides, surface)
    rank = np.empty_like(guide_order)
    rank[guide_order] = np.arange(len(guide_order))
    guide_set = guide_set.take(guide_order)
    child_set.guide_ids = rank[child_set.guide_ids]
    child_set = child_set.take(depth_order(cpos, surface))

    root_width = options.root_width if options.root_width is not None else length / 150.0
    tip_width = options.tip_width if options.tip_width is not None else root_width / 10.0
    stats = {"guides_inside": guides_inside, "children_inside": children_inside, "closed_emitter": inside.closed,
             "poisson_radius": rmax}
    return HairResult(guide_set, child_set, length, root_width, tip_width, spacing, stats)


def depth_order(positions: np.ndarray, surface: SurfaceLookup) -> np.ndarray:
    """Strand order for blending: by mean distance of the strand's vertices to the emitter, nearest first."""
    if len(positions) == 0:
        return np.zeros(0, np.int64)
    s, v, _ = positions.shape
    step = max(1, (v - 1) // 4)  # 5 vertices are plenty to rank strands
    sample = positions[:, ::step].reshape(-1, 3)
    depth = surface.approximate_distance(sample).reshape(s, -1).mean(axis=1)
    return np.argsort(np.round(depth, 12), kind="stable")


def strand_tangents(positions: np.ndarray) -> np.ndarray:
    """Unit tangents (s, v, 3): central differences inside, one-sided at the root and the tip."""
    d = np.empty_like(positions)
    d[:, 1:-1] = positions[:, 2:] - positions[:, :-2]
    d[:, 0] = positions[:, 1] - positions[:, 0]
    d[:, -1] = positions[:, -1] - positions[:, -2]
    return _unit(d)


def ribbon_indices(strands: int, vertices: int) -> np.ndarray:
    """Triangle indices (6 per segment) of ribbon vertices ``2 * line_vertex + side`` (side 0 or 1).

    The runtime draws ``2 * vertex_count`` ribbon vertices; vertex ``r`` reads line vertex ``r / 2`` and extrudes
    it to side ``r % 2`` (``baker_hair_ribbon_position`` in ``runtime-shaders/baker_hair.glsl``).
    """
    base = (np.arange(strands)[:, None] * vertices + np.arange(vertices - 1)[None, :]).reshape(-1) * 2
    quad = np.array([0, 1, 2, 2, 1, 3], np.int64)
    return (base[:, None] + quad[None, :]).reshape(-1)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-30)


def segment_lengths(positions: np.ndarray) -> np.ndarray:
    return np.linalg.norm(np.diff(positions, axis=1), axis=-1)
