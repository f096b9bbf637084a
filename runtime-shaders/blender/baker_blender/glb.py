"""Just enough glTF 2.0 container handling for the add-on, with no dependency beyond numpy (Blender ships it):
read a .glb/.gltf into (json, binary chunk), decode accessors, append accessors/images, write a .glb back."""
from __future__ import annotations

import base64
import json
import os
import struct

import numpy as np

COMPONENT_DTYPES = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
TYPE_WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
GLB_MAGIC, CHUNK_JSON, CHUNK_BIN = 0x46546C67, 0x4E4F534A, 0x004E4942


def load(path: str) -> tuple[dict, bytes]:
    """(glTF JSON, binary buffer 0) of a .glb, or of a .gltf whose buffer 0 is a data URI or a file beside it."""
    with open(path, "rb") as f:
        data = f.read()
    if len(data) >= 12 and struct.unpack_from("<I", data, 0)[0] == GLB_MAGIC:
        offset, gltf, binary = 12, None, b""
        while offset + 8 <= len(data):
            length, kind = struct.unpack_from("<II", data, offset)
            chunk = data[offset + 8:offset + 8 + length]
            if kind == CHUNK_JSON:
                gltf = json.loads(chunk.decode("utf-8"))
            elif kind == CHUNK_BIN:
                binary = bytes(chunk)
            offset += 8 + length
        return gltf, binary
    gltf = json.loads(data.decode("utf-8"))
    binary = b""
    buffers = gltf.get("buffers") or []
    if buffers and "uri" in buffers[0]:
        uri = buffers[0]["uri"]
        if uri.startswith("data:"):
            binary = base64.b64decode(uri.split(",", 1)[1])
        else:
            folder = os.path.dirname(os.path.abspath(path))
            target = os.path.abspath(os.path.join(folder, uri))
            if os.path.commonpath([folder, target]) != folder:
                raise ValueError(f"{path}: buffer URI {uri!r} points outside the asset's folder")
            with open(target, "rb") as f:
                binary = f.read()
    return gltf, binary


def accessor(gltf: dict, binary: bytes, index: int) -> np.ndarray:
    """An accessor's values as stored (no normalization), (count,) or (count, width); sparse is not used by baker."""
    acc = gltf["accessors"][index]
    dtype = np.dtype(COMPONENT_DTYPES[acc["componentType"]])
    width = TYPE_WIDTHS[acc["type"]]
    count = acc["count"]
    if "bufferView" not in acc:
        values = np.zeros(count * width, dtype)
    else:
        view = gltf["bufferViews"][acc["bufferView"]]
        start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
        stride = view.get("byteStride", 0) or dtype.itemsize * width
        if stride == dtype.itemsize * width:
            values = np.frombuffer(binary, dtype, count * width, start).copy()
        else:
            rows = np.frombuffer(binary, np.uint8, stride * (count - 1) + dtype.itemsize * width, start)
            values = np.stack([np.frombuffer(rows[i * stride:i * stride + dtype.itemsize * width].tobytes(), dtype)
                               for i in range(count)]).reshape(-1)
    return values if width == 1 else values.reshape(count, width)


NORMALIZED_MAX = {5120: 127, 5121: 255, 5122: 32767, 5123: 65535}


def values(gltf: dict, binary: bytes, index: int) -> np.ndarray:
    """An accessor's values as numbers (float32): a normalized integer accessor (KHR_mesh_quantization, as
    ``gltf-transform quantize`` writes positions and baker's attributes) read as glTF says, c / max (at least -1), as
    Blender's importer reads it."""
    acc = gltf["accessors"][index]
    raw = accessor(gltf, binary, index)
    if acc.get("normalized") and acc["componentType"] in NORMALIZED_MAX:
        # in float64 then float32, as the importer does: positions are matched by their exact float32 bytes
        return np.maximum(-1.0, raw / float(NORMALIZED_MAX[acc["componentType"]])).astype(np.float32)
    return raw.astype(np.float32)


class Writer:
    """Appends buffer views and accessors to a loaded glTF whose binary chunk is ``binary``."""

    def __init__(self, gltf: dict, binary: bytes):
        self.gltf, self.binary = gltf, bytearray(binary)

    def view(self, data: bytes, target: int | None = None) -> int:
        while len(self.binary) % 4:
            self.binary.append(0)
        view = {"buffer": 0, "byteOffset": len(self.binary), "byteLength": len(data)}
        if target is not None:
            view["target"] = target
        self.binary.extend(data)
        views = self.gltf.setdefault("bufferViews", [])
        views.append(view)
        return len(views) - 1

    def accessor(self, template: dict, values: np.ndarray, target: int | None = None) -> int:
        """A new accessor like ``template`` (componentType, type, normalized, min/max recomputed) holding values."""
        dtype = COMPONENT_DTYPES[template["componentType"]]
        values = np.ascontiguousarray(values, dtype)
        acc = {k: template[k] for k in ("componentType", "type", "normalized", "name") if k in template}
        acc["count"] = int(len(values))
        if values.size:
            acc["bufferView"] = self.view(values.tobytes(), target)
        if "min" in template and values.size:
            flat = values.reshape(len(values), -1)
            cast = float if dtype == np.float32 else int
            acc["min"] = [cast(v) for v in flat.min(axis=0)]
            acc["max"] = [cast(v) for v in flat.max(axis=0)]
        accessors = self.gltf.setdefault("accessors", [])
        accessors.append(acc)
        return len(accessors) - 1

    def save(self, path: str) -> None:
        """Write a .glb atomically (temp file in the same folder, then rename)."""
        buffers = self.gltf.setdefault("buffers", [{}])
        while len(self.binary) % 4:
            self.binary.append(0)
        buffers[0] = {k: v for k, v in buffers[0].items() if k != "uri"}
        buffers[0]["byteLength"] = len(self.binary)
        text = json.dumps(self.gltf, separators=(",", ":")).encode("utf-8")
        text += b" " * (-len(text) % 4)
        chunks = struct.pack("<II", len(text), CHUNK_JSON) + text
        if self.binary:
            chunks += struct.pack("<II", len(self.binary), CHUNK_BIN) + bytes(self.binary)
        temp = path + ".baker-tmp"
        with open(temp, "wb") as f:
            f.write(struct.pack("<III", GLB_MAGIC, 2, 12 + len(chunks)) + chunks)
        os.replace(temp, path)


def encode_array(values: np.ndarray) -> dict:
    """An array as JSON-safe text for a Blender custom property."""
    values = np.ascontiguousarray(values)
    return {"dtype": values.dtype.str, "shape": list(values.shape), "data": base64.b64encode(values.tobytes()).decode()}


def decode_array(stored: dict) -> np.ndarray:
    return np.frombuffer(base64.b64decode(stored["data"]), np.dtype(stored["dtype"])).reshape(stored["shape"]).copy()
