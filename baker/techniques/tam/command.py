"""Standalone generator ``baker tam -o DIR``: the parser; the work is :func:`baker.techniques.tam.step.run_tam`,
imported when it runs. No asset, just the textures: a tonal art map (Praun et al. 2001;
:mod:`baker.techniques.tam.kernel`) as per-level PNGs and a ``tam.json`` manifest, optionally with KTX2 files.
Options are the dataclass of ``--bakes tam`` and use the same flags (``--tam-<option>``).
"""
from __future__ import annotations

from baker.options import add_arguments
from baker.technique import lazy


def add_parser(sub) -> None:
    from baker.techniques.tam.options import TamOptions

    p = sub.add_parser("tam", help="generate a tonal art map for real-time hatching (PNG levels + tam.json)")
    p.add_argument("-o", "--output", required=True, help="output folder (created if missing)")
    p.add_argument("--ktx2", action="store_true", help="also write KTX2 files (uncompressed, every level)")
    p.add_argument("--seed", type=int, default=0, help="random seed; the same seed gives byte-identical files")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary")
    add_arguments(p, TamOptions, "tam")
    p.set_defaults(func=lazy("baker.techniques.tam.step:run_tam"))
