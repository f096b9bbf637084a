"""``baker hair SCALP -o OUT``: the parser; the work is in :mod:`baker.techniques.hair.grow`, imported when it runs."""
from __future__ import annotations

from baker import memory
from baker.options import add_arguments, from_args
from baker.technique import lazy
from baker.techniques.hair.options import HairOptions

OUTPUT_SUFFIXES = (".glb", ".gltf", ".usda", ".usdc", ".usd", ".tfx")


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("hair", help="grow hair guide strands + children on a mesh (glTF, USD or TressFX)")
    p.add_argument("input", help="emitter (scalp) mesh: .gltf .glb .obj .ply .stl .usd .usda .usdc .usdz")
    p.add_argument("-o", "--output", required=True, help=f"output file ({' '.join(OUTPUT_SUFFIXES)})")
    p.add_argument("--seed", type=int, default=0, help="random seed; the same seed gives byte-identical output")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary")
    memory.add_argument(p)
    add_arguments(p, HairOptions, "hair", prefixed_flags=False)
    p.set_defaults(func=lazy("baker.techniques.hair.grow:run"))


def checked_options(args, options_class, prefix: str, suffixes):
    """The options of a hair command from its parsed flags, once the output suffix is known to be one of
    ``suffixes``; a bad suffix or value is a BakerError (one line, exit 2)."""
    from pathlib import Path

    from baker.errors import BakerError

    if Path(args.output).suffix.lower() not in suffixes:
        raise BakerError(args.output, f"unsupported output type (use one of {', '.join(suffixes)})")
    try:
        return from_args(options_class, prefix, args)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
