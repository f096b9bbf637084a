"""Wire the TAM generator to an Asset: one TAM, attached to every material as ``BAKER_tonal_art_map``.

``--tam-strokes field`` (the default): the TAM is applied through a new TEXCOORD set of lapped, field-aligned
patches (:mod:`baker.techniques.tam.strokes`), at a uniform ``scale`` finest-level texels per mesh unit (default:
one tile across about 1/6 of the covered primitives' bounding-box diagonal); the set counts tiles, so the
extension's ``scale`` is the finest size. Splitting vertices, tam runs after every bake that does not
(``Technique.splits_vertices``).

``--tam-strokes uv``: the TAM tiles, so any UV set works, overlapping or not: a material whose primitives all have
``TEXCOORD_0`` uses it; otherwise its primitives are unwrapped with xatlas into a new set (as the texture bakes
do). The tiling rate ``scale`` (finest-level texels per UV unit) defaults to one tile across about 1/6 of the
mesh's bounding-box diagonal, measured through the UV set's own texel density (world area / UV area).

Either way a material without ``TEXCOORD_0`` gets the shared unwrap first, so the stroke set lands at the same
index whether or not a texture bake ran. The standalone ``baker tam -o
DIR`` (:func:`run_tam`) writes the TAM to a folder instead.
"""
from __future__ import annotations

import math
import sys

import numpy as np

from baker.geometry.asset import Asset
from baker.techniques.tam.options import TamOptions
from baker.techniques.tam.kernel import check_options, generate_tam
from baker.errors import BakerError
from baker.options import from_args
from baker.techniques.tam import extension as ext
from baker.progress import QUIET, Progress
from baker.texels.targets import unwrap_material, unwraps_started

TILES_PER_DIAGONAL = 6.0


def _area(points: np.ndarray, faces: np.ndarray) -> float:
    a, b, c = (points[faces[:, k]] for k in range(3))
    if points.shape[1] == 2:
        cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
        return float(0.5 * np.abs(cross).sum())
    return float(0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum())


def auto_scale(geoms: list, texcoord: int, size: int) -> float:
    """Finest-level texels per UV unit so that one tile spans ~1/TILES_PER_DIAGONAL of the bounding diagonal."""
    points = np.concatenate([g.positions for g in geoms])
    diagonal = float(np.linalg.norm(points.max(0) - points.min(0))) or 1.0
    world = sum(_area(g.positions, g.faces) for g in geoms)
    uv = sum(_area(g.texcoords[texcoord], g.faces) for g in geoms)
    if world <= 0.0 or uv <= 0.0:
        return float(size)
    world_per_uv = math.sqrt(world / uv)  # mesh units spanned by one UV unit, on average
    tiles = max(1, round(world_per_uv * TILES_PER_DIAGONAL / diagonal))  # whole tiles: seamless at UV 0/1
    return float(tiles * size)


def strokes_density(asset: Asset, groups: dict, size: int) -> float:
    """Finest-level texels per mesh unit so that one tile spans ~1/TILES_PER_DIAGONAL of the bounding diagonal of
    the primitives ``groups`` covers (``--tam-strokes field`` without ``--tam-scale``)."""
    points = np.concatenate([asset.primitive(m, p).positions for members in groups.values() for m, p in members])
    diagonal = float(np.linalg.norm(points.max(0) - points.min(0)))
    return size * TILES_PER_DIAGONAL / diagonal if diagonal > 0 else float(size)


def run(asset: Asset, options: TamOptions, seed: int = 0, progress: Progress = QUIET) -> None:
    try:
        check_options(options)
    except ValueError as exc:
        raise BakerError(asset.source, str(exc)) from None
    doc = asset.doc
    options = options.for_bake()
    with progress.task("tonal art map", 1) as advance:
        tam = generate_tam(options, seed=seed)
        advance(1)
    groups, unwrapped = {}, []
    for material, members in asset.material_groups().items():
        members = [(m, p) for m, p in members if len(asset.primitive(m, p).faces)]
        if not members:
            continue
        groups[material] = members
        if not all(0 in asset.primitive(m, p).texcoords for m, p in members):
            # no UVs to tile along (uv) or to keep as TEXCOORD_0 beside the strokes (field): the layout the texture
            # bakes, fur and tam share, made once per asset whichever runs first, so the stroke set's index does
            # not depend on which other bakes ran
            unwrapped.append(material)
    if not groups:
        return
    if options.strokes == "field":
        from baker.techniques.tam.strokes import solve_strokes, write_strokes

        density = options.scale if options.scale is not None else strokes_density(asset, groups, options.size)
        # the strokes are solved on the welded mesh, which the unwrap keeps vertex for vertex: the unwrap runs in a
        # child process meanwhile (the bunny: xatlas 1.0 s beside 1.2 s of field and patches)
        with unwraps_started(asset, materials=unwrapped), progress.task("tam strokes", 1) as advance:
            solved = solve_strokes(asset, groups, density, options.size, options.combing)
            for material in unwrapped:
                unwrap_material(asset, material, groups[material], seed)
            textures = ext.write_tam_textures(doc, tam)
            made = write_strokes(asset, groups, solved, direction=options.direction)
            advance(1)
        for material, strokes in made.items():
            record = {"texelsPerUnit": float(density), "field": strokes.field,
                      "patches": len(strokes.patches), "fallbackFaces": strokes.fallback_faces,
                      "singularities": strokes.singular_faces}
            if options.direction:
                record = {"directionAttribute": ext.DIRECTION_ATTRIBUTE, **record}
            # the coordinates count tiles: one finest level of texels per coordinate unit
            ext.write_tam(doc, material, tam, textures, scale=float(options.size), texcoord=strokes.texcoord,
                          strokes=record)
        return
    for material in unwrapped:
        unwrap_material(asset, material, groups[material], seed)
    textures = ext.write_tam_textures(doc, tam)
    for material, members in groups.items():
        geoms = [asset.primitive(m, p) for m, p in members]
        texcoord = 0 if all(0 in g.texcoords for g in geoms) else unwrap_material(asset, material, members, seed)[0]
        scale = options.scale if options.scale is not None else auto_scale(geoms, texcoord, options.size)
        ext.write_tam(doc, material, tam, textures, scale=scale, texcoord=texcoord)


def run_tam(args) -> int:
    """``baker tam -o DIR``: the per-level PNGs and ``tam.json`` (optionally KTX2) in a folder, no asset."""
    from baker.gltf.atomic import output_folder

    folder = output_folder(args.output)
    try:
        options = from_args(TamOptions, "tam", args)
        check_options(options)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    tam = generate_tam(options, seed=args.seed)
    manifest = ext.write_tam_directory(tam, folder, ktx2=args.ktx2)
    if not args.quiet:
        print(f"tam: {len(tam.targets)} tones x {len(tam.sizes)} levels ({tam.sizes[0]}..{tam.sizes[-1]} px), "
              f"{len(tam.strokes['x'])} strokes -> {folder}/tam.json", file=sys.stderr)
    return 0 if manifest else 2
