"""Standalone generators ``baker tam -o DIR`` and ``baker toon-ramp -o DIR``: no asset, just the textures.

``baker tam`` writes a tonal art map (Praun et al. 2001; :mod:`baker.bakes.tam`) as per-level PNGs and a
``tam.json`` manifest, optionally with KTX2 files; ``baker toon-ramp`` writes a toon ramp or an X-Toon map
(:mod:`baker.bakes.toon`) and ``toon.json``. Options are the same dataclasses as ``--bakes tam`` / ``--bakes toon``
and use the same flags (``--tam-<option>``, ``--toon-<option>``).
"""
from __future__ import annotations

import sys
from pathlib import Path

from .errors import BakerError
from .options import add_arguments, from_args


def add_parser(sub) -> None:
    from .bakes.tam import TamOptions
    from .bakes.toon import ToonOptions

    p = sub.add_parser("tam", help="generate a tonal art map for real-time hatching (PNG levels + tam.json)")
    p.add_argument("-o", "--output", required=True, help="output folder (created if missing)")
    p.add_argument("--ktx2", action="store_true", help="also write KTX2 files (uncompressed, every level)")
    p.add_argument("--seed", type=int, default=0, help="random seed; the same seed gives byte-identical files")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary")
    add_arguments(p, TamOptions, "tam")
    p.set_defaults(func=run_tam)

    t = sub.add_parser("toon-ramp", help="generate a toon ramp or an X-Toon map (PNG + toon.json)")
    t.add_argument("-o", "--output", required=True, help="output folder (created if missing)")
    t.add_argument("-q", "--quiet", action="store_true", help="no summary")
    add_arguments(t, ToonOptions, "toon")
    t.set_defaults(func=run_toon)


def _folder(path) -> Path:
    folder = Path(path)
    if folder.exists() and not folder.is_dir():
        raise BakerError(folder, "exists and is not a folder")
    return folder


def run_tam(args) -> int:
    from .bakes.tam import TamOptions, check_options, generate_tam
    from .extensions.tam import write_tam_directory

    folder = _folder(args.output)
    try:
        options = from_args(TamOptions, "tam", args)
        check_options(options)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    tam = generate_tam(options, seed=args.seed)
    manifest = write_tam_directory(tam, folder, ktx2=args.ktx2)
    if not args.quiet:
        print(f"tam: {len(tam.targets)} tones x {len(tam.sizes)} levels ({tam.sizes[0]}..{tam.sizes[-1]} px), "
              f"{len(tam.strokes['x'])} strokes -> {folder}/tam.json", file=sys.stderr)
    return 0 if manifest else 2


def run_toon(args) -> int:
    from .bakes.toon import ToonOptions
    from .extensions.toon import write_toon_directory

    folder = _folder(args.output)
    try:
        options = from_args(ToonOptions, "toon", args)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    manifest = write_toon_directory(options, folder)
    if not args.quiet:
        print(f"toon-ramp: {manifest['width']} x {manifest['height']} -> {folder}/{manifest['file']}", file=sys.stderr)
    return 0
