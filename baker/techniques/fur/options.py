"""Options of the fur technique: one frozen dataclass feeds the CLI flags, recipe keys and the Python API."""
from __future__ import annotations

from dataclasses import dataclass

from baker.options import opt


@dataclass(frozen=True)
class FurOptions:
    """Options of the fur bake (``--bakes fur``)."""

    shells: int = opt(16, "number of shell textures (slices of the hair volume)", min=1, max=64)
    texture_size: int = opt(128, "shell texture width and height in texels (one tile)", min=8, max=4096)
    hairs: int = opt(1200, "hairs per tile", min=1)
    length: float | None = opt(None, "fur length (height of the outermost shell) in mesh units "
                                     "(default: 0.02 x the bounding-box diagonal of all meshes)", min=0.0)
    tiling: float = opt(8.0, "tiles per unit of TEXCOORD_0", min=1e-6)
    root_radius: float = opt(0.010, "hair radius at the root, in tile widths", min=0.0)
    tip_radius: float = opt(0.002, "hair radius at the tip, in tile widths", min=0.0)
    lean: float = opt(0.08, "largest sideways slant of a hair over the full height, in tile widths", min=0.0)
    min_height: float = opt(0.6, "shortest hair as a fraction of the fur length", min=0.0, max=1.0)
    root_color: tuple = opt((0.20, 0.13, 0.08), "hair colour at the root (linear RGB, 0..1)", min=0.0, max=1.0)
    tip_color: tuple = opt((0.75, 0.62, 0.45), "hair colour at the tip (linear RGB, 0..1)", min=0.0, max=1.0)
    fin_depth: float = opt(0.1, "thickness of the volume slab seen on a fin, in tile widths", min=1e-3, max=1.0)
    # off by default (compact files): a fin is 4 vertices of 8 VEC3 attributes per mesh edge, 6x the base mesh's
    # bytes (bunny, all bakes: 40 of 54 MB; benchmarks/RESULTS.md "Compact by default")
    fins: bool = opt(False, "write fin geometry along every mesh edge (needs the edge adjacency of the edges bake; "
                            "about 6x the base mesh's bytes)")
    alpha_cutoff: float = opt(0.5, "alpha-test threshold of the shells and fins (coverage above it is drawn)",
                              min=0.0, max=1.0)
    coverage_mips: bool = opt(True, "also write each shell and fin texture's coverage-preserving mip chain (KTX2 "
                                    "RGBA8, Castano 2010) so the fur does not thin out with distance")
