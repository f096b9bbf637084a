"""Wire the toon-ramp generator to an Asset: one ramp texture, ``BAKER_toon_ramp`` on every material."""
from __future__ import annotations

from baker.geometry.asset import Asset
from baker.techniques.toon.options import ToonOptions
from baker.techniques.toon import extension as ext
from baker.progress import QUIET, Progress


def run(asset: Asset, options: ToonOptions, seed: int = 0, progress: Progress = QUIET) -> None:
    texture = None
    for material in asset.material_groups():
        written = ext.write_toon_ramp(asset.doc, material, options, texture)
        texture = written["rampTexture"]["index"]
