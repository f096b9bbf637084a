"""``BAKER_skin_lut``: Penner's pre-integrated skin LUTs on a material -> glTF JSON + images, and their checks.

The material gets (see ``schemas/BAKER_skin_lut/README.md``): ``lutTexture`` (RGB, u = N.L * 0.5 + 0.5, v = curvature
linear over ``curvatureRange`` in 1/``unit``, endpoint-aligned texels), optionally ``penumbraTexture``, the profile,
``curvatureScale`` (1/mesh units -> 1/``unit``), where the curvature comes from (``curvatureAttribute``,
``curvatureTexture``, else the runtime's derivative estimate) and the runtime's normal-blend and wrap parameters.
The LUTs are stored as PNG (8- or 16-bit, ``encoding`` linear or sRGB) and sampled with clamp-to-edge, linear,
no mipmaps.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from baker.techniques.skin.options import SkinOptions
from baker.gltf.document import GltfDocument
from baker.gltf.images import decoded_texture, encode_image

if TYPE_CHECKING:  # validation and read() must not import the kernel (numba)
    from baker.techniques.skin.kernel import SkinTables

NAME = "BAKER_skin_lut"
CLAMP_LINEAR = {"magFilter": 9729, "minFilter": 9729, "wrapS": 33071, "wrapT": 33071}


def usd_color_space(params: dict, path: tuple) -> str:
    """USD ``sourceColorSpace`` of the LUTs: as their ``encoding`` says (linear values by default)."""
    return "sRGB" if params.get("encoding") == "srgb" else "raw"


def encode_lut(values: np.ndarray, bits: int, encoding: str) -> bytes:
    """(H, W, 3) linear [0, 1] -> RGB PNG, row 0 at the top (v = 0)."""
    from baker.techniques.skin.kernel import quantize

    return encode_image(quantize(values, bits, encoding), ".png")


def add_lut_texture(doc: GltfDocument, png: bytes, name: str) -> int:
    image = doc.add_image(png, "image/png", name)
    return doc.add_texture(image, sampler=CLAMP_LINEAR, name=f"baker {name.replace('_', ' ')}")


def write_material_parameters(doc: GltfDocument, material: int, *, tables: SkinTables, options: SkinOptions,
                              lut_texture: int, penumbra_texture: int | None, curvature_attribute: str | None,
                              curvature_texture: dict | None, curvature_texture_range: list | None) -> dict:
    profile = tables.profile.as_json()
    ext = {
        "lutTexture": {"index": int(lut_texture)},
        "ndotlRange": [-1.0, 1.0],
        "curvatureRange": [float(c) for c in tables.axes.curvature_range],
        "unit": "mm",
        "encoding": options.encoding,
        "curvatureScale": 1.0 / float(options.unit_scale),
        "profile": {k: profile[k] for k in ("name", "variances", "red", "green", "blue")},
        "samples": int(options.samples),
        "ringProfile": options.ring_profile,
        "normalBlend": [float(x) for x in tables.normal_blend],
        "wrap": float(options.wrap),
        "scatterWidth": float(options.scatter_width),
        "scatterColor": [float(c) for c in options.scatter_color],
    }
    if tables.curvature_percentiles is not None:  # the axis was fitted to the asset's curvature (kernel.lut_radii)
        ext["curvatureRangePercentiles"] = [float(p) for p in tables.curvature_percentiles]
    if penumbra_texture is not None:
        ext["penumbraTexture"] = {"index": int(penumbra_texture)}
        ext["penumbraWidthRange"] = [float(x) for x in tables.penumbra_range]
        ext["shadowSharpening"] = float(options.sharpening)
    if curvature_attribute:
        ext["curvatureAttribute"] = curvature_attribute
    if curvature_texture:
        ext["curvatureTexture"] = dict(curvature_texture)
        ext["curvatureTextureRange"] = [float(x) for x in curvature_texture_range]
    return doc.set_material_extension(material, NAME, ext)


def check(doc: GltfDocument, places: list, issues) -> None:
    """Semantic rules of BAKER_skin_lut: ranges ordered, textures resolve to RGB images whose rows do not decrease
    along N.L (u) / the shadow value, and the curvature attribute or texture it names exists."""
    from baker.checks import check_vertex_attribute, is_index, material_extensions, pointer, primitives_using

    gltf = doc.json
    textures = gltf.get("textures") or []
    for material, ext, ext_ptr in material_extensions(places, NAME):
        users = list(primitives_using(gltf, material))
        if not users:
            issues.info("BAKER_SKIN_LUT_UNUSED", "no triangle primitive uses this material", ext_ptr)
        for key in ("curvatureRange", "penumbraWidthRange", "curvatureTextureRange"):
            rng = ext.get(key)
            if isinstance(rng, list) and len(rng) == 2 and all(isinstance(x, (int, float)) for x in rng) \
                    and not rng[0] < rng[1]:
                issues.error("BAKER_SKIN_LUT_RANGE", f"{key} {rng} must be increasing", ext_ptr + "/" + key)
        for key in ("lutTexture", "penumbraTexture"):
            info = ext.get(key)
            if not isinstance(info, dict) or not is_index(info.get("index"), textures):
                continue  # schema or UNRESOLVED_REFERENCE
            pixels = decoded_texture(doc, info["index"])
            tex_ptr = ext_ptr + "/" + key
            if pixels is None:
                issues.warning("BAKER_SKIN_LUT_IMAGE_UNREADABLE", "the LUT image cannot be decoded as PNG", tex_ptr)
                continue
            if pixels.ndim != 3 or pixels.shape[2] < 3 or pixels.shape[0] < 2 or pixels.shape[1] < 2:
                issues.error("BAKER_SKIN_LUT_IMAGE_FORMAT", f"a LUT must be an RGB image of at least 2 x 2, got "
                             f"{pixels.shape}", tex_ptr)
                continue
            values = pixels[..., :3].astype(np.float64)
            # rounding keeps a non-decreasing function non-decreasing; allow one code of slack for other encoders
            tolerance = 1.0 if pixels.dtype.kind in "ui" else 1e-6
            drops = np.diff(values, axis=1) < -tolerance
            if drops.any():
                issues.error("BAKER_SKIN_LUT_NOT_MONOTONIC", f"{int(drops.sum())} texel steps decrease along u "
                             "(a LUT must not get darker as N.L or the shadow value grows)", tex_ptr)
        name = ext.get("curvatureAttribute")
        if isinstance(name, str):
            for m, p, prim in users:
                check_vertex_attribute(doc, m, p, name, issues, code="BAKER_SKIN_LUT")
        info = ext.get("curvatureTexture")
        if isinstance(info, dict) and is_index(info.get("index"), textures):
            if "curvatureTextureRange" not in ext:
                issues.error("BAKER_SKIN_LUT_TEXTURE_RANGE", "curvatureTexture needs curvatureTextureRange", ext_ptr)
            texcoord = info.get("texCoord", 0)
            for m, p, prim in users:
                if f"TEXCOORD_{texcoord}" not in (prim.get("attributes") or {}):
                    issues.error("BAKER_SKIN_LUT_TEXCOORD_MISSING", f"the curvature texture reads TEXCOORD_{texcoord}"
                                 " but this primitive has none", pointer("meshes", m, "primitives", p, "attributes"))


# ---------------------------------------------------------------------------------------------------- reading back
CURVATURE_ATTRIBUTE = "_CURVATURE"


@dataclass(frozen=True)
class SkinMaterial:
    """``BAKER_skin_lut`` of one material as read back: Penner's LUT (+ penumbra LUT), its axes, and where the
    curvature comes from (``curvature_attribute``; None: the runtime estimates it from screen-space derivatives)."""

    lut_texture: int
    encoding: str = "linear"  # "srgb": the LUT texels are sRGB-encoded
    ndotl_range: tuple = (-1.0, 1.0)
    curvature_range: tuple = (0.01, 1.0)  # 1/mm at the LUT's v = 0 and 1
    curvature_scale: float = 1.0  # mesh curvature -> LUT units
    unit: str = "mm"
    penumbra_texture: int | None = None
    penumbra_width_range: tuple = (0.01, 1.0)
    shadow_sharpening: float | None = None
    normal_blend: tuple = (1.0, 1.0, 1.0)
    wrap: float = 0.5
    scatter_width: float = 0.3
    scatter_color: tuple = (0.8, 0.25, 0.1)
    samples: int | None = None
    profile: dict | None = None
    curvature_attribute: str | None = CURVATURE_ATTRIBUTE  # absent: ``_CURVATURE`` (when the primitive has it)
    curvature_texture: int | None = None
    curvature_texcoord: int = 0
    curvature_texture_range: tuple | None = None


def read(doc: GltfDocument, material: int) -> SkinMaterial | None:
    """What :func:`write_material_parameters` wrote on ``material``, or None without ``BAKER_skin_lut``."""
    ext = (doc.json.get("materials", [])[material].get("extensions") or {}).get(NAME)
    if ext is None:
        return None
    pair = lambda key, default: tuple(float(v) for v in ext.get(key, default))  # noqa: E731
    penumbra = ext.get("penumbraTexture") or {}
    curvature = ext.get("curvatureTexture") or {}
    return SkinMaterial(
        lut_texture=int(ext["lutTexture"]["index"]), encoding=ext.get("encoding", "linear"),
        ndotl_range=pair("ndotlRange", (-1.0, 1.0)), curvature_range=pair("curvatureRange", (0.01, 1.0)),
        curvature_scale=float(ext.get("curvatureScale", 1.0)), unit=ext.get("unit", "mm"),
        penumbra_texture=int(penumbra["index"]) if "index" in penumbra else None,
        penumbra_width_range=pair("penumbraWidthRange", (0.01, 1.0)),
        shadow_sharpening=float(ext["shadowSharpening"]) if "shadowSharpening" in ext else None,
        normal_blend=pair("normalBlend", (1.0, 1.0, 1.0)), wrap=float(ext.get("wrap", 0.5)),
        scatter_width=float(ext.get("scatterWidth", 0.3)), scatter_color=pair("scatterColor", (0.8, 0.25, 0.1)),
        samples=int(ext["samples"]) if "samples" in ext else None, profile=ext.get("profile"),
        curvature_attribute=ext.get("curvatureAttribute", CURVATURE_ATTRIBUTE),
        curvature_texture=int(curvature["index"]) if "index" in curvature else None,
        curvature_texcoord=int(curvature.get("texCoord", 0)),
        curvature_texture_range=pair("curvatureTextureRange", ()) if "curvatureTextureRange" in ext else None)
