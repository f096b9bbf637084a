"""Standalone generator ``baker caustics -o DIR``: a looping, tileable caustic sequence
(:mod:`baker.techniques.caustics.kernel`) as 16-bit PNG frames and ``caustics.json`` (optionally one KTX2 array),
with the options and flags of ``--bakes caustics`` (``--caustics-<option>``)."""
from __future__ import annotations

import sys

from baker.errors import BakerError
from baker.options import add_arguments, from_args


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
    p.set_defaults(func=run_caustics)


def run_caustics(args) -> int:
    from baker.gltf.atomic import output_folder
    from baker.techniques.caustics.extension import write_caustics_directory
    from baker.techniques.caustics.kernel import caustic_frames, check_options
    from baker.techniques.caustics.options import CausticsOptions, at_scale

    folder = output_folder(args.output)
    try:
        options = at_scale(from_args(CausticsOptions, "caustics", args))[0]  # no asset: the tile's scale, else 1
        check_options(options)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    if args.seed < 0:
        raise BakerError(None, f"--seed must be >= 0, got {args.seed}")
    frames = caustic_frames(options, seed=args.seed)
    manifest = write_caustics_directory(options, frames, folder, seed=args.seed, ktx2=args.ktx2)
    if not args.quiet:
        e = frames.irradiance
        print(f"caustics: {manifest['frameCount']} frames of {options.size} x {options.size}, irradiance mean "
              f"{e.mean():.3f} max {e.max():.2f} -> {folder}/caustics.json", file=sys.stderr)
    return 0
