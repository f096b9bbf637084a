"""Options of the thickness technique: one frozen dataclass feeds the CLI flags, recipe keys and the Python API."""
from __future__ import annotations

from dataclasses import dataclass

from baker.options import opt


@dataclass(frozen=True)
class ThicknessOptions:
    """Options of the local-thickness bake (``--bakes thickness``)."""

    rays: int = opt(64, "rays per sample point", min=1)
    sampler: str = opt("fibonacci", "ray sample pattern: fibonacci (spherical Fibonacci set, one ray per elevation band, "
                                    "random turn per point), hammersley (shared Hammersley set, random shift per point), "
                                    "sobol (Owen-scrambled Sobol per point) or random (independent rays, plain Monte "
                                    "Carlo)", choices=("fibonacci", "hammersley", "sobol", "random"))
    distribution: str = opt("cosine", "ray distribution around the inverted normal", choices=("cosine", "uniform"))
    spread: float = opt(180.0, "full cone angle of the rays in degrees (180 = the whole hemisphere)", min=1e-3, max=180.0)
    max_distance: float | None = opt(None, "distance given to rays that miss, and the clamp of hits, in mesh units "
                                           "(default: the mesh's bounding-box diagonal; 1 for a mesh collapsed to a "
                                           "point)", min=0.0)
    bias: float | None = opt(None, "ray start offset against self-hits, in mesh units (default: 1e-5 x diagonal)", min=0.0)
    per_vertex: bool = opt(True, "write the per-vertex attribute _THICKNESS")
    per_texel: bool = opt(True, "bake the thickness texture (KHR_materials_volume.thicknessTexture)")
    texture_size: int | None = opt(None, "thickness texture width and height in texels (default: from texel "
                                         "density, per material)", min=4, max=16384)
    texel_density: float | None = opt(None, "texels per mesh unit (metre) of the thickness texture, sizing each "
                                            "material's texture to a power of two in [16, 8192] (default: 8 texels "
                                            "along the mean triangle edge, in [64, 512])", min=1e-9)
    tolerance: float = opt(0.25, "texels whose first 12 rays agree within +-tolerance (relative) with the thickness "
                                 "interpolated from the per-vertex solution take that value, corrected by "
                                 "their neighbours (--thickness-texel-window); the others trace all "
                                 "--thickness-rays, as do texels on the edge of a chart of the asset's own UVs, "
                                 "texels whose normal turns more than 10 degrees from the vertices' (a hard edge) "
                                 "and texels beside those (0: every texel traces them all)", min=0.0, max=1.0)
    texel_window: int = opt(3, "texels that take the per-vertex value add the mean deviation of the first rays "
                               "from it over the (2 x window + 1)^2 texels around them on the surface, shrunk "
                               "toward 0 as far as its noise exceeds the texture's spread of corrections (0: the "
                               "per-vertex value alone)", min=0, max=16)
    # 8 by default (issue 48): its error against a 2048-ray reference equals 16 bits' (benchmarks/RESULTS.md, texel)
    texture_bits: int = opt(8, "bits per channel of the thickness PNG", choices=(8, 16))
    # eq. 14.30 and the GDC variant: written into BAKER_thickness for the runtime, not used by the bake
    distortion: float = opt(0.2, "translucency: normal distortion of the light vector (GDC 2011)")
    power: float = opt(4.0, "translucency: exponent p of (v . -l)^p, a phase-function approximation", min=0.0)
    scale: float = opt(1.0, "translucency: scale of the back-lit term", min=0.0)
    ambient: float = opt(0.0, "translucency: constant back-lit term (GDC 2011)", min=0.0)
    subsurface_color: tuple = opt((1.0, 1.0, 1.0), "translucency: subsurface albedo c_ss (linear RGB, each 0..1)",
                                  min=0.0, max=1.0)
    attenuation_distance: float | None = opt(None, "distance over which transmittance falls to 1/e, t_ss = "
                                                   "exp(-thickness / d), in mesh units (default: the mean thickness)",
                                             min=0.0)
