"""The work of the hair technique's commands: ``baker hair`` (:func:`run_hair`: strands grown on an emitter, by
:mod:`.grow`) and ``baker guides`` (:func:`run_guides`: a groom's guides, weights and LODs, by :mod:`.guides`)."""
from __future__ import annotations

import json
import sys
from pathlib import Path

from baker.errors import BakerError
from baker.memory import parse_limit
from baker.options import from_args
from baker.progress import Progress
from baker.techniques.hair.command import GUIDES_OUTPUT_SUFFIXES, OUTPUT_SUFFIXES
from baker.techniques.hair.options import GuidesOptions, HairOptions
from baker.techniques.hair_shading.options import HairMaterialOptions


def checked_options(args, options_class, prefix: str, suffixes):
    """The options of a hair command from its parsed flags, once the output suffix is known to be one of
    ``suffixes``; a bad suffix or value is a BakerError (one line, exit 2)."""
    if Path(args.output).suffix.lower() not in suffixes:
        raise BakerError(args.output, f"unsupported output type (use one of {', '.join(suffixes)})")
    try:
        return from_args(options_class, prefix, args)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None


def run_hair(args) -> int:
    """``baker hair SCALP -o OUT``: grow guides and children on the emitter mesh, write them, say what was grown."""
    from baker.techniques.hair.grow import make_hair, write_output

    options = checked_options(args, HairOptions, "hair", OUTPUT_SUFFIXES)
    shading = checked_options(args, HairMaterialOptions, "hair", OUTPUT_SUFFIXES)
    asset, result = make_hair(args.input, options, seed=args.seed, max_memory=parse_limit(args.max_memory))
    write_output(asset, result, options, args.output, shading, seed=args.seed)
    if not args.quiet:
        print(f"hair: {result.guides.count} guides + {result.children.count} children x {result.guides.vertices} "
              f"vertices -> {args.output}", file=sys.stderr)
    return 0


def run_guides(args) -> int:
    """``baker guides GROOM -o OUT``: guides, child weights and LODs of a dense groom, written, and a summary."""
    from baker.techniques.hair.guides import make_guides, summary, write_output

    options = checked_options(args, GuidesOptions, "guides", GUIDES_OUTPUT_SUFFIXES)
    shading = checked_options(args, HairMaterialOptions, "hair", GUIDES_OUTPUT_SUFFIXES)
    progress = Progress(enabled=False) if args.quiet else Progress()
    bake = make_guides(args.input, options, progress, max_memory=parse_limit(args.max_memory))
    write_output(bake, args.output, options, shading)
    info = summary(bake, args.input, args.output)
    if args.format == "json":
        print(json.dumps(info, indent=2, sort_keys=True))
    elif not args.quiet:
        skipped = ", ".join(f"{n} {reason}" for reason, n in info["skipped"].items()) or "none"
        print(f"guides: {info['strands']} strands -> {info['guides']} guides x {info['verticesPerStrand']} vertices, "
              f"reconstruction error RMS {100 * info['rmsError']:.2f} % / max {100 * info['maxError']:.2f} % of "
              f"strand length, {len(bake.lods)} LODs, skipped: {skipped} -> {args.output}", file=sys.stderr)
    return 0
