"""Dense groom -> guide strands + 3-guide child weights + blue-noise LOD order (RTR4 14.7; TressFX; Unreal groom).

Every child is rebuilt from guides by the offset interpolation of ``BAKER_hair`` (``interpolation: "offset"``)::

    child(t) = childRoot + sum_i w_i (guide_i(t) - guideRoot_i),   w_i >= 0, sum_i w_i = 1

so the error of a child depends only on its root-relative shape ``D = strand - root`` against its guides' shapes.
Steps, each a function below:

1. :func:`resample_strands` - every curve to ``V`` vertices at equal arc-length steps, its length kept;
2. :func:`select_guides` - k-medoids (Kaufman & Rousseeuw; Voronoi iteration, Park & Jun 2009) over a strand
   descriptor (PCA of the shape + ``locality`` x root position), seeded by weighted k-means++ (Arthur &
   Vassilvitskii 2007); weights 1 / length^2 make the objective the *relative* error. For squared distances the
   medoid of a cluster is the member nearest its weighted mean, so each iteration is exact and cheap;
3. :func:`solve_weights` - per child, among its ``candidates`` nearest guide roots (locality: a child follows the
   guides that will move like it), the triple and simplex weights that minimise its own reconstruction error (a
   3-variable QP on the simplex solved in closed form: interior, else the best edge);
4. :func:`progressive_order` - children ordered so every LOD prefix is a blue-noise subset of the roots:
   nested weighted sample elimination (Yuksel 2015), coarsest level first.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numba
import numpy as np
from scipy.spatial import cKDTree


@dataclass
class GuideSolution:
    guides: np.ndarray  # (N,) strand indices chosen as guides, ascending
    ids: np.ndarray  # (S, 3) int64 guide numbers (indices into ``guides``) per strand
    weights: np.ndarray  # (S, 3) float64, >= 0, rows sum to 1
    stats: dict = field(default_factory=dict)


# ------------------------------------------------------------------------------------------------------ resampling
def resample_strands(points: np.ndarray, counts: np.ndarray, vertices: int, widths: np.ndarray | None = None):
    """Ragged polylines (``points`` (P, 3), ``counts`` (S,), each >= 2 with length > 0) -> (S, V, 3) at equal
    arc-length steps, root and tip kept (curves of ``vertices`` vertices are taken as they are). Every sample lies on the input curve, so the strand keeps its length up to
    the corners the new vertices cut (a tight curl sampled by too few vertices gets shorter; scaling it back would
    distort its shape). Returns (strands, input arc lengths (S,), widths (S, V) or None)."""
    counts = np.asarray(counts, np.int64)
    s = len(counts)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    curve = np.repeat(np.arange(s), counts)
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    seg[curve[1:] != curve[:-1]] = 0.0
    arc = np.concatenate([[0.0], np.cumsum(seg)])
    arc -= arc[starts][curve]
    lengths = arc[starts + counts - 1]
    # one monotone key over all curves: curve index * 2 + normalised arc in [0, 1]
    key = curve * 2.0 + arc / lengths[curve]
    t = np.linspace(0.0, 1.0, vertices)
    target = (np.arange(s)[:, None] * 2.0 + t[None, :]).reshape(-1)
    k = np.searchsorted(key, target, side="right") - 1
    lo = np.repeat(starts, vertices)
    hi = np.repeat(starts + counts - 2, vertices)
    k = np.clip(k, lo, hi)
    k0, k1 = key[k], key[k + 1]
    f = np.where(k1 > k0, (target - k0) / np.where(k1 > k0, k1 - k0, 1.0), 0.0)[:, None]
    out = (points[k] * (1.0 - f) + points[k + 1] * f).reshape(s, vertices, 3)
    # curves that already have ``vertices`` vertices are kept as they are: a written groom reads back unchanged
    # (equal arc-length steps of the source are not equal steps of the resampled polyline, so resampling again
    # would move them)
    same = counts == vertices
    if same.any():
        keep = np.repeat(same, counts)
        out[same] = points[keep].reshape(-1, vertices, 3)
    w = None
    if widths is not None:
        w = (widths[k] * (1.0 - f[:, 0]) + widths[k + 1] * f[:, 0]).reshape(s, vertices)
        if same.any():
            w[same] = widths[keep].reshape(-1, vertices)
    return out, lengths, w


# ------------------------------------------------------------------------------------------------ guide selection
@numba.njit(cache=True, nogil=True)
def _closer(desc, centre, mind):
    """mind[i] = min(mind[i], |desc[i] - desc[centre]|^2) for every strand (serial: called once per centre, a
    parallel region each time costs more than it saves on a busy machine)."""
    s, d = desc.shape
    for i in range(s):
        dist = 0.0
        for j in range(d):
            x = desc[i, j] - desc[centre, j]
            dist += x * x
        if dist < mind[i]:
            mind[i] = dist


@numba.njit(cache=True, nogil=True)
def _kmeans_plus_plus(desc, weight, count, uniforms):
    """Weighted k-means++ seeding: each next centre drawn with probability ~ weight x squared distance to the
    nearest centre so far (``uniforms``: count values in [0, 1))."""
    s, d = desc.shape
    mind = np.full(s, np.inf)
    chosen = np.empty(count, np.int64)
    total = 0.0
    for i in range(s):
        total += weight[i]
    cur = 0
    acc = 0.0
    target = uniforms[0] * total
    for i in range(s):
        acc += weight[i]
        if acc > target:
            cur = i
            break
    for c in range(count):
        chosen[c] = cur
        _closer(desc, cur, mind)
        if c + 1 == count:
            break
        total = 0.0
        for i in range(s):
            total += weight[i] * mind[i]
        if total <= 0.0:  # every strand coincides with a centre: take the first not yet chosen
            for i in range(s):
                taken = False
                for q in range(c + 1):
                    if chosen[q] == i:
                        taken = True
                        break
                if not taken:
                    cur = i
                    break
            continue
        target = uniforms[c + 1] * total
        acc = 0.0
        cur = s - 1
        for i in range(s):
            acc += weight[i] * mind[i]
            if acc > target and mind[i] > 0.0:
                cur = i
                break
    return chosen


@numba.njit(cache=True, nogil=True, parallel=True)
def _assign(desc, centres, candidates, current):
    """Each strand's nearest centre (descriptor distance) among its candidate centres and its current one."""
    s, k = candidates.shape
    d = desc.shape[1]
    label = np.empty(s, np.int64)
    cost = np.empty(s)
    for i in numba.prange(s):
        best, best_c = np.inf, -1
        for q in range(k + 1):
            c = current[i] if q == k else candidates[i, q]
            if c < 0:
                continue
            g = centres[c]
            dist = 0.0
            for j in range(d):
                x = desc[i, j] - desc[g, j]
                dist += x * x
            if dist < best or (dist == best and c < best_c):
                best, best_c = dist, c
        label[i] = best_c
        cost[i] = best
    return label, cost


def strand_descriptors(shapes: np.ndarray, roots: np.ndarray, locality: float, dims: int = 24,
                       sample: int = 8000, rng: np.random.Generator | None = None) -> np.ndarray:
    """(S, dims + 3) descriptors: the shape offsets projected on their first principal axes (fitted on a subsample),
    then ``locality x sqrt(V)`` times the root, so the squared descriptor distance is about
    ||D_a - D_b||^2 + locality^2 V ||root_a - root_b||^2 (both summed over the V vertices)."""
    s = len(shapes)
    flat = shapes.reshape(s, -1)
    pick = np.arange(s) if s <= sample else np.sort((rng or np.random.default_rng(0)).choice(s, sample, replace=False))
    mean = flat[pick].mean(axis=0)
    centred = flat[pick] - mean
    # principal axes from the (3V x 3V) covariance: far cheaper than an SVD of the samples
    values, vectors = np.linalg.eigh(centred.T @ centred)
    basis = vectors[:, ::-1].T[: min(dims, len(values))]
    # fix the sign of each axis (SVD's is arbitrary across LAPACK builds): largest component positive
    basis = basis * np.sign(basis[np.arange(len(basis)), np.abs(basis).argmax(axis=1)])[:, None]
    proj = (flat - mean) @ basis.T
    v = shapes.shape[1]
    return np.ascontiguousarray(np.concatenate([proj, roots * (locality * math.sqrt(v))], axis=1))


def select_guides(shapes: np.ndarray, roots: np.ndarray, lengths: np.ndarray, count: int, *, locality: float,
                  iterations: int, seed: int, neighbours: int = 16) -> tuple[np.ndarray, np.ndarray]:
    """``count`` strand indices (ascending) minimising the length-weighted k-medoids cost; returns (guides, labels)."""
    s = len(shapes)
    if count >= s:
        return np.arange(s), np.arange(s)
    rng = np.random.default_rng(seed)
    desc = strand_descriptors(shapes, roots, locality, rng=rng)
    weight = 1.0 / np.maximum(lengths, 1e-300) ** 2
    weight = weight / weight.mean()
    # seeding on a subsample (a few strands per guide): the Voronoi iterations below then work on every strand
    seed_pool = np.arange(s) if s <= max(8 * count, 10000) else np.sort(rng.choice(s, max(8 * count, 10000),
                                                                                  replace=False))
    centres = seed_pool[_kmeans_plus_plus(np.ascontiguousarray(desc[seed_pool]), weight[seed_pool], count,
                                          rng.random(count))]
    label = np.full(s, -1, np.int64)
    k = min(neighbours, count)
    for _ in range(max(iterations, 1)):
        _, cand = cKDTree(roots[centres]).query(roots, k=k)
        cand = cand.reshape(s, k).astype(np.int64)
        label, _ = _assign(desc, centres, cand, label)
        # Voronoi iteration: the new medoid of each cluster is its member nearest the weighted mean
        sums = np.stack([np.bincount(label, weights=desc[:, j] * weight, minlength=count)
                         for j in range(desc.shape[1])], axis=1)
        mass = np.bincount(label, weights=weight, minlength=count)
        means = sums / np.maximum(mass, 1e-300)[:, None]
        gap = ((desc - means[label]) ** 2).sum(axis=1)
        order = np.lexsort((np.arange(s), gap, label))
        first = np.ones(s, bool)
        first[1:] = label[order][1:] != label[order][:-1]
        best = order[first]
        new = centres.copy()
        new[label[best]] = best
        if np.array_equal(new, centres):
            break
        centres = new
    guides = np.sort(np.unique(centres))
    return guides, label


# -------------------------------------------------------------------------------------------------- child weights
@numba.njit(cache=True, nogil=True, inline="always")
def _segment_min(rr, re, ee):
    """min over t in [0, 1] of |r - t e|^2 -> (error, t)."""
    t = 0.0
    if ee > 0.0:
        t = min(max(re / ee, 0.0), 1.0)
    return rr - 2.0 * t * re + t * t * ee, t


@numba.njit(cache=True, nogil=True, parallel=True)
def _solve_triples(shapes, guides, candidates):
    """Per strand: the best triple of candidate guides and its simplex weights (closed-form 3-variable QP)."""
    s, k = candidates.shape
    d = shapes.shape[1]
    ids = np.zeros((s, 3), np.int64)
    weights = np.zeros((s, 3))
    errors = np.zeros(s)
    for i in numba.prange(s):
        gram = np.empty((k, k))
        b = np.empty(k)
        c0 = 0.0
        for x in range(d):
            c0 += shapes[i, x] * shapes[i, x]
        for p in range(k):
            gp = guides[candidates[i, p]]
            acc = 0.0
            for x in range(d):
                acc += shapes[i, x] * shapes[gp, x]
            b[p] = acc
            for q in range(p + 1):
                gq = guides[candidates[i, q]]
                acc = 0.0
                for x in range(d):
                    acc += shapes[gp, x] * shapes[gq, x]
                gram[p, q] = acc
                gram[q, p] = acc
        best = np.inf
        bi0, bi1, bi2 = 0, 0, 0
        bw0, bw1, bw2 = 1.0, 0.0, 0.0
        for a in range(k):
            # single guide a
            err = c0 - 2.0 * b[a] + gram[a, a]
            if err < best:
                best = err
                bi0, bi1, bi2 = a, a, a
                bw0, bw1, bw2 = 1.0, 0.0, 0.0
            for bb in range(a + 1, k):
                for cc in range(bb + 1, k):
                    # w = (1 - u - v, u, v): residual r - u e1 - v e2 with r = D - Da, e1 = Db - Da, e2 = Dc - Da
                    rr = c0 - 2.0 * b[a] + gram[a, a]
                    re1 = b[bb] - b[a] - gram[a, bb] + gram[a, a]
                    re2 = b[cc] - b[a] - gram[a, cc] + gram[a, a]
                    e11 = gram[bb, bb] - 2.0 * gram[a, bb] + gram[a, a]
                    e22 = gram[cc, cc] - 2.0 * gram[a, cc] + gram[a, a]
                    e12 = gram[bb, cc] - gram[a, bb] - gram[a, cc] + gram[a, a]
                    det = e11 * e22 - e12 * e12
                    done = False
                    if det > 1e-12 * max(e11 * e22, 1e-300):
                        u = (re1 * e22 - re2 * e12) / det
                        v = (re2 * e11 - re1 * e12) / det
                        if u >= 0.0 and v >= 0.0 and u + v <= 1.0:
                            err = rr - u * re1 - v * re2
                            done = True
                            if err < best:
                                best = err
                                bi0, bi1, bi2 = a, bb, cc
                                bw0, bw1, bw2 = 1.0 - u - v, u, v
                    if not done:
                        # the minimum lies on an edge of the simplex (convex problem)
                        err, t = _segment_min(rr, re1, e11)
                        if err < best:
                            best = err
                            bi0, bi1, bi2 = a, bb, cc
                            bw0, bw1, bw2 = 1.0 - t, t, 0.0
                        err, t = _segment_min(rr, re2, e22)
                        if err < best:
                            best = err
                            bi0, bi1, bi2 = a, bb, cc
                            bw0, bw1, bw2 = 1.0 - t, 0.0, t
                        err, t = _segment_min(rr - 2.0 * re1 + e11, re2 - re1 - e12 + e11, e22 - 2.0 * e12 + e11)
                        if err < best:
                            best = err
                            bi0, bi1, bi2 = a, bb, cc
                            bw0, bw1, bw2 = 0.0, 1.0 - t, t
        ids[i, 0] = candidates[i, bi0]
        ids[i, 1] = candidates[i, bi1]
        ids[i, 2] = candidates[i, bi2]
        weights[i, 0] = bw0
        weights[i, 1] = bw1
        weights[i, 2] = bw2
        errors[i] = max(best, 0.0)
    return ids, weights, errors


def solve_weights(shapes: np.ndarray, roots: np.ndarray, guides: np.ndarray, candidates: int,
                  labels: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Per strand the 3 guide numbers and weights (>= 0, sum 1) minimising ||D - sum w_i D_gi||^2 among its
    ``candidates`` nearest guide roots (plus the guide of its k-medoids cluster, ``labels``). Unused slots repeat
    the first guide with weight 0; weights are renormalised in float64."""
    s = len(shapes)
    n = len(guides)
    k = min(candidates, n)
    _, cand = cKDTree(roots[guides]).query(roots, k=k)
    cand = cand.reshape(s, k).astype(np.int64)
    if labels is not None and n > k:
        number = np.searchsorted(guides, labels)
        valid = (number < n) & (guides[np.minimum(number, n - 1)] == labels)
        missing = valid & ~(cand == number[:, None]).any(axis=1)
        cand[missing, -1] = number[missing]
    flat = np.ascontiguousarray(shapes.reshape(s, -1))
    ids, weights, _ = _solve_triples(flat, guides.astype(np.int64), cand)
    # a repeated slot (single guide or an edge) carries weight 0: point it at the first guide for clarity
    weights = np.clip(weights, 0.0, None)
    weights /= weights.sum(axis=1, keepdims=True)
    return ids, weights


def reconstruct(guide_strands: np.ndarray, roots: np.ndarray, ids: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """``child(t) = root + sum_i w_i (guide_i(t) - guide_i(0))`` for every child: (S, V, 3)."""
    shapes = guide_strands - guide_strands[:, :1]
    out = np.repeat(roots[:, None, :].astype(np.float64), guide_strands.shape[1], axis=1)
    for i in range(ids.shape[1]):
        out += weights[:, i, None, None] * shapes[ids[:, i]]
    return out


@numba.njit(cache=True, nogil=True, parallel=True)
def _offset_errors(strands, guides, ids, weights):
    """Per strand: the sum over vertices of the squared distance to its offset reconstruction from the guide
    strands ``strands[guides]``, and the largest vertex distance (no (S, V, 3) temporaries)."""
    s, v, _ = strands.shape
    sum_sq = np.zeros(s)
    worst = np.zeros(s)
    for i in numba.prange(s):
        acc, top = 0.0, 0.0
        for t in range(v):
            d2 = 0.0
            for c in range(3):
                x = strands[i, 0, c]
                for k in range(3):
                    g = guides[ids[i, k]]
                    x += weights[i, k] * (strands[g, t, c] - strands[g, 0, c])
                e = strands[i, t, c] - x
                d2 += e * e
            acc += d2
            top = max(top, d2)
        sum_sq[i] = acc
        worst[i] = math.sqrt(top)
    return sum_sq, worst


def offset_errors(strands: np.ndarray, guides: np.ndarray, ids: np.ndarray, weights: np.ndarray, lengths):
    """(per-strand RMS over its vertices, per-strand max) of the offset reconstruction error relative to length."""
    sum_sq, worst = _offset_errors(np.ascontiguousarray(strands, np.float64), guides.astype(np.int64),
                                   np.ascontiguousarray(ids, np.int64), np.ascontiguousarray(weights, np.float64))
    length = np.maximum(lengths, 1e-300)
    return np.sqrt(sum_sq / strands.shape[1]) / length, worst / length


def reconstruction_error(strands: np.ndarray, rebuilt: np.ndarray, lengths: np.ndarray) -> dict:
    """RMS and max of the per-vertex distance between strands and their reconstruction, relative to the strand's
    length (so 0.01 = 1 % of the strand's length)."""
    rel = np.linalg.norm(strands - rebuilt, axis=2) / np.maximum(lengths, 1e-300)[:, None]
    return {"rms": float(np.sqrt(np.mean(rel ** 2))), "max": float(rel.max())}


# ---------------------------------------------------------------------------------------------------------- LODs
def lod_counts(strands: int, lods: int, minimum: int = 16) -> list[int]:
    """Strand counts of the LODs: all, then about half at each level, never below ``minimum`` (or 1)."""
    counts = [strands]
    while len(counts) < lods and counts[-1] // 2 >= min(minimum, strands):
        counts.append((counts[-1] + 1) // 2)
    return counts


def progressive_order(roots: np.ndarray, counts: list[int], seed: int) -> np.ndarray:
    """A permutation of the strands whose first ``counts[k]`` form, for every k, a blue-noise subset of the roots:
    nested weighted sample elimination (Yuksel 2015) from each level to the next; inside a level the strands it adds
    come in a seeded random order."""
    from baker.techniques.hair.kernel import eliminate_samples

    s = len(roots)
    rng = np.random.default_rng(seed)
    if s < 2:
        return np.arange(s)
    # surface area from the local density: 8 neighbours in a disc of radius r8
    dist, _ = cKDTree(roots).query(roots, k=min(9, s))
    r8 = float(np.median(dist[:, -1]))
    area = s * math.pi * r8 * r8 / max(dist.shape[1] - 1, 1)
    alive = np.arange(s)
    levels = []
    for keep in counts[1:]:
        if area <= 0:
            kept = alive[:keep]
        else:
            rmax = math.sqrt(area / (2.0 * math.sqrt(3.0) * keep))
            kept = alive[eliminate_samples(roots[alive], keep, rmax)]
        levels.append(np.setdiff1d(alive, kept, assume_unique=True))
        alive = kept
    levels.append(alive)
    return np.concatenate([rng.permutation(level) for level in reversed(levels)])


# ---------------------------------------------------------------------------------------------------------- driver
def worst_first(errors: np.ndarray, roots: np.ndarray, exclude: np.ndarray, count: int, radius: float) -> np.ndarray:
    """Up to ``count`` strands in order of decreasing error, none in ``exclude`` and no two whose roots are closer
    than ``radius`` (so one bad region does not take the whole budget)."""
    order = np.argsort(-errors, kind="stable")
    taken = np.zeros(len(errors), bool)
    taken[exclude] = True
    tree = cKDTree(roots)
    picked = []
    for i in order[: 50 * max(count, 1)].tolist():
        if len(picked) == count or errors[i] <= 0:
            break
        if taken[i]:
            continue
        picked.append(i)
        taken[tree.query_ball_point(roots[i], radius)] = True
    return np.asarray(picked, np.int64)


def solve_guides(strands: np.ndarray, lengths: np.ndarray, count: int, *, candidates: int = 10,
                 locality: float = 0.5, iterations: int = 8, seed: int = 0, tail: float = 0.1,
                 tail_rounds: int = 2) -> GuideSolution:
    """Guides and 3-guide weights for resampled strands (S, V, 3); the stats hold the relative errors.

    k-medoids picks ``(1 - tail) x count`` guides (the bulk of the error); the rest go, over ``tail_rounds``
    rounds, to the worst reconstructed strands (spread apart), which lowers the maximum error where the medoid
    objective (a sum) does not look; weights are solved again after each round."""
    roots = strands[:, 0]
    shapes = strands - roots[:, None]
    count = min(count, len(strands))
    extra = int(round(tail * count)) if count >= 20 else 0
    guides, labels = select_guides(shapes, roots, lengths, count - extra, locality=locality,
                                   iterations=iterations, seed=seed)
    ids, weights = solve_weights(shapes, roots, guides, candidates, labels)
    for r in range(tail_rounds if extra else 0):
        rel, _ = offset_errors(strands, guides, ids, weights, lengths)
        spacing = float(np.median(cKDTree(roots[guides]).query(roots[guides], k=2)[0][:, 1]))
        add = worst_first(rel, roots, guides, (count - len(guides)) // (tail_rounds - r), spacing)
        if not len(add):
            break
        guides = np.sort(np.concatenate([guides, add]))
        labels = labels.copy()
        labels[add] = add
        ids, weights = solve_weights(shapes, roots, guides, candidates, labels)
    rms, worst = offset_errors(strands, guides, ids, weights, lengths)
    stats = {"rmsError": float(np.sqrt(np.mean(rms ** 2))), "maxError": float(worst.max())}
    return GuideSolution(guides, ids, weights, stats)
