"""Convolve per-texel vectors on the surface with sums of Gaussians of the Euclidean 3D distance.

Each texel is a surface sample: its position P_j (mesh units), surface area a_j (the texel's share of the surface:
|dP/du x dP/dv| / texels) and a value f_j (a unit normal). For one normalized Gaussian of variance v the result at x is

    B(x) = sum_j a_j g(|x - P_j|) f_j / sum_j a_j g(|x - P_j|),   g(r) = exp(-r^2 / (2 v))

the area-weighted Gaussian mean on the surface: distances are measured between surface points, so the gather
crosses UV seams and goes from one chart to another; dividing by the local weight sum keeps the mean unbiased at
open borders. A plane wave of wavenumber k on a flat (or gently curved, radius >> sqrt(v)) surface comes out scaled
by exp(-k^2 v / 2), the 2D Gaussian's transfer function.

Speed (two levels, each exact to second order):
- **direct**: Gaussians no wider than :data:`DIRECT_SPACINGS` texel spacings gather texel from texel through a bucket grid whose cell is
  the cut-off radius (27 buckets per texel);
- **lattice**: wider ones splat the texels into cells of ``cell_fraction`` sigma (area-weighted centroid and sums),
  gather at the corners of occupied cells, and read back per texel by trilinear interpolation: the sparse
  splat-blur-slice of the bilateral grid (Paris & Durand 2006), with the gather exact rather than separable. Binning
  blurs a wave like a box of the cell size (variance h^2 / 12) and trilinear reading like h^2 / 6 on average, so the
  lattice gathers with v - h^2 / 4 and the whole matches the requested variance.
Sums run in a fixed order per target (numba ``prange`` over targets only): the result is deterministic.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

CUTOFF_SIGMAS = 3.5  # gather radius: a 2D Gaussian keeps exp(-3.5^2 / 2) = 0.2 % of its mass beyond it
# Gaussians up to this many texel spacings wide gather texel by texel: a direct gather visits ~(3.5 sigma /
# spacing)^2 texels per texel, the lattice ~(3.5 / cell_fraction)^2 cells per node at ~3 nodes per cell, so the
# two cost the same near sigma = 1.5 spacings (at the default cell of one sigma)
DIRECT_SPACINGS = 1.5
DENSE_TABLE_LIMIT = 1 << 24  # bucket grids up to this many cubes get a dense lookup table (8 bytes a cube)


@dataclass(frozen=True)
class Buckets:
    """Points sorted into a uniform grid of cubes ``size`` wide: bucket ``keys[i]`` holds
    ``order[starts[i]:starts[i + 1]]``."""

    origin: np.ndarray  # (3,) int64 lowest cube index
    dims: np.ndarray  # (3,) int64 cubes per axis
    size: float
    keys: np.ndarray  # (buckets,) int64, sorted
    starts: np.ndarray  # (buckets + 1,) int64
    order: np.ndarray  # (points,) int64


def bucket_points(points: np.ndarray, size: float) -> Buckets:
    cube = np.floor(points / size).astype(np.int64)
    origin = cube.min(axis=0) - 1
    cube -= origin
    dims = cube.max(axis=0) + 2
    key = (cube[:, 0] * dims[1] + cube[:, 1]) * dims[2] + cube[:, 2]
    order = np.argsort(key, kind="stable")
    keys, starts = np.unique(key[order], return_index=True)
    return Buckets(origin, dims, float(size), keys, np.append(starts, len(key)).astype(np.int64), order)


@numba.njit(cache=True, parallel=True)
def _gather(targets, sources, values, keys, starts, table, origin, dims, size, inv_two_var, cutoff2, out):
    """out[t, k, :] = sum over sources within sqrt(cutoff2[k]) of exp(-d^2 inv_two_var[k]) values[j, :].

    ``sources`` and ``values`` are sorted by bucket (bucket b holds rows starts[b]:starts[b + 1]), so the inner loop
    reads memory in order; a neighbour bucket whose cube lies farther than the largest cut-off is skipped. ``table``
    (every cube's first row, dense, when the grid is small enough) replaces the binary search of ``keys``."""
    gaussians = inv_two_var.shape[0]
    width = values.shape[1]
    reach2 = cutoff2.max()
    for t in numba.prange(targets.shape[0]):
        px, py, pz = targets[t, 0], targets[t, 1], targets[t, 2]
        cx = int(math.floor(px / size)) - origin[0]
        cy = int(math.floor(py / size)) - origin[1]
        cz = int(math.floor(pz / size)) - origin[2]
        for ix in range(cx - 1, cx + 2):
            if ix < 0 or ix >= dims[0]:
                continue
            gx = max(0.0, max((ix + origin[0]) * size - px, px - (ix + origin[0] + 1) * size))
            for iy in range(cy - 1, cy + 2):
                if iy < 0 or iy >= dims[1]:
                    continue
                gy = max(0.0, max((iy + origin[1]) * size - py, py - (iy + origin[1] + 1) * size))
                for iz in range(cz - 1, cz + 2):
                    if iz < 0 or iz >= dims[2]:
                        continue
                    gz = max(0.0, max((iz + origin[2]) * size - pz, pz - (iz + origin[2] + 1) * size))
                    if gx * gx + gy * gy + gz * gz > reach2:
                        continue
                    key = (ix * dims[1] + iy) * dims[2] + iz
                    if table.shape[0] > 0:
                        first, last = table[key], table[key + 1]
                    else:
                        b = np.searchsorted(keys, key)
                        if b >= keys.shape[0] or keys[b] != key:
                            continue
                        first, last = starts[b], starts[b + 1]
                    for j in range(first, last):
                        dx = sources[j, 0] - px
                        dy = sources[j, 1] - py
                        dz = sources[j, 2] - pz
                        d2 = dx * dx + dy * dy + dz * dz
                        if d2 > reach2:
                            continue
                        for k in range(gaussians):
                            if d2 <= cutoff2[k]:
                                w = math.exp(-d2 * inv_two_var[k])
                                for c in range(width):
                                    out[t, k, c] += w * values[j, c]


def gather(targets: np.ndarray, sources: np.ndarray, values: np.ndarray, variances: np.ndarray,
           cutoff: float = CUTOFF_SIGMAS) -> np.ndarray:
    """(targets, gaussians, width) Gaussian-weighted sums of ``values`` (sources, width) over sources within
    ``cutoff`` sigmas of each target, one Gaussian per entry of ``variances``."""
    variances = np.asarray(variances, np.float64)
    radii = cutoff * np.sqrt(variances)
    buckets = bucket_points(sources, float(radii.max()))
    out = np.zeros((len(targets), len(variances), values.shape[1]))
    cubes = int(np.prod(buckets.dims))
    table = np.zeros(0, np.int64)
    if cubes <= DENSE_TABLE_LIMIT:  # each cube's first row: a lookup instead of a binary search
        counts = np.zeros(cubes + 1, np.int64)
        counts[buckets.keys + 1] = np.diff(buckets.starts)
        table = np.cumsum(counts)
    _gather(np.ascontiguousarray(targets, np.float64), np.ascontiguousarray(sources[buckets.order], np.float64),
            np.ascontiguousarray(values[buckets.order], np.float64), buckets.keys, buckets.starts, table,
            buckets.origin,
            buckets.dims, buckets.size, 0.5 / variances, radii * radii, out)
    return out


def _lattice_blur(positions: np.ndarray, weighted: np.ndarray, variance: float, cell: float,
                  cutoff: float) -> np.ndarray:
    """Sparse splat-gather-slice of ``weighted`` (texels, 4: a f, a) at one Gaussian; returns (texels, 4) sums."""
    scaled = positions / cell
    base = np.floor(scaled).astype(np.int64)
    frac = scaled - base
    origin = base.min(axis=0) - 1
    base -= origin
    dims = base.max(axis=0) + 3
    cell_key = (base[:, 0] * dims[1] + base[:, 1]) * dims[2] + base[:, 2]
    cells, texel_cell = np.unique(cell_key, return_inverse=True)
    texel_cell = texel_cell.reshape(-1)
    # splat: per occupied cell the summed values and the area-weighted centroid
    sums = np.zeros((len(cells), weighted.shape[1]))
    np.add.at(sums, texel_cell, weighted)
    centroid = np.zeros((len(cells), 3))
    np.add.at(centroid, texel_cell, positions * weighted[:, -1:])
    area = np.maximum(sums[:, -1:], 1e-300)
    centroid /= area
    # gather at the 8 corners of every occupied cell (lattice nodes at integer multiples of the cell)
    corners = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)], np.int64)
    cell_index = np.stack([cells // (dims[1] * dims[2]), (cells // dims[2]) % dims[1], cells % dims[2]], axis=1)
    corner_index = (cell_index[:, None, :] + corners[None, :, :]).reshape(-1, 3)
    corner_key = (corner_index[:, 0] * dims[1] + corner_index[:, 1]) * dims[2] + corner_index[:, 2]
    nodes, cell_corner = np.unique(corner_key, return_inverse=True)
    cell_corner = cell_corner.reshape(len(cells), 8)
    node_index = np.stack([nodes // (dims[1] * dims[2]), (nodes // dims[2]) % dims[1], nodes % dims[2]], axis=1)
    node_positions = (node_index + origin).astype(np.float64) * cell
    node_values = gather(node_positions, centroid, sums, np.array([variance]), cutoff)[:, 0, :]
    # slice: trilinear weights of each texel's 8 corners
    out = np.zeros_like(weighted)
    for c, (i, j, k) in enumerate(corners):
        w = ((frac[:, 0] if i else 1.0 - frac[:, 0]) * (frac[:, 1] if j else 1.0 - frac[:, 1])
             * (frac[:, 2] if k else 1.0 - frac[:, 2]))
        out += w[:, None] * node_values[cell_corner[texel_cell, c]]
    return out


def texel_spacing(areas: np.ndarray) -> float:
    """A typical distance between neighbouring texel centres: sqrt of the median texel area (mesh units)."""
    positive = areas[areas > 0]
    return float(np.sqrt(np.median(positive))) if len(positive) else 0.0


def surface_blur(positions: np.ndarray, areas: np.ndarray, vectors: np.ndarray, variances,
                 cell_fraction: float = 1.0, cutoff: float = CUTOFF_SIGMAS) -> np.ndarray:
    """Area-weighted Gaussian means of ``vectors`` (texels, c) on the surface, one per variance.

    Parameters
    ----------
    positions : (n, 3) texel surface points, mesh units.
    areas : (n,) surface area each texel stands for, mesh units^2.
    vectors : (n, c) values to blur (unit normals).
    variances : (k,) Gaussian variances, mesh units^2.
    cell_fraction : lattice cell size in sigmas for the Gaussians wider than DIRECT_SPACINGS texel spacings.
    cutoff : gather radius in sigmas.

    Returns
    -------
    (n, k, c) the blurred values (not renormalized).
    """
    variances = np.asarray(variances, np.float64)
    weighted = np.concatenate([vectors * areas[:, None], areas[:, None]], axis=1)
    sums = np.zeros((len(positions), len(variances), weighted.shape[1]))
    spacing = texel_spacing(areas)
    sigma = np.sqrt(variances)
    direct = sigma <= DIRECT_SPACINGS * spacing
    if direct.any():
        sums[:, direct] = gather(positions, positions, weighted, variances[direct], cutoff)
    for k in np.flatnonzero(~direct):
        cell = cell_fraction * sigma[k]
        sums[:, k] = _lattice_blur(positions, weighted, variances[k] - cell * cell / 4.0, cell, cutoff)
    return sums[..., :-1] / np.maximum(sums[..., -1:], 1e-300)
