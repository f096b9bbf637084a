"""``baker cards GROOM -o OUT``: read a groom (any format ``baker guides`` reads), make the cards, write them.

``.glb``/``.gltf``: a ``hair_cards`` mesh + material with ``BAKER_hair_cards`` (:mod:`.extension`);
``.usda``/``.usdc``/``.usd``: the same document through baker's USD writer (a Mesh, UsdPreviewSurface with the
atlas's colour and opacity (``opacityThreshold`` = alphaCutoff), the data and flow textures as ``UsdUVTexture``
outputs of the material, the card layout as ``baker:hair_cards:*`` attributes).
"""
from __future__ import annotations

import json
import sys
import time
from pathlib import Path

from baker.errors import BakerError
from baker.techniques.cards.command import CARDS_OUTPUT_SUFFIXES
from baker.options import from_args
from baker.techniques.cards.options import CardsOptions
from baker.techniques.hair_shading.options import HairMaterialOptions


def checked_options(args) -> CardsOptions:
    if Path(args.output).suffix.lower() not in CARDS_OUTPUT_SUFFIXES:
        raise BakerError(args.output, f"unsupported output type (use one of {', '.join(CARDS_OUTPUT_SUFFIXES)})")
    try:
        options = from_args(CardsOptions, "cards", args)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    if options.atlas_size & (options.atlas_size - 1):
        raise BakerError(None, f"--atlas-size must be a power of two, got {options.atlas_size}")
    return options


def make_cards_from_file(groom_path, options: CardsOptions):
    """(CardsResult, groom counts for BAKER_hair_cards, seconds per step) of a groom file."""
    from baker.techniques.cards.kernel import make_cards
    from baker.readers import read_groom
    from baker.readers.groom import clean_groom
    from baker.techniques.hair.guide_solver import resample_strands

    seconds = {}
    start = time.perf_counter()
    groom = clean_groom(read_groom(groom_path), groom_path, options.bad_curves)
    strands, lengths, widths = resample_strands(groom.points, groom.counts, options.vertices_per_strand,
                                                groom.widths)
    seconds["read"] = time.perf_counter() - start
    start = time.perf_counter()
    try:
        result = make_cards(strands, lengths, widths, options)
    except ValueError as exc:  # the atlas cannot hold the cards
        raise BakerError(None, str(exc)) from None
    seconds["cards"] = time.perf_counter() - start
    counts = {"strandCount": int(groom.count), "pointCount": int(len(groom.points)),
              "verticesPerStrand": int(options.vertices_per_strand),
              "meanStrandLength": float(lengths.mean()),
              "skippedCurves": int(sum((groom.skipped or {}).values()))}
    return result, counts, seconds


def scalp_document(groom_path, options: CardsOptions, max_memory: int | None = None):
    """(the scalp as a one-mesh document in world space, or None; where it came from): ``--scalp MESH``, else the
    groom file's own triangle mesh (a ``baker hair`` output holds its emitter)."""
    from baker.readers.scalp import read_scalp

    source = options.scalp or groom_path
    doc = read_scalp(source, max_memory=max_memory, required=bool(options.scalp))
    if doc is None and options.scalp:
        raise BakerError(options.scalp, "no triangle mesh found (--scalp needs a mesh)")
    return doc, (str(source) if doc is not None else None)


def build_document(result, counts: dict, options: CardsOptions, scalp=None, shading=None):
    """The cards' document: the scalp's (when there is one: the cards are added beside its mesh) or a new one;
    ``shading``: the hair material's options (``--hair-*``, default when None)."""
    from baker.gltf.document import GltfDocument
    from baker.techniques.cards.extension import write_cards

    doc = scalp if scalp is not None else GltfDocument()
    write_cards(doc, result, groom=counts, options=options, shading=shading)
    return doc


def write_output(doc, output) -> None:
    suffix = Path(output).suffix.lower()
    if suffix in (".glb", ".gltf"):
        doc.save(output)
    elif suffix == ".usdz":
        from baker.gltf.usd import write_usd
        from baker.registry import usd_primitive_hooks, usd_texture_color_spaces, vertex_attribute_widths

        write_usd(doc, output, usd_primitive_hooks(), vertex_attribute_widths(), usd_texture_color_spaces())
    else:
        write_usd_with_tables(doc, Path(output))


def write_usd_with_tables(doc, output: Path) -> None:
    """The document as USD (:mod:`baker.gltf.usd`), each hair material's ``BAKER_hair_shading`` tables added as
    ``baker:hair_shading:tableData:*`` (a stage has no bufferViews; :mod:`baker.readers.usd_baked` rebuilds them)."""
    from baker.gltf.usd import build_stage, write_stage_and_textures
    from baker.registry import (usd_primitive_accessors, usd_primitive_hooks, usd_texture_color_spaces,
                                vertex_attribute_widths)
    from baker.techniques.hair_shading.extension import usd_table_data, write_usd_table_data

    folder = f"{output.stem}_textures"
    stage, images = build_stage(doc, folder, usd_primitive_hooks(), vertex_attribute_widths(),
                                usd_texture_color_spaces(), usd_primitive_accessors())
    for prim in stage.Traverse():
        tables = prim.GetAttribute("baker:hair_shading:tables")
        if tables and tables.HasAuthoredValue():
            write_usd_table_data(prim, usd_table_data(doc, int(tables.Get())))
    write_stage_and_textures(stage, output, [(output.parent / folder / name, data) for name, data in images])


def run_cards(args) -> int:
    """``baker cards GROOM -o OUT``: the cards of a groom file, written as glTF or USD, and a summary."""
    options = checked_options(args)
    try:
        shading = from_args(HairMaterialOptions, "hair", args)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    scalp, scalp_source = scalp_document(args.input, options)  # before the bake: a bad --scalp fails at once
    result, counts, seconds = make_cards_from_file(args.input, options)
    start = time.perf_counter()
    write_output(build_document(result, counts, options, scalp, shading), args.output)
    seconds["write"] = time.perf_counter() - start
    s = result.stats
    info = {"input": str(args.input), "output": str(args.output), "strands": counts["strandCount"],
            "skippedCurves": counts["skippedCurves"], "cards": result.card_count, "scalp": scalp_source,
            "cardCountFrom": s["cardCountFrom"], "quads": s["quadCount"],
            "atlasSize": options.atlas_size, "clusteringError": s["clusteringError"],
            "cardDistance": s["cardDistance"], "pointsOnOpaqueTexels": s["pointsOnOpaqueTexels"],
            "fit": fit_verdict(s["cardDistance"]["within5Percent"], options.fit),
            "seconds": {k: round(v, 3) for k, v in seconds.items()}}
    if args.format == "json":
        print(json.dumps(info, indent=2, sort_keys=True))
    elif not args.quiet:
        chosen = " (count from the groom)" if s["cardCountFrom"]["source"] == "groom" else ""
        print(f"cards: {info['strands']} strands -> {info['cards']} cards{chosen}, {info['quads']} quads, atlas "
              f"{options.atlas_size}², fit {fit_text(info['fit'])}, {100 * s['pointsOnOpaqueTexels']:.1f} % on "
              f"opaque texels{', scalp from ' + scalp_source if scalp_source else ''} -> {args.output}",
              file=sys.stderr)
        if not info["fit"]["met"]:
            fit = info["fit"]
            print(f"cards: fit target MISSED: {100 * fit['within5Percent']:.1f} % of the strand points held, below "
                  f"the target {100 * fit['target']:.1f} %" + (
                  (f" ({info['cards']} cards: the cap of one card per 8 strands)"
                   if info["cards"] >= s["cardCountFrom"]["cap"] else
                   f" ({info['cards']} cards: no clump splits further)") if chosen else
                  " (raise --cards, or --cards 0 to split clumps until the target is met)"), file=sys.stderr)
    return 0


def fit_verdict(within: float, target: float) -> dict:
    """The fit figure against its target (``--fit``): the summary says when the cards miss it."""
    return {"within5Percent": float(within), "target": float(target), "met": bool(within >= target)}


def fit_text(fit: dict) -> str:
    """'75.4 % of strand points within 5 % of the mean strand length of their card, target 90.0 %: MISSED'."""
    verdict = "met" if fit["met"] else "MISSED, below target"
    return (f"{100 * fit['within5Percent']:.1f} % of strand points within 5 % of the mean strand length of their "
            f"card, target {100 * fit['target']:.1f} %: {verdict}")
