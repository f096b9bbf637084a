"""Options of the hair technique's commands, one frozen dataclass per verb (``baker hair``, ``baker guides``): each
feeds its CLI flags, recipe keys and the Python API."""
from __future__ import annotations

from dataclasses import dataclass

from baker.options import opt


@dataclass(frozen=True)
class HairOptions:
    """Options of the hair generator (``baker hair``)."""

    guides: int = opt(300, "number of guide strands (roots: blue noise over the emitter's area)", min=1)
    children: int = opt(16, "child strands per guide, interpolated from the 3 nearest guides", min=0)
    segments: int = opt(16, "segments per strand (vertices = segments + 1)", min=1, max=255)
    length: float | None = opt(None, "strand length in mesh units (default: 0.15 x the emitter's bbox diagonal)",
                               min=0.0)
    length_map: str | None = opt(None, "per-root length scale: 'COLOR_0' (vertex colour luminance) or an image "
                                       "file sampled through TEXCOORD_0 (luminance, 0..1)")
    density_map: str | None = opt(None, "density mask: 'COLOR_0' (vertex colour luminance) or an image file "
                                        "sampled through TEXCOORD_0 (luminance, 0 = bald, 1 = full density)")
    mesh: int = opt(0, "index of the emitter mesh in the input", min=0)
    material: int | None = opt(None, "emit only from primitives drawn with this material index", min=0)
    gravity: float = opt(0.5, "gravity: how far (in strand lengths) an unresisting strand falls", min=0.0)
    gravity_direction: tuple = opt((0.0, -1.0, 0.0), "direction of gravity in mesh space (glTF: -Y is down)")
    stiffness: float = opt(0.5, "shape stiffness at the root (0..1; falls to half at the tip)", min=0.0, max=1.0)
    iterations: int = opt(16, "relaxation iterations", min=0, max=1000)
    curl_amplitude: float = opt(0.0, "curl radius as a fraction of the strand length", min=0.0)
    curl_frequency: float = opt(3.0, "curl turns per strand", min=0.0)
    clump: float = opt(0.0, "pull of child tips towards their dominant guide (0..1)", min=0.0, max=1.0)
    spread: float = opt(0.5, "TressFX follow offset: children's tip separation, in guide spacings", min=0.0)
    thinning: float = opt(0.0, "fraction of children shortened at random (0..1)", min=0.0, max=1.0)
    root_width: float | None = opt(None, "strand width at the root in mesh units (default: length / 150)", min=0.0)
    tip_width: float | None = opt(None, "strand width at the tip in mesh units (default: root width / 10)", min=0.0)
    width_variation: float = opt(0.3, "per-strand width scale is uniform in [1 - variation, 1]", min=0.0, max=1.0)
    margin: float | None = opt(None, "clearance kept between strands and the emitter, mesh units "
                                     "(default: 1e-3 x length)", min=0.0)
    curve_type: str = opt("linear", "USD curve type/basis", choices=("linear", "catmullRom", "bspline"))


@dataclass(frozen=True)
class GuidesOptions:
    """Options of the groom -> guides solver (``baker guides``)."""

    guides: int = opt(500, "number of guide strands chosen among the groom's strands", min=1)
    vertices_per_strand: int = opt(32, "vertices of every output strand (equal arc-length steps on the input curve; curves with this count are kept)",
                                   min=2, max=256)
    lods: int = opt(4, "levels of detail: LOD k keeps a blue-noise prefix of about 1/2^k of the children", min=1,
                    max=16)
    locality: float = opt(0.5, "weight of root distance against shape distance when choosing guides (0: shape only)",
                          min=0.0)
    candidates: int = opt(10, "nearest guide roots a child may pick its 3 guides from", min=3, max=32)
    iterations: int = opt(8, "k-medoids refinement iterations", min=0, max=100)
    seed: int = opt(0, "random seed; the same seed gives byte-identical output")
    scalp: str | None = opt(None, "emitter mesh: roots bind to its closest point (triangle + barycentrics written "
                                  "as BAKER_hair rootBinding); default: the groom file's own triangle mesh when it "
                                  "has one (a baker hair output holds its emitter), else none")
    bad_curves: str = opt("skip", "curves with < 2 vertices, NaN/inf points or zero length: skip (counted in the "
                                  "summary) or error", choices=("skip", "error"))
    curve_type: str = opt("linear", "USD output curve type/basis", choices=("linear", "catmullRom", "bspline"))
