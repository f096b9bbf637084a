"""Standalone generator ``baker toon-ramp -o DIR``: the parser; the work is
:func:`baker.techniques.toon.step.run_toon_ramp`, imported when it runs. A toon ramp or an X-Toon map
(:mod:`baker.techniques.toon.kernel`) and ``toon.json``, with the options and flags of ``--bakes toon``
(``--toon-<option>``)."""
from __future__ import annotations

from baker.options import add_arguments
from baker.technique import lazy


def add_parser(sub) -> None:
    from baker.techniques.toon.options import ToonOptions

    t = sub.add_parser("toon-ramp", help="generate a toon ramp or an X-Toon map (PNG + toon.json)")
    t.add_argument("-o", "--output", required=True, help="output folder (created if missing)")
    t.add_argument("-q", "--quiet", action="store_true", help="no summary")
    add_arguments(t, ToonOptions, "toon")
    t.set_defaults(func=lazy("baker.techniques.toon.step:run_toon_ramp"))
