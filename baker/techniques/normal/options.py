"""Options of the normal-map bake: one frozen dataclass feeds the CLI flags, recipe keys and the Python API."""
from __future__ import annotations

from dataclasses import dataclass

from baker.options import opt


@dataclass(frozen=True)
class NormalOptions:
    """Options of the normal-map bake (``--bakes normal --from HIGH``)."""

    space: str = opt("tangent", "tangent: a tangent-space map in the frame of the low mesh's TANGENT (written when "
                                "the mesh has none), as the material's normalTexture; object: mesh-space normals, "
                                "as materials[].extras.baker.objectSpaceNormalTexture (glTF's normalTexture is "
                                "tangent-space only)", choices=("tangent", "object"))
    texture_size: int | None = opt(None, "normal map width and height in texels (default: from texel density, per "
                                         "material)", min=4, max=16384)
    texel_density: float | None = opt(None, "texels per mesh unit (metre) of the normal map, sizing each material's "
                                            "texture to a power of two in [16, 8192] (default: 8 texels along the "
                                            "low mesh's mean triangle edge, in [64, 2048])", min=1e-9)
    texture_bits: int = opt(0, "bits per channel of the normal map PNG: 8, 16, or 0 for 16 where 8 bits would band (more "
                               "than 5% of neighbouring texels change by 0.05 to 0.25 of a step of 8 bits: slow ramps "
                               "that 8 bits turn into bands 4 texels wide and more), else 8 (8x smaller files)", choices=(0, 8, 16))
