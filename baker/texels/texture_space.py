"""Texture space shared by every texture bake: UV layout, texel -> surface sample, and dilation.

- :func:`rasterize_uv` maps each texel centre to (triangle, barycentrics) with a numba scanline-free bounding-box
  rasterizer (one loop per triangle in compiled code; no Python loop over triangles or texels).
- :func:`usable_layout_texels` decides whether an existing UV set can hold a bake: no overlap once wrapped to [0, 1).
- :func:`unwrap` makes a new layout with xatlas when it cannot.
- :func:`dilate` pads results across chart borders so bilinear filtering and mipmapping show no seams.

Conventions: glTF UV (0, 0) is the top-left corner of the image, so texel (row y, column x) covers
u in [x/W, (x+1)/W], v in [y/H, (y+1)/H]; arrays are indexed [row, column].
"""
from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np
from baker import interruptible


@numba.njit(cache=True)
def _rasterize(uv_px, width, height, tri_of_texel, bary_of_texel, hits):
    for t in range(uv_px.shape[0]):
        # UVs repeat (the glTF default sampler wraps): a triangle reaching past [0, 1] is drawn in every tile it
        # touches, so the part at u = -0.05 lands in the texels that u = 0.95 samples
        tx0 = int(np.floor(min(uv_px[t, 0, 0], min(uv_px[t, 1, 0], uv_px[t, 2, 0])) / width))
        tx1 = int(np.floor(max(uv_px[t, 0, 0], max(uv_px[t, 1, 0], uv_px[t, 2, 0])) / width))
        ty0 = int(np.floor(min(uv_px[t, 0, 1], min(uv_px[t, 1, 1], uv_px[t, 2, 1])) / height))
        ty1 = int(np.floor(max(uv_px[t, 0, 1], max(uv_px[t, 1, 1], uv_px[t, 2, 1])) / height))
        if (tx1 - tx0 + 1) * (ty1 - ty0 + 1) > 16:
            continue  # a triangle spanning many tiles is a broken layout; the overlap test rejects it anyway
        for ty in range(ty0, ty1 + 1):
            for tx in range(tx0, tx1 + 1):
                _rasterize_one(uv_px, t, tx * width, ty * height, width, height, tri_of_texel, bary_of_texel,
                               hits)


@numba.njit(cache=True, inline="always")
def _edge(ax, ay, bx, by, px, py):
    """Twice the signed area of (lesser, greater, p) for the edge's endpoints in one fixed order (lexicographic),
    whichever way the triangle runs along it: the two triangles sharing an edge compute the same floating-point
    number for a point (positive: left of the edge from its lesser endpoint)."""
    if ax > bx or (ax == bx and ay > by):
        return (ax - bx) * (py - by) - (ay - by) * (px - bx)
    return (bx - ax) * (py - ay) - (by - ay) * (px - ax)


@numba.njit(cache=True)
def _rasterize_one(uv_px, t, ox, oy, width, height, tri_of_texel, bary_of_texel, hits):
    x0, y0 = uv_px[t, 0, 0] - ox, uv_px[t, 0, 1] - oy
    x1, y1 = uv_px[t, 1, 0] - ox, uv_px[t, 1, 1] - oy
    x2, y2 = uv_px[t, 2, 0] - ox, uv_px[t, 2, 1] - oy
    area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
    if area == 0.0:
        return
    # which side of each edge the triangle lies on (the opposite vertex's edge value: never 0 when area != 0)
    side0 = _edge(x1, y1, x2, y2, x0, y0)
    side1 = _edge(x2, y2, x0, y0, x1, y1)
    side2 = _edge(x0, y0, x1, y1, x2, y2)
    if side0 == 0.0 or side1 == 0.0 or side2 == 0.0:
        return  # collinear in floating point: covers no texel centre
    xmin = max(int(np.floor(min(x0, min(x1, x2)) - 0.5)), 0)
    xmax = min(int(np.ceil(max(x0, max(x1, x2)) - 0.5)), width - 1)
    ymin = max(int(np.floor(min(y0, min(y1, y2)) - 0.5)), 0)
    ymax = min(int(np.ceil(max(y0, max(y1, y2)) - 0.5)), height - 1)
    inv = 1.0 / area
    for y in range(ymin, ymax + 1):
        py = y + 0.5
        for x in range(xmin, xmax + 1):
            px = x + 0.5
            # exact edge tests: the triangles on either side of a shared edge compute the same edge value (of
            # opposite meaning), so no centre is strictly inside both; a centre exactly on an edge or vertex goes to
            # the first triangle that has it (grid-aligned layouts otherwise read as overlapping)
            e0 = _edge(x1, y1, x2, y2, px, py)
            e1 = _edge(x2, y2, x0, y0, px, py)
            e2 = _edge(x0, y0, x1, y1, px, py)
            if (e0 != 0.0 and (e0 > 0.0) != (side0 > 0.0)) or (e1 != 0.0 and (e1 > 0.0) != (side1 > 0.0)) \
                    or (e2 != 0.0 and (e2 > 0.0) != (side2 > 0.0)):
                continue
            if (e0 == 0.0 or e1 == 0.0 or e2 == 0.0) and hits[y, x] > 0:
                continue
            w0 = ((x1 - px) * (y2 - py) - (x2 - px) * (y1 - py)) * inv
            w1 = ((x2 - px) * (y0 - py) - (x0 - px) * (y2 - py)) * inv
            hits[y, x] += 1
            tri_of_texel[y, x] = t
            bary_of_texel[y, x, 0] = min(max(w0, 0.0), 1.0)
            bary_of_texel[y, x, 1] = min(max(w1, 0.0), 1.0)
            bary_of_texel[y, x, 2] = max(1.0 - bary_of_texel[y, x, 0] - bary_of_texel[y, x, 1], 0.0)


@dataclass
class TexelSamples:
    """Texels covered by triangles: ``rows``/``cols`` index the image, ``triangle`` and ``bary`` locate them."""

    width: int
    height: int
    rows: np.ndarray
    cols: np.ndarray
    triangle: np.ndarray
    bary: np.ndarray  # (k, 3)
    overlap_fraction: float  # covered texels hit by more than one triangle / covered texels

    @property
    def mask(self) -> np.ndarray:
        m = np.zeros((self.height, self.width), bool)
        m[self.rows, self.cols] = True
        return m

    def triangles(self, start: int, stop: int) -> "TexelSamples":
        """The texels of triangles ``start``..``stop - 1``, renumbered from 0: one primitive's share of a
        rasterization of several primitives' triangles concatenated."""
        keep = (self.triangle >= start) & (self.triangle < stop)
        return TexelSamples(self.width, self.height, self.rows[keep], self.cols[keep], self.triangle[keep] - start,
                            self.bary[keep], self.overlap_fraction)


def rasterize_uv(uv: np.ndarray, faces: np.ndarray, width: int, height: int) -> TexelSamples:
    """Rasterize triangles ``faces`` with per-vertex ``uv`` (n, 2) into a width x height texel grid."""
    uv_px = uv[faces].astype(np.float64) * np.array([width, height], np.float64)
    tri = np.full((height, width), -1, np.int64)
    bary = np.zeros((height, width, 3), np.float64)
    hits = np.zeros((height, width), np.int32)
    _rasterize(np.ascontiguousarray(uv_px), width, height, tri, bary, hits)
    rows, cols = np.nonzero(hits)
    covered = len(rows)
    overlap = float((hits > 1).sum()) / covered if covered else 0.0
    return TexelSamples(width, height, rows, cols, tri[rows, cols], bary[rows, cols], overlap)


def usable_layout_texels(uv: np.ndarray, faces: np.ndarray, size: int = 512,
                         max_overlap: float = 0.002) -> TexelSamples | None:
    """The size x size texels of the UV set when it can hold a bake, else None: when the UV set, wrapped into
    [0, 1)^2 as a repeating sampler sees it, has overlapping triangles (mirrored or stacked charts, tiling).
    ``max_overlap`` tolerates a few texels covered twice (triangles of one chart that overlap by rounding). A bake at
    ``size`` keeps the rasterization the test made."""
    if len(faces) == 0:
        return None
    corners = uv[faces]
    # a triangle wider than the texture covers some texel twice by itself
    if not np.isfinite(corners).all() or np.ptp(corners, axis=1).max() > 1.0:
        return None
    texels = rasterize_uv(uv, faces, size, size)
    return texels if texels.overlap_fraction <= max_overlap else None


CHART_LIMIT_FROM_FACES = 16384  # triangles in an unwrap above which charts are bounded (below, xatlas takes ~1 s)
MAX_CHART_FACES = 256  # a bounded chart's area: that of this many of the mesh's triangles, on average


def triangle_areas(positions: np.ndarray, faces: np.ndarray) -> np.ndarray:
    a = positions[faces[:, 0]]
    return 0.5 * np.linalg.norm(np.cross(positions[faces[:, 1]] - a, positions[faces[:, 2]] - a), axis=1)


def unwrap(meshes: list[tuple[np.ndarray, np.ndarray]], resolution: int, padding: int = 4, seed: int = 0):
    """Unwrap several meshes into one shared atlas with xatlas.

    Returns one (vmapping, faces, uv) per mesh: new vertex i copies old vertex ``vmapping[i]``; ``uv`` in [0, 1].
    """
    return [_in_source_order(*chart) for chart in _xatlas_charts(meshes, resolution, padding)]


def _xatlas_charts(meshes, resolution: int, padding: int) -> list:
    """xatlas's (vmapping, faces, uv) per mesh, as it returns them."""
    import xatlas

    atlas = xatlas.Atlas()
    for vertices, faces in meshes:
        atlas.add_mesh(np.ascontiguousarray(vertices, np.float32), np.ascontiguousarray(faces, np.uint32))
    chart = xatlas.ChartOptions()
    faces_total = sum(len(f) for _, f in meshes)
    if faces_total > CHART_LIMIT_FROM_FACES:
        # xatlas's chart growth and its re-parameterisation of charts that fold grow much faster than linearly
        # with a chart's triangle count: the 69k-triangle Stanford bunny took ~60 s with unbounded charts. Charts of
        # at most ~MAX_CHART_FACES triangles' area keep it linear; their layout measures as well (benchmarks/unwrap.py)
        area = sum(float(triangle_areas(np.asarray(v, np.float64), np.asarray(f, np.int64)).sum()) for v, f in meshes)
        chart.max_chart_area = area * MAX_CHART_FACES / faces_total
        # no chart-boundary refinement: bounded charts are cut by area, not along features, so refining their
        # borders buys nothing measurable (bunny at 2048^2: utilisation 0.281 vs 0.277, L2 stretch 1.002 vs 1.001)
        # while it is ~40% of xatlas's time (3.3 s -> 2.0 s; benchmarks/unwrap.py --section layout)
        chart.max_iterations = 0
    pack = xatlas.PackOptions()
    pack.resolution = int(resolution)
    pack.padding = int(padding)
    pack.bilinear = True
    pack.bruteForce = False
    atlas.generate(chart, pack)
    return [atlas[i] for i in range(len(meshes))]


UNWRAP_IN_CHILD_FROM_FACES = 4096  # triangles from which an early unwrap runs in a child process (below: ~0.1 s)


class UnwrapInChild:
    """:func:`unwrap` of the same arguments, computed by a forked child process while this one goes on.

    xatlas holds the GIL for its whole run (~1-2 s on the 69k-triangle bunny), so a thread cannot overlap it with
    the BVH build and the per-vertex rays that every texture bake traces first; a process can, on a second core.
    The child runs xatlas alone (imported before the fork: the child imports nothing, takes no lock another thread
    of this process may hold), sends its arrays through a pipe and exits; the layout is byte for byte the one
    :func:`unwrap` computes here (xatlas is deterministic). The child dies by default on SIGINT and SIGTERM (as the
    process group's Ctrl-C sends it), and with this process (Linux's parent-death signal); :meth:`cancel` kills and
    reaps it when this process unwinds first. Where fork is unavailable (not Linux) or the process is one of
    ``baker build --jobs``' (``BAKER_THREADS=1``: its cores are taken), :meth:`result` unwraps here instead."""

    def __init__(self, meshes: list[tuple[np.ndarray, np.ndarray]], resolution: int, padding: int = 4):
        import os
        import sys

        self.meshes = [(np.ascontiguousarray(v, np.float32), np.ascontiguousarray(f, np.uint32)) for v, f in meshes]
        self.resolution, self.padding = int(resolution), int(padding)
        self.pid, self.pipe = None, None
        if sys.platform != "linux" or os.environ.get("BAKER_THREADS") == "1":
            return
        import xatlas  # noqa: F401 - imported before the fork: the child must import nothing
        read, write = os.pipe()
        pid = os.fork()
        if pid == 0:
            _unwrap_child(read, write, self.meshes, self.resolution, self.padding)  # never returns
        os.close(write)
        self.pid, self.pipe = pid, os.fdopen(read, "rb")

    def result(self) -> list:
        """One (vmapping, faces, uv) per mesh, as :func:`unwrap` returns them; waits for the child."""
        if self.pid is None:
            return [_in_source_order(*c) for c in _xatlas_charts(self.meshes, self.resolution, self.padding)]
        import os

        try:
            charts = []
            for vertices, faces in self.meshes:
                count = np.frombuffer(self._read(16), np.int64)
                charts.append((np.frombuffer(self._read(4 * int(count[0])), np.uint32),
                               np.frombuffer(self._read(12 * int(count[1])), np.uint32).reshape(-1, 3),
                               np.frombuffer(self._read(8 * int(count[0])), np.float32).reshape(-1, 2)))
        except EOFError:
            charts = None
        finally:
            self.pipe.close()
            _, status = os.waitpid(self.pid, 0)
            self.pid = None
        if charts is None or status != 0:
            # the child did not finish (killed from outside, out of memory): unwrap here
            charts = _xatlas_charts(self.meshes, self.resolution, self.padding)
        return [_in_source_order(*c) for c in charts]

    def _read(self, size: int) -> bytes:
        data = self.pipe.read(size)
        if len(data) != size:
            raise EOFError
        return data

    def cancel(self) -> None:
        """Kill and reap the child, if it is still there."""
        if self.pid is None:
            return
        import os
        import signal

        try:
            os.kill(self.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        self.pipe.close()
        os.waitpid(self.pid, 0)
        self.pid = None


def _unwrap_child(read: int, write: int, meshes, resolution: int, padding: int) -> None:
    """The forked child: xatlas, its arrays into ``write``, exit. Any failure exits 1 (the parent unwraps)."""
    import os
    import signal

    code = 1
    try:
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        try:
            import ctypes

            ctypes.CDLL(None).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG: die with the parent
        except (OSError, AttributeError):
            pass
        if os.getppid() == 1:
            os._exit(1)  # the parent died before the line above: nobody reads
        os.close(read)
        for vmapping, faces, uv in _xatlas_charts(meshes, resolution, padding):
            vmapping = np.ascontiguousarray(vmapping, np.uint32)
            parts = (np.array([len(vmapping), len(faces)], np.int64), vmapping,
                     np.ascontiguousarray(faces, np.uint32), np.ascontiguousarray(uv, np.float32))
            for part in parts:
                view = memoryview(part.tobytes())
                while len(view):
                    view = view[os.write(write, view):]
        os.close(write)
        code = 0
    finally:
        os._exit(code)


def _in_source_order(vmapping, faces, uv):
    """xatlas's output with its vertices renumbered in the order of the vertices they copy (copies of one vertex in
    xatlas's order). Welding the split mesh (first occurrence) then gives the mesh welded before the split, vertex
    for vertex: a per-vertex bake computes the same values whether or not a texture bake unwrapped first."""
    vmapping = np.asarray(vmapping, np.int64)
    order = np.argsort(vmapping, kind="stable")
    renumber = np.empty_like(order)
    renumber[order] = np.arange(len(order))
    # xatlas gives NaN UVs to the vertices of zero-area triangles (a flat or degenerate mesh); such triangles cover
    # no texel, so any UV serves: 0 keeps NaN out of TEXCOORD_0
    uv = np.nan_to_num(np.asarray(uv, np.float64), nan=0.0, posinf=0.0, neginf=0.0)
    return vmapping[order], renumber[np.asarray(faces, np.int64)], uv[order]


def dilate(image: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Fill every texel outside ``mask`` with the value of the nearest texel inside it (Euclidean).

    Filling the whole background (not a few rings) keeps every mip level free of background bleeding.
    """
    if mask.all() or not mask.any():
        return image
    rows, cols = nearest_inside(mask)
    return image[rows, cols]


def nearest_inside(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(rows, cols): for every texel the nearest texel where ``mask`` is True, by Euclidean distance (exact; ties
    go to the lower row, then the lower column). ``mask`` must hold a True texel."""
    height, width = mask.shape
    rows = np.empty((height, width), np.int64)
    cols = np.empty((height, width), np.int64)
    _nearest_inside(np.ascontiguousarray(mask), rows, cols)
    return rows, cols


@numba.njit(cache=True, nogil=True)
def _nearest_inside(mask, rows, cols):
    # The exact distance transform of Felzenszwalb & Huttenlocher, "Distance Transforms of Sampled Functions"
    # (ToC 2012), keeping the arg-min: per column the nearest inside row, then per row the lower envelope of the
    # parabolas (x - x')^2 + dy(x')^2. Linear in the texels; scipy's distance_transform_edt does the same work but
    # its import alone cost a 1024^2 bake 0.3-0.5 s.
    height, width = mask.shape
    far = height + width + 1
    column_row = np.empty((height, width), np.int64)  # nearest inside row in the same column (far: none)
    for x in range(width):
        last = -far
        for y in range(height):
            if mask[y, x]:
                last = y
            column_row[y, x] = last
        nxt = far + height
        for y in range(height - 1, -1, -1):
            if mask[y, x]:
                nxt = y
            if nxt - y < y - column_row[y, x]:
                column_row[y, x] = nxt
    sites = np.empty(width, np.int64)
    bounds = np.empty(width + 1, np.float64)
    cost = np.empty(width, np.float64)
    for y in range(height):
        count = 0
        for x in range(width):
            dy = column_row[y, x] - y
            if abs(dy) >= far:
                continue  # no inside texel in this column
            cost[x] = float(dy * dy + x * x)
            while count > 0:
                q = sites[count - 1]
                cross = (cost[x] - cost[q]) / (2.0 * (x - q))
                if cross <= bounds[count - 1]:
                    count -= 1
                else:
                    break
            bounds[count] = -np.inf if count == 0 else (cost[x] - cost[sites[count - 1]]) / (2.0 * (x - sites[count - 1]))
            sites[count] = x
            count += 1
        k = 0
        for x in range(width):
            while k + 1 < count and bounds[k + 1] < x:
                k += 1
            rows[y, x] = column_row[y, sites[k]]
            cols[y, x] = sites[k]


def interpolate(values: np.ndarray, faces: np.ndarray, triangle: np.ndarray, bary: np.ndarray) -> np.ndarray:
    """Barycentric interpolation of per-vertex ``values`` at (triangle, bary) samples: (k, ...) float64."""
    flat = np.ascontiguousarray(values, np.float64).reshape(len(values), -1)
    out = np.empty((len(triangle), flat.shape[1]), np.float64)
    _interpolate_rows(flat, np.ascontiguousarray(faces, np.int64), np.ascontiguousarray(triangle, np.int64),
                      np.ascontiguousarray(bary, np.float64), out)
    return out.reshape((len(triangle),) + np.shape(values)[1:])


@numba.njit(cache=True, nogil=True)
def _interpolate_rows(values, faces, triangle, bary, out):
    # one pass, no (k, 3, ...) corner copy: a 1024^2 texture's 0.6M texels gather from the vertices in ~10 ms
    for k in range(triangle.shape[0]):
        a, b, c = faces[triangle[k], 0], faces[triangle[k], 1], faces[triangle[k], 2]
        w0, w1, w2 = bary[k, 0], bary[k, 1], bary[k, 2]
        for j in range(values.shape[1]):
            out[k, j] = w0 * values[a, j] + w1 * values[b, j] + w2 * values[c, j]


def window_mean(size: int, rows: np.ndarray, cols: np.ndarray, values: np.ndarray, include: np.ndarray,
                positions: np.ndarray, normals: np.ndarray, radius: int,
                groups: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per texel, the mean of ``values`` and its squared standard error (the values' variance over the window
    divided by their count) over the included texels of one size x size texture within ``radius``
    texels (a square window) that also lie near it on the surface: within the window's reach in 3D (the texture's
    median texel spacing times (radius + 1) x 2 sqrt 2) and facing the same side (normals at less than 60 degrees).
    The 3D test keeps charts that are neighbours in the image but not on the surface apart, and lets charts that
    meet at a seam share; ``groups`` (e.g. the mesh of each texel: positions are in its own space) must match too.
    A texel with no included texel near it gets NaN (both)."""
    # the texels' data laid out as an image of 32-byte records: a window reads 7 short runs of cache lines
    # (1.5x faster at 1024^2 than gathering 49 scattered texels); float32 halves the image (134 MB at 2048^2) and
    # is ample for a distance test and a mean deviation (the sums are float64)
    planes = np.zeros((size, size, 8), np.float32)  # per texel x, y, z, nx, ny, nz, value, group + 1 (0: left out)
    rows = np.ascontiguousarray(rows, np.int64)
    cols = np.ascontiguousarray(cols, np.int64)
    groups = np.ascontiguousarray(groups, np.int64)
    _scatter_planes(rows, cols, np.ascontiguousarray(positions, np.float64),
                    np.ascontiguousarray(normals, np.float64), np.ascontiguousarray(values, np.float64),
                    np.ascontiguousarray(include, np.bool_), groups, planes)
    reach = 2.0 * np.sqrt(2.0) * (radius + 1) * _median_texel_spacing(rows, cols, planes)
    mean, error = np.empty(len(rows), np.float64), np.empty(len(rows), np.float64)
    half = len(rows) // 2
    with interruptible.thread_pool(2) as pool:  # GIL-free halves
        list(pool.map(lambda part: _window_mean(planes, rows[part], cols[part], groups[part], int(radius),
                                                reach * reach, mean[part], error[part]),
                      (slice(0, half), slice(half, None))))
    return mean, error


@numba.njit(cache=True, nogil=True)
def _scatter_planes(rows, cols, positions, normals, values, include, groups, planes):
    for i in range(rows.shape[0]):
        y, x = rows[i], cols[i]
        for k in range(3):
            planes[y, x, k] = positions[i, k]
            planes[y, x, 3 + k] = normals[i, k]
        planes[y, x, 6] = values[i]
        planes[y, x, 7] = groups[i] + 1.0 if include[i] else 0.0


@numba.njit(cache=True, nogil=True)
def _median_texel_spacing(rows, cols, planes):
    """The median 3D distance from each texel to its right-hand neighbour in the image, where that is a texel too
    (normals of unit length mark texels; 0: no such pair)."""
    width = planes.shape[1]
    gaps = np.empty(rows.shape[0], np.float64)
    count = 0
    for i in range(rows.shape[0]):
        y, x = rows[i], cols[i]
        if x + 1 < width and planes[y, x + 1, 3] ** 2 + planes[y, x + 1, 4] ** 2 + planes[y, x + 1, 5] ** 2 > 0.5:
            dx = planes[y, x, 0] - planes[y, x + 1, 0]
            dy = planes[y, x, 1] - planes[y, x + 1, 1]
            dz = planes[y, x, 2] - planes[y, x + 1, 2]
            gaps[count] = np.sqrt(dx * dx + dy * dy + dz * dz)
            count += 1
    return np.median(gaps[:count]) if count else 0.0


@numba.njit(cache=True, nogil=True)
def _window_mean(planes, rows, cols, groups, radius, reach2, mean, error):
    height, width = planes.shape[0], planes.shape[1]
    for i in range(rows.shape[0]):
        y0, x0 = rows[i], cols[i]
        px, py, pz = planes[y0, x0, 0], planes[y0, x0, 1], planes[y0, x0, 2]
        nx, ny, nz = planes[y0, x0, 3], planes[y0, x0, 4], planes[y0, x0, 5]
        group = float(groups[i]) + 1.0
        total, squares, count = 0.0, 0.0, 0
        for y in range(max(0, y0 - radius), min(height, y0 + radius + 1)):
            for x in range(max(0, x0 - radius), min(width, x0 + radius + 1)):
                if planes[y, x, 7] != group:
                    continue
                dx, dy, dz = planes[y, x, 0] - px, planes[y, x, 1] - py, planes[y, x, 2] - pz
                if dx * dx + dy * dy + dz * dz > reach2:
                    continue
                if planes[y, x, 3] * nx + planes[y, x, 4] * ny + planes[y, x, 5] * nz < 0.5:
                    continue
                total += planes[y, x, 6]
                squares += planes[y, x, 6] * planes[y, x, 6]
                count += 1
        if count:
            mean[i] = total / count
            error[i] = max(0.0, squares / count - mean[i] * mean[i]) / count
        else:
            mean[i] = error[i] = np.nan


# ---------------------------------------------------------------------------------------------------- texel density
# Thickness and curvature vary at the scale of the geometry: across one triangle they change no faster than the
# interpolated normal does, so a few texels per edge show all the shape there is and more texels per edge only add
# rays. Eight texels along the average edge (64 per triangle's bounding square, ~28 inside it) resolve the
# barycentric interpolation of a triangle's normal, and the shading between edges, with ample margin for triangles
# smaller than the average; the 7-sphere scene of issue 27 (960 triangles a sphere) gets 256^2 per material.
TEXELS_PER_EDGE = 8
AUTO_SIZE_RANGE = (64, 2048)  # the texture size chosen from the mesh is clamped to this range
DENSITY_SIZE_RANGE = (16, 8192)  # and when the texel density is given


@dataclass(frozen=True)
class SurfaceStatistics:
    """What the texture size of a texture set follows: its surface in mesh units (metres in glTF) and UV space."""

    area: float  # surface area of the triangles
    uv_coverage: float  # fraction of the unit UV square the triangles cover (<= 1 in a usable layout)
    mean_edge: float  # mean triangle edge length

    @staticmethod
    def of(meshes: list[tuple[np.ndarray, np.ndarray, np.ndarray]]) -> "SurfaceStatistics":
        """Statistics of (positions, faces, uv) triangle sets taken together."""
        area = uv_area = edges = 0.0
        count = 0
        for positions, faces, uv in meshes:
            corners = positions[faces]
            area += 0.5 * float(np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]),
                                               axis=1).sum())
            edges += float(np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=2).sum())
            count += 3 * len(faces)
            t = uv[faces]
            uv_area += 0.5 * float(np.abs((t[:, 1, 0] - t[:, 0, 0]) * (t[:, 2, 1] - t[:, 0, 1])
                                          - (t[:, 2, 0] - t[:, 0, 0]) * (t[:, 1, 1] - t[:, 0, 1])).sum())
        return SurfaceStatistics(area, min(uv_area, 1.0), edges / count if count else 0.0)

    def auto_density(self) -> float:
        """Texels per mesh unit that put :data:`TEXELS_PER_EDGE` texels along the mean triangle edge."""
        return TEXELS_PER_EDGE / self.mean_edge if self.mean_edge > 0 else 0.0


def power_of_two(value: float, lo: int, hi: int) -> int:
    """The power of two nearest ``value`` on a log scale (so within a factor sqrt(2)), clamped to [lo, hi]."""
    if not np.isfinite(value) or value <= lo:
        return lo
    return int(min(hi, max(lo, 1 << int(round(np.log2(value))))))


def size_for_density(stats: SurfaceStatistics, density: float | None = None,
                     auto_range: tuple[int, int] = AUTO_SIZE_RANGE) -> int:
    """Texture width (= height) giving ``density`` texels per mesh unit on the surface: the layout spends
    ``uv_coverage * size^2`` texels on ``area`` square units, so size = density * sqrt(area / uv_coverage).

    ``density`` None: :meth:`SurfaceStatistics.auto_density`, the result clamped to ``auto_range`` (a bake may
    ask for less than :data:`AUTO_SIZE_RANGE`); otherwise clamped to :data:`DENSITY_SIZE_RANGE`. Rounded to a power
    of two (mipmaps, block compression)."""
    lo, hi = auto_range if density is None else DENSITY_SIZE_RANGE
    if density is None:
        density = stats.auto_density()
    if stats.area <= 0 or stats.uv_coverage <= 0 or density <= 0:
        return lo
    return power_of_two(density * np.sqrt(stats.area / stats.uv_coverage), lo, hi)
