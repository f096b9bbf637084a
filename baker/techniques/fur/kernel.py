"""Fur shells and fins: a tileable volume of hair cylinders, sliced into shell textures and one fin texture.

Lengyel, Praun, Finkelstein & Hoppe, "Real-Time Fur over Arbitrary Surfaces", I3D 2001 (RTR4 14.7.3): fur is
drawn as ``N`` shells, copies of the surface pushed out along the normal, each textured with a horizontal slice of
a hair volume, plus *fins*, quads standing on the mesh edges near the silhouette and textured with a vertical slice,
which hide the shells' break-up into dots where they are seen edge-on.

The volume is one tile, periodic in u and v, of unit height. Each hair is a tapered cylinder: a root uniform in the
tile, a lean (a straight slant, uniform in a disc of radius ``lean`` tile units over the full height), a height
uniform in ``[min_height, 1]``, a radius falling linearly from ``root_radius`` to ``tip_radius`` (tile units) over
its height, and a brightness jitter. Shell ``i`` of ``N`` is the slice at height ``(i + 0.5) / N``: a texel's alpha
is the hair coverage of the texel (analytic distance to the cylinder's cross-section, antialiased over one texel),
its colour the colour of the covering hair (``mix(root_color, tip_color, height)`` x jitter). The fin texture is the
side view of a slab of the volume (``fin_depth`` of the tile in v), rows from the tip (top) to the root (bottom).

All loops are compiled (numba, per hair over the texels of its footprint); randomness comes from ``seed``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from baker.techniques.fur.options import FurOptions




@dataclass
class FurVolume:
    roots: np.ndarray  # (h, 2) in [0, 1)
    lean: np.ndarray  # (h, 2) offset at height 1
    height: np.ndarray  # (h,) in [min_height, 1]
    jitter: np.ndarray  # (h,) brightness scale


@dataclass
class FurTextures:
    shells: np.ndarray  # (N, S, S, 4) uint8 RGBA (straight alpha)
    fin: np.ndarray  # (S // 2, S, 4) uint8 RGBA, row 0 = tip
    coverage: np.ndarray  # (N,) mean alpha of each shell (0..1)


def make_volume(options: FurOptions, seed: int = 0) -> FurVolume:
    rng = np.random.default_rng(seed)
    n = options.hairs
    roots = rng.random((n, 2))
    phi = rng.random(n) * 2.0 * math.pi
    r = np.sqrt(rng.random(n)) * options.lean
    lean = np.stack([np.cos(phi) * r, np.sin(phi) * r], axis=1)
    height = options.min_height + (1.0 - options.min_height) * rng.random(n)
    jitter = 0.8 + 0.4 * rng.random(n)
    return FurVolume(roots, lean, height, jitter)


@numba.njit(cache=True, nogil=True)
def _splat_shell(size, h, roots, lean, height, jitter, r_root, r_tip, root_color, tip_color, out_alpha, out_rgb):
    """Union of the hairs' discs at height ``h`` (periodic tile), antialiased over one texel."""
    for i in range(roots.shape[0]):
        if height[i] <= h:
            continue
        s = h / height[i]
        radius = (r_root + (r_tip - r_root) * s) * size
        cx = (roots[i, 0] + lean[i, 0] * h) * size
        cy = (roots[i, 1] + lean[i, 1] * h) * size
        reach = int(math.ceil(radius + 1.0))
        x0, y0 = int(math.floor(cx)), int(math.floor(cy))
        for dy in range(-reach, reach + 1):
            for dx in range(-reach, reach + 1):
                px, py = x0 + dx, y0 + dy
                d = math.sqrt((px + 0.5 - cx) ** 2 + (py + 0.5 - cy) ** 2)
                a = min(1.0, max(0.0, radius - d + 0.5))
                if a <= 0.0:
                    continue
                tx, ty = px % size, py % size
                if a > out_alpha[ty, tx]:
                    out_alpha[ty, tx] = a
                    for c in range(3):
                        out_rgb[ty, tx, c] = min(1.0, (root_color[c] + (tip_color[c] - root_color[c]) * h) * jitter[i])


@numba.njit(cache=True, nogil=True)
def _splat_fin(width, rows, depth, roots, lean, height, jitter, r_root, r_tip, root_color, tip_color, out_alpha,
               out_rgb):
    """Side view (along v) of the hairs whose root lies in the slab v in [0, depth): rows top = tip."""
    for i in range(roots.shape[0]):
        if roots[i, 1] >= depth:
            continue
        for row in range(rows):
            h = 1.0 - (row + 0.5) / rows
            if height[i] <= h:
                continue
            s = h / height[i]
            radius = (r_root + (r_tip - r_root) * s) * width
            cx = (roots[i, 0] + lean[i, 0] * h) * width
            reach = int(math.ceil(radius + 1.0))
            x0 = int(math.floor(cx))
            for dx in range(-reach, reach + 1):
                px = x0 + dx
                a = min(1.0, max(0.0, radius - abs(px + 0.5 - cx) + 0.5))
                if a <= 0.0:
                    continue
                tx = px % width
                if a > out_alpha[row, tx]:
                    out_alpha[row, tx] = a
                    for c in range(3):
                        out_rgb[row, tx, c] = min(1.0, (root_color[c] + (tip_color[c] - root_color[c]) * h) * jitter[i])


def shell_heights(shells: int) -> np.ndarray:
    """Height (0..1 of the fur length) of each shell's slice."""
    return (np.arange(shells) + 0.5) / shells


def bake_fur_textures(options: FurOptions, seed: int = 0) -> FurTextures:
    vol = make_volume(options, seed)
    size = options.texture_size
    root_c = np.asarray(options.root_color, np.float64)
    tip_c = np.asarray(options.tip_color, np.float64)
    shells = np.zeros((options.shells, size, size, 4), np.uint8)
    coverage = np.zeros(options.shells)
    for i, h in enumerate(shell_heights(options.shells)):
        alpha = np.zeros((size, size))
        rgb = np.zeros((size, size, 3)) + (root_c + (tip_c - root_c) * h)  # under transparent texels: no dark halo
        _splat_shell(size, h, vol.roots, vol.lean, vol.height, vol.jitter, options.root_radius, options.tip_radius,
                     root_c, tip_c, alpha, rgb)
        shells[i, ..., :3] = np.rint(np.clip(rgb, 0, 1) ** (1 / 2.2) * 255)  # sRGB-ish encoding for colour
        shells[i, ..., 3] = np.rint(alpha * 255)
        coverage[i] = alpha.mean()
    rows = max(4, size // 2)
    alpha = np.zeros((rows, size))
    rgb = np.zeros((rows, size, 3)) + root_c
    _splat_fin(size, rows, options.fin_depth, vol.roots, vol.lean, vol.height, vol.jitter, options.root_radius,
               options.tip_radius, root_c, tip_c, alpha, rgb)
    fin = np.zeros((rows, size, 4), np.uint8)
    fin[..., :3] = np.rint(np.clip(rgb, 0, 1) ** (1 / 2.2) * 255)
    fin[..., 3] = np.rint(alpha * 255)
    return FurTextures(shells, fin, coverage)
