"""Wire the pre-integrated skin tables to an Asset: one LUT (and penumbra LUT) shared by every material, and a
``BAKER_skin_lut`` on each material naming where its curvature lives (baked attribute, baked texture, or neither:
then the runtime estimates it per pixel)."""
from __future__ import annotations

import numpy as np

from baker.geometry.asset import Asset
from baker.gltf.vertex_attributes import unpadded
from baker.techniques.skin.options import SkinOptions
from baker.techniques.skin.kernel import skin_tables
from baker.techniques.curvature import extension as curvature_ext
from baker.techniques.skin import extension as ext
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
