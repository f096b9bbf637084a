"""``BAKER_normal_blur``: per-channel diffuse normal maps, Penner's smoothed map + blend, the UV stretch map and the
texture-space diffusion kernels on a material -> glTF JSON + images, read back, and checked.

See ``schemas/BAKER_normal_blur/README.md``. The diffuse maps are 8-bit RGB tangent-space normal maps in the frame
and UV set of the material's ``normalTexture`` (its scale already applied: read them with scale 1); the stretch map
is RGB (R = |dP/du|, G = |dP/dv|, B = 0) times ``stretchScale`` in mesh units per UV unit. USD gets every texture
through the generic ``BAKER_*`` path of :mod:`baker.gltf.usd` (``outputs:baker:normal_blur:<key>``).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from baker.diffusion_profile import CHANNELS
from baker.gltf.document import GltfDocument
from baker.gltf.images import decoded_texture, encode_image

NAME = "BAKER_normal_blur"
CLAMP_LINEAR = {"magFilter": 9729, "minFilter": 9729, "wrapS": 33071, "wrapT": 33071}
DEFAULT_SAMPLER = {"magFilter": 9729, "minFilter": 9987}


def encode_png(pixels: np.ndarray) -> bytes:
    return encode_image(pixels, ".png")


def encode_stretch(stretch: np.ndarray, bits: int) -> tuple[bytes, float]:
    """(H, W, 2) |dP/du|, |dP/dv| -> RGB PNG (B = 0) scaled by its maximum; returns (png, stretchScale)."""
    top = float(stretch.max()) if stretch.size and stretch.max() > 0 else 1.0
    scale = (1 << bits) - 1
    rgb = np.zeros(stretch.shape[:2] + (3,))
    rgb[..., :2] = stretch / top
    pixels = np.clip(np.rint(rgb * scale), 0, scale).astype(np.uint16 if bits == 16 else np.uint8)
    return encode_image(pixels, ".png"), top


def add_texture(doc: GltfDocument, png: bytes, name: str, sampler: dict | None) -> int:
    image = doc.add_image(png, "image/png", name)
    return doc.add_texture(image, sampler=sampler or DEFAULT_SAMPLER, name=f"baker {name.replace('_', ' ')}")


def _info(texture: int, texcoord: int) -> dict:
    info = {"index": int(texture)}
    if texcoord:
        info["texCoord"] = int(texcoord)
    return info


def write_material_parameters(doc: GltfDocument, material: int, *, options, profile, variances: np.ndarray,
                              weights: np.ndarray, texcoord: int, diffuse_textures: list, result,
                              stretch_texture: int, stretch_scale: float, generated_tangents: list,
                              size: int) -> dict:
    from baker.techniques.normal_blur.kernel import twelve_tap_kernel
    from baker.techniques.normal_blur.surface_convolution import CUTOFF_SIGMAS

    weights = np.asarray(weights, np.float64)
    normalized = weights / weights.sum(axis=1, keepdims=True)
    order = np.argsort(variances, kind="stable")
    gaussians, previous = [], 0.0
    for k in order:  # d'Eon & Luebke's successive blurs: each adds its variance increment to the previous result
        gaussians.append({"variance": float(variances[k]), "incrementalVariance": float(variances[k] - previous),
                          "weights": [float(normalized[c, k]) for c in range(3)]})
        previous = float(variances[k])
    source = profile.as_json()
    ext = {
        "diffuseNormalTextures": [_info(t, texcoord) for t in diffuse_textures],
        "kernels": [[{"variance": float(variances[k]), "weight": float(normalized[c, k])}
                     for k in range(len(variances)) if normalized[c, k] > 0] for c in range(3)],
        "metersPerUnit": float(options.meters_per_unit),
        "profile": {k: source[k] for k in ("name", "variances", "red", "green", "blue")},
        "distance": "euclidean",
        "cutoffSigmas": float(CUTOFF_SIGMAS),
        "cellFraction": float(options.cell_fraction),
        "smoothedNormalTexture": _info(diffuse_textures[result.smoothed_channel], texcoord),
        "smoothedChannel": CHANNELS[result.smoothed_channel],
        "channelBlend": [float(x) for x in result.channel_blend],
        "channelBlendError": [float(x) for x in result.fit_error],
        "stretchTexture": _info(stretch_texture, texcoord),
        "stretchScale": float(stretch_scale),
        "mapSize": int(size),
        "textureSpaceDiffusion": {"gaussians": gaussians,
                                  "twelveTap": twelve_tap_kernel(variances, weights)},
    }
    if generated_tangents:
        ext["generatedTangents"] = list(generated_tangents)
    return doc.set_material_extension(material, NAME, ext)


def check(doc: GltfDocument, places: list, issues) -> None:
    """Semantic rules of BAKER_normal_blur: three diffuse maps, each an RGB image of unit-ish tangent-space normals
    (z >= 0) of one size; the kernels' weights sum to 1 per channel with positive variances; the UV set every
    texture reads exists on the material's primitives; the stretch map is RGB with a positive scale."""
    from baker.checks import is_index, is_number, material_extensions, pointer, primitives_using

    gltf = doc.json
    textures = gltf.get("textures") or []
    for material, ext, ext_ptr in material_extensions(places, NAME):
        users = list(primitives_using(gltf, material))
        if not users:
            issues.info("BAKER_NORMAL_BLUR_UNUSED", "no triangle primitive uses this material", ext_ptr)
        maps = ext.get("diffuseNormalTextures")
        if isinstance(maps, list) and len(maps) != 3:
            issues.error("BAKER_NORMAL_BLUR_CHANNELS", f"diffuseNormalTextures needs 3 entries (R, G, B), got "
                         f"{len(maps)}", ext_ptr + "/diffuseNormalTextures")
        kernels = ext.get("kernels")
        if isinstance(kernels, list):
            for c, kernel in enumerate(kernels):
                if not isinstance(kernel, list):
                    continue
                total = sum(g.get("weight", 0.0) for g in kernel if isinstance(g, dict) and is_number(g.get("weight")))
                if kernel and abs(total - 1.0) > 1e-3:
                    issues.error("BAKER_NORMAL_BLUR_KERNEL_WEIGHTS", f"channel {c} weights sum to {total:g}, not 1",
                                 f"{ext_ptr}/kernels/{c}")
        infos = [(f"/diffuseNormalTextures/{i}", info) for i, info in enumerate(maps if isinstance(maps, list) else [])]
        infos += [(f"/{key}", ext.get(key)) for key in ("smoothedNormalTexture", "stretchTexture")]
        shapes = set()
        for where, info in infos:
            if not isinstance(info, dict) or not is_index(info.get("index"), textures):
                continue  # schema or UNRESOLVED_REFERENCE
            texcoord = info.get("texCoord", 0)
            for m, p, prim in users:
                if f"TEXCOORD_{texcoord}" not in (prim.get("attributes") or {}):
                    issues.error("BAKER_NORMAL_BLUR_TEXCOORD_MISSING", f"{where[1:]} reads TEXCOORD_{texcoord} but "
                                 "this primitive has none", pointer("meshes", m, "primitives", p, "attributes"))
            pixels = decoded_texture(doc, info["index"])
            if pixels is None:
                issues.warning("BAKER_NORMAL_BLUR_IMAGE_UNREADABLE", "the image cannot be decoded as PNG",
                               ext_ptr + where)
                continue
            if pixels.ndim != 3 or pixels.shape[2] < 3:
                issues.error("BAKER_NORMAL_BLUR_IMAGE_FORMAT", f"an RGB image is needed, got {pixels.shape}",
                             ext_ptr + where)
                continue
            if "stretch" in where:
                continue
            shapes.add(pixels.shape[:2])
            top = float(np.iinfo(pixels.dtype).max) if pixels.dtype.kind in "ui" else 1.0
            n = pixels[..., :3].astype(np.float64) / top * 2.0 - 1.0
            length = np.linalg.norm(n, axis=-1)
            # 8-bit rounding moves a unit vector's length by < 0.7 %; dilated background keeps unit texels too
            bad = int(((np.abs(length - 1.0) > 0.03) | (n[..., 2] < -0.01)).sum())
            if bad:
                issues.error("BAKER_NORMAL_BLUR_NOT_NORMALS", f"{bad} texels are not unit tangent-space normals with "
                             "z >= 0", ext_ptr + where)
        if len(shapes) > 1:
            issues.error("BAKER_NORMAL_BLUR_SIZES", f"the diffuse maps differ in size: {sorted(shapes)}", ext_ptr)
        scale = ext.get("stretchScale")
        if is_number(scale) and not scale > 0:
            issues.error("BAKER_NORMAL_BLUR_STRETCH_SCALE", f"stretchScale must be > 0, got {scale}",
                         ext_ptr + "/stretchScale")


# ---------------------------------------------------------------------------------------------------- reading back
@dataclass(frozen=True)
class NormalBlurMaterial:
    """``BAKER_normal_blur`` of one material as read back."""

    diffuse_textures: tuple  # (red, green, blue) texture indices
    texcoord: int
    kernels: tuple  # per channel ((variance mesh units^2, weight), ...)
    smoothed_texture: int | None = None
    smoothed_channel: str | None = None
    channel_blend: tuple = (0.0, 0.0, 0.0)
    channel_blend_error: tuple = (0.0, 0.0, 0.0)
    stretch_texture: int | None = None
    stretch_scale: float = 1.0
    meters_per_unit: float = 1.0
    texture_space_diffusion: dict | None = None
    generated_tangents: tuple = ()


def read(doc: GltfDocument, material: int) -> NormalBlurMaterial | None:
    """What :func:`write_material_parameters` wrote on ``material``, or None without ``BAKER_normal_blur``."""
    ext = (doc.json.get("materials", [])[material].get("extensions") or {}).get(NAME)
    if ext is None:
        return None
    maps = ext["diffuseNormalTextures"]
    smoothed = ext.get("smoothedNormalTexture") or {}
    stretch = ext.get("stretchTexture") or {}
    return NormalBlurMaterial(
        diffuse_textures=tuple(int(m["index"]) for m in maps), texcoord=int(maps[0].get("texCoord", 0)),
        kernels=tuple(tuple((float(g["variance"]), float(g["weight"])) for g in k) for k in ext.get("kernels", [])),
        smoothed_texture=int(smoothed["index"]) if "index" in smoothed else None,
        smoothed_channel=ext.get("smoothedChannel"),
        channel_blend=tuple(float(x) for x in ext.get("channelBlend", (0.0, 0.0, 0.0))),
        channel_blend_error=tuple(float(x) for x in ext.get("channelBlendError", (0.0, 0.0, 0.0))),
        stretch_texture=int(stretch["index"]) if "index" in stretch else None,
        stretch_scale=float(ext.get("stretchScale", 1.0)), meters_per_unit=float(ext.get("metersPerUnit", 1.0)),
        texture_space_diffusion=ext.get("textureSpaceDiffusion"),
        generated_tangents=tuple(ext.get("generatedTangents", ())))
