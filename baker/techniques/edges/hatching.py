"""Hatching strokes for ``baker lines --hatching``: streamlines of a principal-direction cross field, evenly spaced in
screen space, denser where a Lambert light leaves the surface darker (RTR4 15.3; issue 38 item 4).

1. **Field**: per vertex of the welded scene, principal curvatures (:mod:`baker.techniques.curvature.kernel`) and
   Knöppel et al.'s globally optimal cross field aligned with them where |k1 - k2| is clear
   (:func:`baker.geometry.direction_field.cross_field`, one solve per connected piece: a piece without any
   anisotropy, a plane, gets its smoothest field), weighted ``alignment`` = 0.1 against smoothness: on a scanned
   mesh (the bunny) the strokes then follow the form rather than the fit's noise, while on a torus or a cylinder
   they still follow the principal directions to half a degree (tests/techniques/test_hatching.py). Of the cross's four directions the *primary* one is the branch
   nearest the direction of the largest curvature k1 (around a cylinder, across a torus's tube), the secondary one
   turned by 90 degrees (Hertzmann & Zorin 2000 draw strokes along principal directions the same way).
2. **The visible surface**: one ray per pixel centre from the eye (Embree, the visibility ``baker lines`` uses for its
   lines), giving the surface point, its triangle and barycentrics; there the vertex field is interpolated (each
   corner's cross turned to the branch nearest the first corner's), the smooth normal turned towards the eye, the
   tone is Lambert's max(0, n . l), and both field branches are projected to the screen. A stroke placed on this
   image *is* on the surface: the projection of a surface curve tangent to the field is tangent to the projected
   field, and every stroke point back-projects through its pixel to the surface it was integrated on.
3. **Streamlines** (Jobard & Lefer, "Creating evenly-spaced streamlines of arbitrary density", 1997): a seed is kept
   only at least d_sep from every existing stroke point; from it the field is integrated both ways (midpoint rule,
   ``step`` pixels; at each step the cross branch nearest the previous step's direction, so a stroke never jumps to
   the other family) until it comes within d_test = ``test_ratio`` d_sep of another stroke (or of itself, further
   than 2 d_test along its own arc), leaves the surface, crosses a depth discontinuity (a silhouette, or the edge
   of something in front: the surface point jumps further than the step can move it), grows too foreshortened
   (grazing view) or turns more than ``max_turn`` in one step, or enters a tone too light for it. New seeds are
   taken d_sep to each side of every accepted stroke, then from a shuffled grid (the ``seed``), so the result is
   deterministic for a seed. d_sep follows the tone: ``spacing`` pixels at the darkest, up to ``spacing x
   max_ratio`` at the lightest hatched tone; paper lighter than ``min_darkness`` gets no stroke. Where the surface
   is darker than ``cross_darkness`` a second family along the secondary branch cross-hatches it (placed the same
   way, evenly spaced among itself; it crosses the first family by design).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numba
import numpy as np

from baker.progress import QUIET, Progress


# peak bytes per pixel of the drawing: the pixel rays, the surface image (point, both branches' tangents and
# projections, tone, slack) and the temporaries that build it (measured: 255 on a 1600 x 1600 drawing of a sphere)
BYTES_PER_PIXEL = 320


@dataclass(frozen=True)
class HatchSettings:
    spacing: float = 6.0  # d_sep at the darkest tone, pixels
    test_ratio: float = 0.5  # d_test / d_sep (Jobard & Lefer's recommendation)
    max_ratio: float = 4.0  # d_sep at the lightest hatched tone / spacing
    step: float = 1.0  # integration step, pixels
    min_darkness: float = 0.25  # 1 - Lambert below which the paper stays white
    cross_darkness: float = 0.65  # 1 - Lambert above which a second family cross-hatches
    min_length: float = 3.0  # shortest stroke kept, in units of its seed's d_sep
    max_turn_degrees: float = 20.0  # largest turn of a stroke in one step
    min_foreshortening: float = 0.25  # projected length of a unit tangent / that of one facing the eye
    light: tuple | None = None  # world direction towards a directional light; None: camera-relative default
    alignment: float = 0.1  # the cross field's data weight against its smoothness (``cross_field``'s)
    seed: int = 0


@dataclass
class Hatching:
    primary: list  # (n, 2) pixel polylines along the primary branch
    cross: list  # (n, 2) pixel polylines of the cross-hatching family
    darkness: np.ndarray = field(repr=False)  # (H, W) 1 - Lambert of the visible surface (0 where nothing is hit)
    d_test: np.ndarray = field(repr=False)  # (2, H, W) the separating distance each family kept, pixels


def default_light(camera) -> np.ndarray:
    """Towards a directional light above and to the left of the eye, in front of the subject (a classic key)."""
    right, up, forward = camera.basis()
    light = -0.45 * right + 0.6 * up - 0.65 * forward
    return light / np.linalg.norm(light)


# ---------------------------------------------------------------------------------------------------------- field
def principal_cross_field(positions: np.ndarray, faces: np.ndarray,
                          alignment: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """(unit vertex normals, primary field direction per vertex) of a welded mesh: the cross field of
    :mod:`baker.geometry.direction_field` aligned with the principal directions, turned to its branch nearest
    the k1 direction. A vertex used by no face gets a zero direction."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    from baker.geometry.normals import vertex_normals
    from baker.techniques.curvature.kernel import principal_curvatures
    from baker.geometry.direction_field import anisotropy, cross_field

    positions = np.asarray(positions, np.float64)
    faces = np.asarray(faces, np.int64)
    n = len(positions)
    normals = vertex_normals(positions, faces)
    curvature = principal_curvatures(positions, faces)
    spread = np.abs(curvature.k1 - curvature.k2)
    used = np.zeros(n, bool)
    used[faces.reshape(-1)] = True
    diagonal = float(np.linalg.norm(positions.max(0) - positions.min(0))) or 1.0
    # the noise level: the median spread, but never below what a radius of curvature 100 scene sizes long spreads
    # (on a scene of planes and spheres the median is rounding noise, which would make noise directions count)
    noise = max(float(np.median(spread[used])) if used.any() else 0.0, 0.01 / diagonal)
    strength = anisotropy(curvature.k1, curvature.k2, noise)
    direction = np.zeros((n, 3))
    rows = faces[:, [0, 1, 2]].reshape(-1)
    cols = faces[:, [1, 2, 0]].reshape(-1)
    adjacency = sp.coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n))
    count, label = connected_components(adjacency, directed=False)
    face_label = label[faces[:, 0]]
    order = np.argsort(face_label, kind="stable")
    bounds = np.searchsorted(face_label[order], np.arange(count + 1))
    for c in range(count):
        piece_faces = faces[order[bounds[c]:bounds[c + 1]]]
        if not len(piece_faces):
            continue
        vertices, local = np.unique(piece_faces, return_inverse=True)
        piece = cross_field(positions[vertices], local.reshape(-1, 3), normals[vertices],
                            directions=curvature.direction1[vertices], strength=strength[vertices],
                            alignment=alignment)
        direction[vertices] = piece.direction
    # the branch nearest the k1 direction: d or n x d, whichever is more parallel to it
    turned = np.cross(normals, direction)
    k1 = curvature.direction1
    swap = np.abs(np.einsum("ij,ij->i", turned, k1)) > np.abs(np.einsum("ij,ij->i", direction, k1))
    direction[swap] = turned[swap]
    return normals, direction


# ---------------------------------------------------------------------------------------------------------- image
def pixel_rays(camera) -> tuple[np.ndarray, np.ndarray]:
    """(origins, unit directions) of one ray through each pixel centre, row-major (H * W, 3)."""
    right, up, forward = camera.basis()
    width, height = camera.width, camera.height
    x, y = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
    sx = (2.0 * x / width - 1.0).reshape(-1)
    sy = (1.0 - 2.0 * y / height).reshape(-1)
    aspect = width / height
    eye = np.asarray(camera.eye, np.float64)
    if camera.orthographic:
        origins = eye + np.outer(sx * camera.ymag * aspect, right) + np.outer(sy * camera.ymag, up)
        directions = np.tile(forward, (len(sx), 1))
    else:
        t = math.tan(camera.yfov / 2.0)
        directions = forward + np.outer(sx * t * aspect, right) + np.outer(sy * t, up)
        directions /= np.linalg.norm(directions, axis=1)[:, None]
        origins = np.tile(eye, (len(sx), 1))
    return origins, directions


def matched(reference: np.ndarray, direction: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """``direction``'s cross branch (d, -d, n x d, -(n x d)) nearest ``reference``, row by row."""
    turned = np.cross(normal, direction)
    a = np.einsum("ij,ij->i", direction, reference)
    b = np.einsum("ij,ij->i", turned, reference)
    use_turned = np.abs(b) > np.abs(a)
    out = np.where(use_turned[:, None], turned, direction)
    sign = np.where(use_turned, np.sign(b), np.sign(a))
    return out * np.where(sign == 0, 1.0, sign)[:, None]


@dataclass
class SurfaceImage:
    """What each pixel sees of the surface; arrays (H, W, ...), valid False where the ray hits nothing."""

    valid: np.ndarray
    point: np.ndarray  # (H, W, 3) surface point
    tangent: np.ndarray  # (2, H, W, 3) primary / secondary branch: unit tangents on the surface
    screen: np.ndarray  # (2, H, W, 2) the same projected: pixels per (pixel-sized) world step
    darkness: np.ndarray  # (H, W) 1 - max(0, n . l)
    slack: np.ndarray  # (H, W) world distance a one-pixel move along the surface may cover before it is a jump


def surface_image(camera, scene, positions, faces, normals, direction, light) -> SurfaceImage:
    """Cast the pixel rays and evaluate, per pixel, the surface point, tone and projected field (module doc, 2)."""
    width, height = camera.width, camera.height
    origins, rays = pixel_rays(camera)
    distance, face, u, v = scene.first_hits(origins, rays)
    valid = (face >= 0) & (distance < scene.MISS)
    idx = np.flatnonzero(valid)
    f = faces[face[idx]]
    bary = np.stack([1.0 - u[idx] - v[idx], u[idx], v[idx]], axis=1).astype(np.float64)
    point = np.einsum("pk,pkc->pc", bary, positions[f])
    view = rays[idx]
    face_normal = np.cross(positions[f[:, 1]] - positions[f[:, 0]], positions[f[:, 2]] - positions[f[:, 0]])
    normal = np.einsum("pk,pkc->pc", bary, normals[f])
    # seen from behind (a one-sided plane, an open mesh's inside): shade the side the eye sees
    toward = np.where(np.einsum("ij,ij->i", face_normal, view) > 0, -1.0, 1.0)
    normal *= toward[:, None]
    bad = np.linalg.norm(normal, axis=1) < 1e-12
    normal[bad] = (face_normal[bad] * toward[bad, None])
    normal /= np.maximum(np.linalg.norm(normal, axis=1), 1e-300)[:, None]
    corner = direction[f]  # (p, 3, 3)
    corner_normal = normals[f]
    first = corner[:, 0]
    along = bary[:, :1] * first
    for k in (1, 2):
        along += bary[:, k:k + 1] * matched(first, corner[:, k], corner_normal[:, k])
    along -= normal * np.einsum("ij,ij->i", along, normal)[:, None]
    length = np.linalg.norm(along, axis=1)
    along /= np.maximum(length, 1e-300)[:, None]
    second = np.cross(normal, along)
    darkness = 1.0 - np.clip(normal @ np.asarray(light, np.float64), 0.0, 1.0)
    # the world size of one pixel at the point, facing the eye: projected tangents are measured in it, so that a
    # tangent's projected length is its foreshortening (1: in the image plane)
    if camera.orthographic:
        pixel = np.full(len(idx), 2.0 * camera.ymag / height)
    else:
        depth = (point - camera.eye) @ camera.basis()[2]
        pixel = 2.0 * depth * math.tan(camera.yfov / 2.0) / height
    here, _ = camera.project(point)
    screen = np.zeros((2, height * width, 2))
    tangents = np.zeros((2, height * width, 3))
    for b, tangent in enumerate((along, second)):
        tangents[b, idx] = tangent
        there, _ = camera.project(point + tangent * (1e-3 * pixel)[:, None])
        projected = (there - here) / 1e-3
        projected[length < 1e-9] = 0.0  # no field here (an isolated corner): no stroke either
        screen[b, idx] = projected
        tangents[b, idx[length < 1e-9]] = 0.0
    cos_view = np.abs(np.einsum("ij,ij->i", normal, view))
    out_point = np.zeros((height * width, 3))
    out_point[idx] = point
    out_dark = np.zeros(height * width)
    out_dark[idx] = darkness
    slack = np.zeros(height * width)
    # a one-pixel step along the surface covers at most pixel / cos(view) of it; a few times that is a jump
    slack[idx] = 3.0 * pixel / np.maximum(cos_view, 0.2)
    return SurfaceImage(valid.reshape(height, width), out_point.reshape(height, width, 3),
                        tangents.reshape(2, height, width, 3), screen.reshape(2, height, width, 2), out_dark.reshape(height, width),
                        slack.reshape(height, width))


# ---------------------------------------------------------------------------------------------------- streamlines
@numba.njit(cache=True, nogil=True)
def _direction(screen, tangent, valid, point, slack, x, y, r):
    """The field at pixel position (x, y): the four pixel centres around it, each turned to its cross branch whose
    tangent on the surface is nearest the 3D direction ``r`` (continuity judged on the surface, where the branches
    stay 90 degrees apart, not on screen, where foreshortening can bring them together), weighted bilinearly;
    pixels across a depth jump from the nearest one are left out. Returns (dx, dy, foreshortening, tangent, ok)."""
    h, w = valid.shape
    out = np.zeros(3)
    ix, iy = int(math.floor(x)), int(math.floor(y))
    if ix < 0 or iy < 0 or ix >= w or iy >= h or not valid[iy, ix]:
        return 0.0, 0.0, 0.0, out, False
    gx, gy = x - 0.5, y - 0.5
    x0, y0 = int(math.floor(gx)), int(math.floor(gy))
    fx, fy = gx - x0, gy - y0
    sx, sy, total = 0.0, 0.0, 0.0
    for j in range(2):
        for i in range(2):
            px, py = x0 + i, y0 + j
            if px < 0 or py < 0 or px >= w or py >= h or not valid[py, px]:
                continue
            d2 = 0.0
            for c in range(3):
                d2 += (point[py, px, c] - point[iy, ix, c]) ** 2
            if d2 > (2.0 * slack[iy, ix]) ** 2:
                continue
            weight = (fx if i else 1.0 - fx) * (fy if j else 1.0 - fy)
            best, branch, sign = 0.0, -1, 1.0
            for b in range(2):
                dot = tangent[b, py, px, 0] * r[0] + tangent[b, py, px, 1] * r[1] + tangent[b, py, px, 2] * r[2]
                if abs(dot) > best:
                    best, branch, sign = abs(dot), b, 1.0 if dot >= 0 else -1.0
            if branch < 0:
                continue
            sx += weight * sign * screen[branch, py, px, 0]
            sy += weight * sign * screen[branch, py, px, 1]
            for c in range(3):
                out[c] += weight * sign * tangent[branch, py, px, c]
            total += weight
    if total <= 0.0:
        return 0.0, 0.0, 0.0, out, False
    sx /= total
    sy /= total
    fore = math.sqrt(sx * sx + sy * sy)
    norm = math.sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2])
    if fore <= 0.0 or norm <= 0.0:
        return 0.0, 0.0, 0.0, out, False
    return sx / fore, sy / fore, fore, out / norm, True


@numba.njit(cache=True, nogil=True)
def _near(x, y, radius, line, arc, self_gap, px, py, pline, parc, alive, head, nxt, cell, gw, gh):
    """True when a stroke point lies closer than ``radius`` to (x, y): any point of another live stroke, or of stroke
    ``line`` itself further than ``self_gap`` from ``arc`` along it."""
    cx, cy = int(x // cell), int(y // cell)
    reach = int(math.ceil(radius / cell))
    r2 = radius * radius
    for gy in range(max(cy - reach, 0), min(cy + reach + 1, gh)):
        for gx in range(max(cx - reach, 0), min(cx + reach + 1, gw)):
            k = head[gy * gw + gx]
            while k >= 0:
                if alive[pline[k]] and (pline[k] != line or abs(parc[k] - arc) > self_gap):
                    dx, dy = px[k] - x, py[k] - y
                    if dx * dx + dy * dy < r2:
                        return True
                k = nxt[k]
    return False


@numba.njit(cache=True, nogil=True)
def _push(x, y, line, arc, px, py, pline, parc, head, nxt, cell, gw, state):
    k = state[4]
    if k >= len(px):
        return False
    px[k], py[k], pline[k], parc[k] = x, y, line, arc
    g = int(y // cell) * gw + int(x // cell)
    nxt[k] = head[g]
    head[g] = k
    state[4] = k + 1
    return True


@numba.njit(cache=True, nogil=True)
def _trace(sx, sy, sign, line, screen, tangent, valid, point, slack, darkness, dsep, floor, params,
           px, py, pline, parc, alive, head, nxt, cell, gw, gh, state):
    """Grow stroke ``line`` from its seed (sx, sy) one way (sign +1: along the seed's direction, -1: against it);
    returns the arc length covered."""
    step, test_ratio, max_turn_cos, min_fore = params[0], params[1], params[2], params[3]
    h, w = valid.shape
    # the seed's own branch (index 0 is this family's), the way ``sign`` says
    ix, iy = int(math.floor(sx)), int(math.floor(sy))
    ax, ay = screen[0, iy, ix, 0], screen[0, iy, ix, 1]
    if math.sqrt(ax * ax + ay * ay) < min_fore:  # seen nearly end on: its direction on screen is not to be trusted
        return 0.0
    r = sign * tangent[0, iy, ix].copy()
    rx, ry = 0.0, 0.0
    x, y, arc = sx, sy, 0.0
    first = True
    limit = 4 * (h + w) * (h + w) / step  # a stroke can't be longer than the image's area in steps
    for _ in range(int(limit)):
        d1x, d1y, f1, t1, ok = _direction(screen, tangent, valid, point, slack, x, y, r)
        if not ok:
            break
        mx, my = x + 0.5 * step * d1x, y + 0.5 * step * d1y
        d2x, d2y, f2, t2, ok = _direction(screen, tangent, valid, point, slack, mx, my, t1)
        if not ok or f2 < min_fore or (not first and d2x * rx + d2y * ry < max_turn_cos):
            break
        nx, ny = x + step * d2x, y + step * d2y
        ix, iy = int(math.floor(nx)), int(math.floor(ny))
        if ix < 0 or iy < 0 or ix >= w or iy >= h or not valid[iy, ix]:
            break
        if darkness[iy, ix] < floor:
            break
        jump = 0.0
        ox, oy = int(math.floor(x)), int(math.floor(y))
        for c in range(3):
            jump += (point[iy, ix, c] - point[oy, ox, c]) ** 2
        if jump > (step * slack[oy, ox]) ** 2:
            break
        d_test = test_ratio * dsep[iy, ix]
        next_arc = arc + sign * step
        if _near(nx, ny, d_test, line, next_arc, 2.0 * d_test, px, py, pline, parc, alive, head, nxt, cell, gw, gh):
            break
        if not _push(nx, ny, line, next_arc, px, py, pline, parc, head, nxt, cell, gw, state):
            break
        x, y, rx, ry, r, arc = nx, ny, d2x, d2y, t2, next_arc
        first = False
    return abs(arc)


@numba.njit(cache=True, nogil=True)
def _try_seed(x, y, screen, tangent, valid, point, slack, darkness, dsep, floor, params, px, py, pline, parc, alive,
              line_start, line_end, head, nxt, cell, gw, gh, state, queue):
    """Place a stroke from seed (x, y) if it is far enough from every other; True when one was kept."""
    h, w = valid.shape
    ix, iy = int(math.floor(x)), int(math.floor(y))
    if ix < 0 or iy < 0 or ix >= w or iy >= h or not valid[iy, ix] or darkness[iy, ix] < floor:
        return False
    line = state[5]
    if line >= len(alive) or state[4] >= len(px):
        return False
    if _near(x, y, dsep[iy, ix], -1, 0.0, 0.0, px, py, pline, parc, alive, head, nxt, cell, gw, gh):
        return False
    start = state[4]
    alive[line] = True
    if not _push(x, y, line, 0.0, px, py, pline, parc, head, nxt, cell, gw, state):
        return False
    length = _trace(x, y, 1.0, line, screen, tangent, valid, point, slack, darkness, dsep, floor, params,
                    px, py, pline, parc, alive, head, nxt, cell, gw, gh, state)
    length += _trace(x, y, -1.0, line, screen, tangent, valid, point, slack, darkness, dsep, floor, params,
                     px, py, pline, parc, alive, head, nxt, cell, gw, gh, state)
    line_start[line], line_end[line] = start, state[4]
    state[5] = line + 1
    if length < params[4] * dsep[iy, ix]:
        alive[line] = False  # too short: its points stay in the arrays but no query sees them
        return False
    queue[state[1]] = line
    state[1] += 1
    return True


@numba.njit(cache=True, nogil=True)
def _place(screen, tangent, valid, point, slack, darkness, dsep, floor, params, seeds, px, py, pline, parc, alive,
           line_start, line_end, head, nxt, cell, gw, gh, state, queue, budget):
    """Jobard & Lefer's loop for up to ``budget`` seed tries: seeds beside accepted strokes first (queue), else the
    next shuffled grid seed. ``state``: queue head, queue tail, position in the head stroke, side, points used,
    strokes used, grid seeds used."""
    tries = 0
    while tries < budget:
        if state[0] < state[1]:
            line = queue[state[0]]
            k = line_start[line] + state[2]
            if k >= line_end[line]:
                state[0] += 1
                state[2], state[3] = 0, 0
                continue
            # the stroke's tangent at point k: its neighbours in storage order that are one step away along the arc
            # (a stroke is stored seed, forward points, backward points)
            a, b = k, k
            if k - 1 >= line_start[line] and abs(parc[k - 1] - parc[k]) < 1.5 * params[0]:
                a = k - 1
            if k + 1 < line_end[line] and abs(parc[k + 1] - parc[k]) < 1.5 * params[0]:
                b = k + 1
            if parc[a] > parc[b]:
                a, b = b, a
            tx, ty = px[b] - px[a], py[b] - py[a]
            norm = math.sqrt(tx * tx + ty * ty)
            side = 1.0 if state[3] == 0 else -1.0
            if state[3] == 0:
                state[3] = 1
            else:
                state[3] = 0
                # the next candidates a few steps on: about a third of the local spacing
                ix, iy = int(px[k]), int(py[k])
                stride = 1
                if 0 <= ix < valid.shape[1] and 0 <= iy < valid.shape[0]:
                    stride = max(1, int(dsep[iy, ix] / (3.0 * params[0])))
                state[2] += stride
            if norm <= 0.0:
                continue
            ix, iy = int(px[k]), int(py[k])
            d = dsep[iy, ix]
            sx, sy = px[k] - side * ty / norm * d, py[k] + side * tx / norm * d
            _try_seed(sx, sy, screen, tangent, valid, point, slack, darkness, dsep, floor, params, px, py, pline,
                      parc, alive, line_start, line_end, head, nxt, cell, gw, gh, state, queue)
            tries += 1
        elif state[6] < len(seeds):
            s = state[6]
            state[6] += 1
            _try_seed(seeds[s, 0], seeds[s, 1], screen, tangent, valid, point, slack, darkness, dsep, floor, params,
                      px, py, pline, parc, alive, line_start, line_end, head, nxt, cell, gw, gh, state, queue)
            tries += 1
        else:
            break
    return tries


def separating_distance(darkness: np.ndarray, floor: float, settings: HatchSettings) -> np.ndarray:
    """d_sep per pixel: ``spacing`` at darkness 1, growing as the tone lightens towards ``floor`` (the stroke length
    per area then falls with the tone) up to ``spacing x max_ratio``."""
    share = np.clip((darkness - floor) / max(1.0 - floor, 1e-9), 1.0 / settings.max_ratio, 1.0)
    return settings.spacing / share


def place_family(image: SurfaceImage, family: int, floor: float, settings: HatchSettings, rng, progress: Progress,
                 label: str) -> tuple[list, np.ndarray]:
    """Evenly spaced strokes of one family (0: primary, 1: secondary) where the darkness is at least ``floor``."""
    height, width = image.valid.shape
    dsep = separating_distance(image.darkness, floor, settings)
    # the family's field first, the other branch second: strokes start on their family's branch and may then only
    # turn continuously (the branch nearest the previous direction)
    screen = np.ascontiguousarray(image.screen if family == 0 else image.screen[::-1])
    tangent = np.ascontiguousarray(image.tangent if family == 0 else image.tangent[::-1])
    hatched = image.valid & (image.darkness >= floor)
    stride = max(1, int(settings.spacing // 2))
    ys, xs = np.nonzero(hatched[::stride, ::stride])
    seeds = np.stack([xs * stride + 0.5, ys * stride + 0.5], axis=1).astype(np.float64)
    seeds = seeds[rng.permutation(len(seeds))]
    d_test_min = settings.test_ratio * settings.spacing
    capacity = int(2.5 * hatched.sum() / max(d_test_min * settings.step, 1e-9)) + 4096
    cell = max(d_test_min, 1.0)
    gw, gh = int(width // cell) + 1, int(height // cell) + 1
    px, py, parc = np.zeros(capacity), np.zeros(capacity), np.zeros(capacity)
    pline = np.zeros(capacity, np.int64)
    lines_cap = capacity // 2 + 1
    alive = np.zeros(lines_cap, np.bool_)
    line_start, line_end = np.zeros(lines_cap, np.int64), np.zeros(lines_cap, np.int64)
    queue = np.zeros(lines_cap, np.int64)
    head = np.full(gw * gh, -1, np.int64)
    nxt = np.full(capacity, -1, np.int64)
    state = np.zeros(7, np.int64)
    params = np.array([settings.step, settings.test_ratio, math.cos(math.radians(settings.max_turn_degrees)),
                       settings.min_foreshortening, settings.min_length])
    budget = 512
    # the bar counts stroke points against what evenly spaced strokes would need (one stroke per d_sep across, a
    # point per step along); most seeds come from beside earlier strokes, so the grid seeds used would not move it
    expected = int(np.sum(1.0 / dsep[hatched]) / settings.step) + 1
    with progress.task(label, expected) as advance:
        done = 0
        while True:
            # short compiled batches: Ctrl-C lands between them, and the bar moves
            tries = _place(screen, tangent, image.valid, image.point, image.slack, image.darkness, dsep, floor,
                           params, seeds, px, py, pline, parc, alive, line_start, line_end, head, nxt, cell, gw, gh,
                           state, queue, budget)
            placed = min(int(state[4]), expected - 1)
            advance(max(placed - done, 0))
            done = max(done, placed)
            if tries < budget:
                break
        advance(expected - done)
    strokes = []
    for line in np.flatnonzero(alive[:state[5]]):
        s, e = line_start[line], line_end[line]
        order = np.argsort(parc[s:e], kind="stable")
        strokes.append(np.stack([px[s:e][order], py[s:e][order]], axis=1))
    return strokes, settings.test_ratio * dsep


def hatch(camera, scene, positions: np.ndarray, faces: np.ndarray, settings: HatchSettings = HatchSettings(),
          progress: Progress = QUIET) -> Hatching:
    """Hatching strokes of the welded scene (``positions``, ``faces``, traced by ``scene``) seen by ``camera``."""
    with progress.task("hatching field", 1) as advance:
        normals, direction = principal_cross_field(positions, faces, settings.alignment)
        advance(1)
    light = np.asarray(settings.light, np.float64) if settings.light is not None else default_light(camera)
    light = light / np.linalg.norm(light)
    image = surface_image(camera, scene, np.asarray(positions, np.float64), np.asarray(faces, np.int64), normals,
                          direction, light)
    rng = np.random.default_rng(settings.seed)
    primary, d_test0 = place_family(image, 0, settings.min_darkness, settings, rng, progress, "hatching strokes")
    cross, d_test1 = place_family(image, 1, settings.cross_darkness, settings, rng, progress, "cross-hatching")
    return Hatching(primary, cross, image.darkness, np.stack([d_test0, d_test1]))
