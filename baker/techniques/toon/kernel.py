"""Toon shading ramps: 1D band ramps and Barla et al.'s X-Toon 2D maps (RTR4 section 15.1).

A toon shader looks up a shade in a small texture instead of using the diffuse term directly: the ramp turns the
continuous ``u = 0.5 + 0.5 N.L`` into a few flat bands (*hard*, a step per band) or bands joined by short smooth
transitions (*soft*). Barla, Thollot & Markosian, "X-Toon: An Extended Toon Shader", NPAR 2006, add a second axis,
the *detail* D in [0, 1] (depth-based, D = 1 - log(z / z_min) / log(z_max / z_min), or orientation-based,
D = |N.V|^r): row D = 1 holds the full ramp and rows towards D = 0 lose contrast and sharpness, so distant or
grazing surfaces soften (the "abstraction" of the paper).

The texel at column i samples u at the texel centre (i + 0.5) / width, so a runtime's ``texture(ramp, vec2(u, v))``
with LINEAR filtering reproduces the analytic band function :func:`band_value` up to the filter's half-texel blur.
"""
from __future__ import annotations


import numpy as np

from baker.techniques.toon.options import ToonOptions




def band_value(u, bands: int, softness: float, shadow: float = 0.0) -> np.ndarray:
    """The analytic ramp: band k covers u in [k / bands, (k + 1) / bands) with value shadow + (1 - shadow) k/(bands-1).

    With ``softness`` s > 0 each step becomes a smoothstep over s / bands centred on the band boundary.
    """
    u = np.clip(np.asarray(u, np.float64), 0.0, 1.0) * bands
    if softness <= 0.0:
        level = np.minimum(np.floor(u), bands - 1)
    else:
        boundaries = np.arange(1, bands, dtype=np.float64)
        x = np.clip((u[..., None] - boundaries + 0.5 * softness) / softness, 0.0, 1.0)
        level = (x * x * (3.0 - 2.0 * x)).sum(axis=-1)
    return shadow + (1.0 - shadow) * level / (bands - 1)


def toon_ramp(options: ToonOptions = ToonOptions()) -> np.ndarray:
    """A 1D ramp, (width,) float64 in [shadow, 1], sampled at texel centres."""
    u = (np.arange(options.width) + 0.5) / options.width
    return band_value(u, options.bands, options.softness, options.shadow)


def xtoon_map(options: ToonOptions = ToonOptions()) -> np.ndarray:
    """An X-Toon map (height, width) float64, row 0 (top, v = 0) at detail D = 1, the last row at D = 0.

    Going down, the band transitions widen (softness s + (1 - s)(1 - D), i.e. a plain ramp at D = 0) and the
    contrast around the ramp's mean falls to ``min_contrast``.
    """
    u = (np.arange(options.width) + 0.5) / options.width
    detail = 1.0 - (np.arange(options.height) + 0.5) / options.height
    rows = np.empty((options.height, options.width))
    for i, d in enumerate(detail):  # one row per detail level: height is small (a loop over rows, not texels)
        soft = options.softness + (1.0 - options.softness) * (1.0 - d)
        ramp = band_value(u, options.bands, soft, options.shadow)
        mid = 0.5 * (options.shadow + 1.0)
        contrast = options.min_contrast + (1.0 - options.min_contrast) * d
        rows[i] = mid + (ramp - mid) * contrast
    return rows


def encode_u8(values: np.ndarray) -> np.ndarray:
    return np.rint(np.clip(values, 0.0, 1.0) * 255.0).astype(np.uint8)
