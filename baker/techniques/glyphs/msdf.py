"""Field types from the distance kernel: SDF, pseudo-SDF, MSDF and MTSDF, in normalized texel values.

A value v in [0, 1] encodes the signed distance d (pixels, + inside) as v = 0.5 + d / range, clamped; ``range`` is
the full width of the encoded band (msdf-atlas-gen's ``distanceRange``), so distances in [-range/2, range/2] are kept.

- ``sdf``: the exact signed distance (Green, *Improved Alpha-Tested Magnification for Vector Textures and Special
  Effects*, SIGGRAPH 2007 course), sign by the nonzero rule.
- ``psdf``: the pseudo-distance of the nearest edge (Chlumsky 2015, section 2.3); sharper than ``sdf`` along
  straight edges but still one channel.
- ``msdf``: three channels, each the pseudo-distance to the nearest edge of its color (:mod:`.coloring`); the
  shader takes the median (Chlumsky 2015, chapter 3), which keeps corners sharp under bilinear magnification.
- ``mtsdf``: ``msdf`` plus alpha = the true SDF, for soft effects (glow, shadow) that need a true distance.

Two corrections follow: the **sign correction** makes the median agree at every texel centre with the winding-number
sign (needed where contours overlap or edges of one color pass close to another contour), and the **error
correction** (:func:`.correction.correct_edge_priority`, msdfgen's edge-priority method) finds texels whose bilinear
interpolation puts the median's edge in the wrong place and makes them single-channel.
"""
from __future__ import annotations

import numba
import numpy as np

from baker.techniques.glyphs.coloring import WHITE
from baker.techniques.glyphs.correction import correct_edge_priority
from baker.techniques.glyphs.sdf import GlyphBatch, distance_fields
from baker.techniques.glyphs.options import FIELD_TYPES

CHANNELS = {"sdf": 1, "psdf": 1, "msdf": 3, "mtsdf": 4}


@numba.njit(cache=True)
def _median3(a, b, c):
    return max(min(a, b), min(max(a, b), c))


@numba.njit(cache=True, parallel=True)
def _sign_correct(true, channels):
    """Where the median (or the single channel) has the wrong sign at a texel centre, use the true distance."""
    n, k = channels.shape
    for t in numba.prange(n):
        m = channels[t, 0] if k == 1 else _median3(channels[t, 0], channels[t, 1], channels[t, 2])
        if (m > 0.0) != (true[t] > 0.0) and true[t] != 0.0:
            for c in range(k):
                channels[t, c] = true[t]


def glyph_fields(batch: GlyphBatch, corners: list, field_type: str, distance_range: float,
                 error_correction: bool = True) -> np.ndarray:
    """Normalized field values (T, channels) float64 in [0, 1] for every texel of ``batch``.

    ``corners``: per glyph, an (m, 2) array of the corner points the MSDF must keep sharp (box pixel space), which
    the error correction leaves alone.
    """
    if field_type not in FIELD_TYPES:
        raise ValueError(f"unknown field type {field_type!r} (known: {', '.join(FIELD_TYPES)})")
    if field_type == "sdf":
        true, _ = distance_fields(batch)
        channels = true[:, None]
    elif field_type == "psdf":
        true, channels = distance_fields(batch, (WHITE,))
        _sign_correct(true, channels)
    else:
        true, channels = distance_fields(batch, (1, 2, 4))
        _sign_correct(true, channels)
    true_values = np.clip(0.5 + true / distance_range, 0.0, 1.0)
    values = 0.5 + channels / distance_range
    if field_type in ("msdf", "mtsdf") and error_correction:
        # on the unclamped field, as msdfgen corrects its float output before it is quantized
        correct_edge_priority(batch, corners, values, distance_range)
    np.clip(values, 0.0, 1.0, out=values)
    if field_type == "mtsdf":
        values = np.concatenate([values, true_values[:, None]], axis=1)
    return values
