"""Options of the curvature technique: one frozen dataclass feeds the CLI flags, recipe keys and the Python API."""
from __future__ import annotations

from dataclasses import dataclass

from baker.options import opt


@dataclass(frozen=True)
class CurvatureOptions:
    """Options of the curvature bake (``--bakes curvature``)."""

    rings: int = opt(2, "neighbourhood size in edge rings around each vertex for the cubic fit", min=1, max=8)
    radius: float | None = opt(None, "neighbourhood radius in mesh units instead of rings: the vertices reachable "
                                     "through edges within this distance (default: use rings)", min=0.0)
    smoothing: int = opt(2, "smoothing passes of the curvature tensor over 1-ring neighbours", min=0, max=100)
    fit: str = opt("cubic", "estimator: cubic (Goldfeather & Interrante adjacent-normal fit with osculating-circle "
                            "terms) or quadric (height-field quadric)", choices=("cubic", "quadric"))
    per_vertex: bool = opt(True, "write _CURVATURE, _PRINCIPAL_CURVATURES and _PRINCIPAL_DIRECTION")
    directions: bool = opt(True, "also write the principal curvatures and direction attributes")
    per_texel: bool = opt(False, "also bake a mean-curvature texture (BAKER_curvature.curvatureTexture)")
    texture_size: int | None = opt(None, "curvature texture width and height in texels (default: from texel "
                                         "density, per material)", min=4, max=16384)
    texel_density: float | None = opt(None, "texels per mesh unit (metre) of the curvature texture, sizing each "
                                            "material's texture to a power of two in [16, 8192] (default: 8 texels "
                                            "along the mean triangle edge, in [64, 2048])", min=1e-9)
    texture_bits: int = opt(16, "bits per channel of the curvature PNG", choices=(8, 16))
