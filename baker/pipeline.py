"""Run bakes on an asset and write the result: the Python API behind ``baker bake``."""
from __future__ import annotations

from pathlib import Path

from .asset import Asset
from .errors import BakerError
from .options import from_mapping
from .progress import QUIET
from .steps import BAKES

OUTPUT_SUFFIXES = {".glb", ".gltf", ".usd", ".usda", ".usdc", ".usdz"}


def resolve_options(name: str, value):
    step = BAKES[name]
    if value is None:
        return step.options()
    if isinstance(value, step.options):
        return value
    return from_mapping(step.options, dict(value))


def bake(path_or_asset, bakes=("thickness",), options=None, seed: int = 0, progress=None) -> Asset:
    asset = path_or_asset if isinstance(path_or_asset, Asset) else Asset.load(path_or_asset)
    options = options or {}
    unknown = [b for b in bakes if b not in BAKES]
    if unknown:
        raise BakerError(None, f"unknown bake(s) {', '.join(unknown)} (known: {', '.join(BAKES)})")
    for name in bakes:
        BAKES[name].run(asset, resolve_options(name, options.get(name)), seed=seed, progress=progress or QUIET)
    return asset


def save(asset: Asset, path) -> list[Path]:
    """Write ``asset`` as glTF/GLB or USD (by the suffix of ``path``); returns every file written."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in OUTPUT_SUFFIXES:
        raise BakerError(path, f"unsupported output type '{suffix}' (use one of {', '.join(sorted(OUTPUT_SUFFIXES))})")
    if suffix in (".glb", ".gltf"):
        return asset.doc.save(path)
    from .io.usd import write_usd

    return write_usd(asset.doc, path)
