"""The normal map on a material: ``normalTexture`` (tangent space; Khronos core) or
``materials[].extras.baker.objectSpaceNormalTexture`` (object space, which core glTF has no slot for), the vertex
TANGENT it is decoded with, and ``materials[].extras.baker.normal`` (space, source, bits); read back for tests and
tools."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from baker.gltf.document import GltfDocument

SAMPLER = {"magFilter": 9729, "minFilter": 9987}  # linear, trilinear mips: the map is dilated past its charts


def encode_png(pixels: np.ndarray) -> bytes:
    from baker.gltf.images import encode_image  # OpenImageIO: loaded only when a texture is written

    return encode_image(pixels, ".png")


def write_normal_texture(doc: GltfDocument, material: int, png: bytes, texcoord: int, space: str,
                         source: str, bits: int) -> bool:
    """Add the map to ``material``; returns whether it replaced an existing ``normalTexture``."""
    image = doc.add_image(png, "image/png", f"normal_m{material}")
    texture = doc.add_texture(image, sampler=dict(SAMPLER), name=f"baker normal (material {material})")
    info = {"index": texture}
    if texcoord:
        info["texCoord"] = int(texcoord)
    mat = doc.json["materials"][material]
    replaced = False
    extras = mat.setdefault("extras", {})
    baker_extras = extras.setdefault("baker", {}) if isinstance(extras, dict) else {}
    if space == "tangent":
        replaced = "normalTexture" in mat
        mat["normalTexture"] = info
    else:
        baker_extras["objectSpaceNormalTexture"] = info
    baker_extras["normal"] = {"space": space, "source": source, "bits": int(bits)}
    return replaced


@dataclass
class NormalMap:
    space: str
    texture: int
    texcoord: int


def read(doc: GltfDocument, material: int) -> NormalMap | None:
    """The baked map of ``material`` (None when it has none)."""
    mat = (doc.json.get("materials") or [])[material]
    baked = ((mat.get("extras") or {}).get("baker") or {}).get("normal")
    if not isinstance(baked, dict):
        return None
    space = baked.get("space")
    info = mat.get("normalTexture") if space == "tangent" else mat["extras"]["baker"].get("objectSpaceNormalTexture")
    if not isinstance(info, dict):
        return None
    return NormalMap(space, int(info["index"]), int(info.get("texCoord", 0)))
