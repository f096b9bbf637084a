"""Wire the pre-integrated skin tables to an Asset: one LUT (and penumbra LUT) shared by every material, and a
``BAKER_skin_lut`` on each material naming where its curvature lives (baked attribute, baked texture, or neither:
then the runtime estimates it per pixel)."""
from __future__ import annotations

from baker.geometry.asset import Asset
from baker.techniques.skin.options import SkinOptions
from baker.techniques.skin.kernel import skin_tables
from baker.techniques.curvature import extension as curvature_ext
from baker.techniques.skin import extension as ext
from baker.progress import QUIET, Progress
from baker.geometry.texture_target import material_groups


def run(asset: Asset, options: SkinOptions, seed: int = 0, progress: Progress = QUIET) -> None:
    doc = asset.doc
    groups = material_groups(asset)
    with progress.task("skin LUTs", 1) as advance:
        tables = skin_tables(options)
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
