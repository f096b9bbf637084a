"""Options of the tam technique: one frozen dataclass feeds the CLI flags, recipe keys and the Python API."""
from __future__ import annotations

from dataclasses import dataclass, replace

from baker.options import opt


STYLES = ("hatching", "cross-hatching", "stippling")
STROKES = ("field", "uv")
DEFAULT_ANGLE = {"field": 0.0, "uv": 30.0}  # strokes along the field's u axis; across arbitrary UVs, diagonal


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
    angle: float | None = opt(None, "main stroke direction in degrees, from the texture's +u axis towards +v (down "
                                    "the image) (default: 0 on a material baked with --tam-strokes field, so "
                                    "strokes run along the field; else 30, across UV charts of any direction)")
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
    scale: float | None = opt(None, "on a baked material, texels of the finest level per mesh unit (metre) with "
                                    "--tam-strokes field, per UV unit with uv (default: a tile spans about 1/6 of "
                                    "the mesh's bounding-box diagonal)", min=1e-6)
    strokes: str = opt("field", "texture coordinates the TAM is applied through on a baked material: field: a new "
                                "TEXCOORD set of lapped patches whose u axis follows a cross field aligned with the "
                                "principal curvature directions (Praun et al. 2000/2001); uv: the mesh's own UVs "
                                "(an unwrap when it has none)", choices=STROKES)
    direction: bool = opt(False, "with --tam-strokes field: also write the stroke u axis per vertex as "
                                 "_HATCHING_DIRECTION (VEC3; no runtime reads it: it is the u gradient of the stroke "
                                 "set, derived at load like a tangent)")
    combing: str = opt("_HATCHING_COMBING", "with --tam-strokes field: vertex attribute (VEC3, mesh space) of an "
                                            "artist's stroke directions, honoured where non-zero over the principal "
                                            "directions")

    @property
    def stroke_angle(self) -> float:
        """The main stroke direction in degrees: ``angle``, or 30 (the standalone map's and ``uv``'s default; the
        bake resolves ``field``'s 0 with :meth:`for_bake`)."""
        return float(self.angle) if self.angle is not None else DEFAULT_ANGLE["uv"]

    def for_bake(self) -> "TamOptions":
        """The options a bake generates its map with: ``angle`` resolved by the ``strokes`` mode."""
        return self if self.angle is not None else replace(self, angle=DEFAULT_ANGLE[self.strokes])
