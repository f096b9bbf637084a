"""A second, held-out groom for the hair-card tests and benchmark, unlike ``cards_groom.py``'s: wide clumps (roots
spread over a disc, not a line) that are all curly, on a sphere's upper half, with no tip pull for a third of the
clumps, so a clump's cross-section is a thick blob and a single card cannot cover it. Deterministic for a seed;
returned as the same (curves, widths) lists :func:`cards_groom.write_groom_usd` writes with pxr.

Per clump: a path leaving the scalp along its normal and bending down under gravity (kept off the sphere); per
strand: a root offset on a disc of radius ``clump_radius`` (both directions across the path), scaled down towards
the tip by the clump's tightening, plus a helix around the path (clump's amplitude and turns, the strand's own phase
and amplitude jitter), plus a small random walk.
"""
from __future__ import annotations

import math

import numpy as np

RADIUS = 0.09


def _unit(v):
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-300)


def make_curly_groom(strands: int = 6000, clumps: int = 50, seed: int = 23, clump_radius: float = 0.025,
                     curl: tuple = (0.008, 0.014), lengths: tuple = (0.09, 0.14), turns: tuple = (1.5, 3.0)):
    """(curves: list of (n_i, 3) arrays, widths: list of (n_i,) arrays)."""
    rng = np.random.default_rng(seed)
    # clump centres: Fibonacci-like spread over the upper half (y > -0.2), jittered
    u = (np.arange(clumps) + 0.5) / clumps
    y = -0.2 + 1.2 * u
    y = np.clip(y + rng.normal(0.0, 0.02, clumps), -0.2, 0.98)
    phi = np.arange(clumps) * math.pi * (3.0 - math.sqrt(5.0)) + rng.uniform(0, 0.3, clumps)
    normal = np.stack([np.sqrt(1 - y ** 2) * np.cos(phi), y, np.sqrt(1 - y ** 2) * np.sin(phi)], axis=1)
    steps = 72
    length = rng.uniform(*lengths, clumps)
    paths = np.empty((clumps, steps, 3))
    p = normal * RADIUS
    direction = _unit(normal + 0.3 * rng.normal(size=normal.shape))
    h = length / (steps - 1)
    for j in range(steps):
        paths[:, j] = p
        direction = _unit(direction + np.array([0.0, -0.12, 0.0]))
        p = p + direction * h[:, None]
        r = np.linalg.norm(p, axis=1)
        p = p * (np.maximum(r, RADIUS * 1.03) / r)[:, None]
    tangents = _unit(np.gradient(paths, axis=1))
    side = _unit(np.cross(tangents, _unit(paths)))
    up = np.cross(side, tangents)
    amplitude = rng.uniform(*curl, clumps)
    turns = rng.uniform(*turns, clumps)
    tighten = np.where(rng.random(clumps) < 1 / 3, 0.0, rng.uniform(0.3, 0.7, clumps))
    owner = rng.integers(0, clumps, strands)
    t = np.linspace(0.0, 1.0, steps)
    curves, widths = [], []
    for i in range(strands):
        k = owner[i]
        radius = clump_radius * math.sqrt(rng.random())  # uniform on the disc
        angle = rng.uniform(0, 2 * math.pi)
        disc = radius * (math.cos(angle) * side[k] + math.sin(angle) * up[k])  # (steps, 3)
        taper = 1.0 - tighten[k] * t
        phase = 2 * math.pi * turns[k] * t + rng.normal(0.0, 0.5)
        a = amplitude[k] * rng.uniform(0.8, 1.2) * np.minimum(1.0, 6 * t)
        helix = a[:, None] * (np.cos(phase)[:, None] * side[k] + np.sin(phase)[:, None] * up[k])
        walk = np.cumsum(rng.normal(0.0, 0.0003, (steps, 3)), axis=0) * t[:, None]
        curve = paths[k] + disc * taper[:, None] + helix + walk
        curve = curve[: max(10, int(round(steps * rng.uniform(0.8, 1.0))))]
        n = int(rng.integers(24, 57))
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(curve, axis=0), axis=1))])
        s = np.linspace(0.0, arc[-1], n)
        curves.append(np.stack([np.interp(s, arc, curve[:, d]) for d in range(3)], axis=1))
        widths.append(np.linspace(7e-5, 2e-5, n))
    return curves, widths
