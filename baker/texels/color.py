"""Colour transfer functions, written once: the sRGB curve (IEC 61966-2-1, which glTF uses for base colour and
emissive textures) and the other encodings a texture may hold, by name.

Every function keeps its input's float type, so a float32 image stays float32.
"""
from __future__ import annotations

import numpy as np


def srgb_to_linear(c: np.ndarray) -> np.ndarray:
    """sRGB-encoded [0, 1] -> linear light."""
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(c: np.ndarray) -> np.ndarray:
    """Linear light -> sRGB-encoded [0, 1] (clipped to [0, 1] first)."""
    c = np.clip(c, 0.0, 1.0)
    return np.where(c <= 0.0031308, c * 12.92, 1.055 * c ** (1 / 2.4) - 0.055)


# name -> (decode to linear, encode from linear)
TRANSFERS = {
    "srgb": (srgb_to_linear, linear_to_srgb),
    "gamma2.2": (lambda c: c ** 2.2, lambda c: np.clip(c, 0.0, 1.0) ** (1 / 2.2)),
    "linear": (lambda c: c, lambda c: c),
}
