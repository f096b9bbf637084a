"""Options of the skin technique: one frozen dataclass feeds the CLI flags, recipe keys and the Python API."""
from __future__ import annotations

from dataclasses import dataclass

from baker.errors import BakerError
from baker.options import opt


# ---------------------------------------------------------------------------------------------------- kernels
JIMENEZ_STRENGTH = (0.48, 0.41, 0.28)


JIMENEZ_FALLOFF = (1.0, 0.37, 0.3)


# ---------------------------------------------------------------------------------------------------- options
DEFAULT_RADII = (1.0, 100.0)  # mm: the LUT's radii when neither the options nor the asset's curvature set them
FIT_PERCENTILES = (1.0, 99.0)  # of the asset's |mean curvature|: the part of the distribution the LUT's axis spans
MAX_RADIUS_RATIO = 1000.0  # a fitted axis spans at most this ratio of radii (a flat asset's 1st percentile is ~0)
@dataclass(frozen=True)
class SkinOptions:
    """Options of the pre-integrated skin bake (``--bakes skin``) and of ``baker skin-lut``."""

    width: int = opt(256, "LUT texels along N.L (u = N.L * 0.5 + 0.5)", min=2, max=4096)
    height: int = opt(256, "LUT texels along the curvature 1/r", min=2, max=4096)
    min_radius: float | None = opt(None, "smallest radius of curvature in the LUT, mm (its last row; default: from "
                                         "the asset, 1 / the 99th percentile of its baked |mean curvature| x the "
                                         "curvature scale; 1 mm without baked curvature and for baker skin-lut)",
                                   min=1e-6)
    max_radius: float | None = opt(None, "largest radius of curvature in the LUT, mm (its first row; default: from "
                                         "the asset, 1 / the 1st percentile of its baked |mean curvature| x the "
                                         "curvature scale, at most 1000 x min-radius; 100 mm without baked "
                                         "curvature and for baker skin-lut)", min=1e-6)
    samples: int = opt(256, "integration samples per Gaussian and LUT row", min=3, max=65536)
    ring_profile: str = opt("line", "the profile on Penner's ring: line (the 2D profile integrated across the ring, "
                                    "as light varying along one direction diffuses; the penumbra LUT's too) or radial "
                                    "(the 2D profile R(d) as Penner 2011 writes it: broad red lobes weigh 1/sigma, "
                                    "several times less red at the terminator)", choices=("line", "radial"))
    profile: str | None = opt(None, "diffusion profile JSON (variances + red/green/blue weights; default: d'Eon & "
                                    "Luebke's skin)")
    bits: int = opt(16, "bits per channel of PNG LUTs (EXR output is always 32-bit float)", choices=(8, 16))
    encoding: str = opt("linear", "how LUT values are stored: linear, or srgb (better for 8-bit)",
                        choices=("linear", "srgb"))
    penumbra: bool = opt(True, "also make Penner's shadow-penumbra LUT")
    penumbra_size: int = opt(128, "penumbra LUT width and height in texels", min=2, max=4096)
    penumbra_min_width: float = opt(1.0, "narrowest penumbra in the LUT, mm", min=1e-6)
    penumbra_max_width: float = opt(100.0, "widest penumbra in the LUT, mm", min=1e-6)
    sharpening: float = opt(1.0, "shadow sharpening: the true shadow ramps over penumbra width / sharpening", min=1.0)
    unit_scale: float = opt(1000.0, "millimetres per mesh unit: the profile is physical, so this is the asset's real "
                                    "size (glTF is metres by spec: 1000; OBJ/PLY/STL carry no unit and are taken "
                                    "as metres too); curvatureScale = 1 / this", min=1e-12)
    normal_blend: tuple = opt((-1.0, -1.0, -1.0), "per-channel weight (0..1) of the smooth normal in Penner's "
                                                  "normal blending; negative: each channel's RMS scatter distance / "
                                                  "the largest", max=1.0)
    wrap: float = opt(0.5, "wrap lighting: how far light wraps past the terminator (RTR4 14.6.1)", min=0.0)
    scatter_width: float = opt(0.3, "wrap lighting: width of the color-shifted band at the terminator", min=1e-6)
    scatter_color: tuple = opt((0.8, 0.25, 0.1), "wrap lighting: color of the shifted band (linear RGB)",
                               min=0.0, max=1.0)
    jimenez_taps: int = opt(17, "taps of the Jimenez separable SSS kernel", choices=(11, 17, 25))
    jimenez_strength: tuple = opt(JIMENEZ_STRENGTH, "Jimenez kernel strength per channel", min=0.0, max=1.0)
    jimenez_falloff: tuple = opt(JIMENEZ_FALLOFF, "Jimenez kernel falloff per channel", min=0.0)

    def check(self) -> None:
        if self.min_radius is not None and self.max_radius is not None and self.min_radius >= self.max_radius:
            raise BakerError(None, f"skin min-radius ({self.min_radius}) must be below max-radius ({self.max_radius})")
        if self.penumbra_min_width >= self.penumbra_max_width:
            raise BakerError(None, "skin penumbra-min-width must be below penumbra-max-width")
