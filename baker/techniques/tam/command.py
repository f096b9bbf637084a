"""Standalone generator ``baker tam -o DIR``: no asset, just the textures.

It writes a tonal art map (Praun et al. 2001; :mod:`baker.techniques.tam.kernel`) as per-level PNGs and a
``tam.json`` manifest, optionally with KTX2 files. Options are the dataclass of ``--bakes tam`` and use the same
flags (``--tam-<option>``).
"""
from __future__ import annotations

import sys

from baker.errors import BakerError
from baker.options import add_arguments, from_args


def add_parser(sub) -> None:
    from baker.techniques.tam.options import TamOptions

    p = sub.add_parser("tam", help="generate a tonal art map for real-time hatching (PNG levels + tam.json)")
    p.add_argument("-o", "--output", required=True, help="output folder (created if missing)")
    p.add_argument("--ktx2", action="store_true", help="also write KTX2 files (uncompressed, every level)")
    p.add_argument("--seed", type=int, default=0, help="random seed; the same seed gives byte-identical files")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary")
    add_arguments(p, TamOptions, "tam")
    p.set_defaults(func=run_tam)


def run_tam(args) -> int:
    from baker.techniques.tam.options import TamOptions
    from baker.techniques.tam.kernel import check_options, generate_tam
    from baker.gltf.atomic import output_folder
    from baker.techniques.tam.extension import write_tam_directory

    folder = output_folder(args.output)
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
