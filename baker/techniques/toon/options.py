"""Options of the toon technique: one frozen dataclass feeds the CLI flags, recipe keys and the Python API."""
from __future__ import annotations

from dataclasses import dataclass

from baker.options import opt


@dataclass(frozen=True)
class ToonOptions:
    """Options of the toon-ramp generator (``baker toon-ramp`` and ``--bakes toon``)."""

    bands: int = opt(3, "number of flat shades", min=2, max=64)
    softness: float = opt(0.0, "width of the transition between two bands, as a fraction of a band (0 = hard)",
                          min=0.0, max=1.0)
    shadow: float = opt(0.25, "value of the darkest band (the lightest is 1)", min=0.0, max=1.0)
    width: int = opt(256, "ramp width in texels (along u = 0.5 + 0.5 N.L)", min=2, max=4096)
    xtoon: str = opt("none", "X-Toon second axis (Barla et al. 2006): none writes a 1D ramp, depth or orientation "
                             "a 2D map", choices=("none", "depth", "orientation"))
    height: int = opt(64, "X-Toon map height in texels (the detail axis, D = 1 in the top row)", min=2, max=4096)
    min_contrast: float = opt(0.2, "X-Toon: contrast kept at detail D = 0 (1 = no loss)", min=0.0, max=1.0)
    depth_range: tuple = opt((1.0, 100.0), "X-Toon depth: z_min,z_max of D = 1 - log(z/z_min)/log(z_max/z_min)",
                             min=1e-6)
    orientation_power: float = opt(1.0, "X-Toon orientation: r of D = |N.V|^r", min=0.0)
