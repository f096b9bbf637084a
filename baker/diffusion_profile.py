"""Diffusion profiles: sums of normalized 2D Gaussians with per-channel weights (d'Eon & Luebke, GPU Gems 3 ch. 14).

The one place profiles live, beside the techniques rather than in one of them: the skin LUTs
(:mod:`baker.techniques.skin.kernel`) and the surface normal blur (:mod:`baker.techniques.normal_blur`) both read the
default and the ``--*-profile`` JSON files from here, and neither technique imports the other.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from baker.errors import BakerError

CHANNELS = ("red", "green", "blue")


@dataclass(frozen=True)
class Profile:
    """A diffusion profile: a sum of normalized 2D Gaussians with per-channel weights. Lengths in mm."""

    name: str
    variances: tuple  # (k,) mm^2
    weights: tuple  # (3, k): red, green, blue weight of each Gaussian

    def arrays(self) -> tuple[np.ndarray, np.ndarray]:
        return np.asarray(self.variances, np.float64), np.asarray(self.weights, np.float64).reshape(3, -1)

    def value(self, radius) -> np.ndarray:
        """R(radius) per channel: (..., 3), radius in mm, in 1/mm^2."""
        v, w = self.arrays()
        r = np.asarray(radius, np.float64)[..., None]
        g = np.exp(-r * r / (2.0 * v)) / (2.0 * math.pi * v)
        return g @ w.T

    def rms_radius(self) -> np.ndarray:
        """Per channel sqrt(sum w v / sum w): the standard deviation of the profile along a line, mm."""
        v, w = self.arrays()
        return np.sqrt((w * v).sum(axis=1) / np.maximum(w.sum(axis=1), 1e-300))

    def as_json(self) -> dict:
        v, w = self.arrays()
        return {"name": self.name, "unit": "mm", "variances": [float(x) for x in v],
                **{c: [float(x) for x in w[i]] for i, c in enumerate(CHANNELS)}}


# d'Eon & Luebke, GPU Gems 3 ch. 14, table 14-1 (three-layer skin), variances in mm^2
DEON_SKIN = Profile(
    name="d'Eon & Luebke 2007 skin",
    variances=(0.0064, 0.0484, 0.187, 0.567, 1.99, 7.41),
    weights=((0.233, 0.100, 0.118, 0.113, 0.358, 0.078),
             (0.455, 0.336, 0.198, 0.007, 0.004, 0.0),
             (0.649, 0.344, 0.0, 0.007, 0.0, 0.0)),
)


def load_profile(path) -> Profile:
    """Read a profile JSON: ``{"name": ..., "unit": "mm", "variances": [...], "red": [...], "green": [...],
    "blue": [...]}`` (variances in unit^2; ``unit`` mm, cm or m, default mm). Raises BakerError on bad input."""
    path = Path(path)
    try:
        data = json.loads(path.read_text("utf-8"))
    except FileNotFoundError:
        raise BakerError(path, "profile file not found") from None
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise BakerError(path, f"broken profile JSON: {exc}") from None
    if not isinstance(data, dict):
        raise BakerError(path, "a profile is a JSON object with variances, red, green and blue")
    to_mm = {"mm": 1.0, "cm": 10.0, "m": 1000.0}
    unit = data.get("unit", "mm")
    if unit not in to_mm:
        raise BakerError(path, f"profile unit must be one of {', '.join(to_mm)}, got {unit!r}")
    try:
        variances = np.asarray(data["variances"], np.float64) * to_mm[unit] ** 2
        weights = np.asarray([data[c] for c in CHANNELS], np.float64)
    except KeyError as exc:
        raise BakerError(path, f"profile lacks {exc.args[0]!r}") from None
    except (TypeError, ValueError):
        raise BakerError(path, "profile variances and weights must be lists of numbers") from None
    if variances.ndim != 1 or not len(variances) or weights.shape != (3, len(variances)):
        raise BakerError(path, "variances, red, green and blue must be lists of the same non-zero length")
    if not np.isfinite(variances).all() or (variances <= 0).any():
        raise BakerError(path, "every variance must be > 0")
    if not np.isfinite(weights).all() or (weights < 0).any() or (weights.sum(axis=1) <= 0).any():
        raise BakerError(path, "weights must be >= 0 with a positive sum per channel")
    return Profile(str(data.get("name", path.stem)), tuple(map(float, variances)),
                   tuple(tuple(map(float, row)) for row in weights))
