"""Local thickness: the mean distance to the far side of the surface, seen from inside.

Barré-Brisebois & Bouchard, "Approximating Translucency for a Fast, Cheap and Convincing Subsurface Scattering
Look", GDC 2011 (RTR4 section 14.6, eq. 14.30): ambient occlusion computed with the normals inverted. From each
surface point we cast rays into the hemisphere (or a narrower cone) around -n and average the distance to the first
hit; a miss counts as ``max_distance``. Unlike the paper's 0-1 texture we keep the mean chord **in mesh units**:
the runtime turns it into a transmittance (see ``schemas/BAKER_thickness``), and KHR_materials_volume wants units.

For a sphere of radius r, a chord leaving at angle theta from the inward normal has length 2 r cos(theta): cosine-
weighted rays average 4r/3, uniform (solid-angle) rays average r. The tests check exactly that.

Rays are generated, traced by Embree and averaged in one compiled, GIL-free loop per batch of points, run from
two threads (see :mod:`baker.geometry.embree_trace`); there is no per-ray Python. One call can trace points of
several meshes (one ray stream over all texture sets), and points with a ``prior`` stop after 12 rays that agree
with it (``local_thickness``; the texture bake's prior is its per-vertex solution interpolated).

Sample patterns (``sampler``), all mapped through the same cosine-weighted (or uniform) warp, so every one estimates
the same integral and only the error differs:

- ``sobol``: the first two dimensions of the Sobol sequence (a (0, 2)-sequence: every power-of-2 prefix is
  stratified in every elementary interval) with a per-point Owen scramble, the nested uniform scrambling of Owen
  (1995) computed by a hash as in Burley, "Practical Hash-based Owen Scrambling", JCGT 9(4), 2020. Owen
  scrambling keeps the stratification and makes each point's estimate unbiased and independent of its neighbours'.
- ``hammersley``: the Hammersley set shared by all points with a random toroidal shift per point
  (Cranley-Patterson rotation). Measured on spot, the bunny and a torus it is as good as ``sobol`` or slightly
  better at every ray count (both are (0, m, 2)-nets at powers of 2; the shift keeps the first coordinate's
  1/n strata).
- ``fibonacci`` (default): a spherical Fibonacci set (Marques et al., "Spherical Fibonacci Point Sets for
  Illumination Integrals", CGF 2013; here on the cosine-weighted hemisphere, i.e. Vogel's sunflower spiral on the
  projected disk): ray k of n sits at the middle of the k-th of n equal-probability elevation bands,
  u0 = (k + 1/2) / n, at azimuth frac(k / golden ratio), and each point turns the whole set by a random angle about
  its axis. The elevation strata are exact (no shift: the estimate of a function of elevation alone is the
  midpoint rule, error O(1/n^2)); the random rotation keeps neighbouring points' errors independent. Measured on
  spot, suzanne, a torus and the bunny it has a lower error than ``hammersley`` at 8-128 rays (8-18% lower at 64)
  and matches the error of 64 random rays with 10-15 rays on the first three (a shift in elevation, as
  ``hammersley`` draws, or Owen scrambling of either net measured worse; see ``benchmarks/RESULTS.md``).
- ``random``: independent uniform random numbers per ray (plain Monte Carlo), the reference point of the error
  curves in ``benchmarks/thickness_sampler.py``.
"""
from __future__ import annotations

import math
import os

import numba
import numpy as np

from baker.geometry import embree_trace
from baker.geometry.raycast import RayScene
from baker import interruptible




def hemisphere_samples(n: int, seed: int) -> np.ndarray:
    """``n`` stratified 2D samples in [0, 1)^2 (Hammersley set, base-2 radical inverse), shared by all points."""
    i = np.arange(n, dtype=np.uint64)
    bits = i.copy()
    # Van der Corput radical inverse in base 2 via bit reversal of 32-bit integers
    bits = ((bits << np.uint64(16)) | (bits >> np.uint64(16))) & np.uint64(0xFFFFFFFF)
    bits = ((bits & np.uint64(0x55555555)) << np.uint64(1)) | ((bits & np.uint64(0xAAAAAAAA)) >> np.uint64(1))
    bits = ((bits & np.uint64(0x33333333)) << np.uint64(2)) | ((bits & np.uint64(0xCCCCCCCC)) >> np.uint64(2))
    bits = ((bits & np.uint64(0x0F0F0F0F)) << np.uint64(4)) | ((bits & np.uint64(0xF0F0F0F0)) >> np.uint64(4))
    bits = ((bits & np.uint64(0x00FF00FF)) << np.uint64(8)) | ((bits & np.uint64(0xFF00FF00)) >> np.uint64(8))
    return np.stack([(i.astype(np.float64) + 0.5) / n, bits.astype(np.float64) / 2.0**32], axis=1)






SAMPLERS = ("hammersley", "sobol", "random", "fibonacci")
GOLDEN_FRACTION = (math.sqrt(5.0) - 1.0) / 2.0  # 1 / golden ratio: the azimuth step of the Fibonacci set


def fibonacci_samples(n: int) -> np.ndarray:
    """The ``n``-point spherical Fibonacci set in [0, 1)^2: (elevation band midpoint, azimuth fraction) per ray."""
    k = np.arange(n, dtype=np.float64)
    return np.stack([(k + 0.5) / n, (k * GOLDEN_FRACTION) % 1.0], axis=1)


U = np.uint64  # every integer below is uint64: numba turns a uint64 mixed with an int64 into a float


@numba.njit(cache=True, nogil=True, inline="always")
def _reverse32(x):
    x = ((x << U(16)) | (x >> U(16))) & U(0xFFFFFFFF)
    x = ((x & U(0x55555555)) << U(1)) | ((x & U(0xAAAAAAAA)) >> U(1))
    x = ((x & U(0x33333333)) << U(2)) | ((x & U(0xCCCCCCCC)) >> U(2))
    x = ((x & U(0x0F0F0F0F)) << U(4)) | ((x & U(0xF0F0F0F0)) >> U(4))
    return ((x & U(0x00FF00FF)) << U(8)) | ((x & U(0xFF00FF00)) >> U(8))


@numba.njit(cache=True, nogil=True, inline="always")
def _owen32(x, seed):
    """Nested uniform (Owen) scramble of the 32-bit fraction ``x``: a hash of the bit-reversed value in which each
    bit only depends on the bits above it (Laine-Karras permutation, Burley 2020 with Vegdahl's constants)."""
    m = U(0xFFFFFFFF)
    x = _reverse32(x)
    x ^= (x * U(0x3D20ADEA)) & m
    x = (x + seed) & m
    x = (x * ((seed >> U(16)) | U(1))) & m
    x ^= (x * U(0x05526C56)) & m
    x ^= (x * U(0x53A22864)) & m
    return _reverse32(x)


@numba.njit(cache=True, nogil=True, inline="always")
def _hash32(x):
    """A 32-bit integer hash (lowbias32 by C. Wellons): independent-looking bits for the ``random`` sampler."""
    m = U(0xFFFFFFFF)
    x ^= x >> U(16)
    x = (x * U(0x7FEB352D)) & m
    x ^= x >> U(15)
    x = (x * U(0x846CA68B)) & m
    return x ^ (x >> U(16))


@numba.njit(cache=True, nogil=True, inline="always")
def _sobol2(k):
    """Dimension 2 of the Sobol sequence at index k as a 32-bit fraction (direction numbers v_j = v_{j-1} ^
    (v_{j-1} >> 1), v_0 = 2^31: the generator matrix of the polynomial x + 1)."""
    v = U(0x80000000)
    y = U(0)
    while k:
        if k & U(1):
            y ^= v
        k >>= U(1)
        v ^= v >> U(1)
    return y


@numba.njit(cache=True, nogil=True, inline="always")
def _sample(sampler, samples, shifts, seeds, i, k):
    """The 2D sample of ray k of point i in [0, 1)^2."""
    if sampler == 1:  # sobol, Owen-scrambled per point (two independent scrambles, one per dimension)
        x = _owen32(_reverse32(U(k)), seeds[i, 0])
        y = _owen32(_sobol2(U(k)), seeds[i, 1])
        return (x + 0.5) * 2.0 ** -32, (y + 0.5) * 2.0 ** -32
    if sampler == 0:  # hammersley + Cranley-Patterson shift
        return (samples[k, 0] + shifts[i, 0]) % 1.0, (samples[k, 1] + shifts[i, 1]) % 1.0
    if sampler == 3:  # fibonacci: exact elevation strata, the azimuths turned by a random angle per point
        return samples[k, 0], (samples[k, 1] + shifts[i, 1]) % 1.0
    h = _hash32((seeds[i, 0] ^ _hash32(U(k) ^ seeds[i, 1])) & U(0xFFFFFFFF))
    return (h + 0.5) * 2.0 ** -32, (_hash32(h ^ U(0x9E3779B9)) + 0.5) * 2.0 ** -32


@numba.njit(cache=True, nogil=True, inline="always")
def _frame(nx, ny, nz):
    """Two unit tangents completing the unit axis (nx, ny, nz) to a right-handed frame (Duff et al. 2017)."""
    sign = 1.0 if nz >= 0.0 else -1.0
    a = -1.0 / (sign + nz)
    b = nx * ny * a
    return 1.0 + sign * nx * nx * a, sign * b, -sign * nx, b, sign + ny * ny * a, -ny


@numba.njit(cache=True, nogil=True, inline="always")
def _direction(u0, u1, cosine, sin_max, cos_max):
    """Local direction (x, y along the tangents; cos theta along the axis) for a sample (u0, u1) in [0, 1)^2.

    Cosine-weighted within a cone of half-angle theta_max: sin^2(theta) uniform on [0, sin^2(theta_max)];
    uniform: cos(theta) uniform on [cos(theta_max), 1]."""
    if cosine:
        st = np.sqrt(u0) * sin_max
        ct = np.sqrt(max(0.0, 1.0 - st * st))
    else:
        ct = 1.0 - u0 * (1.0 - cos_max)
        st = np.sqrt(max(0.0, 1.0 - ct * ct))
    phi = 2.0 * np.pi * u1
    return st * np.cos(phi), st * np.sin(phi), ct


@numba.njit(cache=True, nogil=True, inline="always")
def _trace_chords(scene, rayhit, sampler, samples, shifts, seeds, i, k0, k1, ox, oy, oz, nx, ny, nz, tx, ty, tz,
                  bx, by, bz, cosine, sin_max, cos_max, bias, max_distance):
    """Sum of the clamped chords of rays k0..k1-1 of point i."""
    acc = 0.0
    for k in range(k0, k1):
        u0, u1 = _sample(sampler, samples, shifts, seeds, i, k)
        c, s, ct = _direction(u0, u1, cosine, sin_max, cos_max)
        t = embree_trace.trace_one(scene, rayhit, ox, oy, oz, tx * c + bx * s + nx * ct, ty * c + by * s + ny * ct,
                                   tz * c + bz * s + nz * ct)
        acc += min(t + bias * ct, max_distance)
    return acc


@numba.njit(cache=True, nogil=True)  # cacheable: Embree is called by symbol name (baker.geometry.embree_trace)
def _thickness_direct(scenes, scene_of, points, axes, sampler, samples, first_samples, prefix, tolerance, prior,
                      shifts, seeds, cosine, sin_max, cos_max, biases, max_distances, out, used, first_means):
    """Generate, trace and average each point's rays in one GIL-free loop (Embree called directly).

    Point i traces into ``scenes[scene_of[i]]``. With ``tolerance`` > 0 and a ``prior`` estimate (>= 0) it first
    traces the rays of ``first_samples`` (the first of ``samples`` when ``prefix``, else a pattern of their own);
    when their mean is within +-tolerance x prior of the prior it takes the prior, else it traces all of
    ``samples`` (continuing after the prefix). ``used[i]``: rays traced; ``first_means[i]``: the mean chord of the
    first rays (NaN for a point that traced no test)."""
    rayhit = np.zeros(48, np.uint32)
    offset = (-rayhit.ctypes.data % 16) // 4
    rayhit = rayhit[offset: offset + 32]
    rays = samples.shape[0]
    first = first_samples.shape[0]
    for i in range(points.shape[0]):
        s = scene_of[i]
        scene, bias, max_distance = scenes[s], biases[s], max_distances[s]
        nx, ny, nz = axes[i, 0], axes[i, 1], axes[i, 2]
        tx, ty, tz, bx, by, bz = _frame(nx, ny, nz)
        ox, oy, oz = points[i, 0] + nx * bias, points[i, 1] + ny * bias, points[i, 2] + nz * bias
        acc, start, traced = 0.0, 0, 0
        first_means[i] = np.nan
        if tolerance > 0.0 and prior[i] >= 0.0:
            acc = _trace_chords(scene, rayhit, sampler, first_samples, shifts, seeds, i, 0, first, ox, oy, oz, nx,
                                ny, nz, tx, ty, tz, bx, by, bz, cosine, sin_max, cos_max, bias, max_distance)
            traced = first
            first_means[i] = acc / first
            if abs(acc / first - prior[i]) <= tolerance * prior[i]:
                out[i] = prior[i]
                used[i] = traced
                continue
            if prefix:
                start = first
            else:
                acc = 0.0
        acc += _trace_chords(scene, rayhit, sampler, samples, shifts, seeds, i, start, rays, ox, oy, oz, nx, ny, nz,
                             tx, ty, tz, bx, by, bz, cosine, sin_max, cos_max, bias, max_distance)
        out[i] = acc / rays
        used[i] = traced + rays - start


@numba.njit(cache=True, nogil=True)
def _make_rays(points, axes, sampler, samples, shifts, seeds, cosine, sin_max, cos_max, bias, origins, directions,
               cos_theta):
    """The rays of :func:`_thickness_direct` written out (float32), for the embreex batch path and benchmarks."""
    rays = samples.shape[0]
    for i in range(points.shape[0]):
        nx, ny, nz = axes[i, 0], axes[i, 1], axes[i, 2]
        tx, ty, tz, bx, by, bz = _frame(nx, ny, nz)
        ox, oy, oz = points[i, 0] + nx * bias, points[i, 1] + ny * bias, points[i, 2] + nz * bias
        for k in range(rays):
            u0, u1 = _sample(sampler, samples, shifts, seeds, i, k)
            c, s, ct = _direction(u0, u1, cosine, sin_max, cos_max)
            r = i * rays + k
            directions[r, 0] = tx * c + bx * s + nx * ct
            directions[r, 1] = ty * c + by * s + ny * ct
            directions[r, 2] = tz * c + bz * s + nz * ct
            origins[r, 0] = ox
            origins[r, 1] = oy
            origins[r, 2] = oz
            cos_theta[r] = ct


@numba.njit(cache=True, nogil=True)
def _mean_chords(dist, cos_theta, bias, max_distance, rays, out):
    for i in range(out.shape[0]):
        acc = 0.0
        for k in range(rays):
            r = i * rays + k
            acc += min(dist[r] + bias * cos_theta[r], max_distance)
        out[i] = acc / rays


@numba.njit(cache=True, nogil=True)
def _fill_samples(sampler, samples, shifts, seeds, out):
    for i in range(out.shape[0]):
        for k in range(out.shape[1]):
            out[i, k, 0], out[i, k, 1] = _sample(sampler, samples, shifts, seeds, i, k)


def _sampler_inputs(sampler: str, rays: int, n: int, seed: int):
    """(kernel code, pattern shared by all points, per-point shifts, per-point scramble seeds) of ``sampler``."""
    if sampler not in SAMPLERS:
        raise ValueError(f"unknown sampler {sampler!r}")
    samples = fibonacci_samples(rays) if sampler == "fibonacci" else hemisphere_samples(rays, seed)
    rng = np.random.default_rng(seed)
    shifts = rng.random((n, 2))  # drawn first for every sampler: hammersley's values do not depend on the others
    scrambled = sampler in ("sobol", "random")
    seeds = rng.integers(0, 1 << 32, (n, 2), dtype=np.uint64) if scrambled else np.zeros((n, 2), np.uint64)
    return SAMPLERS.index(sampler), samples, shifts, seeds


def unit_samples(sampler: str, rays: int, count: int, seed: int = 0) -> np.ndarray:
    """(count, rays, 2) samples in [0, 1)^2 that :func:`local_thickness` maps to the rays of ``count`` points
    (same ``sampler``, ``rays`` and ``seed``): column 0 picks the elevation, column 1 the azimuth (a turn)."""
    out = np.empty((count, rays, 2), np.float64)
    _fill_samples(*_sampler_inputs(sampler, rays, count, seed), out)
    return out


def default_max_distance(vertices: np.ndarray) -> float:
    """The bounding-box diagonal; 1 (a mesh unit) when there is none: no vertices, or a mesh collapsed to a point,
    whose zero would break BAKER_thickness' ``maxDistance > 0``."""
    diagonal = float(np.linalg.norm(vertices.max(0) - vertices.min(0))) if len(vertices) else 0.0
    return diagonal if diagonal > 0 else 1.0


# rays a point traces before it may stop on its prior: 3/16 of the default 64 (step.corrected_by_neighbours pools them)
FIRST_RAYS = 12


def local_thickness(scene, points: np.ndarray, normals: np.ndarray, *, rays: int = 64,
                    distribution: str = "cosine", spread: float = 180.0, max_distance=1.0,
                    bias=1e-5, seed: int = 0, sampler: str = "fibonacci", progress=None,
                    threads: int | None = None, scene_of: np.ndarray | None = None, prior: np.ndarray | None = None,
                    tolerance: float = 0.0, rays_used: np.ndarray | None = None,
                    first_means: np.ndarray | None = None) -> np.ndarray:
    """Mean distance from each point to the first surface hit along rays around ``-normals``.

    Parameters
    ----------
    scene : RayScene or list of RayScene
        The mesh the rays hit (in the same space as ``points``); a list with ``scene_of``: one ray stream over
        several meshes, point i tracing into ``scene[scene_of[i]]``.
    points, normals : (n, 3) arrays
        Sample points on the surface and their outward unit normals.
    rays : int
        Rays per point (the most, with ``tolerance``).
    distribution : {'cosine', 'uniform'}
        Cosine-weighted (AO-style, the default) or uniform over the solid angle.
    spread : float
        Full cone angle in degrees; 180 is the hemisphere.
    max_distance : float, or one per scene
        Length given to misses and clamp of hits, in mesh units.
    bias : float, or one per scene
        Rays start ``bias`` inside the surface (along -n) to skip the surface they leave; the offset's share along
        each ray is added back to its distance.
    seed : int
        Seeds the per-point scramble (sobol), shift (hammersley), rotation (fibonacci) or random numbers (random).
    sampler : {'fibonacci', 'hammersley', 'sobol', 'random'}
        The sample pattern (see the module docstring).
    progress : callable(int) or None
        Called with the number of points finished after each batch.
    scene_of : (n,) int array or None
        With a list of scenes: the scene of each point.
    prior : (n,) array or None
        An estimate of each point's result (e.g. interpolated from a finer per-vertex solution; < 0: none).
    tolerance : float
        With ``prior``: a point first traces :data:`FIRST_RAYS` rays (the start of the ``sobol`` and ``random``
        sequences, a ``FIRST_RAYS``-point set of the ``fibonacci`` or ``hammersley`` pattern with the point's own
        rotation or shift) and, when their mean chord is within +-tolerance x prior of the prior, takes the prior;
        otherwise it traces its ``rays`` rays (the first ones reused by ``sobol`` and ``random``) and the result is
        exactly the estimate without a prior. 0, no prior, the embreex fallback or ``rays`` <= FIRST_RAYS: every
        point traces ``rays`` rays.
    rays_used : (n,) int array or None
        Filled with the rays traced per point.
    first_means : (n,) float array or None
        Filled with the mean chord of each point's first :data:`FIRST_RAYS` rays (NaN where none were traced first),
        whether or not the point then stopped on its prior.

    Returns
    -------
    (n,) float64 mean chord length in mesh units.
    """
    if distribution not in ("cosine", "uniform"):
        raise ValueError(f"unknown distribution {distribution!r}")
    scenes = list(scene) if isinstance(scene, (list, tuple)) else [scene]
    n = len(points)
    scene_of = np.zeros(n, np.int64) if scene_of is None else np.ascontiguousarray(scene_of, np.int64)
    max_distances = np.broadcast_to(np.asarray(max_distance, np.float64), (len(scenes),)).copy()
    biases = np.broadcast_to(np.asarray(bias, np.float64), (len(scenes),)).copy()
    code, samples, shifts, seeds = _sampler_inputs(sampler, rays, n, seed)
    out = np.empty(n, np.float64)
    used = np.full(n, rays, np.int64)
    firsts = np.full(n, np.nan)
    if n == 0:
        return out
    batch = max(1, (1 << 19) // rays)  # ~0.5 M rays per Embree call: large enough to amortize, small for memory
    direct = all(s.direct is not None for s in scenes)
    if prior is None or not direct or rays <= FIRST_RAYS:
        tolerance = 0.0
    prior = np.full(n, -1.0) if prior is None else np.ascontiguousarray(prior, np.float64)
    # sobol and random sequences are extensible: their first rays are a stratified (or plain random) set and the
    # rest continues them; the fibonacci and hammersley sets of n points are not, so the test uses a set of its own
    prefix = sampler in ("sobol", "random")
    first_samples = samples[:FIRST_RAYS] if prefix else _sampler_inputs(sampler, FIRST_RAYS, 0, seed)[1]
    pointers = np.array([s.direct.pointer if s.direct is not None else 0 for s in scenes], np.int64)

    half = math.radians(spread) / 2.0
    sin_max, cos_max = math.sin(min(half, math.pi / 2)), math.cos(half)
    # trace points by scene, then in Morton (Z-curve) order: consecutive batches then walk the same BVH nodes,
    # which measured ~10% faster in Embree than file order and ~25% faster than random order
    order = morton_order(points)
    if len(scenes) > 1:
        order = order[np.argsort(scene_of[order], kind="stable")]
    points, axes, shifts, seeds = _sorted_inputs(order, np.ascontiguousarray(points, np.float64),
                                                 np.ascontiguousarray(normals, np.float64), shifts, seeds)
    sorted_scene_of = scene_of[order]
    prior = prior[order]
    result = np.empty(n, np.float64)

    def run(start: int) -> int:
        stop = min(n, start + batch)
        if direct:
            _thickness_direct(pointers, sorted_scene_of[start:stop], points[start:stop], axes[start:stop], code,
                              samples, first_samples, prefix, tolerance, prior[start:stop],
                              shifts[start:stop],
                              seeds[start:stop], distribution == "cosine", sin_max, cos_max, biases, max_distances,
                              out[start:stop], used[start:stop], firsts[start:stop])
            return stop - start
        for s in np.unique(sorted_scene_of[start:stop]):
            # one scene at a time (the batch is sorted by scene: each is one run of points)
            first = start + int(np.searchsorted(sorted_scene_of[start:stop], s, "left"))
            last = start + int(np.searchsorted(sorted_scene_of[start:stop], s, "right"))
            count = (last - first) * rays
            origins = np.empty((count, 3), np.float32)
            directions = np.empty((count, 3), np.float32)
            cos_t = np.empty(count, np.float64)
            # start `bias` inside the solid (along -n), not along the ray: grazing rays from a vertex of a faceted
            # surface would otherwise leave through the facets' gap below the tangent plane and count as misses
            _make_rays(points[first:last], axes[first:last], code, samples, shifts[first:last], seeds[first:last],
                       distribution == "cosine", sin_max, cos_max, biases[s], origins, directions, cos_t)
            dist = scenes[s].distances(origins, directions)
            _mean_chords(dist, cos_t, biases[s], max_distances[s], rays, out[first:last])
        return stop - start

    # BAKER_THREADS caps the ray threads (``baker build --jobs`` sets 1 per process); results do not depend on it
    threads = threads or int(os.environ.get("BAKER_THREADS", 0)) or min(2, os.cpu_count() or 1)
    with interruptible.thread_pool(threads) as pool:
        for done in pool.map(run, range(0, n, batch)):
            if progress:
                progress(done)
    result[order] = out
    if rays_used is not None:
        rays_used[order] = used
    if first_means is not None:
        first_means[order] = firsts
    return result


@numba.njit(cache=True, nogil=True)
def _sorted_inputs(order, points, normals, shifts, seeds):
    """Points, inward unit axes ``-n / max(|n|, 1e-30)``, shifts and seeds gathered in ``order``: one pass instead of
    a norm, a division and four fancy-index copies (the same values: |n| summed x, y, z in numpy's order)."""
    n = order.shape[0]
    points_out = np.empty((n, 3), np.float64)
    axes_out = np.empty((n, 3), np.float64)
    shifts_out = np.empty((n, 2), np.float64)
    seeds_out = np.empty((n, 2), np.uint64)
    for i in range(n):
        j = order[i]
        x, y, z = normals[j, 0], normals[j, 1], normals[j, 2]
        length = max(np.sqrt(x * x + y * y + z * z), 1e-30)
        for k in range(3):
            points_out[i, k] = points[j, k]
            axes_out[i, k] = -normals[j, k] / length
        for k in range(2):
            shifts_out[i, k] = shifts[j, k]
            seeds_out[i, k] = seeds[j, k]
    return points_out, axes_out, shifts_out, seeds_out


@numba.njit(cache=True, nogil=True)
def _morton_codes(points, lo, extent, bits):
    """Z-order code of each point: the grid cell ``int((p - lo) / extent * (2^bits - 1))`` per axis (numpy's
    operation order, so the same cells), bit b of x, y, z interleaved at bits 3b, 3b + 1, 3b + 2."""
    n = points.shape[0]
    scale = float((1 << bits) - 1)
    codes = np.empty(n, np.int64)
    for i in range(n):
        code = np.int64(0)
        for axis in range(3):
            q = np.int64((points[i, axis] - lo[axis]) / extent[axis] * scale)
            for b in range(bits):
                code |= ((q >> b) & 1) << (3 * b + axis)
        codes[i] = code
    return codes


@numba.njit(cache=True, nogil=True)
def _stable_argsort_codes(codes, bits):
    """``np.argsort(codes, kind="stable")`` for codes in [0, 2^bits): LSD radix sort, 15-bit digits (a stable sort,
    so the same permutation). The keys travel with the indices, so each pass reads both in order."""
    n = codes.shape[0]
    order, keys = np.arange(n), codes.copy()
    order_out, keys_out = np.empty(n, np.int64), np.empty(n, np.int64)
    shift = 0
    while shift < bits:
        counts = np.zeros((1 << 15) + 1, np.int64)
        for i in range(n):
            counts[((keys[i] >> shift) & 0x7FFF) + 1] += 1
        for d in range(1 << 15):
            counts[d + 1] += counts[d]
        for i in range(n):
            d = (keys[i] >> shift) & 0x7FFF
            slot = counts[d]
            order_out[slot] = order[i]
            keys_out[slot] = keys[i]
            counts[d] = slot + 1
        order, order_out = order_out, order
        keys, keys_out = keys_out, keys
        shift += 15
    return order


def morton_order(points: np.ndarray, bits: int = 10) -> np.ndarray:
    """Indices sorting ``points`` along a 3D Z-order curve on a 2^bits grid over their bounding box."""
    points = np.ascontiguousarray(points, np.float64)
    lo, hi = points.min(0), points.max(0)
    # compiled: the codes in one pass, then a radix sort (3 x bits numpy passes + argsort took 1 s at 2.2M points)
    return _stable_argsort_codes(_morton_codes(points, lo, np.maximum(hi - lo, 1e-30), bits), 3 * bits)


@numba.njit(cache=True, nogil=True)
def _ring_fit(positions, faces, normals, values, self_weight, min_cos, out):
    n = positions.shape[0]
    sums = np.zeros((n, 9), np.float64)  # per vertex: w, wx, wy, wxx, wxy, wyy, wv, wxv, wyv
    frames = np.empty((n, 6), np.float64)
    for i in range(n):
        tx, ty, tz, bx, by, bz = _frame(normals[i, 0], normals[i, 1], normals[i, 2])
        frames[i, 0], frames[i, 1], frames[i, 2], frames[i, 3], frames[i, 4], frames[i, 5] = tx, ty, tz, bx, by, bz
        sums[i, 0] = self_weight
        sums[i, 6] = self_weight * values[i]
    for f in range(faces.shape[0]):
        for a in range(3):
            i = faces[f, a]
            for b in range(3):
                if a == b:
                    continue
                j = faces[f, b]
                if normals[i, 0] * normals[j, 0] + normals[i, 1] * normals[j, 1] + normals[i, 2] * normals[j, 2] \
                        < min_cos:
                    continue  # across a crease: another surface's value
                dx = positions[j, 0] - positions[i, 0]
                dy = positions[j, 1] - positions[i, 1]
                dz = positions[j, 2] - positions[i, 2]
                x = dx * frames[i, 0] + dy * frames[i, 1] + dz * frames[i, 2]
                y = dx * frames[i, 3] + dy * frames[i, 4] + dz * frames[i, 5]
                v = values[j]
                sums[i, 0] += 1.0
                sums[i, 1] += x
                sums[i, 2] += y
                sums[i, 3] += x * x
                sums[i, 4] += x * y
                sums[i, 5] += y * y
                sums[i, 6] += v
                sums[i, 7] += x * v
                sums[i, 8] += y * v
    for i in range(n):
        w, sx, sy, sxx, sxy, syy, sv, sxv, syv = (sums[i, 0], sums[i, 1], sums[i, 2], sums[i, 3], sums[i, 4],
                                                  sums[i, 5], sums[i, 6], sums[i, 7], sums[i, 8])
        # the intercept of the weighted plane fit, by Cramer's rule on the 3 x 3 normal equations
        det = w * (sxx * syy - sxy * sxy) - sx * (sx * syy - sxy * sy) + sy * (sx * sxy - sxx * sy)
        scale = w * sxx * syy
        if scale > 0.0 and det > 1e-9 * scale:
            out[i] = (sv * (sxx * syy - sxy * sxy) - sx * (sxv * syy - sxy * syv) + sy * (sxv * sxy - sxx * syv)) / det
        else:
            out[i] = sv / w  # a vertex with no spread of neighbours (isolated, or all on a line): their mean


def ring_fit(positions: np.ndarray, faces: np.ndarray, normals: np.ndarray, values: np.ndarray,
             self_weight: float = 2.0, min_cos: float = -1.0) -> np.ndarray:
    """Per vertex, the value at the vertex of the least-squares linear function (in its tangent plane) through its
    own value and its one-ring neighbours' (each neighbour once per face it shares with the vertex; the vertex's own
    value ``self_weight`` times): local linear regression (a degree-1 local polynomial fit, e.g. Cleveland & Devlin,
    "Locally Weighted Regression", JASA 1988), which averages the neighbours' independent ray noise down and, unlike a
    plain neighbour mean, keeps a field that varies linearly across the ring exactly."""
    out = np.empty(len(positions), np.float64)
    if len(positions):
        _ring_fit(np.ascontiguousarray(positions, np.float64), np.ascontiguousarray(faces, np.int64),
                  np.ascontiguousarray(normals, np.float64), np.ascontiguousarray(values, np.float64),
                  float(self_weight), float(min_cos), out)
    return out
