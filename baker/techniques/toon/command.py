"""Standalone generator ``baker toon-ramp -o DIR``: a toon ramp or an X-Toon map
(:mod:`baker.techniques.toon.kernel`) and ``toon.json``, with the options and flags of ``--bakes toon``
(``--toon-<option>``)."""
from __future__ import annotations

import sys

from baker.errors import BakerError
from baker.options import add_arguments, from_args


def add_parser(sub) -> None:
    from baker.techniques.toon.options import ToonOptions

    t = sub.add_parser("toon-ramp", help="generate a toon ramp or an X-Toon map (PNG + toon.json)")
    t.add_argument("-o", "--output", required=True, help="output folder (created if missing)")
    t.add_argument("-q", "--quiet", action="store_true", help="no summary")
    add_arguments(t, ToonOptions, "toon")
    t.set_defaults(func=run_toon)


def run_toon(args) -> int:
    from baker.techniques.toon.options import ToonOptions
    from baker.gltf.atomic import output_folder
    from baker.techniques.toon.extension import write_toon_directory

    folder = output_folder(args.output)
    try:
        options = from_args(ToonOptions, "toon", args)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    manifest = write_toon_directory(options, folder)
    if not args.quiet:
        print(f"toon-ramp: {manifest['width']} x {manifest['height']} -> {folder}/{manifest['file']}", file=sys.stderr)
    return 0
