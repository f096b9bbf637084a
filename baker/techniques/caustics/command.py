"""Standalone generator ``baker caustics -o DIR``: the parser; the work is
:func:`baker.techniques.caustics.step.run_caustics`, imported when it runs. A looping, tileable caustic sequence
(:mod:`baker.techniques.caustics.kernel`) as 16-bit PNG frames and ``caustics.json`` (optionally one KTX2 array),
with the options and flags of ``--bakes caustics`` (``--caustics-<option>``)."""
from __future__ import annotations

from baker.options import add_arguments
from baker.technique import lazy


def add_parser(sub) -> None:
    from baker.techniques.caustics.options import CausticsOptions

    p = sub.add_parser("caustics", help="generate looping, tileable water caustics (16-bit PNG frames + "
                                        "caustics.json)")
    p.add_argument("-o", "--output", required=True, help="output folder (created if missing)")
    p.add_argument("--ktx2", action="store_true", help="also write caustics.ktx2: the frames as one array texture "
                                                       "with mips (8-bit UNORM)")
    p.add_argument("--seed", type=int, default=0, help="random seed of the wave phases; the same seed gives "
                                                       "byte-identical files")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary")
    add_arguments(p, CausticsOptions, "caustics")
    p.set_defaults(func=lazy("baker.techniques.caustics.step:run_caustics"))
