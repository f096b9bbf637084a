"""``BAKER_toon_ramp``: a toon ramp or an X-Toon map (:mod:`baker.techniques.toon.kernel`) -> a texture + material JSON.

See ``schemas/BAKER_toon_ramp/README.md``. The ramp is a gray PNG, width x 1 (1D ramp, u = 0.5 + 0.5 N.L) or
width x height (X-Toon, v = 1 - detail); the extension does not change the material's core fields.
"""
from __future__ import annotations

import json

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from baker.techniques.toon.options import ToonOptions
from baker.gltf.atomic import write_files_atomic
from baker.gltf.document import GltfDocument
from baker.gltf.images import encode_image

NAME = "BAKER_toon_ramp"
RAMP_SAMPLER = {"magFilter": 9729, "minFilter": 9729, "wrapS": 33071, "wrapT": 33071}  # LINEAR, CLAMP_TO_EDGE


def toon_parameters(options: ToonOptions) -> dict:
    params = {"bands": int(options.bands), "softness": float(options.softness), "shadow": float(options.shadow),
              "xtoon": options.xtoon}
    if options.xtoon == "depth":
        params["depthRange"] = [float(v) for v in options.depth_range]
    elif options.xtoon == "orientation":
        params["orientationPower"] = float(options.orientation_power)
    if options.xtoon != "none":
        params["minContrast"] = float(options.min_contrast)
    return params


def toon_pixels(options: ToonOptions) -> np.ndarray:
    """The ramp (1, width) or X-Toon map (height, width) as uint8 gray."""
    from baker.techniques.toon.kernel import encode_u8, toon_ramp, xtoon_map

    values = toon_ramp(options)[None, :] if options.xtoon == "none" else xtoon_map(options)
    return encode_u8(values)


def write_toon_ramp(doc: GltfDocument, material: int, options: ToonOptions, texture: int | None = None) -> dict:
    """Add the ramp texture (or reuse ``texture``) and ``BAKER_toon_ramp`` on ``material``; returns the extension."""
    if texture is None:
        image = doc.add_image(encode_image(toon_pixels(options), ".png"), "image/png", "toon_ramp")
        texture = doc.add_texture(image, sampler=RAMP_SAMPLER, name="baker toon ramp")
    ext = toon_parameters(options)
    ext["rampTexture"] = {"index": texture}
    return doc.set_material_extension(material, NAME, ext)


def write_toon_directory(options: ToonOptions, folder) -> dict:
    folder = Path(folder)
    pixels = toon_pixels(options)
    name = "toon_ramp.png" if options.xtoon == "none" else "xtoon_map.png"
    image = encode_image(pixels, ".png")
    manifest = {"generator": "baker", **toon_parameters(options), "file": name, "width": int(pixels.shape[1]),
                "height": int(pixels.shape[0])}
    write_files_atomic([(folder / name, image),  # one atomic group, the manifest last
                        (folder / "toon.json", (json.dumps(manifest, indent=2) + "\n").encode("utf-8"))])
    return manifest



# ---------------------------------------------------------------------------------------------------------- validate
def check(doc: GltfDocument, places: list, issues) -> None:
    """Semantic rules of BAKER_toon_ramp: the ramp texture exists and has the shape its mode needs."""
    from baker.checks import is_index, material_extensions
    from baker.gltf.images import decoded_texture

    textures = doc.json.get("textures") or []
    for material, ext, ptr in material_extensions(places, NAME):
        info = ext.get("rampTexture")
        if not isinstance(info, dict) or not is_index(info.get("index"), textures):
            continue  # the reference pass reports it (rampTexture is a textureInfo)
        pixels = decoded_texture(doc, info["index"])
        if pixels is None:
            continue
        if ext.get("xtoon", "none") == "none" and pixels.shape[0] != 1:
            issues.warning("BAKER_TOON_RAMP_NOT_1D", f"a 1D ramp is expected to be 1 texel high, got {pixels.shape[0]}",
                           ptr + "/rampTexture")
        bands = ext.get("bands")
        if isinstance(bands, int) and pixels.shape[1] < bands:
            issues.error("BAKER_TOON_RAMP_TOO_NARROW", f"{pixels.shape[1]} texels cannot hold {bands} bands",
                         ptr + "/rampTexture")


# ---------------------------------------------------------------------------------------------------- reading back
@dataclass(frozen=True)
class ToonRamp:
    """``BAKER_toon_ramp`` of one material as read back: the ramp (or X-Toon map) texture and how to index it."""

    ramp_texture: int
    xtoon: str = "none"  # "none" (1D ramp by N.L), "depth" or "orientation" (X-Toon detail on v)
    bands: int | None = None
    softness: float | None = None
    shadow: float | None = None
    depth_range: tuple = (1.0, 50.0)  # X-Toon depth detail: (z_min, z_max) in mesh units
    orientation_power: float = 1.0
    min_contrast: float | None = None


def read(doc: GltfDocument, material: int) -> ToonRamp | None:
    """What :func:`write_toon_ramp` wrote on ``material``, or None without ``BAKER_toon_ramp``."""
    ext = (doc.json.get("materials", [])[material].get("extensions") or {}).get(NAME)
    if ext is None:
        return None
    optional = lambda key, kind: kind(ext[key]) if key in ext else None  # noqa: E731
    return ToonRamp(
        ramp_texture=int(ext["rampTexture"]["index"]), xtoon=ext.get("xtoon", "none"), bands=optional("bands", int),
        softness=optional("softness", float), shadow=optional("shadow", float),
        depth_range=tuple(float(v) for v in ext.get("depthRange", (1.0, 50.0))),
        orientation_power=float(ext.get("orientationPower", 1.0)), min_contrast=optional("minContrast", float))
