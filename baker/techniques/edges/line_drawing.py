"""Line drawings from a viewpoint: contour + feature edges, chained, ray-cast for visibility, projected.

The offline hidden-line-removal path of RTR4 section 15.2.5: find the contour edges for the camera (eq. 15.1, see
:func:`baker.geometry.edges.contour_edges`), add the view-independent boundary, crease and material edges, link them
into chains through vertices where exactly two edges of the same type meet, sample each chain finely in screen space,
cast one ray per sample from the eye (Embree, :class:`baker.geometry.raycast.RayScene`) and cut the chain wherever
its visibility changes. What is left is a list of polylines in pixels, each with a type and a visibility.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from baker.geometry import edges as E

# line types, in order of precedence when an edge has several classes (the widest stroke wins)
CONTOUR, BOUNDARY, CREASE, MATERIAL = 0, 1, 2, 3
TYPE_NAMES = ("contour", "boundary", "crease", "material")


@dataclass
class Camera:
    """A pinhole (``yfov`` radians) or orthographic (``ymag`` half-height) camera looking from ``eye`` at ``target``."""

    eye: np.ndarray
    target: np.ndarray
    up: np.ndarray
    width: int = 800
    height: int = 800
    yfov: float | None = math.radians(40.0)
    ymag: float | None = None
    znear: float = 1e-3

    @property
    def orthographic(self) -> bool:
        return self.yfov is None

    def basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Right, up, forward unit vectors (forward points from the eye to the target)."""
        forward = np.asarray(self.target, np.float64) - np.asarray(self.eye, np.float64)
        forward /= np.linalg.norm(forward)
        right = np.cross(forward, np.asarray(self.up, np.float64))
        if np.linalg.norm(right) < 1e-12:  # up parallel to the view direction: any perpendicular will do
            right = np.cross(forward, [1.0, 0.0, 0.0] if abs(forward[0]) < 0.9 else [0.0, 1.0, 0.0])
        right /= np.linalg.norm(right)
        return right, np.cross(right, forward), forward

    def project(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pixel coordinates (x right, y down, origin top-left) and view depth of ``points``."""
        right, up, forward = self.basis()
        rel = np.asarray(points, np.float64) - np.asarray(self.eye, np.float64)
        x, y, z = rel @ right, rel @ up, rel @ forward
        aspect = self.width / self.height
        if self.orthographic:
            sx, sy = x / (self.ymag * aspect), y / self.ymag
        else:
            t = math.tan(self.yfov / 2.0)
            zz = np.where(z > 1e-300, z, 1e-300)
            sx, sy = x / (zz * t * aspect), y / (zz * t)
        return np.stack([(sx + 1.0) * 0.5 * self.width, (1.0 - sy) * 0.5 * self.height], axis=1), z


def fit_camera(points: np.ndarray, width: int = 800, height: int = 800, yfov_deg: float = 40.0,
               direction=(0.0, 0.0, -1.0), up=(0.0, 1.0, 0.0)) -> Camera:
    """A camera looking along ``direction`` at the bounding-sphere centre, far enough for the sphere to fit."""
    lo, hi = points.min(0), points.max(0)
    center = (lo + hi) / 2.0
    radius = float(np.linalg.norm(hi - lo)) / 2.0 or 1.0
    half = math.radians(yfov_deg) / 2.0
    if width < height:
        half = math.atan(math.tan(half) * width / height)
    distance = radius / math.sin(half) * 1.05
    d = np.asarray(direction, np.float64) / np.linalg.norm(direction)
    return Camera(center - d * distance, center, np.asarray(up, np.float64), width, height, math.radians(yfov_deg))


@dataclass
class Polyline:
    points: np.ndarray  # (n, 2) pixels
    kind: int  # CONTOUR, BOUNDARY, CREASE, MATERIAL
    visible: bool
    closed: bool


def line_types(mesh: E.MeshEdges, camera: Camera, *, creases: bool = True, boundaries: bool = True,
               materials: bool = True) -> np.ndarray:
    """(E,) type of every edge drawn for ``camera`` (-1: not drawn)."""
    eye = None if camera.orthographic else camera.eye
    direction = camera.basis()[2] if camera.orthographic else None
    contour = E.contour_edges(mesh, eye=eye, direction=direction)
    flags = mesh.flags
    kind = np.full(len(flags), -1, np.int64)
    if materials:
        kind[(flags & E.MATERIAL) != 0] = MATERIAL
    if creases:
        kind[(flags & E.CREASE) != 0] = CREASE
    if boundaries:
        kind[(flags & (E.BOUNDARY | E.NON_MANIFOLD)) != 0] = BOUNDARY
    kind[contour] = CONTOUR
    return kind


@numba.njit(cache=True, nogil=True)
def _chain(edges, kinds, n_vertices):
    """Link edges into chains through vertices where exactly two edges of one type meet.

    Returns (vertices, offsets, closed, kind): chain c is vertices[offsets[c]:offsets[c+1]] (a closed chain repeats
    its first vertex at the end).
    """
    n = edges.shape[0]
    degree = np.zeros(n_vertices + 1, np.int64)
    for e in range(n):
        degree[edges[e, 0] + 1] += 1
        degree[edges[e, 1] + 1] += 1
    for v in range(n_vertices):
        degree[v + 1] += degree[v]
    fill = degree[:n_vertices].copy()
    incident = np.empty(2 * n, np.int64)
    for e in range(n):
        for j in range(2):
            v = edges[e, j]
            incident[fill[v]] = e
            fill[v] += 1
    joint = np.zeros(n_vertices, np.bool_)
    for v in range(n_vertices):
        s = degree[v]
        if degree[v + 1] - s == 2 and kinds[incident[s]] == kinds[incident[s + 1]]:
            joint[v] = True
    visited = np.zeros(n, np.bool_)
    out_vertices = np.empty(2 * n + 1, np.int64)
    offsets = np.empty(n + 1, np.int64)
    closed = np.zeros(n, np.bool_)
    kind = np.empty(n, np.int64)
    n_out, n_chains = 0, 0
    offsets[0] = 0
    for phase in range(2):  # open chains from their non-joint ends first, then the closed loops left over
        for start_edge in range(n):
            if visited[start_edge]:
                continue
            a, b = edges[start_edge, 0], edges[start_edge, 1]
            if phase == 0:
                if not joint[a]:
                    v = a
                elif not joint[b]:
                    v = b
                else:
                    continue
            else:
                v = a
            e = start_edge
            out_vertices[n_out] = v
            n_out += 1
            kind[n_chains] = kinds[e]
            while True:
                visited[e] = True
                v = edges[e, 1] if edges[e, 0] == v else edges[e, 0]
                out_vertices[n_out] = v
                n_out += 1
                if not joint[v]:
                    break
                s = degree[v]
                nxt = incident[s] if incident[s] != e else incident[s + 1]
                if visited[nxt]:
                    break
                e = nxt
            closed[n_chains] = phase == 1
            n_chains += 1
            offsets[n_chains] = n_out
    return out_vertices[:n_out], offsets[: n_chains + 1], closed[:n_chains], kind[:n_chains]


def chain_edges(edges: np.ndarray, kinds: np.ndarray, n_vertices: int):
    """Chains of ``edges`` (S, 2): (vertices, offsets, closed, kind), see :func:`_chain`."""
    return _chain(np.ascontiguousarray(edges, np.int64), np.ascontiguousarray(kinds, np.int64), int(n_vertices))


def trace_lines(mesh: E.MeshEdges, camera: Camera, scene, *, step: float = 2.0, max_samples: int = 512,
                creases: bool = True, boundaries: bool = True, materials: bool = True) -> list[Polyline]:
    """Visible and hidden polylines (pixels) of ``mesh`` for ``camera``.

    ``scene`` is a ray scene of the same triangles (``distances(origins, unit_directions)``). Each chain is cut into
    pieces at most ``step`` pixels long; one ray per piece, aimed at its midpoint, decides its visibility, and
    consecutive pieces of equal visibility form one polyline. Chains behind the camera's near plane are dropped.
    """
    kinds = line_types(mesh, camera, creases=creases, boundaries=boundaries, materials=materials)
    chosen = np.flatnonzero(kinds >= 0)
    if len(chosen) == 0:
        return []
    verts, offsets, closed, chain_kind = chain_edges(mesh.topology.edges[chosen], kinds[chosen], len(mesh.welded))
    positions = mesh.welded
    # segments: consecutive vertices inside each chain
    seg_a = np.delete(np.arange(len(verts) - 1), offsets[1:-1] - 1)
    seg_chain = np.searchsorted(offsets, seg_a, side="right") - 1
    pa, pb = positions[verts[seg_a]], positions[verts[seg_a + 1]]
    xa, za = camera.project(pa)
    xb, zb = camera.project(pb)
    pixels = np.linalg.norm(xb - xa, axis=1)
    pieces = np.clip(np.ceil(np.nan_to_num(pixels / step, nan=1.0, posinf=max_samples)), 1, max_samples).astype(np.int64)
    # sub-segments: piece j of segment s spans t in [j/n, (j+1)/n]
    sub_seg = np.repeat(np.arange(len(seg_a)), pieces)
    j = np.arange(len(sub_seg)) - np.repeat(np.cumsum(pieces) - pieces, pieces)
    n = pieces[sub_seg]
    t0, t1 = j / n, (j + 1) / n
    d = pb - pa
    q0 = pa[sub_seg] + d[sub_seg] * t0[:, None]
    q1 = pa[sub_seg] + d[sub_seg] * t1[:, None]
    mid = (q0 + q1) / 2.0
    visible = _visible(scene, mesh, camera, mid)
    _, z0 = camera.project(q0)
    _, z1 = camera.project(q1)
    in_front = (z0 > camera.znear) & (z1 > camera.znear) if not camera.orthographic else np.ones(len(q0), bool)
    chain_of_sub = seg_chain[sub_seg]
    # runs: break where the chain, the visibility or the in-front state changes
    start = np.ones(len(sub_seg), bool)
    start[1:] = ((chain_of_sub[1:] != chain_of_sub[:-1]) | (visible[1:] != visible[:-1])
                 | (in_front[1:] != in_front[:-1]))
    run_start = np.flatnonzero(start)
    run_end = np.append(run_start[1:], len(sub_seg))
    x0, _ = camera.project(q0)
    x1, _ = camera.project(q1)
    lines = []
    for rs, re in zip(run_start.tolist(), run_end.tolist()):  # one iteration per output polyline
        if not in_front[rs]:
            continue
        pts = np.concatenate([x0[rs:re], x1[re - 1: re]])
        c = int(chain_of_sub[rs])
        whole = rs == 0 or chain_of_sub[rs - 1] != c
        whole &= re == len(sub_seg) or chain_of_sub[re] != c
        is_closed = bool(closed[c] and whole)
        if is_closed:
            pts = pts[:-1]
        lines.append(Polyline(pts, int(chain_kind[c]), bool(visible[rs]), is_closed))
    return lines


def _visible(scene, mesh: E.MeshEdges, camera: Camera, points: np.ndarray) -> np.ndarray:
    """True where nothing lies between the eye and ``points`` (a small tolerance lets the surface carrying the
    point, met at the point itself, not count)."""
    diag = float(np.linalg.norm(mesh.welded.max(0) - mesh.welded.min(0))) or 1.0
    if camera.orthographic:
        forward = camera.basis()[2]
        back = 4.0 * diag + float(np.abs((points - camera.eye) @ forward).max())
        directions = np.tile(forward, (len(points), 1))
        origins = points - directions * back
        dist = np.full(len(points), back)
    else:
        rel = points - np.asarray(camera.eye, np.float64)
        dist = np.linalg.norm(rel, axis=1)
        directions = rel / np.maximum(dist, 1e-300)[:, None]
        origins = np.tile(np.asarray(camera.eye, np.float64), (len(points), 1))
    hit = np.asarray(scene.distances(origins.astype(np.float32), directions.astype(np.float32)), np.float64)
    return hit >= dist * (1.0 - 1e-5) - 1e-4 * diag
