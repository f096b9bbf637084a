"""EXT_meshopt_compression written by baker (``baker bake --compress meshopt``, ``meshopt-gzip`` or
``meshopt-lossless``): every bufferView that only accessors read is stored with meshoptimizer's codecs, so the bake is
intact (every extension, custom attribute, accessor and bufferView stays where it was, and decodes to the same bytes)
but for the float vertex attributes of :data:`EXPONENTIAL_BITS`, which ``meshopt`` and ``meshopt-gzip`` store with the
EXPONENTIAL filter (``meshopt-lossless`` does not).

The method follows the extension's specification (Khronos glTF, extensions/2.0/Vendor/EXT_meshopt_compression):

- Each bufferView is tried in the modes its data allows and stored in the encoding that decodes back to its exact
  bytes (every candidate is decoded and compared before it is kept) and is the smallest (``meshopt``) or the
  smallest once deflated (``meshopt-gzip``, for servers that gzip); when no encoding beats the plain bytes the view
  stays as it is:
  - ``ATTRIBUTES`` (vertex codec, version 0 as the extension requires) with the view's ``byteStride``, or the
    accessors' element size when it is a multiple of 4, or the bytes as 4-byte rows (any data, e.g. 16-bit scalars
    and indices, zero-padded to a whole last row, which the view's ``byteLength`` then covers);
  - ``TRIANGLES`` (index codec) for a primitive's triangle-list indices. The codec may rotate a triangle's corners
    (same winding), which would move per-corner data (edge-visibility bits, wireframe masks) off their edges, so it
    is kept only where the decoded indices equal the stored ones;
  - ``INDICES`` (index-sequence codec) for other 16/32-bit unsigned data: line and edge lists, vertex id lists, and
    triangle indices the triangle codec would rotate.
- EXPONENTIAL filter for the float vertex attributes baker bakes (:data:`EXPONENTIAL_BITS`): each float keeps a
  mantissa of the stated bits and decodes to float32 again, so the accessors keep their type and every reader, shader
  and validator reads them as before. The exponent is the vector's (``SharedVector``: the error of each component
  is at most 2^(1 - bits) of the vector's largest component) or each value's (``Separate``: at most 2^(1 - bits) of
  the value itself, for scalars padded to VEC3, whose zero padding then costs nothing). Every filtered view is
  decoded and checked against that bound before it is kept, and the accessor's ``min``/``max`` follow the decoded
  values. Unit vectors keep 12 bits (length within 4e-4 of 1, under ``baker validate``'s 1e-3), positions and the
  unwrap 16 bits, the principal curvatures share their exponent so k1 >= k2 holds exactly.
- OCTAHEDRAL filter for ``NORMAL`` and ``_PRINCIPAL_DIRECTION`` (:data:`OCTAHEDRAL_BITS`) where every vector is unit
  length: they decode to normalized SHORT VEC3 in 8-byte rows, which ``KHR_mesh_quantization`` allows for NORMAL
  (the file then requires it) and every baker reader takes for its attributes (c / 32767); each component within
  2^(2 - bits) of the float, the length within 1e-4 of 1. ``_OUTLINE_NORMAL`` is zero at open boundaries, so it
  keeps the exponential filter. QUATERNION is not used. No vertex or index reordering either
  (it would renumber what the bake indexes).
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
COMPRESSIONS = ("none", "meshopt", "meshopt-gzip", "meshopt-lossless")
# vertex attribute -> (EXPONENTIAL filter mode, mantissa bits): the precision each baked quantity keeps (module doc)
EXPONENTIAL_BITS = {
    "POSITION": ("SharedVector", 16),  # 3.1e-5 of the vertex's largest coordinate
    "NORMAL": ("SharedVector", 12),  # unit vectors: 2.4e-4 per component (where OCTAHEDRAL does not apply)
    "_OUTLINE_NORMAL": ("SharedVector", 12),  # zero on open boundaries: no octahedral form
    "_PRINCIPAL_DIRECTION": ("SharedVector", 12),
    "TEXCOORD_0": ("SharedVector", 16),  # the unwrap in [0, 1]: 1.5e-5, 1/32 texel of a 2048 texture
    "TEXCOORD_1": ("SharedVector", 14),  # the stroke set's coordinates (tam): 1.2e-4 of the larger one
    "_PRINCIPAL_CURVATURES": ("SharedVector", 16),  # one exponent for k1 and k2: their order kept
    "_CURVATURE": ("Separate", 16),  # H: 3.1e-5 of itself, so H = (k1 + k2) / 2 within 1e-4 of the largest k
    "_THICKNESS": ("Separate", 12),  # 2.4e-4 of itself (the thickness texture is 8-bit)
}
# vertex attribute -> bits of the OCTAHEDRAL filter, for views whose every vector is unit length (within 1e-3): it
# decodes to normalized SHORT VEC3 in 8-byte rows (KHR_mesh_quantization), each component within 2^(2 - bits) of
# the float (1e-3 at 12 bits, 0.06 degrees), the length within 1e-4 of 1
OCTAHEDRAL_BITS = {"NORMAL": 12, "_PRINCIPAL_DIRECTION": 12}
QUANTIZATION = "KHR_mesh_quantization"
SHORT = 5122
GZIP_LEVEL = 6  # deflate's default, what web servers use


def _cost(data: bytes, target: str) -> tuple[int, int]:
    """What a view's candidate bytes cost for ``target``: (deflated size, size) or (size,)."""
    if target == "gzip":
        return len(zlib.compress(data, GZIP_LEVEL)), len(data)
    return (len(data),)


def compress_meshopt(gltf: dict, binary: bytes, target: str = "size",
                     filters: bool = True) -> tuple[dict, bytearray, dict]:
    """``gltf`` (a JSON dict changed in place) and its single binary buffer, with every bufferView that only
    accessors read stored as EXT_meshopt_compression (see the module docstring).

    ``target``: what each view's encoding minimizes. ``"size"``: its bytes (the file as stored, and as sent by a
    server that does not compress). ``"gzip"``: its bytes after deflate (what a server that gzips sends), with the
    plain bytes as one more candidate: the codecs' byte deltas undo the long repeats deflate finds in data that is
    neither quantized nor reordered (duplicated fin vertices, padded scalars, texel levels). ``filters``: the
    attributes of :data:`EXPONENTIAL_BITS` through the EXPONENTIAL filter (else every view decodes to its bytes).

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
    filtered_views = _filtered_views(gltf, uses) if filters else {}
    summary = {"ATTRIBUTES": 0, "TRIANGLES": 0, "INDICES": 0, "EXPONENTIAL": 0, "OCTAHEDRAL": 0, "uncompressed": 0,
               "bytes": len(binary)}
    encoded = {}  # view index -> (mode, stride, count, compressed bytes, raw length, filter)
    for index, view in enumerate(views):
        use = uses.get(index)
        if use is None or use.other or view.get("buffer", 0) != 0:
            continue
        start = int(view.get("byteOffset", 0))
        raw = bytes(binary[start: start + int(view["byteLength"])])
        best, best_cost = None, _cost(raw, target)
        if index in filtered_views:
            accessor, name = filtered_views[index]
            candidate = _octahedral(raw, accessors[accessor], OCTAHEDRAL_BITS[name]) if name in OCTAHEDRAL_BITS \
                else None
            if candidate is not None:
                packed, stride, count, decoded = candidate
                best, best_cost = ("ATTRIBUTES", stride, count, packed, count * stride, "OCTAHEDRAL", accessor,
                                   decoded), _cost(packed, target)
            else:
                candidate = _exponential(raw, accessors[accessor], *EXPONENTIAL_BITS[name])
                if candidate is not None:
                    packed, stride, count, decoded = candidate
                    best, best_cost = ("ATTRIBUTES", stride, count, packed, len(raw), "EXPONENTIAL", accessor,
                                       decoded), _cost(packed, target)
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
                best, best_cost = (mode, stride, count, packed, len(data), None, None, None), cost
        if best is not None:
            encoded[index] = best
    if not encoded:
        summary["uncompressed"] = sum(1 for use in uses.values() if not use.other)
        summary["compressed"] = len(binary)
        return gltf, bytearray(binary), summary

    out = bytearray()
    fallback_length = 0
    quantized = False
    for index, view in enumerate(views):
        start = int(view.get("byteOffset", 0))
        if index in encoded:
            mode, stride, count, packed, length, filter_name, accessor, decoded = encoded[index]
            out.extend(b"\0" * (-len(out) % 4))
            ext = {"buffer": 0, "byteOffset": len(out), "byteLength": len(packed), "byteStride": stride,
                   "mode": mode, "count": count}
            if filter_name:
                ext["filter"] = filter_name
                summary[filter_name] += 1
                acc = accessors[accessor]
                if filter_name == "OCTAHEDRAL":  # decodes to normalized 16-bit integers in 8-byte rows
                    acc["componentType"], acc["normalized"] = SHORT, True
                    view["byteStride"] = stride
                    quantized = True
                if "min" in acc and "max" in acc:  # the bounds of what readers decode (stored values: the spec)
                    acc["min"] = [x.item() for x in decoded.min(axis=0)]
                    acc["max"] = [x.item() for x in decoded.max(axis=0)]
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
        for name in (EXTENSION, QUANTIZATION) if quantized else (EXTENSION,):
            if name not in names:
                names.append(name)
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


def _filtered_views(gltf: dict, uses: dict) -> dict[int, tuple[int, str]]:
    """bufferView -> (its accessor, its attribute name) for the vertex attributes of :data:`EXPONENTIAL_BITS`
    that are float32, not normalized, not sparse and alone in a tightly packed view."""
    accessors = gltf.get("accessors") or []
    views = gltf.get("bufferViews") or []
    found = {}
    for mesh in gltf.get("meshes") or []:
        for prim in mesh.get("primitives") or []:
            for name, a in (prim.get("attributes") or {}).items():
                if name not in EXPONENTIAL_BITS or not isinstance(a, int) or not 0 <= a < len(accessors):
                    continue
                acc = accessors[a]
                view = acc.get("bufferView")
                if (not isinstance(view, int) or acc.get("componentType") != 5126 or acc.get("normalized")
                        or acc.get("sparse") or acc.get("byteOffset", 0) or acc.get("type") not in TYPE_SIZES):
                    continue
                use = uses.get(view)
                element = 4 * TYPE_SIZES[acc["type"]]
                if (use is None or use.other or use.accessors != [a] or views[view].get("byteStride", element) != element
                        or int(views[view]["byteLength"]) != element * int(acc.get("count", 0)) or element % 4):
                    continue
                if found.get(view, (a, name))[1] != name:  # one view under two names: lossless
                    found[view] = (a, None)
                else:
                    found[view] = (a, name)
    return {view: entry for view, entry in found.items() if entry[1] is not None}


def _exponential(raw: bytes, accessor: dict, filter_mode: str, bits: int):
    """A view of float32 vectors through the EXPONENTIAL filter and the vertex codec: (compressed bytes, byteStride,
    count, decoded values), or None when a value is not finite or the decoded values miss the bound."""
    import meshopt
    import numpy as np

    width = TYPE_SIZES[accessor["type"]]
    values = np.frombuffer(raw, np.float32).reshape(-1, width)
    if not len(values) or not np.isfinite(values).all():
        return None
    rows = meshopt.encode_filter_exp(np.ascontiguousarray(values), bits, filter_mode)
    stride = 4 * width
    packed = meshopt.encode_gltf_buffer(np.ascontiguousarray(rows).view(np.uint8).reshape(len(values), stride),
                                        "ATTRIBUTES", 0)
    decoded = np.ascontiguousarray(meshopt.decode_gltf_buffer(packed, len(values), stride, "ATTRIBUTES",
                                                              "EXPONENTIAL")).view(np.float32).reshape(values.shape)
    scale = np.abs(values) if filter_mode == "Separate" else np.abs(values).max(axis=1, keepdims=True)
    bound = scale * 2.0 ** (1 - bits) + 1e-30  # the module doc's precision, checked on every value
    if not (np.isfinite(decoded).all() and (np.abs(decoded.astype(np.float64) - values) <= bound).all()):
        return None
    return packed, stride, len(values), decoded


def _octahedral(raw: bytes, accessor: dict, bits: int):
    """A view of float32 unit VEC3 through the OCTAHEDRAL filter (normalized SHORT in 8-byte rows) and the vertex
    codec: (compressed bytes, byteStride, count, decoded int16 VEC3), or None when a vector is not unit length (a
    zero outline normal at a boundary) or the decoded values miss :data:`OCTAHEDRAL_BITS`' bound."""
    import meshopt
    import numpy as np

    if accessor.get("type") != "VEC3":
        return None
    values = np.frombuffer(raw, np.float32).reshape(-1, 3)
    if not len(values) or not np.isfinite(values).all() or \
            (np.abs(np.linalg.norm(values.astype(np.float64), axis=1) - 1.0) > 1e-3).any():
        return None
    padded = np.zeros((len(values), 4), np.float32)
    padded[:, :3] = values
    rows = np.ascontiguousarray(meshopt.encode_filter_oct(padded, 8, bits)).view(np.uint8).reshape(len(values), 8)
    packed = meshopt.encode_gltf_buffer(rows, "ATTRIBUTES", 0)
    decoded = np.ascontiguousarray(meshopt.decode_gltf_buffer(packed, len(values), 8, "ATTRIBUTES", "OCTAHEDRAL"))
    decoded = decoded.view(np.int16).reshape(len(values), 4)[:, :3]
    unit = decoded.astype(np.float64) / 32767.0
    if (np.abs(unit - values).max() > 2.0 ** (2 - bits)
            or np.abs(np.linalg.norm(unit, axis=1) - 1.0).max() > 1e-4):
        return None
    return packed, 8, len(values), decoded


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
    byteStride (glTF lets the last element of a strided view end short; the extension needs whole rows) or of 4
    bytes (the vertex codec's smallest row); the view's ``byteLength`` then covers the padding."""
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
    if len(raw) % 4:  # 8 and 16-bit data of any length (indices, edge masks): 4-byte rows, the last one zero-padded
        yield "ATTRIBUTES", 4, raw + b"\0" * (-len(raw) % 4)


def _rows(data: bytes, mode: str, stride: int):
    """The bytes as the encoder takes them: rows of ``stride`` bytes, or 16/32-bit indices (a numpy array)."""
    import numpy as np

    if mode == "ATTRIBUTES":
        return np.frombuffer(data, np.uint8).reshape(-1, stride)
    return np.frombuffer(data, np.uint16 if stride == 2 else np.uint32).astype(np.uint32)
