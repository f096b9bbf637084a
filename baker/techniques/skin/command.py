"""``baker skin-lut -o OUT``: the parser; the work is :func:`baker.techniques.skin.step.run_skin_lut`, imported when
it runs."""
from __future__ import annotations

from baker.options import add_arguments
from baker.technique import lazy
from baker.techniques.skin.options import SkinOptions


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("skin-lut", help="write Penner's pre-integrated skin LUT (+ penumbra LUT, kernels) "
                                               "as EXR/PNG with a JSON sidecar")
    p.add_argument("-o", "--output", required=True, help="LUT image (.exr float, .png 8/16-bit)")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary line")
    add_arguments(p, SkinOptions, "skin")
    p.set_defaults(func=lazy("baker.techniques.skin.step:run_skin_lut"))
