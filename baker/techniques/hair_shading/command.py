"""``baker hair-lut -o DIR``: the parser; the work is :func:`baker.techniques.hair_shading.step.run_hair_lut`,
imported when it runs."""
from __future__ import annotations

from baker.options import add_arguments
from baker.technique import lazy
from baker.techniques.hair_shading.options import HairShadingOptions


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("hair-lut", help="write the hair fibre BSDF tables (Chiang et al. 2016: M and N, "
                                               "half-float EXR) with a JSON sidecar")
    p.add_argument("-o", "--output", required=True, help="output folder (created if missing)")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary line")
    add_arguments(p, HairShadingOptions, "hair")
    p.set_defaults(func=lazy("baker.techniques.hair_shading.step:run_hair_lut"))
