"""Coverage images of strands and of hair cards, rendered the same way (orthographic, numpy): what the card tests,
the Blender test and ``benchmarks/cards.py`` compare. Cards are alpha-tested at pixel centres on the nearest texel
of the base colour's alpha; strands mark every pixel a segment crosses; both at a supersampled size, reduced by
:func:`coverage_image`."""
from __future__ import annotations

import numpy as np


def alpha_at(cards, uv):
    size = cards["color"].shape[0]
    texel = np.clip(np.floor(uv * size).astype(np.int64), 0, size - 1)
    return cards["color"][texel[:, 1], texel[:, 0], 3]


def view_basis(azimuth, elevation):
    a, e = np.radians(azimuth), np.radians(elevation)
    forward = np.array([np.cos(e) * np.sin(a), np.sin(e), np.cos(e) * np.cos(a)])
    right = np.cross([0.0, 1.0, 0.0], forward)
    right /= np.linalg.norm(right)
    return right, np.cross(forward, right)


def strand_silhouette(curves, basis, box, size):
    """Pixels crossed by any strand segment (orthographic, segments sampled every quarter pixel)."""
    image = np.zeros((size, size), bool)
    lo, span = box
    for c in curves:
        xy = (np.stack([c @ basis[0], c @ basis[1]], 1) - lo) / span * size
        steps = np.maximum(np.ceil(np.linalg.norm(np.diff(xy, axis=0), axis=1) * 4).astype(int), 1)
        seg = np.repeat(np.arange(len(steps)), steps)
        # k / steps for k = 0 .. steps - 1 along each segment (np.linspace(0, 1, steps, endpoint=False), at once)
        t = (np.arange(len(seg)) - np.repeat(np.cumsum(steps) - steps, steps)) / np.repeat(steps, steps)
        pts = xy[seg] + t[:, None] * (xy[seg + 1] - xy[seg])
        ij = np.clip(pts.astype(int), 0, size - 1)
        image[ij[:, 1], ij[:, 0]] = True
    return image


def card_silhouette(cards, basis, box, size, cutoff):
    """Pixels whose centre falls on a card triangle at a texel whose alpha passes the cutoff (nearest texel)."""
    image = np.zeros((size, size), bool)
    lo, span = box
    pos = cards["positions"]
    xy = (np.stack([pos @ basis[0], pos @ basis[1]], 1) - lo) / span * size
    for tri in cards["triangles"]:
        a, b, c = xy[tri]
        x0, y0 = np.floor(np.minimum(np.minimum(a, b), c)).astype(int)
        x1, y1 = np.ceil(np.maximum(np.maximum(a, b), c)).astype(int)
        x0, y0, x1, y1 = max(x0, 0), max(y0, 0), min(x1, size), min(y1, size)
        if x1 <= x0 or y1 <= y0:
            continue
        gx, gy = np.meshgrid(np.arange(x0, x1) + 0.5, np.arange(y0, y1) + 0.5)
        p = np.stack([gx.ravel(), gy.ravel()], 1)
        det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
        if abs(det) < 1e-12:
            continue
        l1 = ((p[:, 0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (p[:, 1] - a[1])) / det
        l2 = ((b[0] - a[0]) * (p[:, 1] - a[1]) - (p[:, 0] - a[0]) * (b[1] - a[1])) / det
        inside = (l1 >= 0) & (l2 >= 0) & (l1 + l2 <= 1)
        if not inside.any():
            continue
        w = np.stack([1 - l1 - l2, l1, l2], 1)[inside]
        uv = w @ cards["uv"][tri]
        hit = alpha_at(cards, uv) >= round(cutoff * 255)
        q = p[inside][hit].astype(int)
        image[q[:, 1], q[:, 0]] = True
    return image


def coverage_image(samples, size):
    """A pixel is covered when any of its sub-pixel samples is (both silhouettes are rendered at the same
    supersampled resolution, then reduced the same way)."""
    k = samples.shape[0] // size
    return samples.reshape(size, k, size, k).any(axis=(1, 3))
