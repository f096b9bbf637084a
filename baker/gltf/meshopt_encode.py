"""EXT_meshopt_compression written by baker (``baker bake --compress meshopt`` or ``meshopt-gzip``): every bufferView
that only accessors read is stored with meshoptimizer's codecs, losslessly, so the bake is intact (every extension,
custom attribute, accessor and bufferView stays where it was, and decodes to the same bytes).

The method follows the extension's specification (Khronos glTF, extensions/2.0/Vendor/EXT_meshopt_compression):

- Each bufferView is tried in the modes its data allows and stored in the encoding that decodes back to its exact
  bytes (every candidate is decoded and compared before it is kept) and is the smallest (``meshopt``) or the
  smallest once deflated (``meshopt-gzip``, for servers that gzip); when no encoding beats the plain bytes the view
  stays as it is:
  - ``ATTRIBUTES`` (vertex codec, version 0 as the extension requires) with the view's ``byteStride``, or the
    accessors' element size when it is a multiple of 4, or the bytes as 4-byte rows (any data, e.g. 16-bit scalars);
  - ``TRIANGLES`` (index codec) for a primitive's triangle-list indices. The codec may rotate a triangle's corners
    (same winding), which would move per-corner data (edge-visibility bits, wireframe masks) off their edges, so it
    is kept only where the decoded indices equal the stored ones;
  - ``INDICES`` (index-sequence codec) for other 16/32-bit unsigned data: line and edge lists, vertex id lists, and
    triangle indices the triangle codec would rotate.
- No filter: OCTAHEDRAL, QUATERNION and EXPONENTIAL quantize, which changes the data. No vertex or index reordering
  either (it would renumber what the bake indexes).
- The extension is *required* and the uncompressed bufferViews point into a fallback buffer that has a size and no
  data (``"fallback": true``), the smallest file: three.js's GLTFLoader (with ``setMeshoptDecoder``) and
  Babylon.js's loader (built in) both decode it; a consumer without a meshopt decoder takes the uncompressed bake.
  Views that something other than an accessor reads (an image) stay uncompressed in the binary buffer.

Fallback and binary-buffer views keep their byte offset modulo 16, so every accessor stays aligned.
"""
from __future__ import annotations

import zlib

# no numpy at import: ``baker bake``'s parser reads COMPRESSIONS, and ``baker --version`` builds that parser

EXTENSION = "EXT_meshopt_compression"
TRIANGLES_MODE = 4  # a primitive's default mode
INDEX_COMPONENTS = (5123, 5125)  # unsigned short, unsigned int: what the index codecs hold
COMPONENT_SIZES = {5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4}
TYPE_SIZES = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
MAX_ATTRIBUTE_STRIDE = 256
TARGETS = ("size", "gzip")
# ``--compress`` choices: none, or meshopt aiming at each target
COMPRESSIONS = ("none", "meshopt", "meshopt-gzip")
GZIP_LEVEL = 6  # deflate's default, what web servers use


def _cost(data: bytes, target: str) -> tuple[int, int]:
    """What a view's candidate bytes cost for ``target``: (deflated size, size) or (size,)."""
    if target == "gzip":
        return len(zlib.compress(data, GZIP_LEVEL)), len(data)
    return (len(data),)


def compress_meshopt(gltf: dict, binary: bytes, target: str = "size") -> tuple[dict, bytearray, dict]:
    """``gltf`` (a JSON dict changed in place) and its single binary buffer, with every bufferView that only
    accessors read stored as EXT_meshopt_compression (see the module docstring).

    ``target``: what each view's encoding minimizes. ``"size"``: its bytes (the file as stored, and as sent by a
    server that does not compress). ``"gzip"``: its bytes after deflate (what a server that gzips sends), with the
    plain bytes as one more candidate: the codecs' byte deltas undo the long repeats deflate finds in data that is
    neither quantized nor reordered (duplicated fin vertices, padded scalars, texel levels).

    Returns the JSON, the new binary buffer (the compressed data and the views left uncompressed) and a summary:
    view count per mode and the bytes before and after."""
    import meshopt
    import numpy as np

    if target not in TARGETS:
        raise ValueError(f"unknown target {target!r} (use one of {', '.join(TARGETS)})")
    views = gltf.get("bufferViews") or []
    accessors = gltf.get("accessors") or []
    uses = _view_uses(gltf)
    triangles = _triangle_index_accessors(gltf)
    summary = {"ATTRIBUTES": 0, "TRIANGLES": 0, "INDICES": 0, "uncompressed": 0, "bytes": len(binary)}
    encoded = {}  # view index -> (mode, stride, count, compressed bytes, raw length)
    for index, view in enumerate(views):
        use = uses.get(index)
        if use is None or use.other or view.get("buffer", 0) != 0:
            continue
        start = int(view.get("byteOffset", 0))
        raw = bytes(binary[start: start + int(view["byteLength"])])
        best, best_cost = None, _cost(raw, target)
        for mode, stride, data in _candidates(view, raw, use, accessors, triangles):
            count = len(data) // stride
            try:
                packed = meshopt.encode_gltf_buffer(_rows(data, mode, stride), mode, 0)
                decoded = meshopt.decode_gltf_buffer(packed, count, stride, mode)
            except (ValueError, RuntimeError):  # the codec refuses this layout: another candidate may fit
                continue
            if np.ascontiguousarray(decoded).tobytes() != data:
                continue  # the triangle codec rotated a triangle: not this mode
            cost = _cost(packed, target)
            if cost < best_cost:
                best, best_cost = (mode, stride, count, packed, len(data)), cost
        if best is not None:
            encoded[index] = best
    if not encoded:
        summary["uncompressed"] = sum(1 for use in uses.values() if not use.other)
        summary["compressed"] = len(binary)
        return gltf, bytearray(binary), summary

    out = bytearray()
    fallback_length = 0
    for index, view in enumerate(views):
        start = int(view.get("byteOffset", 0))
        if index in encoded:
            mode, stride, count, packed, length = encoded[index]
            out.extend(b"\0" * (-len(out) % 4))
            ext = {"buffer": 0, "byteOffset": len(out), "byteLength": len(packed), "byteStride": stride,
                   "mode": mode, "count": count}
            out.extend(packed)
            fallback_offset = fallback_length + (start % 16 - fallback_length % 16) % 16
            view["buffer"] = 1
            view["byteOffset"] = fallback_offset
            view["byteLength"] = length
            view.setdefault("extensions", {})[EXTENSION] = ext
            fallback_length = fallback_offset + length
            summary[mode] += 1
        elif view.get("buffer", 0) == 0:
            data = binary[start: start + int(view["byteLength"])]
            new = len(out) + (start % 16 - len(out) % 16) % 16
            out.extend(b"\0" * (new - len(out)))
            out.extend(data)
            view["byteOffset"] = new
            if index in uses and not uses[index].other:
                summary["uncompressed"] += 1
    buffers = gltf.setdefault("buffers", [{}])
    if len(buffers) != 1:  # baker's documents hold one merged buffer; anything else is a bug upstream
        raise ValueError(f"{EXTENSION}: expected one binary buffer, found {len(buffers)}")
    buffers.append({"byteLength": fallback_length, "extensions": {EXTENSION: {"fallback": True}}})
    for key in ("extensionsUsed", "extensionsRequired"):
        names = gltf.setdefault(key, [])
        if EXTENSION not in names:
            names.append(EXTENSION)
    summary["compressed"] = len(out)
    return gltf, out, summary


class ViewUse:
    """How accessors read one bufferView: what the index codecs may hold and the element size of its rows."""

    def __init__(self):
        self.other = False  # read by something that is not an accessor (an image, a Draco primitive)
        self.accessors = []

    def index_size(self, accessors) -> int | None:
        """2 or 4 when every accessor of the view holds unsigned 16 or 32-bit integers of that size, else None."""
        types = {accessors[a].get("componentType") for a in self.accessors}
        if len(types) != 1 or any(accessors[a].get("normalized") for a in self.accessors):
            return None
        kind = types.pop()
        return COMPONENT_SIZES[kind] if kind in INDEX_COMPONENTS else None

    def element_size(self, accessors) -> int | None:
        """The byte size of one element when every accessor of the view has the same, else None."""
        sizes = {COMPONENT_SIZES.get(accessors[a].get("componentType"), 0) * TYPE_SIZES.get(accessors[a].get("type"), 0)
                 for a in self.accessors}
        return sizes.pop() if len(sizes) == 1 else None


def _view_uses(gltf: dict) -> dict[int, ViewUse]:
    """Each bufferView's readers: its accessors (sparse parts count as accessors of the view), or other readers."""
    uses: dict[int, ViewUse] = {}
    for a, acc in enumerate(gltf.get("accessors") or []):
        if isinstance(acc.get("bufferView"), int):
            uses.setdefault(acc["bufferView"], ViewUse()).accessors.append(a)
        sparse = acc.get("sparse")
        if isinstance(sparse, dict):  # sparse parts: a view read as raw rows (no element size of its own)
            for part in ("indices", "values"):
                if isinstance(sparse.get(part), dict) and isinstance(sparse[part].get("bufferView"), int):
                    uses.setdefault(sparse[part]["bufferView"], ViewUse()).accessors.append(None)
    for image in gltf.get("images") or []:
        if isinstance(image.get("bufferView"), int):
            uses.setdefault(image["bufferView"], ViewUse()).other = True
    for mesh in gltf.get("meshes") or []:
        for prim in mesh.get("primitives") or []:
            draco = (prim.get("extensions") or {}).get("KHR_draco_mesh_compression")
            if isinstance(draco, dict) and isinstance(draco.get("bufferView"), int):
                uses.setdefault(draco["bufferView"], ViewUse()).other = True
    return uses


def _triangle_index_accessors(gltf: dict) -> set:
    found = set()
    for mesh in gltf.get("meshes") or []:
        for prim in mesh.get("primitives") or []:
            if "indices" in prim and prim.get("mode", TRIANGLES_MODE) == TRIANGLES_MODE:
                found.add(prim["indices"])
    return found


def _candidates(view: dict, raw: bytes, use: ViewUse, accessors: list, triangles: set):
    """(mode, byteStride, data) to try for one view: the data is ``raw``, zero-padded to whole rows of a declared
    byteStride (glTF lets the last element of a strided view end short; the extension needs whole rows)."""
    stride = view.get("byteStride")
    if stride:
        if stride % 4 == 0 and stride <= MAX_ATTRIBUTE_STRIDE:
            yield "ATTRIBUTES", stride, raw + b"\0" * (-len(raw) % stride)
        return
    plain = None not in use.accessors
    size = use.index_size(accessors) if plain else None
    if size and len(raw) % size == 0:
        whole = len(use.accessors) == 1 and not accessors[use.accessors[0]].get("byteOffset")
        if whole and use.accessors[0] in triangles and (len(raw) // size) % 3 == 0:
            yield "TRIANGLES", size, raw
        yield "INDICES", size, raw
    element = use.element_size(accessors) if plain else None
    for rows in dict.fromkeys((element, 4)):
        if rows and rows % 4 == 0 and rows <= MAX_ATTRIBUTE_STRIDE and len(raw) % rows == 0:
            yield "ATTRIBUTES", rows, raw


def _rows(data: bytes, mode: str, stride: int):
    """The bytes as the encoder takes them: rows of ``stride`` bytes, or 16/32-bit indices (a numpy array)."""
    import numpy as np

    if mode == "ATTRIBUTES":
        return np.frombuffer(data, np.uint8).reshape(-1, stride)
    return np.frombuffer(data, np.uint16 if stride == 2 else np.uint32).astype(np.uint32)
