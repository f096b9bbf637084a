"""The ``baker`` command: parse, run, report. No algorithm lives here.

Exit codes: 0 success, 1 validation errors found, 2 bad input or usage.
"""
from __future__ import annotations

import argparse
import sys

from . import __version__
from .errors import BakerError
from .options import add_arguments, from_args
from .progress import Progress
from .steps import BAKES

# modules with ``add_parser(subparsers)`` that set ``func(args) -> exit code``; a new command adds one line here
from . import build as build_command  # noqa: E402
from . import preview  # noqa: E402
from . import tam_commands  # noqa: E402
from . import lines as lines_command  # noqa: E402
from . import skin_commands  # noqa: E402
from . import hair_command  # noqa: E402
from . import glyphs_command, text_command  # noqa: E402

COMMANDS: list = [build_command, preview, tam_commands, lines_command, skin_commands, hair_command, glyphs_command, text_command]


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="baker", description="Bake real-time rendering data into glTF and USD assets.")
    parser.add_argument("--version", action="version", version=f"baker {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("bake", help="bake data into an asset and write it as glTF/GLB or USD")
    p.add_argument("input", help="input asset (.gltf .glb .obj .ply .stl .usd .usda .usdc .usdz)")
    p.add_argument("-o", "--output", required=True, help="output file (.glb .gltf .usda .usdc .usdz)")
    p.add_argument("--bakes", default="thickness", help=f"comma-separated bakes to run (known: {', '.join(BAKES)})")
    p.add_argument("--seed", type=int, default=0, help="random seed; the same seed gives byte-identical output")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bars or summary")
    for name, step in BAKES.items():
        add_arguments(p, step.options, name)

    v = sub.add_parser("validate", help="check BAKER_* extensions and the structure baker needs (exit 1 on errors)")
    v.add_argument("files", nargs="+", help="glTF or GLB files")
    v.add_argument("--format", choices=("text", "json"), default="text", help="report format")
    v.add_argument("--no-khronos", action="store_true", help="do not run Khronos' gltf-validator even if present")
    v.add_argument("-q", "--quiet", action="store_true", help="print only errors")

    i = sub.add_parser("inspect", help="print a table of what is in an asset")
    i.add_argument("file")
    i.add_argument("--format", choices=("text", "json"), default="text")

    # standalone generators (LUTs, atlases, drawings...): each module adds its parser and sets ``func``
    for command in COMMANDS:
        command.add_parser(sub)
    return parser


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    try:
        if args.command == "bake":
            return _bake(args)
        if args.command == "validate":
            from .validate import main as validate_main

            return validate_main(args.files, fmt=args.format, khronos=not args.no_khronos, quiet=args.quiet)
        if args.command == "inspect":
            from .inspect import main as inspect_main

            return inspect_main(args.file, fmt=args.format)
        if hasattr(args, "func"):
            return args.func(args)
    except BakerError as exc:
        print(f"baker: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("baker: interrupted", file=sys.stderr)
        return 130
    return 2


def _bake(args) -> int:
    from .pipeline import OUTPUT_SUFFIXES, bake, save
    from pathlib import Path

    names = [b.strip() for b in args.bakes.split(",") if b.strip()]
    unknown = [b for b in names if b not in BAKES]
    if unknown:
        raise BakerError(None, f"unknown bake(s) {', '.join(unknown)} (known: {', '.join(BAKES)})")
    if Path(args.output).suffix.lower() not in OUTPUT_SUFFIXES:
        raise BakerError(args.output, f"unsupported output type (use one of {', '.join(sorted(OUTPUT_SUFFIXES))})")
    try:
        options = {name: from_args(BAKES[name].options, name, args) for name in names}
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    progress = Progress(enabled=False if args.quiet else None)
    asset = bake(args.input, bakes=names, options=options, seed=args.seed, progress=progress)
    save(asset, args.output)
    if not args.quiet:
        print(f"baked {', '.join(names)} -> {args.output}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
