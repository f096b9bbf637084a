"""Options of ``baker guides``: one frozen dataclass feeds the CLI flags, recipe keys and the Python API."""
from __future__ import annotations

from dataclasses import dataclass

from baker.options import opt


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
                                  "as BAKER_hair rootBinding)")
    bad_curves: str = opt("skip", "curves with < 2 vertices, NaN/inf points or zero length: skip (counted in the "
                                  "summary) or error", choices=("skip", "error"))
    curve_type: str = opt("linear", "USD output curve type/basis", choices=("linear", "catmullRom", "bspline"))
