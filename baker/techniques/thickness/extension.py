"""``BAKER_thickness`` and the Khronos fields it rides on: result arrays -> glTF JSON/accessors/images, and USD.

Where the data goes (see ``schemas/BAKER_thickness/README.md``):
- per vertex: the primitive attribute ``_THICKNESS`` (mean chord in mesh units; FLOAT SCALAR in the ``native`` layout,
  in x of a FLOAT VEC3 in the ``blender`` one: :mod:`baker.gltf.vertex_attributes`);
- per texel: ``BAKER_thickness.thicknessTexture`` (green channel, 1.0 = ``BAKER_thickness.thicknessFactor`` mesh
  units), mirrored in ``KHR_materials_volume.thicknessTexture``/``thicknessFactor`` on single-sided materials only
  (the Khronos validator warns about KHR_materials_volume on a double-sided one);
- ``BAKER_thickness`` on the material: how it was baked and the translucency parameters of RTR4 eq. 14.30.

KHR_materials_transmission is never added: KHR_materials_volume without a transmission extension has no effect in
a standard viewer, so an opaque asset looks exactly as before (README, "Relation to Khronos extensions").
"""
from __future__ import annotations

import math

from dataclasses import dataclass

import numpy as np

from baker.gltf.document import GltfDocument
from baker.gltf.vertex_attributes import add_vertex_attribute

NAME = "BAKER_thickness"
ATTRIBUTE = "_THICKNESS"
VERTEX_ATTRIBUTES = {ATTRIBUTE: 1}  # name -> the data's width (USD writes it so; baker.registry)
KHR_VOLUME = "KHR_materials_volume"


def write_vertex_thickness(doc: GltfDocument, mesh: int, primitive: int, thickness: np.ndarray) -> int:
    """Add ``_THICKNESS`` to a primitive; returns the accessor index."""
    attributes = doc.json["meshes"][mesh]["primitives"][primitive]["attributes"]
    return add_vertex_attribute(doc, mesh, attributes, ATTRIBUTE, thickness, min_max=True,
                                leave_out="--thickness-per-vertex false")


def encode_thickness_texture(thickness: np.ndarray, bits: int) -> tuple[bytes, float]:
    """Normalize a (H, W) thickness image by its maximum into a grayscale PNG; returns (png, thicknessFactor).

    Grayscale: every decoder expands it to R = G = B, so the green channel KHR_materials_volume reads is the value.
    """
    factor = float(thickness.max()) if thickness.size and thickness.max() > 0 else 1.0
    scale = (1 << bits) - 1
    quantized = np.clip(np.rint(thickness / factor * scale), 0, scale)
    pixels = quantized.astype(np.uint16 if bits == 16 else np.uint8)
    from baker.gltf.images import encode_image  # OpenImageIO: loaded only when a texture is written

    return encode_image(pixels, ".png"), factor


def volume_allowed(doc: GltfDocument, material: int) -> bool:
    """Whether ``KHR_materials_volume`` is valid on ``material``: the extension describes a closed volume, so the
    Khronos validator warns about it on a double-sided material (KHR_MATERIALS_VOLUME_DOUBLE_SIDED)."""
    return not doc.json["materials"][material].get("doubleSided", False)


def write_thickness_texture(doc: GltfDocument, material: int, png: bytes, factor: float, texcoord: int) -> dict:
    """Add the thickness texture of ``material``; returns its textureInfo (``{"index", "texCoord"?}``), which
    :func:`write_material_parameters` keeps in ``BAKER_thickness``. Where ``KHR_materials_volume`` is valid
    (:func:`volume_allowed`) its ``thicknessTexture``/``thicknessFactor`` point at the same texture."""
    image = doc.add_image(png, "image/png", f"thickness_m{material}")
    texture = doc.add_texture(image, sampler={"magFilter": 9729, "minFilter": 9987},
                              name=f"baker thickness (material {material})")
    info = {"index": texture}
    if texcoord:
        info["texCoord"] = texcoord
    if volume_allowed(doc, material):
        volume = doc.json["materials"][material].setdefault("extensions", {}).setdefault(KHR_VOLUME, {})
        volume["thicknessTexture"] = dict(info)
        volume["thicknessFactor"] = factor
        doc.use_extension(KHR_VOLUME)
    return {"texture": info, "factor": factor}


def write_material_parameters(doc: GltfDocument, material: int, *, options, max_distance: float, bias: float,
                              mean_thickness: float, per_vertex: bool, texture: dict | None,
                              texel_rule: dict | None = None) -> dict:
    """Write ``BAKER_thickness`` on ``material``: bake settings, eq. 14.30 parameters and the thickness texture
    (``texture``: what :func:`write_thickness_texture` returned, or None); ``texel_rule`` (``texelTolerance``,
    ``texelFirstRays``, ``texelWindow``) when texels stopped on the per-vertex prior."""
    ext = {
        "rays": int(options.rays),
        "distribution": options.distribution,
        "sampler": options.sampler,
        "spreadAngle": math.radians(options.spread),
        "maxDistance": float(max_distance),
        "bias": float(bias),
        "meanThickness": float(mean_thickness),
        "attenuationDistance": float(options.attenuation_distance or mean_thickness or 1.0),
        "distortion": float(options.distortion),
        "power": float(options.power),
        "scale": float(options.scale),
        "ambient": float(options.ambient),
        "subsurfaceColor": [float(c) for c in options.subsurface_color],
    }
    if texture is not None:
        ext["thicknessTexture"] = dict(texture["texture"])
        ext["thicknessFactor"] = float(texture["factor"])
        if texel_rule:  # texels stopped early on the per-vertex prior: say how (the kernel's and the step's rule)
            ext.update(texel_rule)
    if per_vertex:
        ext["attribute"] = ATTRIBUTE
    return doc.set_material_extension(material, NAME, ext)


def check(doc: GltfDocument, places: list, issues) -> None:
    """Semantic rules of BAKER_thickness (``baker validate``): the attribute and texture it announces exist and
    hold sane thickness. ``places`` lists (JSON path parts, extension object) for every occurrence."""
    from baker.checks import check_vertex_attribute, is_index, is_number, material_extensions, pointer, primitives_using

    gltf = doc.json
    for material, ext, ext_ptr in material_extensions(places, NAME):
        users = list(primitives_using(gltf, material))
        if not users:
            issues.info("BAKER_THICKNESS_UNUSED", "no triangle primitive uses this material", ext_ptr)
        max_distance = ext.get("maxDistance")
        name = ext.get("attribute")
        if isinstance(name, str):
            for m, p, prim in users:
                values = check_vertex_attribute(doc, m, p, name, issues, code="BAKER_THICKNESS")
                if values is None:
                    continue
                values = values[np.isfinite(values)]
                acc_ptr = pointer("accessors", prim["attributes"][name])
                if (values < 0).any():
                    issues.error("BAKER_THICKNESS_VALUE_NEGATIVE", f"{int((values < 0).sum())} of {len(values)} "
                                 f"values are negative (min {values.min():g})", acc_ptr)
                if is_number(max_distance) and len(values) and values.max() > max_distance * 1.001:
                    issues.warning("BAKER_THICKNESS_VALUE_ABOVE_MAX", f"largest value {values.max():g} exceeds "
                                   f"maxDistance {max_distance:g}", acc_ptr)
        info = ext.get("thicknessTexture")
        if not isinstance(info, dict) or not is_index(info.get("index"), gltf.get("textures") or []):
            continue  # absent, or reported as UNRESOLVED_REFERENCE
        texcoord = info.get("texCoord", 0)
        for m, p, prim in users:
            if f"TEXCOORD_{texcoord}" not in (prim.get("attributes") or {}):
                issues.error("BAKER_THICKNESS_TEXCOORD_MISSING", f"the thickness texture reads TEXCOORD_{texcoord}"
                             " but this primitive has none", pointer("meshes", m, "primitives", p, "attributes"))
        volume = (gltf["materials"][material].get("extensions") or {}).get(KHR_VOLUME)
        if isinstance(volume, dict) and KHR_VOLUME not in (gltf.get("extensionsUsed") or []):
            issues.warning("BAKER_EXTENSION_NOT_DECLARED", "KHR_materials_volume is used but missing from "
                           "extensionsUsed", pointer("materials", material, "extensions", KHR_VOLUME))


# ---------------------------------------------------------------------------------------------------- reading back
@dataclass(frozen=True)
class ThicknessMaterial:
    """``BAKER_thickness`` of one material as read back, with its thickness texture.

    The translucency parameters (RTR4 eq. 14.30, GDC 2011) default to what a runtime assumes when a field is absent.
    """

    attenuation_distance: float = 1.0  # mesh units
    distortion: float = 0.2
    power: float = 4.0
    scale: float = 1.0
    ambient: float = 0.0
    subsurface_color: tuple = (1.0, 0.45, 0.3)  # linear RGB
    attribute: str | None = None  # the per-vertex attribute (``_THICKNESS``) when baked per vertex
    rays: int | None = None
    distribution: str | None = None
    spread_angle: float | None = None  # radians
    max_distance: float | None = None
    bias: float | None = None
    mean_thickness: float | None = None
    has_texture: bool = False  # ``thicknessTexture``: whether the bake wrote the per-texel map
    thickness_texture: int | None = None  # BAKER_thickness.thicknessTexture.index (green channel)
    thickness_texcoord: int = 0
    thickness_factor: float = 1.0  # mesh units at texel value 1.0


def read(doc: GltfDocument, material: int) -> ThicknessMaterial | None:
    """What :func:`write_material_parameters` and :func:`write_thickness_texture` wrote on ``material``, or None
    when the material has no ``BAKER_thickness``."""
    extensions = doc.json.get("materials", [])[material].get("extensions") or {}
    ext = extensions.get(NAME)
    if ext is None:
        return None
    info = ext.get("thicknessTexture") if isinstance(ext.get("thicknessTexture"), dict) else {}

    def optional(key, kind):
        return kind(ext[key]) if key in ext else None

    return ThicknessMaterial(
        attenuation_distance=float(ext.get("attenuationDistance", 1.0)), distortion=float(ext.get("distortion", 0.2)),
        power=float(ext.get("power", 4.0)), scale=float(ext.get("scale", 1.0)), ambient=float(ext.get("ambient", 0.0)),
        subsurface_color=tuple(float(c) for c in ext.get("subsurfaceColor", (1.0, 0.45, 0.3))),
        attribute=ext.get("attribute"), rays=optional("rays", int), distribution=ext.get("distribution"),
        spread_angle=optional("spreadAngle", float), max_distance=optional("maxDistance", float),
        bias=optional("bias", float), mean_thickness=optional("meanThickness", float),
        has_texture="index" in info, thickness_texture=int(info["index"]) if "index" in info else None,
        thickness_texcoord=int(info.get("texCoord", 0)), thickness_factor=float(ext.get("thicknessFactor", 1.0)))
