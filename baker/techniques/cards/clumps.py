"""Clumps of a groom: strands grouped by the guide selection's k-medoids, each clump's representative curve and
the scalp normal under it (RTR4 14.7.1: a card follows a clump of hair).

The clustering is :func:`baker.techniques.hair.guide_solver.select_guides` (length-weighted k-medoids over a strand
descriptor of root-relative shape + ``locality`` x root position), so a clump holds strands that start close
together and run alike: the strands one card can show.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from baker.techniques.hair.guide_solver import select_guides


@dataclass
class Clumps:
    labels: np.ndarray  # (S,) clump number of every strand, 0..K-1
    curves: np.ndarray  # (K, V, 3) representative curve of each clump: its members' mean, vertex by vertex
    scalp_normals: np.ndarray  # (K, 3) unit normal of the root surface under each clump, pointing out of the scalp
    error_rms: float  # RMS over strand points of |point - representative|, relative to the strand's length
    error_max: float  # the largest such distance, relative to the strand's length

    @property
    def count(self) -> int:
        return len(self.curves)


def mean_curves(strands: np.ndarray, labels: np.ndarray, count: int) -> np.ndarray:
    """(K, V, 3): per clump the vertex-by-vertex mean of its strands (all resampled to V equal arc-length steps)."""
    s, v, _ = strands.shape
    flat = strands.reshape(s, -1)
    sums = np.zeros((count, flat.shape[1]))
    np.add.at(sums, labels, flat)
    members = np.bincount(labels, minlength=count).astype(np.float64)
    return (sums / members[:, None]).reshape(count, v, 3)


def root_surface_normals(roots: np.ndarray, growth: np.ndarray, at: np.ndarray, neighbours: int = 24):
    """Unit normals of the surface the roots lie on, at the points ``at`` (K, 3): the least-variance axis of the
    ``neighbours`` nearest roots (a plane fit), turned to agree with ``growth`` (K, 3: the way hair leaves the
    scalp there). Where the roots do not span a plane (a row of roots, a lone clump), ``growth`` itself."""
    k = min(neighbours, len(roots))
    _, near = cKDTree(roots).query(at, k=k)
    near = near.reshape(len(at), k)
    local = roots[near] - roots[near].mean(axis=1, keepdims=True)
    covariance = np.einsum("kni,knj->kij", local, local)
    values, vectors = np.linalg.eigh(covariance)
    normal = vectors[:, :, 0]
    planar = (k >= 3) & (values[:, 0] < 0.25 * values[:, 1]) & (values[:, 1] > 0)
    g = growth / np.maximum(np.linalg.norm(growth, axis=1, keepdims=True), 1e-300)
    normal = np.where((np.einsum("ki,ki->k", normal, g) < 0)[:, None], -normal, normal)
    return np.where(planar[:, None], normal, g)


def describe_clumps(strands: np.ndarray, lengths: np.ndarray, labels: np.ndarray) -> Clumps:
    """The :class:`Clumps` of strands (S, V, 3) grouped by ``labels`` (S,: 0..K-1, every number used)."""
    roots = strands[:, 0]
    k = int(labels.max()) + 1
    curves = mean_curves(strands, labels, k)
    growth = np.zeros((k, 3))
    np.add.at(growth, labels, strands[:, 1] - strands[:, 0])
    normals = root_surface_normals(roots, growth, curves[:, 0])
    distance = np.linalg.norm(strands - curves[labels], axis=2) / np.maximum(lengths, 1e-300)[:, None]
    return Clumps(labels, curves, normals, float(np.sqrt(np.mean(distance ** 2))), float(distance.max()))


def cluster_strands(strands: np.ndarray, lengths: np.ndarray, count: int, *, locality: float, seed: int,
                    iterations: int = 8) -> Clumps:
    """Group resampled strands (S, V, 3) into at most ``count`` clumps (fewer when strands coincide)."""
    roots = strands[:, 0]
    shapes = strands - roots[:, None]
    _, medoid = select_guides(shapes, roots, lengths, min(count, len(strands)), locality=locality,
                              iterations=iterations, seed=seed)
    _, labels = np.unique(medoid, return_inverse=True)  # clump numbers in the order of their medoid strands
    return describe_clumps(strands, lengths, labels.reshape(-1).astype(np.int64))


def split_by_depth(depth: np.ndarray, iterations: int = 8) -> np.ndarray | None:
    """Two groups of a clump's members whose offsets along the card normal (n, V: per member and station) one card
    cannot hold: 2-means on those depth profiles, started from the sign of their principal component (PCA of the
    members' offsets from the clump's mean curve, seen along the card normal). Returns a bool mask (n,) of the
    second group, or None when the members do not separate."""
    n = len(depth)
    if n < 2:
        return None
    centred = depth - depth.mean(axis=0)
    # the principal axis by power iteration on the (V, V) covariance, from the member farthest from the mean
    covariance = np.einsum("nv,nw->vw", centred, centred)
    axis = centred[int(np.argmax(np.einsum("nv,nv->n", centred, centred)))]
    for _ in range(24):
        axis = covariance @ axis
        axis = axis / max(float(np.sqrt(axis @ axis)), 1e-300)
    side = centred @ axis > 0
    for _ in range(iterations):
        if side.all() or not side.any():
            return None
        a, b = depth[~side].mean(axis=0), depth[side].mean(axis=0)
        new = ((depth - b) ** 2).sum(axis=1) < ((depth - a) ** 2).sum(axis=1)
        if np.array_equal(new, side):
            break
        side = new
    return None if side.all() or not side.any() else side
