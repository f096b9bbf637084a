"""Options of the tam technique: one frozen dataclass feeds the CLI flags, recipe keys and the Python API."""
from __future__ import annotations

from dataclasses import dataclass

from baker.options import opt


STYLES = ("hatching", "cross-hatching", "stippling")


@dataclass(frozen=True)
class TamOptions:
    """Options of the tonal-art-map generator (``baker tam`` and ``--bakes tam``)."""

    tones: int = opt(6, "number of tones (darkness targets), lightest first; the packed layout needs exactly 6",
                     min=1, max=64)
    levels: int = opt(4, "mip levels with their own strokes, the finest of `size` pixels, each coarser one half",
                      min=1, max=12)
    size: int = opt(256, "width and height of the finest level in pixels (a power of two)", min=8, max=4096)
    style: str = opt("hatching", "stroke style", choices=STYLES)
    darkest: float = opt(0.85, "darkness target of the darkest tone; tone i aims at darkest * (i + 1) / tones "
                               "(0 = white paper, 1 = black)", min=0.01, max=0.98)
    stroke_width: float = opt(1.5, "stroke width in pixels, the same at every level (dot diameter for stippling)",
                              min=0.5, max=16.0)
    stroke_length: tuple = opt((0.3, 0.6), "min,max stroke length as a fraction of the tile width", min=0.0, max=1.0)
    angle: float = opt(30.0, "main stroke direction in degrees, from the texture's +u axis towards +v (down the image)")
    angle_jitter: float = opt(6.0, "random deviation of each stroke's direction, +- degrees", min=0.0, max=90.0)
    curvature: float = opt(0.04, "largest bend of a stroke: sagitta as a fraction of its length (0 = straight)",
                           min=0.0, max=0.5)
    cross_angle: float = opt(90.0, "cross-hatching: second direction, degrees relative to `angle`")
    cross_threshold: float = opt(0.4, "cross-hatching: tones whose target exceeds this darkness also draw strokes in "
                                      "the second direction", min=0.0, max=1.0)
    candidates: int = opt(16, "random candidate strokes per stroke added (K of Praun et al.)", min=1, max=1024)
    layout: str = opt("packed", "packed: tones 0-2 and 3-5 in the RGB of two textures per level (Praun et al. 2001);"
                                " volume: one gray layer per tone, tone as the third axis (Webb et al. 2002)",
                      choices=("packed", "volume"))
    scale: float | None = opt(None, "texels of the finest level per UV unit on a baked material (default: a tile "
                                    "spans about 1/6 of the mesh's bounding-box diagonal)", min=1e-6)
