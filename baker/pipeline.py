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
         allow_outside=None, max_memory: int | None = None, attribute_layout="blender", source=None, cage=None,
         cage_distance: float | None = None) -> Asset:
    """Load (or take) an asset and run ``bakes`` on it; each technique runs after those it ``requires``.
    ``allow_outside``: folders (beside the asset's own) its buffer and image URIs may point into. ``max_memory``:
    bytes; a job whose estimated working memory (:mod:`baker.memory`) exceeds it is refused before it starts (None:
    no limit; ``baker bake`` defaults to 75% of RAM). ``attribute_layout``: ``"blender"`` (custom vertex attributes
    share one width per mesh) or ``"native"`` (each at its data's width), see :mod:`baker.gltf.vertex_attributes`;
    a mesh whose attributes cannot share a width under ``"blender"`` gives one ``BlenderWidthWarning``.

    ``source``: a high mesh (path) to bake from (:mod:`baker.texels.transfer`): each texel's ray leaves the ``cage``
    (a mesh file with the asset's topology) or the surface pushed out by ``cage_distance`` (mesh units; None:
    automatic) and samples the source; only bakes whose technique ``transfers`` may be asked for."""
    from baker import memory
    from baker.gltf.vertex_attributes import AttributeLayout, parse

    try:
        layout = AttributeLayout(parse(attribute_layout))
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None

    order = registry.bake_order(bakes)
    if source is None and (cage is not None or cage_distance is not None):
        raise BakerError(cage, "--cage and --cage-distance need --from HIGH (the mesh to bake from)")
    if source is not None:
        unable = [n for n in order if not registry.bakes()[n].transfers]
        if unable:
            able = ", ".join(n for n, t in registry.bakes().items() if t.transfers)
            raise BakerError(source, f"bake(s) {', '.join(unable)} cannot bake from another mesh (--from works "
                             f"with: {able})")
    asset = path_or_asset if isinstance(path_or_asset, Asset) else readers.read(path_or_asset, allow_outside, max_memory)
    if source is not None:
        asset.transfer = read_transfer(asset, source, cage, cage_distance, allow_outside, max_memory)
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
    if asset.transfer is not None:
        write_transfer_summary(asset)
    for text in asset.notes:
        warnings.warn(BakeNote(text), stacklevel=2)
    layout.warn(asset.doc.path.name if asset.doc.path else None)
    return asset


def save(asset: Asset, path, compress: str | None = None) -> list[Path]:
    """Write ``asset`` as glTF/GLB or USD (by the suffix of ``path``); returns every file written. ``compress``:
    ``"meshopt"`` stores the geometry as EXT_meshopt_compression, each bufferView as small as it gets;
    ``"meshopt-gzip"`` each as small as it gets once gzipped, both with the float vertex attributes through the
    EXPONENTIAL filter; ``"meshopt-lossless"`` every byte kept (glTF/GLB only; the bake intact)."""
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


def read_transfer(asset: Asset, source, cage, cage_distance, allow_outside, max_memory):
    """Read the high mesh (and the cage) of a bake from another mesh, checked before any bake runs."""
    from baker.texels.transfer import check_cage_topology, read_request

    for path, what in ((source, "--from"), (cage, "--cage")):
        if path is not None and not Path(path).is_file():
            raise BakerError(path, f"{what}: no such file")
    if cage_distance is not None and not (cage_distance >= 0.0 and cage_distance < float("inf")):
        raise BakerError(None, f"--cage-distance must be a finite distance >= 0, got {cage_distance}")
    source_asset = readers.read(source, allow_outside, max_memory)
    cage_asset = None if cage is None else readers.read(cage, allow_outside, max_memory)
    request = read_request(source, source_asset, cage, cage_asset, cage_distance)
    check_cage_topology(request, asset)
    return request


def write_transfer_summary(asset: Asset) -> None:
    """``asset.extras.baker.transfer``: the source, the cage and, per bake, the texels whose ray missed the source
    (filled from their neighbours); misses are also a note."""
    request = asset.transfer
    summary = {"source": request.source_path.name, "sourceTriangles": int(len(request.source.faces))}
    if request.cage_path is not None:
        summary["cage"] = request.cage_path.name
    elif request.cage_distance is not None:
        summary["cageDistance"] = float(request.cage_distance)
        summary["cageDistanceAutomatic"] = bool(request.summary.get("cageDistanceAutomatic", False))
    if request.summary.get("parts"):
        summary["parts"] = request.summary["parts"]
    bakes = request.summary.get("bakes", {})
    if bakes:
        summary["bakes"] = bakes
    extras = asset.doc.json.setdefault("asset", {}).setdefault("extras", {})
    if isinstance(extras, dict):
        baker_extras = extras.setdefault("baker", {})
        if isinstance(baker_extras, dict):
            baker_extras["transfer"] = summary
    for name, kinds in bakes.items():
        for kind, counts in kinds.items():
            if counts["misses"]:
                asset.note(f"{name}: {counts['misses']} of {counts['samples']} {kind} found no source surface within "
                           "the cage; they take their neighbours' hits")
