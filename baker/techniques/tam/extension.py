"""``BAKER_tonal_art_map`` and ``BAKER_toon_ramp``: TAMs and toon ramps -> images, glTF material JSON, manifests.

Where the data goes (see ``schemas/BAKER_tonal_art_map/README.md`` and ``schemas/BAKER_toon_ramp/README.md``):

- a TAM is a set of per-level images: ``packed`` layout (Praun et al. 2001), per level two RGB PNGs holding tones
  0-2 and 3-5 in their red, green and blue channels; ``volume`` layout (Webb et al. 2002), per level one gray PNG
  of the tone slices stacked vertically (an array texture's layers). White (255) is paper, strokes are dark.
  Levels are listed **finest first** (level i has ``size >> i`` pixels): the order of glTexImage2D's ``level``;
- on a material, ``BAKER_tonal_art_map`` references one glTF texture per image and says how to use them; the
  standalone command writes the same images plus a ``tam.json`` manifest (and optionally KTX2 files);
- ``BAKER_toon_ramp`` references a 1D ramp (width x 1) or an X-Toon map (width x height) texture.

Neither extension changes the material's core fields: a viewer that ignores them draws the asset as before.
"""
from __future__ import annotations

import json
import math

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from baker.gltf.atomic import write_files_atomic
from baker.gltf.document import GltfDocument
from baker.gltf.images import encode_image
from baker.gltf.ktx2 import encode_ktx2
from baker.gltf.images import decoded_texture

if TYPE_CHECKING:  # validation and read() must not import the kernel (numba)
    from baker.techniques.tam.kernel import TonalArtMap

NAME = "BAKER_tonal_art_map"
# the stroke chart's u axis per vertex (unit, mesh space), written with the stroke TEXCOORD set on request
# (--tam-direction; issue 38): the u gradient of the stroke set gives it, so by default it is not stored (issue 48)
DIRECTION_ATTRIBUTE = "_HATCHING_DIRECTION"
VERTEX_ATTRIBUTES = {DIRECTION_ATTRIBUTE: 3}  # name -> the data's width (baker.registry)
LEVEL_ORDER = "finestFirst"
# the level images of one mip chain: REPEAT (the TAM tiles), trilinear across the custom levels
TAM_SAMPLER = {"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}


# ---------------------------------------------------------------------------------------------------------- images
def level_images(tam: TonalArtMap) -> list[list[np.ndarray]]:
    """Per level (finest first), the uint8 images of the layout: [A (R,R,3), B (R,R,3)] or [stack (T*R, R)]."""
    from baker.techniques.tam.kernel import pack_rgb, pack_volume

    if tam.options.layout == "packed":
        return [pack_rgb(tam, i) for i in range(len(tam.darkness))]
    return [[pack_volume(tam, i)] for i in range(len(tam.darkness))]


def tam_parameters(tam: TonalArtMap) -> dict:
    """The stroke and layout parameters shared by the extension and the manifest (angles in radians)."""
    o = tam.options
    params = {
        "layout": o.layout,
        "style": o.style,
        "tones": [float(t) for t in tam.targets],
        "levelOrder": LEVEL_ORDER,
        "strokeWidth": float(o.stroke_width),
        "strokeLength": [float(v) for v in o.stroke_length],
        "angle": math.radians(o.stroke_angle),
        "angleJitter": math.radians(o.angle_jitter),
        "curvature": float(o.curvature),
        "candidates": int(o.candidates),
        "seed": int(tam.seed),
    }
    if o.style == "cross-hatching":
        params["crossAngle"] = math.radians(o.cross_angle)
        params["crossThreshold"] = float(o.cross_threshold)
    return params


def measured_tones(tam: TonalArtMap) -> list[list[float]]:
    """Mean darkness of every (level, tone) of the 8-bit images, finest level first."""
    return [[round(float(1.0 - b.mean() / 255.0), 6) for b in tam.brightness_u8(i)] for i in range(len(tam.darkness))]


# ---------------------------------------------------------------------------------------------------------- glTF
def write_tam_textures(doc: GltfDocument, tam: TonalArtMap) -> list[list[int]]:
    """Add every level image as a PNG image + texture (REPEAT, trilinear); returns texture indices per level."""
    textures = []
    for i, level in enumerate(level_images(tam)):
        indices = []
        for j, pixels in enumerate(level):
            suffix = ("tones012", "tones345")[j] if len(level) > 1 else "tones"
            image = doc.add_image(encode_image(pixels, ".png"), "image/png", f"tam_level{i}_{suffix}")
            indices.append(doc.add_texture(image, sampler=TAM_SAMPLER, name=f"baker TAM level {i} {suffix}"))
        textures.append(indices)
    return textures


def write_tam(doc: GltfDocument, material: int, tam: TonalArtMap, textures: list, *, scale: float,
              texcoord: int = 0, strokes: dict | None = None) -> dict:
    """Write ``BAKER_tonal_art_map`` on ``material``, pointing at ``textures`` (from :func:`write_tam_textures`;
    materials sharing one TAM share them). ``strokes``: the stroke parameterization's record when ``texcoord``
    is its set (``texelsPerUnit``, ``field``, ``patches``, ``fallbackFaces``, ``singularities``, and
    ``directionAttribute`` when the u axis was written). Returns the
    extension object."""
    ext = tam_parameters(tam)
    levels = []
    for size, indices in zip(tam.sizes, textures):
        if tam.options.layout == "packed":
            levels.append({"size": size, "textures": [{"index": k} for k in indices]})
        else:
            levels.append({"size": size, "texture": {"index": indices[0]}})
    ext["levels"] = levels
    ext["scale"] = float(scale)
    ext["texCoord"] = int(texcoord)
    if strokes is not None:
        ext["strokes"] = dict(strokes)
    return doc.set_material_extension(material, NAME, ext)


# ---------------------------------------------------------------------------------------------------------- files
def write_tam_directory(tam: TonalArtMap, folder, ktx2: bool = False) -> dict:
    """Write the per-level PNGs, ``tam.json`` (and KTX2 files) into ``folder``; returns the manifest.

    The files are written as one atomic group, the manifest renamed last: a reader never sees it before its images,
    and a failed or killed run leaves every earlier file as it was.
    """
    folder = Path(folder)
    images = level_images(tam)
    manifest = {"generator": "baker", **tam_parameters(tam), "size": tam.sizes[0],
                "measuredTones": measured_tones(tam), "levels": []}
    packed = tam.options.layout == "packed"
    outputs = []  # (path, bytes), written as one atomic group at the end
    for i, (size, level) in enumerate(zip(tam.sizes, images)):
        names = [f"tam_level{i}_tones012.png", f"tam_level{i}_tones345.png"] if packed else [f"tam_level{i}.png"]
        for name, pixels in zip(names, level):
            outputs.append((folder / name, encode_image(pixels, ".png")))
        entry = {"level": i, "size": size}
        if packed:
            entry["files"] = names
        else:
            entry["file"] = names[0]
            entry["layers"] = len(tam.targets)
        manifest["levels"].append(entry)
    if ktx2:
        if packed:
            files = []
            for j, name in enumerate(("tam_tones012.ktx2", "tam_tones345.ktx2")):
                rgba = []
                for level in images:
                    a = np.full(level[j].shape[:2] + (4,), 255, np.uint8)
                    a[..., :3] = level[j]
                    rgba.append(a)
                outputs.append((folder / name, encode_ktx2(rgba)))
                files.append(name)
            manifest["ktx2"] = {"files": files, "vkFormat": "VK_FORMAT_R8G8B8A8_UNORM", "levelCount": len(images),
                                "layerCount": 0}
        else:
            tones = len(tam.targets)
            chain = [level[0].reshape(tones, -1, level[0].shape[1], 1) for level in images]
            outputs.append((folder / "tam.ktx2", encode_ktx2(chain)))
            manifest["ktx2"] = {"file": "tam.ktx2", "vkFormat": "VK_FORMAT_R8_UNORM", "levelCount": len(images),
                                "layerCount": tones}
    outputs.append((folder / "tam.json", (json.dumps(manifest, indent=2) + "\n").encode("utf-8")))
    write_files_atomic(outputs)
    return manifest




def from_usd(doc: GltfDocument, material: int, params: dict) -> None:
    """A stage read back (:mod:`baker.readers.usd_baked`) keeps each level's textures but not its ``size`` (a list
    of objects carries no USD attribute): the width of the level's first image."""
    for level in params.get("levels") or []:
        textures = level.get("textures") if isinstance(level, dict) else None
        if isinstance(textures, list) and textures and isinstance(textures[0], dict) and "size" not in level:
            pixels = decoded_texture(doc, textures[0]["index"])
            if pixels is not None:
                level["size"] = int(pixels.shape[1])


def check(doc: GltfDocument, places: list, issues) -> None:
    """Semantic rules of BAKER_tonal_art_map: tones increase, levels halve finest-first and the images exist with
    those sizes, and the primitives using the material have the texture coordinates it reads."""
    from baker.checks import is_index, material_extensions, pointer, primitives_using

    gltf = doc.json
    textures = gltf.get("textures") or []
    for material, ext, ptr in material_extensions(places, NAME):
        tones = ext.get("tones")
        if isinstance(tones, list) and len(tones) > 1 and any(b <= a for a, b in zip(tones, tones[1:])
                                                              if isinstance(a, (int, float)) and
                                                              isinstance(b, (int, float))):
            issues.error("BAKER_TAM_TONES_NOT_INCREASING", "tones must increase strictly (lightest first)",
                         ptr + "/tones")
        layout = ext.get("layout")
        if layout == "packed" and isinstance(tones, list) and len(tones) != 6:
            issues.error("BAKER_TAM_TONE_COUNT", f"the packed layout holds 6 tones, got {len(tones)}", ptr + "/tones")
        levels = ext.get("levels") if isinstance(ext.get("levels"), list) else []
        for i, level in enumerate(levels):
            if not isinstance(level, dict):
                continue
            lptr = f"{ptr}/levels/{i}"
            size = level.get("size")
            if i and isinstance(size, int) and isinstance(levels[i - 1], dict) and \
                    levels[i - 1].get("size") != size * 2:
                issues.error("BAKER_TAM_LEVEL_SIZE", f"level {i} must be half of level {i - 1} (finest first)",
                             lptr + "/size")
            infos = level.get("textures") if layout == "packed" else [level.get("texture")]
            for j, info in enumerate(infos or []):
                iptr = lptr + (f"/textures/{j}" if layout == "packed" else "/texture")
                if not isinstance(info, dict) or not is_index(info.get("index"), textures):
                    issues.error("UNRESOLVED_REFERENCE", "texture does not exist", iptr + "/index")
                    continue
                pixels = decoded_texture(doc, info["index"])
                if pixels is None or not isinstance(size, int):
                    continue
                expected = (size * len(tones), size) if layout == "volume" and isinstance(tones, list) else (size,
                                                                                                             size)
                if pixels.shape[:2] != expected:
                    issues.error("BAKER_TAM_IMAGE_SIZE", f"image is {pixels.shape[1]} x {pixels.shape[0]}, expected "
                                 f"{expected[1]} x {expected[0]}", iptr)
        texcoord = ext.get("texCoord", 0)
        users = list(primitives_using(gltf, material))
        if not users:
            issues.info("BAKER_TAM_UNUSED", "no triangle primitive uses this material", ptr)
        strokes = ext.get("strokes") if isinstance(ext.get("strokes"), dict) else None
        direction = strokes.get("directionAttribute") if strokes else None
        faces = 0
        for m, p, prim in users:
            attributes = prim.get("attributes") or {}
            if f"TEXCOORD_{texcoord}" not in attributes:
                issues.error("BAKER_TAM_TEXCOORD_MISSING", f"the TAM reads TEXCOORD_{texcoord} but this primitive has "
                             "none", pointer("meshes", m, "primitives", p, "attributes"))
            if isinstance(direction, str) and direction not in attributes:
                issues.error("BAKER_TAM_DIRECTION_MISSING", f"strokes.directionAttribute names {direction} but this "
                             "primitive has none", pointer("meshes", m, "primitives", p, "attributes"))
            faces += triangle_count(gltf, prim)
        if strokes and users and isinstance(strokes.get("fallbackFaces"), int) and strokes["fallbackFaces"] > faces:
            issues.error("BAKER_TAM_FALLBACK_COUNT", f"{strokes['fallbackFaces']} fallback faces of {faces} "
                         "triangles", ptr + "/strokes/fallbackFaces")


def triangle_count(gltf: dict, prim: dict) -> int:
    """Triangles of a primitive from its accessor counts (indices, else POSITION), as the mode makes them."""
    accessors = gltf.get("accessors") or []
    source = prim.get("indices", (prim.get("attributes") or {}).get("POSITION"))
    count = accessors[source].get("count", 0) if isinstance(source, int) and 0 <= source < len(accessors) else 0
    if not isinstance(count, int):
        return 0
    mode = prim.get("mode", 4)
    return count // 3 if mode == 4 else max(count - 2, 0)


# ---------------------------------------------------------------------------------------------------------- reading back
@dataclass(frozen=True)
class TamLevel:
    """One level of the map, finest first: its size in texels and its textures (packed: tones 0-2 and 3-5 in RGB;
    volume: one layered texture)."""

    size: int
    textures: tuple


@dataclass(frozen=True)
class TamMaterial:
    """``BAKER_tonal_art_map`` of one material as read back (Praun et al. 2001)."""

    layout: str  # "packed" (two RGB textures per level) or "volume"
    tones: tuple  # target darkness of each tone, lightest first
    levels: tuple  # TamLevel, finest first
    scale: float  # TAM tiles per texture-coordinate unit x finest size
    texcoord: int = 0
    style: str | None = None
    level_order: str = LEVEL_ORDER
    parameters: dict | None = None  # the stroke parameters (tam_parameters: angles in radians)
    strokes: dict | None = None  # the stroke parameterization's record when ``texcoord`` is its set (issue 38)


def read(doc: GltfDocument, material: int) -> TamMaterial | None:
    """What :func:`write_tam` wrote on ``material``, or None without ``BAKER_tonal_art_map``."""
    ext = (doc.json.get("materials", [])[material].get("extensions") or {}).get(NAME)
    if ext is None:
        return None
    levels = tuple(TamLevel(int(lv["size"]), tuple(int(t["index"]) for t in lv["textures"]) if "textures" in lv
                            else (int(lv["texture"]["index"]),)) for lv in ext["levels"])
    skip = {"layout", "tones", "levels", "scale", "texCoord", "style", "levelOrder", "strokes"}
    return TamMaterial(layout=ext.get("layout", "packed"), tones=tuple(float(t) for t in ext["tones"]),
                       levels=levels, scale=float(ext["scale"]), texcoord=int(ext.get("texCoord", 0)),
                       style=ext.get("style"), level_order=ext.get("levelOrder", LEVEL_ORDER),
                       parameters={k: v for k, v in ext.items() if k not in skip}, strokes=ext.get("strokes"))
