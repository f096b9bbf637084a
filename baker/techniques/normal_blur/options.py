"""Options of the normal-blur technique: one frozen dataclass feeds the CLI flags, recipe keys and the Python API."""
from __future__ import annotations

from dataclasses import dataclass

from baker.options import opt


@dataclass(frozen=True)
class NormalBlurOptions:
    """Options of the surface normal blur (``--bakes normal-blur``)."""

    profile: str | None = opt(None, "diffusion profile JSON (variances + red/green/blue weights, as the skin bake "
                                    "reads; default: d'Eon & Luebke's skin)")
    meters_per_unit: float = opt(1.0, "metres per mesh unit (glTF: 1); the profile's millimetres are scaled by it",
                                 min=1e-12)
    cell_fraction: float = opt(1.0, "lattice cell, in sigmas, of the Gaussians wider than 1.5 texel spacings "
                                    "(smaller: closer to the brute-force convolution, slower)", min=0.05, max=1.5)
    texture_size: int | None = opt(None, "width and height of the output maps (default: the input normal map's "
                                         "larger side)", min=4, max=16384)
    stretch_bits: int = opt(16, "bits per channel of the stretch PNG", choices=(8, 16))
