"""Image encoding and decoding through OpenImageIO (PNG 8/16-bit, EXR half/float)."""
from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

from baker.errors import BakerError

_FORMATS = {np.dtype(np.uint8): "uint8", np.dtype(np.uint16): "uint16", np.dtype(np.float16): "half",
            np.dtype(np.float32): "float"}


def write_image(path, pixels: np.ndarray) -> None:
    """Write ``pixels`` (H, W) or (H, W, C), row 0 at the top, to ``path``; the format follows the extension."""
    pixels = np.ascontiguousarray(pixels)
    if pixels.ndim == 2:
        pixels = pixels[:, :, None]
    h, w, c = pixels.shape
    spec = oiio.ImageSpec(w, h, c, _FORMATS[pixels.dtype])
    # no timestamps or host names in the file: outputs must be byte-identical run to run
    spec.attribute("DateTime", "")
    # our alpha is straight (glTF, PNG and MTSDF atlases all expect that): without this OpenImageIO takes RGBA as
    # premultiplied and divides colour by alpha when it writes a PNG
    spec.attribute("oiio:UnassociatedAlpha", 1)
    out = oiio.ImageOutput.create(str(path))
    if out is None:
        raise BakerError(path, f"cannot write image: {oiio.geterror()}")
    try:
        if not out.open(str(path), spec) or not out.write_image(pixels):
            raise BakerError(path, f"cannot write image: {out.geterror()}")
    finally:
        out.close()


def encode_image(pixels: np.ndarray, suffix: str = ".png") -> bytes:
    """Encode ``pixels`` to bytes in the format named by ``suffix``."""
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / f"image{suffix}"
        write_image(p, pixels)
        return p.read_bytes()


def read_image(path) -> np.ndarray:
    """Read an image as (H, W, C) in its stored pixel type, alpha as stored (not premultiplied)."""
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)
    inp = oiio.ImageInput.open(str(path), config)
    if inp is None:
        raise BakerError(path, f"cannot read image: {oiio.geterror()}")
    try:
        return inp.read_image(format=inp.spec().format)
    finally:
        inp.close()


def decode_image(data: bytes, suffix: str = ".png") -> np.ndarray:
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / f"image{suffix}"
        p.write_bytes(data)
        return read_image(p)


# ---------------------------------------------------------------------------------------------------------- validate
def decoded_texture(doc, texture: int):
    """The pixels of texture ``texture`` of a document decoded as PNG, or None when it has no image (or names one
    that does not exist) or the image cannot be decoded."""
    source = (doc.json.get("textures") or [])[texture].get("source")
    images = doc.json.get("images") or []
    if not isinstance(source, int) or not 0 <= source < len(images):
        return None
    try:
        return decode_image(doc.image_bytes(source), ".png")
    except Exception:  # not a PNG, or undecodable: the Khronos validator reports the image itself
        return None
