"""A sculpt with an analytic surface and its game mesh, for the bakes from another mesh (``--from``).

The high mesh is a geodesic sphere (an icosahedron whose faces are split into ``frequency``^2 triangles, projected
to the sphere) displaced radially by a height field: r(u) = 1 + a f(u) on unit directions u, with f smooth in
Cartesian coordinates (no pole singularity). Its analytic normal is the gradient of F(x) = |x| - 1 - a f(x/|x|).
The low mesh is a UV sphere (latitude-longitude layout, a seam at u = 0/1, pole triangles).
"""
from __future__ import annotations

import numpy as np

AMPLITUDE = 0.04


def height(u: np.ndarray) -> np.ndarray:
    x, y, z = u[..., 0], u[..., 1], u[..., 2]
    return np.sin(3.0 * x + 1.0) * np.cos(4.0 * y) + 0.5 * np.sin(5.0 * z + 0.3 * x)


def height_gradient(u: np.ndarray) -> np.ndarray:
    x, y, z = u[..., 0], u[..., 1], u[..., 2]
    gx = 3.0 * np.cos(3.0 * x + 1.0) * np.cos(4.0 * y) + 0.15 * np.cos(5.0 * z + 0.3 * x)
    gy = -4.0 * np.sin(3.0 * x + 1.0) * np.sin(4.0 * y)
    gz = 2.5 * np.cos(5.0 * z + 0.3 * x)
    return np.stack([gx, gy, gz], axis=-1)


def surface_point(u: np.ndarray, amplitude: float = AMPLITUDE) -> np.ndarray:
    """The displaced surface along unit directions ``u``."""
    return u * (1.0 + amplitude * height(u))[..., None]


def analytic_normal(points: np.ndarray, amplitude: float = AMPLITUDE) -> np.ndarray:
    """Unit outward normal of the displaced sphere at points on it: grad F / |grad F|."""
    r = np.linalg.norm(points, axis=-1, keepdims=True)
    u = points / r
    g = height_gradient(u)
    tangential = g - u * np.sum(g * u, axis=-1, keepdims=True)
    n = u - amplitude * tangential / r
    return n / np.linalg.norm(n, axis=-1, keepdims=True)


def icosahedron():
    t = (1.0 + 5 ** 0.5) / 2.0
    v = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
                  [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], float)
    f = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2],
                  [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5],
                  [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]])
    return v / np.linalg.norm(v, axis=1, keepdims=True), f


def geodesic_sphere(frequency: int) -> tuple[np.ndarray, np.ndarray]:
    """20 frequency^2 triangles, vertices shared (welded by rounding), outward winding."""
    base_v, base_f = icosahedron()
    verts, faces = [], []
    index = {}

    def vid(p):
        key = tuple(np.round(p, 9))
        if key not in index:
            index[key] = len(verts)
            verts.append(p)
        return index[key]

    n = frequency
    for a, b, c in base_f:
        A, B, C = base_v[a], base_v[b], base_v[c]
        grid = {}
        for i in range(n + 1):
            for j in range(n + 1 - i):
                p = A + (B - A) * i / n + (C - A) * j / n
                grid[(i, j)] = vid(p / np.linalg.norm(p))
        for i in range(n):
            for j in range(n - i):
                faces.append((grid[(i, j)], grid[(i + 1, j)], grid[(i, j + 1)]))
                if j < n - i - 1:
                    faces.append((grid[(i + 1, j)], grid[(i + 1, j + 1)], grid[(i, j + 1)]))
    return np.array(verts), np.array(faces, np.int64)


def high_mesh(frequency: int = 45, amplitude: float = AMPLITUDE) -> tuple[np.ndarray, np.ndarray]:
    u, faces = geodesic_sphere(frequency)
    return surface_point(u, amplitude), faces


def uv_sphere(slices: int = 32, stacks: int = 32):
    """(positions, uvs, faces): a unit UV sphere, 2 slices (stacks - 1) triangles, glTF UVs (v down from the top)."""
    positions, uvs, faces = [], [], []
    for s in range(stacks + 1):
        theta = np.pi * s / stacks
        for k in range(slices + 1):
            phi = 2.0 * np.pi * k / slices
            positions.append((np.sin(theta) * np.cos(phi), np.cos(theta), -np.sin(theta) * np.sin(phi)))
            uvs.append((k / slices, s / stacks))
    row = slices + 1
    for s in range(stacks):
        for k in range(slices):
            a, b, c, d = s * row + k, s * row + k + 1, (s + 1) * row + k, (s + 1) * row + k + 1
            if s > 0:
                faces.append((a, c, b))
            if s < stacks - 1:
                faces.append((b, c, d))
    return np.array(positions), np.array(uvs), np.array(faces, np.int64)


def write_obj(path, positions, faces, uvs=None) -> None:
    """Wavefront OBJ (vt with v flipped: OBJ's v grows upwards)."""
    lines = [f"v {x:.9f} {y:.9f} {z:.9f}" for x, y, z in positions]
    if uvs is not None:
        lines += [f"vt {u:.9f} {1.0 - v:.9f}" for u, v in uvs]
        lines += [f"f {a + 1}/{a + 1} {b + 1}/{b + 1} {c + 1}/{c + 1}" for a, b, c in faces]
    else:
        lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    path.write_text("\n".join(lines) + "\n")


def write_obj_parts(path, parts) -> None:
    """Wavefront OBJ of several named meshes (one ``usemtl NAME`` group each: baker reads a mesh per material, named
    by it): ``parts`` lists (name, positions, faces, uvs or None)."""
    lines, base, base_uv = [], 0, 0
    for name, positions, faces, uvs in parts:
        lines.append(f"usemtl {name}")
        lines += [f"v {x:.9f} {y:.9f} {z:.9f}" for x, y, z in positions]
        if uvs is not None:
            lines += [f"vt {u:.9f} {1.0 - v:.9f}" for u, v in uvs]
            lines += [f"f {a + base + 1}/{a + base_uv + 1} {b + base + 1}/{b + base_uv + 1} {c + base + 1}/{c + base_uv + 1}"
                      for a, b, c in faces]
            base_uv += len(uvs)
        else:
            lines += [f"f {a + base + 1} {b + base + 1} {c + base + 1}" for a, b, c in faces]
        base += len(positions)
    path.write_text("\n".join(lines) + "\n")
