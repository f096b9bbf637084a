"""Wire the toon-ramp generator to an Asset: one ramp texture, ``BAKER_toon_ramp`` on every material; and to a
folder, for the standalone ``baker toon-ramp -o DIR`` (:func:`run_toon_ramp`)."""
from __future__ import annotations

import sys

from baker.errors import BakerError
from baker.geometry.asset import Asset
from baker.options import from_args
from baker.techniques.toon.options import ToonOptions
from baker.techniques.toon import extension as ext
from baker.progress import QUIET, Progress


def run(asset: Asset, options: ToonOptions, seed: int = 0, progress: Progress = QUIET) -> None:
    texture = None
    for material in asset.material_groups():
        written = ext.write_toon_ramp(asset.doc, material, options, texture)
        texture = written["rampTexture"]["index"]


def run_toon_ramp(args) -> int:
    """``baker toon-ramp -o DIR``: the ramp (or X-Toon map) PNG and ``toon.json`` in a folder, no asset."""
    from baker.gltf.atomic import output_folder

    folder = output_folder(args.output)
    try:
        options = from_args(ToonOptions, "toon", args)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    manifest = ext.write_toon_directory(options, folder)
    if not args.quiet:
        print(f"toon-ramp: {manifest['width']} x {manifest['height']} -> {folder}/{manifest['file']}", file=sys.stderr)
    return 0
