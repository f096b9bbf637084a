"""Wire the caustics generator to an Asset: one frame sequence, ``BAKER_caustics`` on every material."""
from __future__ import annotations

from baker.geometry.asset import Asset
from baker.geometry.texture_target import material_groups
from baker.progress import QUIET, Progress
from baker.techniques.caustics import extension as ext
from baker.techniques.caustics.options import CausticsOptions


def run(asset: Asset, options: CausticsOptions, seed: int = 0, progress: Progress = QUIET) -> None:
    from baker.techniques.caustics.kernel import caustic_frames, check_options

    try:
        check_options(options)
    except ValueError as exc:
        from baker.errors import BakerError

        raise BakerError(None, str(exc)) from None
    materials = list(material_groups(asset))
    frames = caustic_frames(options, seed=seed)
    textures, scale = ext.write_frame_textures(asset.doc, frames)
    for material in materials:
        ext.write_caustics(asset.doc, material, options, frames, textures, scale)
