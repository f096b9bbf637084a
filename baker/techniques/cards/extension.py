"""``BAKER_hair_cards``: hair cards (:mod:`baker.techniques.cards.kernel`) as a glTF mesh + alpha-tested material.

Where the data goes (see ``schemas/BAKER_hair_cards/README.md``):

- a ``hair_cards`` mesh with one triangle primitive: POSITION, NORMAL, TANGENT (the +u direction across the card,
  w = -1 so that glTF's bitangent cross(normal, tangent) x w runs from root to tip, +v), TEXCOORD_0 into the atlas;
  indices card after card, inner cards (near the scalp) first; ``BAKER_hair_cards`` on the primitive: card count,
  each card's atlas region and first index (accessors), the draw order, the source groom's counts and the
  clustering error;
- its material: the atlas's base colour (sRGB) with coverage in alpha, ``alphaMode: MASK`` + ``alphaCutoff``,
  double-sided; ``BAKER_hair_cards`` on the material: the data texture (depth offset from the card plane,
  root-to-tip parameter, per-strand random value) and the flow texture (the strands' direction in tangent space),
  what each channel holds, the depth range and the atlas layout parameters; ``coverageMips``: the base colour's
  coverage-preserving mip chain (Castaño 2010; :mod:`baker.texels.alpha_mips`), an RGBA8 KTX2 in an accessor, so
  the cards keep their alpha-test coverage with distance (RTR4 14.7.1) in a runtime that loads it.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from baker.texels.alpha_mips import check_coverage_mips, write_coverage_mips
from baker.gltf.document import TARGET_ELEMENT_ARRAY_BUFFER, GltfDocument
from baker.gltf.images import encode_image

NAME = "BAKER_hair_cards"
# LINEAR, LINEAR_MIPMAP_LINEAR, CLAMP_TO_EDGE: regions are padded, nothing wraps
ATLAS_SAMPLER = {"magFilter": 9729, "minFilter": 9987, "wrapS": 33071, "wrapT": 33071}
DATA_CHANNELS = {"r": "depth", "g": "rootToTip", "b": "strandRandom"}
FLOW_ENCODING = "tangentSpace"


def alpha_tested_image(result) -> tuple[np.ndarray, float]:
    """(base colour RGBA uint8 (S, S, 4), alphaCutoff): the alpha-tested texture of a
    :class:`~baker.techniques.cards.kernel.CardsResult`, for a coverage-preserving mip chain."""
    return result.base_color, result.alpha_cutoff


def write_cards(doc: GltfDocument, result, *, groom: dict, options, shading=None) -> tuple[int, int]:
    """Add the cards mesh, its node, material and textures to ``doc`` (with ``options.coverage_mips``, the base
    colour's coverage-preserving mip chain too; ``BAKER_hair_shading`` from ``shading``, a
    :class:`~baker.techniques.hair_shading.options.HairMaterialOptions`, default when None); returns (mesh,
    material)."""
    from baker.techniques.hair_shading.extension import NAME as SHADING, material_extension
    from baker.techniques.hair_shading.options import HairMaterialOptions

    images = [doc.add_image(encode_image(np.ascontiguousarray(pixels), ".png"), "image/png", name)
              for pixels, name in ((result.base_color, "hair_cards_color"), (result.data, "hair_cards_data"),
                                   (result.flow, "hair_cards_flow"))]
    color, data, flow = (doc.add_texture(i, sampler=ATLAS_SAMPLER, name=f"baker hair cards {what}")
                         for i, what in zip(images, ("color", "data", "flow")))
    materials = doc.json.setdefault("materials", [])
    materials.append({
        "name": "baker_hair_cards",
        "pbrMetallicRoughness": {"baseColorTexture": {"index": color}, "metallicFactor": 0.0,
                                 "roughnessFactor": 0.55},
        "alphaMode": "MASK", "alphaCutoff": float(result.alpha_cutoff), "doubleSided": True,
        "extensions": {NAME: {
            "dataTexture": {"index": data}, "dataChannels": dict(DATA_CHANNELS),
            "flowTexture": {"index": flow}, "flowEncoding": FLOW_ENCODING,
            "depthRange": float(result.depth_range), "atlasSize": int(result.base_color.shape[0]),
            "padding": int(options.padding), "texelDensity": float(result.texel_density)}}})
    material = len(materials) - 1
    # the fibre model on the cards too (its parameters and tables; no per-vertex strand data on a card)
    materials[material]["extensions"][SHADING] = material_extension(doc, shading or HairMaterialOptions())
    doc.use_extension(SHADING)
    if options.coverage_mips:
        rgba, cutoff = alpha_tested_image(result)
        # the base colour is sRGB (glTF): the chain filters its colour in linear light
        materials[material]["extensions"][NAME]["coverageMips"] = [
            write_coverage_mips(doc, color, rgba, cutoff, transfer="srgb")]
    attributes = {
        "POSITION": doc.add_accessor(result.positions, min_max=True),
        "NORMAL": doc.add_accessor(result.normals),
        "TANGENT": doc.add_accessor(result.tangents),
        "TEXCOORD_0": doc.add_accessor(result.texcoords),
    }
    big = len(result.positions) > 0xFFFF
    stats = result.stats
    prim = {"attributes": attributes, "mode": 4, "material": material,
            "indices": doc.add_accessor(result.indices.astype(np.uint32 if big else np.uint16),
                                        target=TARGET_ELEMENT_ARRAY_BUFFER),
            "extensions": {NAME: {
                "cardCount": int(result.card_count),
                "regions": doc.add_accessor(result.regions.astype(np.float32), target=None),
                "cardFirstIndex": doc.add_accessor(result.card_first_index.astype(np.uint32), target=None),
                "drawOrder": "innerFirst",
                "groom": dict(groom),
                "clusteringError": {k: float(v) for k, v in stats["clusteringError"].items()},
                "cardDistance": {k: float(v) for k, v in stats["cardDistance"].items()}}}}
    meshes = doc.json.setdefault("meshes", [])
    meshes.append({"name": "hair_cards", "primitives": [prim]})
    mesh = len(meshes) - 1
    nodes = doc.json.setdefault("nodes", [])
    nodes.append({"name": "hair_cards", "mesh": mesh})
    scenes = doc.json.setdefault("scenes", [{"nodes": []}])
    doc.json.setdefault("scene", 0)
    scenes[doc.json["scene"]].setdefault("nodes", []).append(len(nodes) - 1)
    doc.use_extension(NAME)
    return mesh, material


# ---------------------------------------------------------------------------------------------------------- validate
def check(doc: GltfDocument, places: list, issues) -> None:
    """Semantic rules of BAKER_hair_cards: on the material, textures exist, alphaMode is MASK, the depth range is
    positive; on the primitive, a triangle primitive with TEXCOORD_0 whose regions (cardCount x VEC4 in [0, 1],
    u0 < u1, v0 < v1) and first indices (cardCount, ascending, inside the index count, multiples of 3) agree."""
    from baker.checks import is_index, is_number, pointer

    gltf = doc.json
    textures = gltf.get("textures") or []
    meshes = gltf.get("meshes") or []
    accessors = gltf.get("accessors") or []
    for parts, ext in places:
        if not isinstance(ext, dict):
            continue
        if len(parts) == 2 and parts[0] == "materials":
            ptr = pointer("materials", parts[1], "extensions", NAME)
            material = gltf["materials"][parts[1]]
            if material.get("alphaMode") != "MASK":
                issues.warning("BAKER_HAIR_CARDS_ALPHA_MODE", "hair cards are alpha-tested: alphaMode should be "
                               "MASK", pointer("materials", parts[1], "alphaMode"))
            for key in ("dataTexture", "flowTexture"):
                info = ext.get(key)
                if isinstance(info, dict) and not is_index(info.get("index"), textures):
                    issues.error("UNRESOLVED_REFERENCE", f"texture {info.get('index')!r} does not exist",
                                 f"{ptr}/{key}/index")
            if is_number(ext.get("depthRange")) and not ext["depthRange"] > 0:
                issues.error("BAKER_HAIR_CARDS_DEPTH_RANGE", "depthRange must be > 0", ptr + "/depthRange")
            if "coverageMips" in ext:
                check_coverage_mips(doc, ext["coverageMips"], ptr + "/coverageMips", issues)
                base = ((material.get("pbrMetallicRoughness") or {}).get("baseColorTexture") or {}).get("index")
                mipped = [e.get("texture") for e in ext["coverageMips"] if isinstance(e, dict)] \
                    if isinstance(ext["coverageMips"], list) else []
                if base is not None and base not in mipped:
                    issues.warning("BAKER_HAIR_CARDS_COVERAGE_MIPS", f"the base colour texture {base!r} has no "
                                   "coverage-preserving mip chain", ptr + "/coverageMips")
                for i, entry in enumerate(ext["coverageMips"] if isinstance(ext["coverageMips"], list) else []):
                    if isinstance(entry, dict) and is_number(entry.get("alphaCutoff")) and \
                            is_number(material.get("alphaCutoff", 0.5)) and \
                            abs(entry["alphaCutoff"] - material.get("alphaCutoff", 0.5)) > 1e-6:
                        issues.warning("BAKER_HAIR_CARDS_COVERAGE_MIPS", f"the chain preserves the coverage of "
                                       f"alphaCutoff {entry['alphaCutoff']}, the material cuts at "
                                       f"{material.get('alphaCutoff', 0.5)}", f"{ptr}/coverageMips/{i}/alphaCutoff")
        elif len(parts) == 4 and parts[0] == "meshes" and parts[2] == "primitives":
            m, p = parts[1], parts[3]
            prim = meshes[m]["primitives"][p]
            ptr = pointer("meshes", m, "primitives", p, "extensions", NAME)
            if prim.get("mode", 4) != 4 or "TEXCOORD_0" not in (prim.get("attributes") or {}):
                issues.error("BAKER_HAIR_CARDS_PRIMITIVE", "hair cards are a TRIANGLES primitive with TEXCOORD_0",
                             ptr)
                continue
            count = ext.get("cardCount")
            regions, first = ext.get("regions"), ext.get("cardFirstIndex")
            if not (is_index(regions, accessors) and is_index(first, accessors) and isinstance(count, int)):
                continue  # the schema and reference passes report them
            r_acc, f_acc = accessors[regions], accessors[first]
            if r_acc.get("type") != "VEC4" or r_acc.get("componentType") != 5126 or r_acc.get("count") != count:
                issues.error("BAKER_HAIR_CARDS_REGIONS", f"regions must be {count} FLOAT VEC4", ptr + "/regions")
                continue
            if f_acc.get("type") != "SCALAR" or f_acc.get("componentType") != 5125 or f_acc.get("count") != count:
                issues.error("BAKER_HAIR_CARDS_FIRST_INDEX", f"cardFirstIndex must be {count} UNSIGNED_INT",
                             ptr + "/cardFirstIndex")
                continue
            rect = np.asarray(doc.accessor(regions), np.float64).reshape(-1, 4)
            if not np.isfinite(rect).all() or (rect < 0).any() or (rect > 1).any() or \
                    (rect[:, 2] <= rect[:, 0]).any() or (rect[:, 3] <= rect[:, 1]).any():
                issues.error("BAKER_HAIR_CARDS_REGIONS", "every region is u0 < u1, v0 < v1 inside [0, 1]",
                             ptr + "/regions")
            starts = np.asarray(doc.accessor(first), np.int64).reshape(-1)
            index_count = accessors[prim["indices"]].get("count", 0) if is_index(prim.get("indices"),
                                                                                  accessors) else 0
            if len(starts) and (starts[0] != 0 or (np.diff(starts) <= 0).any() or (starts % 3).any()
                                or starts[-1] >= index_count):
                issues.error("BAKER_HAIR_CARDS_FIRST_INDEX", "cardFirstIndex must start at 0, ascend in steps of "
                             "whole triangles and stay below the index count", ptr + "/cardFirstIndex")


# ---------------------------------------------------------------------------------------------------- reading back
@dataclass(frozen=True)
class HairCardsMaterial:
    """``BAKER_hair_cards`` of a material as read back."""

    data_texture: int
    flow_texture: int
    depth_range: float
    data_channels: dict
    flow_encoding: str
    atlas_size: int | None = None
    padding: int | None = None
    coverage_mips: dict = field(default_factory=dict)  # texture index -> its coverageMips entry


@dataclass(frozen=True)
class HairCards:
    """``BAKER_hair_cards`` of a primitive as read back."""

    card_count: int
    regions: np.ndarray  # (K, 4) u0, v0, u1, v1
    card_first_index: np.ndarray  # (K,)
    draw_order: str
    groom: dict
    clustering_error: dict


def read_material(doc: GltfDocument, material: int) -> HairCardsMaterial | None:
    ext = (doc.json.get("materials", [])[material].get("extensions") or {}).get(NAME)
    if ext is None:
        return None
    return HairCardsMaterial(int(ext["dataTexture"]["index"]), int(ext["flowTexture"]["index"]),
                             float(ext["depthRange"]), dict(ext.get("dataChannels", DATA_CHANNELS)),
                             str(ext.get("flowEncoding", FLOW_ENCODING)), ext.get("atlasSize"), ext.get("padding"),
                             {int(e["texture"]): dict(e) for e in ext.get("coverageMips", ())})


def read(doc: GltfDocument, mesh: int, primitive: int) -> HairCards | None:
    """What :func:`write_cards` wrote on a primitive, accessors read; None without ``BAKER_hair_cards``."""
    prim = doc.json["meshes"][mesh]["primitives"][primitive]
    ext = (prim.get("extensions") or {}).get(NAME)
    if ext is None:
        return None
    return HairCards(int(ext["cardCount"]), np.asarray(doc.accessor(ext["regions"]), np.float64).reshape(-1, 4),
                     np.asarray(doc.accessor(ext["cardFirstIndex"]), np.int64).reshape(-1),
                     str(ext.get("drawOrder", "innerFirst")), dict(ext.get("groom") or {}),
                     dict(ext.get("clusteringError") or {}))


def summary(doc: GltfDocument, mesh: int, primitive: int) -> dict | None:
    """What ``baker inspect`` shows of a ``BAKER_hair_cards`` primitive: cards, quads, the source groom, errors."""
    cards = read(doc, mesh, primitive)
    if cards is None:
        return None
    prim = doc.json["meshes"][mesh]["primitives"][primitive]
    triangles = doc.json["accessors"][prim["indices"]]["count"] // 3 if "indices" in prim else 0
    out = {"cards": cards.card_count, "quads": triangles // 2, "drawOrder": cards.draw_order}
    for key in ("strandCount", "meanStrandLength"):
        if key in cards.groom:
            out[key] = cards.groom[key]
    if "rms" in cards.clustering_error:
        out["clusteringErrorRms"] = cards.clustering_error["rms"]
    return out


def to_usd_primitive(stage, name: str, parent: str, doc: GltfDocument, mesh: int, primitive: int) -> None:
    """USD hook (called by baker.gltf.usd for primitives carrying BAKER_hair_cards): a ``Scope`` beside the cards
    mesh with ``baker:hair_cards:*`` attributes: card count, regions (float4[]), first indices (int[]), draw order,
    the groom's counts, the clustering error and the cards' tangents (float4[] per vertex, glTF's TANGENT, which
    the flow texture is relative to). The mesh itself, its material and every texture are the USD writer's."""
    from pxr import Sdf, UsdGeom, Vt

    from baker.gltf.usd import custom_attributes

    cards = read(doc, mesh, primitive)
    scope = UsdGeom.Scope.Define(stage, f"{parent}/{name}").GetPrim()
    ns = "baker:hair_cards"
    scope.CreateAttribute(f"{ns}:cardCount", Sdf.ValueTypeNames.Int, custom=True).Set(cards.card_count)
    scope.CreateAttribute(f"{ns}:regions", Sdf.ValueTypeNames.Float4Array, custom=True).Set(
        Vt.Vec4fArray.FromNumpy(cards.regions.astype(np.float32)))
    scope.CreateAttribute(f"{ns}:cardFirstIndex", Sdf.ValueTypeNames.IntArray, custom=True).Set(
        Vt.IntArray.FromNumpy(cards.card_first_index.astype(np.int32)))
    scope.CreateAttribute(f"{ns}:drawOrder", Sdf.ValueTypeNames.String, custom=True).Set(cards.draw_order)
    custom_attributes(scope, f"{ns}:groom", cards.groom)
    custom_attributes(scope, f"{ns}:clusteringError", cards.clustering_error)
    attrs = doc.json["meshes"][mesh]["primitives"][primitive]["attributes"]
    if "TANGENT" in attrs:
        scope.CreateAttribute(f"{ns}:tangents", Sdf.ValueTypeNames.Float4Array, custom=True).Set(
            Vt.Vec4fArray.FromNumpy(np.asarray(doc.accessor(attrs["TANGENT"]), np.float32)))
