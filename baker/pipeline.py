"""Run bakes on an asset in dependency order and write the result atomically: the engine behind ``baker bake``."""
from __future__ import annotations

import warnings

from pathlib import Path

from baker import readers, registry
from baker.errors import BakeNote, BakerError
from baker.geometry.asset import Asset
from baker.gltf.meshopt_encode import COMPRESSIONS
from baker.options import from_mapping
from baker.progress import QUIET

OUTPUT_SUFFIXES = {".glb", ".gltf", ".usd", ".usda", ".usdc", ".usdz"}


def resolve_options(name: str, value):
    """Options of bake ``name`` from None (defaults), an options instance, or a mapping of option values."""
    options = registry.bakes()[name].options
    if value is None:
        return options()
    if isinstance(value, options):
        return value
    return from_mapping(options, dict(value))


def bake(path_or_asset, bakes=("thickness",), options=None, seed: int = 0, progress=None,
         allow_outside=None, max_memory: int | None = None, attribute_layout="blender") -> Asset:
    """Load (or take) an asset and run ``bakes`` on it; each technique runs after those it ``requires``.
    ``allow_outside``: folders (beside the asset's own) its buffer and image URIs may point into. ``max_memory``:
    bytes; a job whose estimated working memory (:mod:`baker.memory`) exceeds it is refused before it starts (None:
    no limit; ``baker bake`` defaults to 75% of RAM). ``attribute_layout``: ``"blender"`` (custom vertex attributes
    share one width per mesh) or ``"native"`` (each at its data's width), see :mod:`baker.gltf.vertex_attributes`;
    a mesh whose attributes cannot share a width under ``"blender"`` gives one ``BlenderWidthWarning``."""
    from baker import memory
    from baker.gltf.vertex_attributes import AttributeLayout, parse

    try:
        layout = AttributeLayout(parse(attribute_layout))
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None

    order = registry.bake_order(bakes)
    asset = path_or_asset if isinstance(path_or_asset, Asset) else readers.read(path_or_asset, allow_outside, max_memory)
    options = options or {}
    resolved = {name: resolve_options(name, options.get(name)) for name in order}
    memory.check_bake(asset, order, resolved, max_memory)
    layout.width = registry.vertex_attribute_width(order)
    asset.doc.attribute_layout = layout
    asset.doc.vertex_index_members = registry.vertex_index_members()
    from baker.validate import referenced_accessors

    asset.doc.accessor_references = referenced_accessors
    techniques = registry.bakes()
    for name in order:
        techniques[name].bake(asset, resolved[name], seed=seed, progress=progress or QUIET)
    for text in asset.notes:
        warnings.warn(BakeNote(text), stacklevel=2)
    layout.warn(asset.doc.path.name if asset.doc.path else None)
    return asset


def save(asset: Asset, path, compress: str | None = None) -> list[Path]:
    """Write ``asset`` as glTF/GLB or USD (by the suffix of ``path``); returns every file written. ``compress``:
    ``"meshopt"`` stores the geometry as EXT_meshopt_compression, each bufferView as small as it gets;
    ``"meshopt-gzip"`` each as small as it gets once gzipped (glTF/GLB only; lossless, the bake intact)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in OUTPUT_SUFFIXES:
        raise BakerError(path, f"unsupported output type '{suffix}' (use one of {', '.join(sorted(OUTPUT_SUFFIXES))})")
    if compress not in (None, *COMPRESSIONS):
        raise BakerError(path, f"unknown compression {compress!r} (use one of {', '.join(COMPRESSIONS)})")
    if suffix in (".glb", ".gltf"):
        return asset.doc.save(path, compress=compress)
    if compress not in (None, "none"):
        raise BakerError(path, f"--compress {compress} writes glTF/GLB only, not '{suffix}'")
    from baker.gltf.usd import write_usd

    return write_usd(asset.doc, path, registry.usd_primitive_hooks(), registry.vertex_attribute_widths(),
                     registry.usd_texture_color_spaces(), registry.usd_primitive_accessors())
