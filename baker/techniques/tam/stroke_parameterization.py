"""A stroke parameterization for hatching: lapped patches whose u axis follows a cross field (RTR4 15.3; issue 38
step 2).

Praun, Webb, Finkelstein & Hoppe's real-time hatching (SIGGRAPH 2001) applies the tonal art map through the
*lapped texture* parameterization of Praun, Finkelstein & Hoppe ("Lapped Textures", SIGGRAPH 2000): patches are
grown over the surface from seed faces while they stay nearly flat, and each patch is parameterized so that the
texture's axes follow a tangent direction field at a uniform texture scale (their section 4, "aligning the
texture to the field"). Here every face ends up in exactly one patch (no overlapping, alpha-blended patch edges:
the TAM's strokes tile, so a cut between patches is enough):

1. the field: the cross field of ``baker.geometry.direction_field.cross_field`` (Knöppel et al. 2013), carried
   from each vertex into each face by the minimal rotation of the vertex normal onto the face normal and averaged
   there as a 4-RoSy value exp(4 i theta);
2. growing: seeds are taken in order of the field's confidence (away from singularities first); a patch grows
   across manifold edges, nearest faces first (Dijkstra over centroid distances), while a face's normal stays
   within a cone around the seed's, the field turns little across the edge, and the face's choice among the
   cross's four directions (the one that continues its neighbour's, a period jump per edge) agrees with every
   neighbour already in the patch; so inside a patch the chosen directions form one smooth vector field;
3. parameterizing: per patch, the least-squares (Poisson) problem min sum_f A_f |grad u - s a_f|^2 + |grad v -
   s b_f|^2, a_f the chosen direction, b_f = n_f x a_f, s the scale (texture repeats per mesh unit), one vertex
   pinned per patch; all patches are one block-diagonal sparse solve;
4. checking: a face whose chart is flipped, whose area scale leaves [1/band, band] of s^2, or whose u axis strays
   from its field direction by more than ``max_stray`` degrees leaves its patch and goes back into the pool, from
   which the next round grows new patches (the rest of its patch keeps its solved, valid coordinates). Rounds
   repeat until every face has a chart; a face left after the last round is its own patch, whose chart is exact
   (its gradients are the targets), so no face ends flipped and every face's area scale is within the band;
5. attaching: a face that ended as a patch of its own joins a neighbouring patch when a chart continuing that
   patch's coordinates across their shared edge passes the same check (on the bunny: single-face patches, whose
   strokes break at every edge, 3.2% -> 0.5% of the faces; half as many patches).

The vertices are split at patch borders: new vertex k copies old vertex ``vertex_map[k]``. A degenerate face (zero
area, or a repeated vertex) gets a tiny positive-area chart of its own; an edge shared by more than two faces, or by
two faces wound the same way, is a cut no patch grows across. Both count as faces that fell back. The result is
deterministic: no randomness, ties broken by face index.
"""
from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from baker.geometry.direction_field import ROSY

QUARTER = np.pi / 2


@dataclass
class StrokeParameterization:
    """A texture-coordinate set for a welded mesh, split at patch borders."""

    vertex_map: np.ndarray  # (m,) new vertex k copies old vertex vertex_map[k]
    faces: np.ndarray  # (f, 3) the input's faces, in order, on the new vertices
    uv: np.ndarray  # (m, 2) texture coordinates, ``scale`` repeats per mesh unit; may leave [0, 1] (tiled)
    patch: np.ndarray  # (f,) the patch (chart) of each face
    fallback: np.ndarray  # (f,) faces that are degenerate or touch a non-manifold edge
    stroke_direction: np.ndarray  # (f, 3) the chart's u axis on the surface: where the strokes run
    rounds: int  # growing rounds it took

    @property
    def faces_per_patch(self) -> np.ndarray:
        """(p,) how many faces each patch holds."""
        return np.bincount(self.patch)

    @property
    def fallback_count(self) -> int:
        return int(self.fallback.sum())


def rotate_onto(vectors: np.ndarray, source: np.ndarray, target: np.ndarray) -> np.ndarray:
    """``vectors`` turned by the minimal rotation taking unit ``source`` onto unit ``target`` (row by row); where
    the two are opposite (no unique rotation) the vectors are projected onto the target's plane instead."""
    axis = np.cross(source, target)
    sin = np.linalg.norm(axis, axis=1)
    cos = np.einsum("ij,ij->i", source, target)
    k = np.divide(axis, sin[:, None], out=np.zeros_like(axis), where=sin[:, None] > 1e-12)
    rotated = (vectors * cos[:, None] + np.cross(k, vectors) * sin[:, None]
               + k * np.einsum("ij,ij->i", k, vectors)[:, None] * (1.0 - cos)[:, None])
    opposite = cos < -0.999
    rotated[opposite] = vectors[opposite] - target[opposite] * np.einsum(
        "ij,ij->i", vectors[opposite], target[opposite])[:, None]
    return rotated


def face_frames(positions: np.ndarray, faces: np.ndarray):
    """Per face: unit normal (from the winding), twice the area, and an in-plane frame (t1 along edge 01, t2 = n x
    t1); zero-area faces get zero vectors."""
    tri = positions[faces]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    double_area = np.linalg.norm(cross, axis=1)
    normal = np.divide(cross, double_area[:, None], out=np.zeros_like(cross), where=double_area[:, None] > 0)
    edge = tri[:, 1] - tri[:, 0]
    length = np.linalg.norm(edge, axis=1)
    t1 = np.divide(edge, length[:, None], out=np.zeros_like(edge), where=length[:, None] > 0)
    return normal, double_area, t1, np.cross(normal, t1)


def face_field(faces, normals, directions, face_normal, t1, t2):
    """(theta, confidence) per face: the cross field's angle in the face frame (one of the four) and |mean of
    exp(4 i theta)| over the corners, near 0 where the corners disagree (a singularity)."""
    total = np.zeros(len(faces), complex)
    for corner in range(3):
        v = faces[:, corner]
        carried = rotate_onto(directions[v], normals[v], face_normal)
        total += np.exp(1j * ROSY * np.arctan2(np.einsum("ij,ij->i", carried, t2),
                                               np.einsum("ij,ij->i", carried, t1)))
    total /= 3.0
    return np.angle(total) / ROSY, np.abs(total)


def wrap(angle: np.ndarray) -> np.ndarray:
    """Angles wrapped into [-pi, pi)."""
    return (angle + np.pi) % (2 * np.pi) - np.pi


def face_adjacency(faces: np.ndarray, usable: np.ndarray):
    """Pairs of usable faces across manifold edges: (f, g, shared vertex a, shared vertex b), each pair once per
    direction, and a per-face mask of faces on a cut (an edge of more than two faces, or two faces wound alike)."""
    f_idx = np.repeat(np.arange(len(faces)), 3)
    start = faces.reshape(-1)
    end = faces[:, [1, 2, 0]].reshape(-1)
    keep = usable[f_idx] & (start != end)
    f_idx, start, end = f_idx[keep], start[keep], end[keep]
    lo, hi = np.minimum(start, end), np.maximum(start, end)
    order = np.lexsort((f_idx, hi, lo))
    f_idx, start, end, lo, hi = f_idx[order], start[order], end[order], lo[order], hi[order]
    new_edge = np.ones(len(lo), bool)
    new_edge[1:] = (lo[1:] != lo[:-1]) | (hi[1:] != hi[:-1])
    edge_id = np.cumsum(new_edge) - 1
    count = np.bincount(edge_id)
    first = np.nonzero(new_edge)[0]
    pair = count[edge_id] == 2
    a = first[edge_id[pair & new_edge]]  # the first half-edge of each two-face edge
    b = a + 1
    opposite = start[a] == end[b]
    a, b = a[opposite], b[opposite]
    cut = np.zeros(len(faces), bool)
    bad_edge = (count > 2)[edge_id] | (pair & ~np.isin(edge_id, edge_id[a]))
    cut[f_idx[bad_edge]] = True
    fa, fb = f_idx[a], f_idx[b]
    pairs = np.stack([np.concatenate([fa, fb]), np.concatenate([fb, fa]),
                      np.concatenate([start[a], start[a]]), np.concatenate([end[a], end[a]])], axis=1)
    return pairs, cut


def period_jumps(pairs, theta, face_normal, t1, t2):
    """Per directed pair (f, g): the quarter turns k so that direction c of f continues as direction c + k of g,
    and the angle the field turns across the edge beyond them (radians)."""
    f, g = pairs[:, 0], pairs[:, 1]
    direction_f = np.cos(theta[f])[:, None] * t1[f] + np.sin(theta[f])[:, None] * t2[f]
    # unfolding across the shared edge is the minimal rotation of one face normal onto the other
    carried = rotate_onto(direction_f, face_normal[f], face_normal[g])
    angle = np.arctan2(np.einsum("ij,ij->i", carried, t2[g]), np.einsum("ij,ij->i", carried, t1[g]))
    difference = wrap(angle - theta[g])
    k = np.rint(difference / QUARTER)
    return (k.astype(np.int64) % 4), np.abs(difference - k * QUARTER)


@numba.njit(cache=True, nogil=True, inline="always")
def _before(d1, f1, d2, f2):
    """Heap order: nearest first, ties by face index."""
    return d1 < d2 or (d1 == d2 and f1 < f2)


@numba.njit(cache=True, nogil=True)
def _grow(pool, seeds, first, neighbour, jump, turn, step, normal, cone_cos, max_turn, patch, choice):
    """The growing loop of :func:`grow_patches`; ``first``/``neighbour``/``jump``/``turn``/``step`` are the face
    adjacency in CSR form. Fills ``patch`` and ``choice``; returns the number of patches."""
    heap_distance = np.empty(len(pool) + 1)
    heap_face = np.empty(len(pool) + 1, np.int64)
    count = 0
    for seed in seeds:
        if not pool[seed] or patch[seed] >= 0:
            continue
        pid = count
        count += 1
        patch[seed] = pid
        size = 1
        heap_distance[0], heap_face[0] = 0.0, seed
        while size:
            distance, f = heap_distance[0], heap_face[0]
            size -= 1
            if size:  # the last element sifts down from the root
                d, g = heap_distance[size], heap_face[size]
                i = 0
                while True:
                    child = 2 * i + 1
                    if child >= size:
                        break
                    if child + 1 < size and _before(heap_distance[child + 1], heap_face[child + 1],
                                                    heap_distance[child], heap_face[child]):
                        child += 1
                    if not _before(heap_distance[child], heap_face[child], d, g):
                        break
                    heap_distance[i], heap_face[i] = heap_distance[child], heap_face[child]
                    i = child
                heap_distance[i], heap_face[i] = d, g
            for e in range(first[f], first[f + 1]):
                g = neighbour[e]
                if patch[g] >= 0 or not pool[g] or turn[e] > max_turn:
                    continue
                if (normal[g, 0] * normal[seed, 0] + normal[g, 1] * normal[seed, 1]
                        + normal[g, 2] * normal[seed, 2]) < cone_cos:
                    continue
                c = (choice[f] + jump[e]) % 4
                agrees = True
                for e_g in range(first[g], first[g + 1]):
                    # (h, k_gh): h continues g's c as c + k_gh, so g's c = h's - k_gh
                    h = neighbour[e_g]
                    if patch[h] == pid and ((choice[h] - jump[e_g]) % 4 != c or turn[e_g] > max_turn):
                        agrees = False
                        break
                if not agrees:
                    continue
                patch[g] = pid
                choice[g] = c
                # push (distance + step, g): sift up
                d = distance + step[e]
                i = size
                size += 1
                while i > 0:
                    parent = (i - 1) // 2
                    if not _before(d, g, heap_distance[parent], heap_face[parent]):
                        break
                    heap_distance[i], heap_face[i] = heap_distance[parent], heap_face[parent]
                    i = parent
                heap_distance[i], heap_face[i] = d, g
    return count


@numba.njit(cache=True, nogil=True)
def _absorb_small_patches(patch, choice, count, first, neighbour, jump, turn, max_turn, small, passes):
    """See :func:`grow_patches`: a face of a patch of fewer than ``small`` faces joins a neighbouring larger patch
    whose field it continues consistently; then the ids are renumbered densely in order of first face."""
    size = np.zeros(max(count, 1), np.int64)
    for f in range(len(patch)):
        if patch[f] >= 0:
            size[patch[f]] += 1
    for _ in range(passes):
        moved = False
        for f in range(len(patch)):
            p = patch[f]
            if p < 0 or size[p] >= small:
                continue
            for e in range(first[f], first[f + 1]):
                g = neighbour[e]
                q = patch[g]
                if q < 0 or q == p or size[q] < small or turn[e] > max_turn:
                    continue
                c = (choice[g] - jump[e]) % 4
                consistent = True
                for e_f in range(first[f], first[f + 1]):
                    h = neighbour[e_f]
                    if patch[h] == q and ((choice[h] - jump[e_f]) % 4 != c or turn[e_f] > max_turn):
                        consistent = False
                        break
                if consistent:
                    size[p] -= 1
                    size[q] += 1
                    patch[f], choice[f] = q, c
                    moved = True
                    break
        if not moved:
            break
    remap = np.full(max(count, 1), -1, np.int64)
    used = 0
    for f in range(len(patch)):
        if patch[f] >= 0:
            if remap[patch[f]] < 0:
                remap[patch[f]] = used
                used += 1
            patch[f] = remap[patch[f]]


def grow_patches(pool, seeds, adjacency, face_normal, cone_cos, max_turn, small=4, passes=4):
    """Lapped patches over the ``pool`` faces (Praun et al. 2000, section 3): each seed not yet taken starts a
    patch that grows nearest-first (Dijkstra over centroid steps, ties by face index) while the conditions of the
    module docstring hold. ``adjacency``: (first, neighbour, jump, turn, step), the directed face pairs of
    :func:`face_adjacency` grouped by their first face. Greedy growth leaves slivers between patches whose cones
    closed on them; afterwards a face of a patch of fewer than ``small`` faces joins a neighbouring larger patch
    whose field it continues consistently (the cone is waived: the solve and its check still decide whether it
    keeps the face), ``passes`` times in face order. Returns (patch id per face, -1 outside the pool, numbered in
    order of first face; chosen quarter turn per face)."""
    first, neighbour, jump, turn, step = adjacency
    n = len(pool)
    patch = np.full(n, -1, np.int64)
    choice = np.zeros(n, np.int64)
    count = _grow(np.ascontiguousarray(pool, np.bool_), np.ascontiguousarray(seeds, np.int64), first, neighbour,
                  jump, turn, step, np.ascontiguousarray(face_normal, np.float64), float(cone_cos), float(max_turn),
                  patch, choice)
    _absorb_small_patches(patch, choice, count, first, neighbour, jump, turn, float(max_turn), int(small),
                          int(passes))
    return patch, choice


def adjacency_arrays(pairs, jump, turn, step, n_faces: int):
    """The directed face pairs as CSR arrays grouped by their first face, each face's pairs in ``pairs`` order."""
    order = np.argsort(pairs[:, 0], kind="stable")
    first = np.zeros(n_faces + 1, np.int64)
    np.cumsum(np.bincount(pairs[:, 0], minlength=n_faces), out=first[1:])
    return (first, np.ascontiguousarray(pairs[order, 1], np.int64), np.ascontiguousarray(jump[order], np.int64),
            np.ascontiguousarray(turn[order], np.float64), np.ascontiguousarray(step[order], np.float64))


def split_components(patch: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """Relabel ``patch`` (-1: none) so that each label is one edge-connected set of faces, numbered by its lowest
    face."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    n = len(patch)
    same = (patch[pairs[:, 0]] == patch[pairs[:, 1]]) & (patch[pairs[:, 0]] >= 0)
    graph = coo_matrix((np.ones(int(same.sum())), (pairs[same, 0], pairs[same, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    label = np.where(patch >= 0, label, -1)
    members = np.nonzero(label >= 0)[0]
    _, first_index, inverse = np.unique(label[members], return_index=True, return_inverse=True)
    rank = np.argsort(np.argsort(members[first_index], kind="stable"), kind="stable")
    out = np.full(n, -1, np.int64)
    out[members] = rank[inverse]
    return out


def local_coordinates(positions, faces, t1, t2):
    """(f, 3, 2) each face's corners in its own frame, corner 0 at the origin."""
    tri = positions[faces] - positions[faces][:, :1]
    return np.stack([np.einsum("fkj,fj->fk", tri, t1), np.einsum("fkj,fj->fk", tri, t2)], axis=-1)


def gradient_rows(local: np.ndarray, double_area: np.ndarray) -> np.ndarray:
    """(f, 3, 2): the gradient (in the face frame) of the hat function of each corner: the opposite edge turned by
    +90 degrees over twice the area (the faces are counter-clockwise in their own frame)."""
    opposite = np.roll(local, -2, axis=1) - np.roll(local, -1, axis=1)  # corner k: edge (k+1) -> (k+2)
    return np.stack([-opposite[..., 1], opposite[..., 0]], axis=-1) / double_area[:, None, None]


def solve_patches(patch, faces, local, gradients, double_area, target_u, target_v):
    """Per-patch least-squares coordinates for the faces with patch >= 0: returns (f, 3, 2) corner coordinates."""
    import scipy.sparse as sp
    from scipy.sparse.linalg import splu

    members = np.nonzero(patch >= 0)[0]
    corner_uv = np.zeros((len(faces), 3, 2))
    if not len(members):
        return corner_uv
    n_old = int(faces.max()) + 1
    keys = patch[members][:, None] * n_old + faces[members]
    unique_keys, new_vertex = np.unique(keys.reshape(-1), return_inverse=True)
    new_vertex = new_vertex.reshape(-1, 3)
    m = len(unique_keys)
    weight = 0.5 * double_area[members]
    grad = gradients[members]  # (k, 3, 2)
    # L = G^T A G and rhs = G^T A g over the faces, assembled per corner pair
    rows = np.repeat(new_vertex, 3, axis=1).reshape(-1)
    cols = np.tile(new_vertex, (1, 3)).reshape(-1)
    values = (weight[:, None, None] * np.einsum("fad,fbd->fab", grad, grad)).reshape(-1)
    laplacian = sp.csc_matrix((values, (rows, cols)), shape=(m, m))
    rhs = np.zeros((m, 2))
    for column, target in enumerate((target_u[members], target_v[members])):
        np.add.at(rhs[:, column], new_vertex.reshape(-1),
                  (weight[:, None] * np.einsum("fad,fd->fa", grad, target)).reshape(-1))
    # pin one vertex (the lowest new index) per patch: the solution is defined up to a translation per patch
    vertex_patch = unique_keys // n_old
    pinned = np.ones(m, bool)
    pinned[1:] = vertex_patch[1:] != vertex_patch[:-1]
    free = np.nonzero(~pinned)[0]
    uv = np.zeros((m, 2))
    if len(free):
        reduced = laplacian[free][:, free].tocsc()
        uv[free] = splu(reduced, permc_spec="MMD_AT_PLUS_A").solve(rhs[free])
    # keep coordinates small (float32 on the GPU) without moving the tiled texture: a whole-period shift per patch
    offset = np.floor(np.stack([np.bincount(vertex_patch, uv[:, c]) for c in range(2)], axis=1)
                      / np.bincount(vertex_patch)[:, None])
    uv -= offset[vertex_patch]
    corner_uv[members] = uv[new_vertex]
    return corner_uv


@numba.njit(cache=True, nogil=True)
def _attach_single_faces(faces, local, gradients, theta, patch, choice, corner_uv, first, neighbour, jump, scale,
                         band, min_stray_cos, passes):
    """A face left as a patch of its own (its field turns too fast for the growth, or its chart failed the check in
    its patch) joins a neighbouring patch of several faces when its chart can continue that patch's across their
    shared edge: the corners the patch already has keep its coordinates, a third corner gets the face's field-aligned
    gradient from them, and the chart must pass the same check (area scale within [1/band, band], u axis within the
    stray angle of the field). Then the strokes run on across that edge instead of breaking at it. ``passes`` times
    in face order, neighbours in adjacency order, so deterministic; in place."""
    n_vertices = faces.max() + 1
    size = np.zeros(patch.max() + 1, np.int64)
    for f in range(len(patch)):
        if patch[f] >= 0:
            size[patch[f]] += 1
    # (patch, vertex) -> its coordinates, from the patches of several faces (a patch's corners agree per vertex)
    vertex_uv = dict()
    for f in range(len(patch)):
        if patch[f] >= 0 and size[patch[f]] > 1:
            for k in range(3):
                key = patch[f] * n_vertices + faces[f, k]
                if key not in vertex_uv:
                    vertex_uv[key] = (corner_uv[f, k, 0], corner_uv[f, k, 1])
    uv = np.empty((3, 2))
    known = np.zeros(3, np.bool_)
    for _ in range(passes):
        moved = False
        for f in range(len(patch)):
            p = patch[f]
            if p < 0 or size[p] != 1:
                continue
            for e in range(first[f], first[f + 1]):
                g = neighbour[e]
                q = patch[g]
                if q < 0 or q == p or size[q] < 2:
                    continue
                c = (choice[g] - jump[e]) % 4  # f's direction that continues g's
                angle = theta[f] + c * (np.pi / 2)
                du0, du1 = np.cos(angle), np.sin(angle)
                count = 0
                for k in range(3):
                    key = q * n_vertices + faces[f, k]
                    known[k] = key in vertex_uv
                    if known[k]:
                        uv[k, 0], uv[k, 1] = vertex_uv[key]
                        count += 1
                if count < 2:
                    continue
                for k in range(3):
                    if known[k]:
                        continue
                    su, sv = 0.0, 0.0
                    for j in range(3):
                        if known[j]:
                            dx = local[f, k, 0] - local[f, j, 0]
                            dy = local[f, k, 1] - local[f, j, 1]
                            su += uv[j, 0] + scale * (du0 * dx + du1 * dy)
                            sv += uv[j, 1] + scale * (-du1 * dx + du0 * dy)
                    uv[k, 0], uv[k, 1] = su / count, sv / count
                # the chart's Jacobian in the face frame (rows: grad u, grad v), as chart_measures computes it
                j00 = j01 = j10 = j11 = 0.0
                for k in range(3):
                    j00 += uv[k, 0] * gradients[f, k, 0]
                    j01 += uv[k, 0] * gradients[f, k, 1]
                    j10 += uv[k, 1] * gradients[f, k, 0]
                    j11 += uv[k, 1] * gradients[f, k, 1]
                area_scale = (j00 * j11 - j01 * j10) / (scale * scale)
                if not (1.0 / band <= area_scale <= band):
                    continue
                length = np.sqrt(j11 * j11 + j10 * j10)
                if length <= 0.0 or (j11 * du0 - j10 * du1) / length < min_stray_cos:
                    continue
                patch[f], choice[f] = q, c
                size[p] -= 1
                size[q] += 1
                for k in range(3):
                    corner_uv[f, k, 0], corner_uv[f, k, 1] = uv[k, 0], uv[k, 1]
                    if not known[k]:
                        vertex_uv[q * n_vertices + faces[f, k]] = (uv[k, 0], uv[k, 1])
                moved = True
                break
        if not moved:
            break


def chart_measures(corner_uv, local, gradients, direction_u, scale):
    """Per face: the area scale (UV area over scale^2 times surface area; negative: flipped) and the angle
    (radians) between the chart's u axis and the intended direction, with the u axis in the face frame."""
    jacobian = np.einsum("fkc,fkd->fcd", corner_uv, gradients)  # rows: grad u, grad v in the face frame
    determinant = jacobian[:, 0, 0] * jacobian[:, 1, 1] - jacobian[:, 0, 1] * jacobian[:, 1, 0]
    # the u axis: the surface direction along which v stays constant and u grows, J^-1 (1, 0)
    u_axis = np.stack([jacobian[:, 1, 1], -jacobian[:, 1, 0]], axis=1)
    u_axis /= np.maximum(np.linalg.norm(u_axis, axis=1), 1e-300)[:, None]
    stray = np.arccos(np.clip(np.einsum("fd,fd->f", u_axis, direction_u), -1.0, 1.0))
    return determinant / (scale * scale), stray, u_axis


def stroke_parameterization(positions: np.ndarray, faces: np.ndarray, normals: np.ndarray, directions: np.ndarray,
                            scale: float = 1.0, cone_degrees: float = 30.0, max_turn_degrees: float = 12.0,
                            band: float = 1.4, max_stray_degrees: float = 15.0,
                            rounds: int = 8) -> StrokeParameterization:
    """Lapped, field-aligned texture coordinates for the welded mesh (``positions``, ``faces``, unit vertex
    ``normals``) following the cross field ``directions`` (n, 3) (``CrossField.direction``), ``scale`` texture
    repeats per mesh unit.

    ``cone_degrees``: how far a face normal may turn from its patch seed's (in the first round; round r allows
    cone/r); ``max_turn_degrees``: how far the field
    may turn across an edge inside a patch; ``band``: a chart's area scale must stay within [1/band, band] (so the
    max/min area distortion is at most band^2, 1.96 by default); ``max_stray_degrees``: how far a chart's u axis
    may stray from the field; ``rounds``: growing rounds before the faces left become patches of one face."""
    positions = np.asarray(positions, np.float64)
    faces = np.asarray(faces, np.int64).reshape(-1, 3)
    normals = np.asarray(normals, np.float64)
    directions = np.asarray(directions, np.float64)
    n_faces = len(faces)
    face_normal, double_area, t1, t2 = face_frames(positions, faces)
    longest = np.max(np.linalg.norm(positions[faces] - positions[faces[:, [1, 2, 0]]], axis=2), axis=1) \
        if n_faces else np.zeros(0)
    repeated = (faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2]) | (faces[:, 2] == faces[:, 0])
    degenerate = repeated | (double_area <= 1e-10 * longest ** 2) | ~np.isfinite(double_area)
    usable = ~degenerate

    theta, confidence = face_field(faces, normals, directions, face_normal, t1, t2)
    theta[degenerate] = 0.0
    pairs, cut = face_adjacency(faces, usable)
    jump, turn = period_jumps(pairs, theta, face_normal, t1, t2)
    centroid = positions[faces].mean(axis=1)
    step = np.linalg.norm(centroid[pairs[:, 0]] - centroid[pairs[:, 1]], axis=1)
    adjacency = adjacency_arrays(pairs, jump, turn, step, n_faces)
    seeds = np.lexsort((np.arange(n_faces), -confidence))  # most confident first, ties by index
    seeds = seeds[usable[seeds]]

    local = local_coordinates(positions, faces, t1, t2)
    gradients = gradient_rows(local, np.where(usable, double_area, 1.0))
    max_turn = float(np.radians(max_turn_degrees))
    max_stray = float(np.radians(max_stray_degrees))

    final_patch = np.full(n_faces, -1, np.int64)
    final_choice = np.zeros(n_faces, np.int64)
    corner_uv = np.zeros((n_faces, 3, 2))
    pool = usable.copy()
    next_id = 0
    used_rounds = 0
    while pool.any():
        last = used_rounds == rounds
        used_rounds += 1
        if last:  # what is left: one face per patch, whose chart is exact
            patch = np.full(n_faces, -1, np.int64)
            members = np.nonzero(pool)[0]
            patch[members] = np.arange(len(members))
            choice = np.zeros(n_faces, np.int64)
        else:
            # later rounds grow narrower patches: the faces a wide patch could not hold get smaller ones
            cone_cos = float(np.cos(np.radians(cone_degrees) / used_rounds))
            patch, choice = grow_patches(pool, seeds, adjacency, face_normal, cone_cos, max_turn)
            # absorbing slivers can cut a small patch in two; one pinned vertex per connected piece keeps the
            # solve non-singular
            patch = split_components(patch, pairs)
        angle = theta + choice * QUARTER
        direction_u = np.stack([np.cos(angle), np.sin(angle)], axis=1)  # in the face frame
        direction_v = np.stack([-direction_u[:, 1], direction_u[:, 0]], axis=1)  # n x a
        solved = solve_patches(patch, faces, local, gradients, double_area, scale * direction_u, scale * direction_v)
        area_scale, stray, _ = chart_measures(solved, local, gradients, direction_u, scale)
        good = (patch >= 0) & (area_scale >= 1.0 / band) & (area_scale <= band) & (stray <= max_stray)
        if last:
            good = patch >= 0
        kept = split_components(np.where(good, patch, -1), pairs)
        members = np.nonzero(kept >= 0)[0]
        final_patch[members] = kept[members] + next_id
        next_id += int(kept.max()) + 1 if len(members) else 0
        corner_uv[members] = solved[members]
        final_choice[members] = choice[members]
        pool &= ~good

    if next_id:
        _attach_single_faces(faces, local, gradients, theta, final_patch, final_choice, corner_uv, *adjacency[:3],
                             float(scale), float(band), float(np.cos(max_stray)), 4)
        used, final_patch[usable] = np.unique(final_patch[usable], return_inverse=True)  # dense, in the same order
        next_id = len(used)

    # degenerate faces: a tiny chart of their own (they cover no area; any tone will do)
    for f in np.nonzero(degenerate)[0]:
        final_patch[f] = next_id
        next_id += 1
        corner_uv[f] = [[0.0, 0.0], [1e-3, 0.0], [0.0, 1e-3]]

    # split the vertices: one new vertex per (patch, old vertex); a degenerate face's corners are kept apart even
    # where it repeats a vertex, so that its chart has an area
    n_old = len(positions)
    slot = np.where(degenerate[:, None], np.arange(1, 4)[None, :], 0)
    keys = ((final_patch[:, None] * n_old + faces) * 4 + slot).reshape(-1)
    unique_keys, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    vertex_map = (unique_keys // 4) % n_old if n_faces else np.zeros(0, np.int64)
    uv = corner_uv.reshape(-1, 2)[first]
    new_faces = inverse.reshape(-1, 3).astype(np.int64)

    _, _, u_axis = chart_measures(uv[new_faces], local, gradients, np.zeros((n_faces, 2)), scale)
    stroke = u_axis[:, :1] * t1 + u_axis[:, 1:] * t2
    stroke[degenerate] = 0.0
    return StrokeParameterization(vertex_map=vertex_map.astype(np.int64), faces=new_faces, uv=uv, patch=final_patch,
                                  fallback=degenerate | cut, stroke_direction=stroke, rounds=used_rounds)
