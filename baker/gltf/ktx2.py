"""KTX 2.0 containers, uncompressed: write a texture with its own mip chain (and layers), and read one back.

Written from the Khronos KTX File Format Specification 2.0 (https://registry.khronos.org/KTX/specs/2.0/
ktxspec.v2.html) and the Khronos Data Format Specification 1.3 (basic data format descriptor):

- identifier, header (vkFormat, typeSize, pixelWidth/Height/Depth, layerCount, faceCount, levelCount,
  supercompressionScheme = 0), index (DFD, KVD, SGD offsets), level index (level 0 = the base, largest level);
- the data format descriptor of an 8-bit UNORM format: one basic block, color model RGBSDA, BT.709 primaries,
  linear transfer (tone maps are data, not colour), one sample per channel;
- key/value data: ``KTXwriter`` (required when a writer is known) and ``KTXorientation`` = ``rd`` (rows go down:
  row 0 of each image is the top, as in our PNGs), sorted by key, each entry padded to 4 bytes;
- the mip levels stored smallest first in the file, each aligned to lcm(texel block size, 4) bytes; within a level,
  layer after layer, each layer a tightly packed image of rows.

Only what baker writes is supported: R8, RG8, RGB8 or RGBA8 UNORM, 2D, one face, no supercompression.
"""
from __future__ import annotations

import math
import struct

import numpy as np

IDENTIFIER = b"\xabKTX 20\xbb\r\n\x1a\n"
# VkFormat values (Vulkan spec) of the 8-bit UNORM formats, by channel count
VK_FORMATS = {1: 9, 2: 16, 3: 23, 4: 37}  # VK_FORMAT_R8_UNORM, R8G8_UNORM, R8G8B8_UNORM, R8G8B8A8_UNORM
CHANNEL_IDS = {1: (0,), 2: (0, 1), 3: (0, 1, 2), 4: (0, 1, 2, 15)}  # KHR_DF_CHANNEL_RGBSDA_R, G, B, ALPHA = 15
KHR_DF_MODEL_RGBSDA = 1
KHR_DF_PRIMARIES_BT709 = 1
KHR_DF_TRANSFER_LINEAR = 1


def _dfd(channels: int) -> bytes:
    """Basic data format descriptor of an 8-bit-per-channel UNORM format, with its leading dfdTotalSize."""
    block_size = 24 + 16 * channels
    words = [
        0,                                  # vendorId 0 (Khronos) | descriptorType 0 (basic) << 17
        2 | (block_size << 16),             # versionNumber 2 (KDF 1.3) | descriptorBlockSize
        KHR_DF_MODEL_RGBSDA | (KHR_DF_PRIMARIES_BT709 << 8) | (KHR_DF_TRANSFER_LINEAR << 16),  # flags 0: straight
        0,                                  # texelBlockDimension0..3 = 1 x 1 x 1 x 1 (stored minus one)
        channels,                           # bytesPlane0 = bytes per texel; bytesPlane1..3 = 0
        0,                                  # bytesPlane4..7
    ]
    samples = []
    for i, channel in enumerate(CHANNEL_IDS[channels]):
        # bitOffset | (bitLength - 1) << 16 | channelType << 24 (no qualifiers: unsigned, not float, not linear)
        samples += [(8 * i) | (7 << 16) | (channel << 24), 0, 0, 255]  # position 0; sampleLower 0; sampleUpper 255
    body = struct.pack(f"<{len(words) + len(samples)}I", *words, *samples)
    return struct.pack("<I", 4 + len(body)) + body


def _kvd(pairs: dict) -> bytes:
    out = b""
    for key in sorted(pairs):  # entries sorted by key (byte-wise)
        entry = key.encode("utf-8") + b"\0" + pairs[key].encode("utf-8") + b"\0"
        out += struct.pack("<I", len(entry)) + entry + b"\0" * (-len(entry) % 4)
    return out


def encode_ktx2(levels: list, writer: str = "baker") -> bytes:
    """A KTX2 file of 8-bit UNORM images with a custom mip chain.

    Parameters
    ----------
    levels : list of uint8 arrays, base (largest) level first
        Each (H, W, C) for a 2D texture or (layers, H, W, C) for an array texture, C in 1..4; level i must be
        ``max(1, W >> i)`` x ``max(1, H >> i)``. Fewer levels than the full chain are allowed (levelCount says
        how many): a runtime uploads exactly these.
    writer : str
        The ``KTXwriter`` value.
    """
    arrays = [np.ascontiguousarray(a, np.uint8) for a in levels]
    if not arrays:
        raise ValueError("a KTX2 file needs at least one level")
    layered = arrays[0].ndim == 4
    base = arrays[0] if layered else arrays[0][None]
    layers, height, width, channels = base.shape
    if channels not in VK_FORMATS:
        raise ValueError(f"{channels} channels: baker writes R8, RG8, RGB8 or RGBA8 only")
    if len(arrays) > int(math.log2(max(width, height))) + 1:
        raise ValueError(f"{len(arrays)} levels exceed the full mip chain of {width} x {height}")
    for i, a in enumerate(arrays):
        a = a if layered else a[None]
        expected = (layers, max(1, height >> i), max(1, width >> i), channels)
        if a.shape != expected:
            raise ValueError(f"level {i} has shape {a.shape}, expected {expected}")

    dfd = _dfd(channels)
    kvd = _kvd({"KTXorientation": "rd", "KTXwriter": writer})
    header_size = 12 + 9 * 4 + 4 * 4 + 2 * 8
    level_index_size = 24 * len(arrays)
    dfd_offset = header_size + level_index_size
    kvd_offset = dfd_offset + len(dfd)
    end = kvd_offset + len(kvd)
    align = math.lcm(channels, 4)  # lcm(texel block size, 4)
    # level data: smallest level first in the file, each aligned
    offsets = [0] * len(arrays)
    data = b""
    position = end
    for i in reversed(range(len(arrays))):
        pad = -position % align
        data += b"\0" * pad
        position += pad
        offsets[i] = position
        blob = arrays[i].tobytes()  # layer-major, then rows (top first, KTXorientation rd), then texels
        data += blob
        position += len(blob)

    header = IDENTIFIER + struct.pack(
        "<9I", VK_FORMATS[channels], 1, width, height, 0, layers if layered else 0, 1, len(arrays), 0)
    index = struct.pack("<4I2Q", dfd_offset, len(dfd), kvd_offset, len(kvd), 0, 0)
    level_index = b"".join(struct.pack("<3Q", offsets[i], arrays[i].nbytes, arrays[i].nbytes)
                           for i in range(len(arrays)))
    return header + index + level_index + dfd + kvd + data


def decode_ktx2(blob: bytes) -> dict:
    """Parse a KTX2 file written by :func:`encode_ktx2` (uncompressed 8-bit UNORM) back into its parts.

    Returns a dict: ``vkFormat``, ``width``, ``height``, ``layers`` (0 = not an array), ``levels`` (list of uint8
    arrays, base first, shaped as given to :func:`encode_ktx2`), ``kvd`` (dict), ``dfd`` (tuple of uint32 words).
    Raises ValueError on anything malformed.
    """
    if blob[:12] != IDENTIFIER:
        raise ValueError("not a KTX2 file (bad identifier)")
    if len(blob) < 80:
        raise ValueError(f"{len(blob)} bytes: shorter than the KTX2 header")
    vk, type_size, width, height, depth, layers, faces, level_count, scheme = struct.unpack_from("<9I", blob, 12)
    dfd_off, dfd_len, kvd_off, kvd_len, sgd_off, sgd_len = struct.unpack_from("<4I2Q", blob, 48)
    channels = {v: k for k, v in VK_FORMATS.items()}.get(vk)
    if channels is None or type_size != 1 or depth != 0 or faces != 1 or scheme != 0 or sgd_len != 0:
        raise ValueError("only uncompressed 8-bit UNORM 2D textures are supported")
    if level_count > 32 or 80 + 24 * max(1, level_count) > len(blob):
        raise ValueError(f"levelCount {level_count}: the level index does not fit in the file")
    for name, offset, length in (("DFD", dfd_off, dfd_len), ("KVD", kvd_off, kvd_len)):
        if offset + length > len(blob) or (name == "DFD" and length < 4):
            raise ValueError(f"the {name} ({length} bytes at {offset}) lies outside the file")
    (total,) = struct.unpack_from("<I", blob, dfd_off)
    if total != dfd_len:
        raise ValueError(f"dfdTotalSize {total} != dfdByteLength {dfd_len}")
    dfd = struct.unpack_from(f"<{dfd_len // 4}I", blob, dfd_off)
    kvd, pos = {}, kvd_off
    while pos < kvd_off + kvd_len:
        (n,) = struct.unpack_from("<I", blob, pos)
        if pos + 4 + n > kvd_off + kvd_len:
            raise ValueError("a key/value entry runs past the KVD")
        key, _, value = blob[pos + 4: pos + 4 + n].partition(b"\0")
        kvd[key.decode("utf-8")] = value.rstrip(b"\0").decode("utf-8")
        pos += 4 + n + (-n % 4)
    levels = []
    for i in range(max(1, level_count)):
        offset, length, uncompressed = struct.unpack_from("<3Q", blob, 80 + 24 * i)
        if length != uncompressed or offset + length > len(blob):
            raise ValueError(f"level {i}: bad byte range")
        if offset % math.lcm(channels, 4):
            raise ValueError(f"level {i}: offset {offset} is not aligned")
        h, w = max(1, height >> i), max(1, width >> i)
        shape = (max(1, layers), h, w, channels)
        if length != int(np.prod(shape)):
            raise ValueError(f"level {i}: {length} bytes for {shape}")
        a = np.frombuffer(blob, np.uint8, length, offset).reshape(shape)
        levels.append(a if layers else a[0])
    return {"vkFormat": vk, "width": width, "height": height, "layers": layers, "levels": levels, "kvd": kvd,
            "dfd": dfd}


def coverage_mips_bytes(doc, entry: dict) -> bytes:
    """The KTX2 file of one ``coverageMips`` entry (its accessor's bytes; :mod:`baker.texels.alpha_mips` makes the
    chain and the entry); ValueError when it is not one. Here, beside the container, so that writers (USD) read the
    file without the mip kernel."""
    accessors = doc.json.get("accessors") or []
    index = entry.get("accessor") if isinstance(entry, dict) else None
    if not isinstance(index, int) or isinstance(index, bool) or not 0 <= index < len(accessors):
        raise ValueError(f"accessor {index!r} does not exist")
    acc = accessors[index]
    if acc.get("componentType") != 5121 or acc.get("type") != "SCALAR" or acc.get("normalized"):
        raise ValueError(f"accessor {index} is not UNSIGNED_BYTE SCALAR (one element per byte of the KTX2)")
    return doc.accessor(index).tobytes()
