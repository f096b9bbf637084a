"""``BAKER_caustics``: a looping, tileable caustic sequence (:mod:`baker.techniques.caustics.kernel`) -> frame
textures + material JSON, and the standalone ``caustics.json`` folder.

See ``schemas/BAKER_caustics/README.md``. Frames are 16-bit gray (or RGB with per-channel IOR) PNGs; texel value /
65535 x ``intensityScale`` is the floor irradiance relative to flat water. The kernel's tile axes (x, y, z up) sit
in glTF's world as x -> +X, y -> -Z, z -> +Y, so the texture coordinate of a floor point is (X, -Z) / tileSize.
"""
from __future__ import annotations

import json
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from baker.gltf.atomic import write_files_atomic
from baker.gltf.document import GltfDocument
from baker.gltf.images import encode_image
from baker.techniques.caustics.options import CausticsOptions

NAME = "BAKER_caustics"
# LINEAR, LINEAR_MIPMAP_LINEAR, REPEAT: the frames tile
FRAME_SAMPLER = {"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}


def to_gltf_axes(vector) -> list:
    """A kernel-frame vector (x, y horizontal, z up) in glTF's frame (Y up, right-handed): (x, z, -y)."""
    x, y, z = (float(v) for v in vector)
    return [x, z, -y]


def frame_pixels(frames) -> tuple[list, float]:
    """The frames of a :class:`~baker.techniques.caustics.kernel.CausticFrames` as uint16 (H, W) or (H, W, 3)
    arrays, and the intensity scale they are encoded with."""
    from baker.techniques.caustics.kernel import encode_u16

    scale = frames.intensity_scale
    codes = encode_u16(frames.irradiance, scale)
    return [c[..., 0] if c.shape[-1] == 1 else c for c in codes], scale


def caustics_parameters(options: CausticsOptions, frames, scale: float, water_scale: float | None = None) -> dict:
    """The runtime parameters of ``BAKER_caustics`` (everything but the textures), with the water the bake used
    (wind speed, RMS height and, when the lengths followed the asset, their scale)."""
    params = {"tileSize": float(options.tile_size), "period": float(options.period), "intensityScale": scale,
              "depth": float(options.depth), "waterLevel": float(options.water_level),
              "fadeDistance": float(options.fade_distance), "strength": float(options.strength),
              "projectionDirection": [round(v, 7) for v in to_gltf_axes(frames.projection)],
              "windSpeed": float(options.wind_speed), "amplitude": float(options.amplitude)}
    if water_scale is not None:
        params["waterScale"] = float(water_scale)
    return params


def write_frame_textures(doc: GltfDocument, frames) -> tuple[list, float]:
    """Add one PNG texture per frame; returns (texture indices, intensity scale)."""
    pixels, scale = frame_pixels(frames)
    textures = []
    for f, image in enumerate(pixels):
        index = doc.add_image(encode_image(image, ".png"), "image/png", f"caustics_{f:03d}")
        textures.append(doc.add_texture(index, sampler=FRAME_SAMPLER, name=f"baker caustics frame {f}"))
    return textures, scale


def write_caustics(doc: GltfDocument, material: int, options: CausticsOptions, frames, textures: list,
                   scale: float, water_scale: float | None = None) -> dict:
    """``BAKER_caustics`` on ``material`` referencing the frame ``textures``; returns the extension object."""
    ext = {"frameTextures": [{"index": int(t)} for t in textures],
           **caustics_parameters(options, frames, scale, water_scale)}
    return doc.set_material_extension(material, NAME, ext)


def write_caustics_directory(options: CausticsOptions, frames, folder, seed: int = 0, ktx2: bool = False) -> dict:
    """Write ``caustics_NNN.png`` frames, ``caustics.json`` (and ``caustics.ktx2``) into ``folder`` as one atomic
    group, the manifest last; returns the manifest."""
    from baker.gltf.ktx2 import encode_ktx2
    from baker.techniques.caustics.kernel import channel_iors, mip_chain

    folder = Path(folder)
    pixels, scale = frame_pixels(frames)
    names = [f"caustics_{f:03d}.png" for f in range(len(pixels))]
    outputs = [(folder / name, encode_image(image, ".png")) for name, image in zip(names, pixels)]
    from baker.techniques.caustics.light import sun_direction

    sun = sun_direction(options.sun_elevation, options.sun_azimuth)
    manifest = {
        "generator": "baker", "frames": names, "frameCount": len(names), "size": int(options.size),
        "channels": int(frames.irradiance.shape[-1]), "bitDepth": 16, "intensityScale": scale,
        "encoding": "irradiance relative to flat water = PNG value / 65535 x intensityScale",
        "tileSize": float(options.tile_size), "depth": float(options.depth), "period": float(options.period),
        "frameDuration": float(options.period) / len(names),
        "sun": {"elevation": float(options.sun_elevation), "azimuth": float(options.sun_azimuth),
                "direction": [round(float(v), 7) for v in sun]},
        "ior": list(channel_iors(options)) if any(options.ior_rgb) else float(options.ior),
        "projectionDirection": [round(float(v), 7) for v in frames.projection],
        "axes": "tile x = texture u (columns), tile y = texture v (rows, down), z up; "
                "in glTF: x -> +X, y -> -Z, z -> +Y",
        "seed": int(seed), "options": options_json(options)}
    if ktx2:
        # 8-bit UNORM array with box-filtered mips (codes / 255 x intensityScale, as the PNGs' / 65535)
        layers = np.clip(frames.irradiance / scale, 0.0, 1.0)
        chain = [np.rint(level * 255.0).astype(np.uint8) for level in mip_chain(layers)]
        outputs.append((folder / "caustics.ktx2", encode_ktx2(chain)))
        channels = chain[0].shape[-1]
        manifest["ktx2"] = {"file": "caustics.ktx2", "vkFormat": "VK_FORMAT_R8_UNORM" if channels == 1
                            else "VK_FORMAT_R8G8B8_UNORM", "levelCount": len(chain), "layerCount": len(names),
                            "encoding": "irradiance = value / 255 x intensityScale"}
    outputs.append((folder / "caustics.json", (json.dumps(manifest, indent=2) + "\n").encode("utf-8")))
    write_files_atomic(outputs)
    return manifest


def options_json(options: CausticsOptions) -> dict:
    """Every option, JSON-ready, under its camelCase name."""
    def camel(name: str) -> str:
        head, *rest = name.split("_")
        return head + "".join(part.title() for part in rest)

    return {camel(k): (list(v) if isinstance(v, tuple) else v) for k, v in asdict(options).items()}


# ---------------------------------------------------------------------------------------------------------- validate
def check(doc: GltfDocument, places: list, issues) -> None:
    """Semantic rules of BAKER_caustics: frames are square, equal in size and a power of two; the projection
    direction points down."""
    from baker.checks import is_index, material_extensions
    from baker.gltf.images import decoded_texture

    textures = doc.json.get("textures") or []
    for material, ext, ptr in material_extensions(places, NAME):
        direction = ext.get("projectionDirection")
        if isinstance(direction, list) and len(direction) == 3 and all(
                isinstance(v, (int, float)) for v in direction) and not direction[1] < 0:
            issues.error("BAKER_CAUSTICS_PROJECTION_UP", "projectionDirection must point down (negative y)",
                         ptr + "/projectionDirection")
        shapes = set()
        for i, info in enumerate(ext.get("frameTextures") or []):
            if not isinstance(info, dict) or not is_index(info.get("index"), textures):
                continue  # the reference pass reports it (frameTextures holds textureInfos)
            pixels = decoded_texture(doc, info["index"])
            if pixels is None:
                continue
            height, width = pixels.shape[:2]
            if height != width or width & (width - 1):
                issues.warning("BAKER_CAUSTICS_FRAME_SHAPE", f"a frame is expected square and a power of two, got "
                               f"{width} x {height}", f"{ptr}/frameTextures/{i}")
            shapes.add((height, width))
        if len(shapes) > 1:
            issues.error("BAKER_CAUSTICS_FRAME_SIZES", f"frames differ in size: {sorted(shapes)}", ptr + "/frameTextures")


# ---------------------------------------------------------------------------------------------------- reading back
@dataclass(frozen=True)
class Caustics:
    """``BAKER_caustics`` of one material as read back."""

    frame_textures: tuple
    tile_size: float
    period: float
    intensity_scale: float
    depth: float
    projection_direction: tuple
    water_level: float = 0.0
    fade_distance: float = 1.0
    strength: float = 1.0


def read(doc: GltfDocument, material: int) -> Caustics | None:
    """What :func:`write_caustics` wrote on ``material``, or None without ``BAKER_caustics``."""
    ext = (doc.json.get("materials", [])[material].get("extensions") or {}).get(NAME)
    if ext is None:
        return None
    return Caustics(
        frame_textures=tuple(int(info["index"]) for info in ext["frameTextures"]), tile_size=float(ext["tileSize"]),
        period=float(ext["period"]), intensity_scale=float(ext["intensityScale"]), depth=float(ext["depth"]),
        projection_direction=tuple(float(v) for v in ext["projectionDirection"]),
        water_level=float(ext.get("waterLevel", 0.0)), fade_distance=float(ext.get("fadeDistance", 1.0)),
        strength=float(ext.get("strength", 1.0)))
