"""Options of the glyphs technique: one frozen dataclass feeds the CLI flags, recipe keys and the Python API."""
from __future__ import annotations

from dataclasses import dataclass

import math

from baker.options import opt

FIELD_TYPES = ("sdf", "psdf", "msdf", "mtsdf")


@dataclass(frozen=True)
class GlyphOptions:
    """Options of a glyph atlas (``baker glyphs``, ``baker text``)."""

    type: str = opt("msdf", "field type: sdf (true distance), psdf (pseudo-distance), msdf (3 channels), mtsdf "
                            "(msdf + true distance in alpha)", choices=FIELD_TYPES)
    size: float = opt(48.0, "glyph scale in atlas pixels per em", min=1.0, max=4096.0)
    range: float = opt(4.0, "distance range in atlas pixels: the full width of the encoded band (+-range/2)",
                       min=0.01, max=1024.0)
    charset: str = opt("ascii", "characters: ascii, latin1, ranges such as 0x20-0x7E,U+00E9, str:TEXT or file:PATH")
    angle_threshold: float = opt(3.0, "edge coloring: smallest direction change (radians) that is a corner",
                                 min=0.0, max=math.pi)
    coloring: str = opt("notch", "edge coloring strategy: notch (ink-trap rule for notches under one texel), inktrap "
                                 "(msdf-atlas-gen's default), simple (msdfgen's edgeColoringSimple) or distance (close "
                                 "splines get different channels)", choices=("notch", "inktrap", "simple", "distance"))
    error_correction: bool = opt(True, "fix MSDF texels whose interpolation would misplace the edge")
    padding: int = opt(1, "empty texels between glyph boxes and around the atlas border", min=0, max=256)
    pot: bool = opt(False, "power-of-two atlas width and height")
    square: bool = opt(False, "square atlas")
    font_number: int = opt(0, "font index inside a collection (.ttc)", min=0)
    instance: str | None = opt(None, "named instance of a variable font (subfamily name, or axis=value,...)")
    kerning: bool = opt(True, "read kerning (GPOS pair adjustment, else the legacy kern table)")

