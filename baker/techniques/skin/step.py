"""Wire the pre-integrated skin tables to an Asset: one LUT (and penumbra LUT) shared by every material, and a
``BAKER_skin_lut`` on each material naming where its curvature lives (baked attribute, baked texture, or neither:
then the runtime estimates it per pixel); and the standalone ``baker skin-lut -o OUT`` (:func:`run_skin_lut`)."""
from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from baker.errors import BakerError
from baker.geometry.asset import Asset
from baker.gltf.vertex_attributes import unpadded
from baker.techniques.skin.options import SkinOptions
from baker.techniques.skin.kernel import skin_tables
from baker.techniques.curvature import extension as curvature_ext
from baker.techniques.skin import extension as ext
from baker.options import from_args
from baker.progress import QUIET, Progress


def baked_curvature(doc, groups: dict) -> np.ndarray:
    """The mean curvature (1 / mesh units) of every vertex whose primitive has the curvature bake's attribute, over
    the primitives of ``groups``: the distribution the LUT's curvature axis is fitted to (empty without one)."""
    values = [np.zeros(0)]
    for members in groups.values():
        for m, p in members:
            attributes = doc.json["meshes"][m]["primitives"][p].get("attributes", {})
            if curvature_ext.ATTRIBUTE in attributes:
                values.append(unpadded(doc.accessor(attributes[curvature_ext.ATTRIBUTE]), 1).astype(np.float64))
    return np.concatenate(values)


def run(asset: Asset, options: SkinOptions, seed: int = 0, progress: Progress = QUIET) -> None:
    doc = asset.doc
    groups = asset.material_groups()
    with progress.task("skin LUTs", 1) as advance:
        tables = skin_tables(options, baked_curvature(doc, groups) / options.unit_scale)
        advance(1)
    lut = ext.add_lut_texture(doc, ext.encode_lut(tables.lut, options.bits, options.encoding), "skin_lut")
    penumbra = None
    if tables.penumbra is not None:
        penumbra = ext.add_lut_texture(doc, ext.encode_lut(tables.penumbra, options.bits, options.encoding),
                                       "skin_penumbra_lut")
    for material, members in groups.items():
        prims = [doc.json["meshes"][m]["primitives"][p] for m, p in members]
        attribute = curvature_ext.ATTRIBUTE
        has_attribute = all(attribute in prim.get("attributes", {}) for prim in prims)
        baked = (doc.json["materials"][material].get("extensions") or {}).get(curvature_ext.NAME) or {}
        texture = baked.get("curvatureTexture")
        ext.write_material_parameters(doc, material, tables=tables, options=options, lut_texture=lut,
                                      penumbra_texture=penumbra,
                                      curvature_attribute=attribute if has_attribute else None,
                                      curvature_texture=texture, curvature_texture_range=baked.get("textureRange"))


def run_skin_lut(args) -> int:
    """``baker skin-lut -o OUT``: the LUT images and their JSON sidecar, one atomic group."""
    from baker.gltf.atomic import write_files_atomic
    from baker.gltf.images import encode_image
    from baker.techniques.skin.lut_files import SUFFIXES, lut_pixels, sidecar


    out = Path(args.output)
    suffix = out.suffix.lower()
    if suffix not in SUFFIXES:
        raise BakerError(out, f"unsupported LUT image type (use one of {', '.join(SUFFIXES)})")
    try:
        options = from_args(SkinOptions, "skin", args)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    tables = skin_tables(options)
    penumbra_path = out.with_name(f"{out.stem}_penumbra{out.suffix}") if tables.penumbra is not None else None
    json_path = out.with_suffix(".json")
    fmt = "exr-float32" if suffix == ".exr" else f"png-{options.bits}bit"
    files = [(out, encode_image(lut_pixels(tables.lut, suffix, options), suffix))]
    if penumbra_path is not None:
        files.append((penumbra_path, encode_image(lut_pixels(tables.penumbra, suffix, options), suffix)))
    doc = sidecar(tables, options, out.name, penumbra_path.name if penumbra_path else None, fmt)
    files.append((json_path, (json.dumps(doc, indent=2) + "\n").encode("utf-8")))
    write_files_atomic(files)  # one atomic group, the sidecar last: all new files or all earlier ones
    if not args.quiet:
        extra = f", {penumbra_path}" if penumbra_path else ""
        print(f"skin LUT {tables.axes.width}x{tables.axes.height} -> {out}{extra}, {json_path}", file=sys.stderr)
    return 0
