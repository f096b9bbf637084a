"""Compressed glTF geometry decoded into plain accessors, so every bake reads (and every writer keeps) real data.

- ``KHR_draco_mesh_compression`` (on a primitive): decoded with DracoPy (Google's Draco decoder). Each attribute
  the extension names, and the indices, become ordinary data in the primitive's own accessors (same indices; their
  ``count`` is the decoded count, ``min``/``max`` those of the decoded values, which Draco's quantization moves
  slightly); the compressed bufferView is reused for the first decoded array, so no bufferView is left unused.
- ``EXT_meshopt_compression`` and ``KHR_meshopt_compression`` (on a bufferView; the KHR one is the ratified
  successor with the same JSON, whose data may also use the vertex codec's version 1 and the COLOR filter): decoded
  with ``meshopt`` (meshoptimizer's decoder, vendored from meshoptimizer 1.3: vertex codec versions 0 and 1, modes
  ATTRIBUTES, TRIANGLES, INDICES, filters OCTAHEDRAL, QUATERNION, EXPONENTIAL, COLOR undone; any other mode or filter
  is refused with one line). The bufferView keeps its index and gets the decoded bytes; the fallback buffer (size
  only, no data) goes away.

The extension is then removed from the primitive or bufferView and from ``extensionsUsed``/``extensionsRequired``,
bytes nothing points at any more (compressed data, the fallback buffer's zeros) are dropped from the binary buffer,
and ``asset.extras.baker.decompressed`` records how the input was stored: one entry per extension with the decoder
and the primitives or bufferViews it decoded. Accessor, mesh and bufferView indices never change. The decoded
positions, normals and UVs then get the NaN/infinity check the load gave the plain ones.
"""
from __future__ import annotations

import numpy as np

from baker.checks import Issues, pointer
from baker.errors import BakerError
from baker.gltf.structure import MESHOPT_EXTENSIONS, check_finite_attributes, first_error, meshopt_extension

# no import of baker.gltf.document: GltfDocument.load may call decompress() (``doc`` is any GltfDocument)
COMPONENT_DTYPES = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32,
                    5126: np.float32}
TYPE_SIZES = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
TARGET_ARRAY_BUFFER = 34962
TARGET_ELEMENT_ARRAY_BUFFER = 34963

DRACO = "KHR_draco_mesh_compression"
DECODED = (DRACO, *MESHOPT_EXTENSIONS)

MESHOPT_MODES = ("ATTRIBUTES", "TRIANGLES", "INDICES")
MESHOPT_FILTERS = ("NONE", "OCTAHEDRAL", "QUATERNION", "EXPONENTIAL", "COLOR")


def is_compressed(gltf: dict) -> bool:
    """Whether the document uses an extension :func:`decompress` decodes."""
    used = gltf.get("extensionsUsed") or []
    return any(name in used for name in DECODED)


def decompress(doc) -> list[dict]:
    """Decode every Draco primitive and meshopt bufferView of ``doc`` in place (see the module docstring).

    Returns the entries added to ``asset.extras.baker.decompressed`` (empty when nothing was compressed)."""
    gltf = doc.json
    if not is_compressed(gltf):
        return []
    record = []
    views = _decode_meshopt(doc)  # extension name -> bufferViews
    for name in MESHOPT_EXTENSIONS:
        if views.get(name):
            record.append({"extension": name, "decoder": _version("meshopt"), "bufferViews": views[name]})
    prims, filled = _decode_draco(doc)
    if prims:
        record.append({"extension": DRACO, "decoder": _version("DracoPy"), "primitives": prims})
    # the load's finite check saw the compressed accessors' placeholders: check what the decoders made
    decoded_views = {v for found in views.values() for v in found}
    decoded = filled | {a for a, acc in enumerate(gltf.get("accessors") or [])
                        if acc.get("bufferView") in decoded_views}
    issues = Issues()
    check_finite_attributes(doc, issues, only=decoded,
                            decoded=f" (decoded from {' and '.join(r['extension'] for r in record)})")
    problem = first_error(issues)
    if problem:
        raise BakerError(doc.path, problem)
    for name in DECODED:
        _unuse(gltf, name)
    for buffer in gltf.get("buffers") or []:
        for name in MESHOPT_EXTENSIONS:
            _drop_extension(buffer, name)
    _compact(doc)
    if record:
        asset = gltf.setdefault("asset", {})
        extras = asset.setdefault("extras", {})
        if isinstance(extras, dict):
            baker = extras.setdefault("baker", {})
            if isinstance(baker, dict):
                baker.setdefault("decompressed", []).extend(record)
    return record


# ---------------------------------------------------------------------------------------------- meshopt
def _decode_meshopt(doc) -> dict[str, list[int]]:
    """Decode every meshopt-compressed bufferView; returns the decoded bufferViews by extension name."""
    decoded = {}
    for i, view in enumerate(doc.json.get("bufferViews") or []):
        name, ext = meshopt_extension(view)
        if ext is None:
            continue
        meshopt = _import(doc, "meshopt", name)
        ptr = pointer("bufferViews", i, "extensions", name)
        count, stride = int(ext.get("count", 0)), int(ext.get("byteStride", 0))
        mode, filt = ext.get("mode"), ext.get("filter", "NONE")
        start, length = int(ext.get("byteOffset", 0)), int(ext.get("byteLength", 0))
        if mode not in MESHOPT_MODES or filt not in MESHOPT_FILTERS or count <= 0 or stride <= 0:
            raise BakerError(doc.path, f"{ptr}: unsupported mode {mode!r}, filter {filt!r}, count {count} or "
                                       f"byteStride {stride}")
        if start + length > len(doc.bin):
            raise BakerError(doc.path, f"{ptr}: compressed data runs past the end of its buffer")
        try:
            out = meshopt.decode_gltf_buffer(bytes(doc.bin[start: start + length]), count, stride, mode,
                                             None if filt == "NONE" else filt)
        except (ValueError, RuntimeError) as exc:
            raise BakerError(doc.path, f"{ptr}: meshopt data does not decode: {exc}") from None
        data = np.ascontiguousarray(out).tobytes()
        view["byteOffset"] = _append(doc, data)
        view["byteLength"] = len(data)
        view["buffer"] = 0
        _drop_extension(view, name)
        decoded.setdefault(name, []).append(i)
    return decoded


# ---------------------------------------------------------------------------------------------- Draco
def _decode_draco(doc) -> tuple[list[str], set]:
    """Decode every Draco primitive; returns the decoded primitives' pointers and the accessors filled."""
    gltf = doc.json
    decoded, done = [], {}  # done: (bufferView, attribute ids) -> decoded mesh, for primitives sharing one
    reusable = set()  # compressed bufferViews whose slot the next decoded array may take
    filled = set()  # accessors already written (shared by two primitives)
    for m, mesh in enumerate(gltf.get("meshes") or []):
        for p, prim in enumerate(mesh.get("primitives") or []):
            ext = (prim.get("extensions") or {}).get(DRACO)
            if not isinstance(ext, dict):
                continue
            ptr = pointer("meshes", m, "primitives", p, "extensions", DRACO)
            attributes = prim.get("attributes") or {}
            if all("bufferView" in gltf["accessors"][a] for a in attributes.values()) and (
                    "indices" not in prim or "bufferView" in gltf["accessors"][prim["indices"]]):
                _drop_extension(prim, DRACO)  # uncompressed fallback data is there: use it
                continue
            draco = _import(doc, "DracoPy", DRACO)
            view = ext.get("bufferView")
            ids = ext.get("attributes") or {}
            key = (view, tuple(sorted(ids.items())))
            if key not in done:
                raw = _view_bytes(doc, view, ptr)
                try:
                    done[key] = draco.decode(raw)
                except Exception as exc:  # DracoPy raises its own and plain exception types
                    raise BakerError(doc.path, f"{ptr}: Draco data does not decode: {exc}") from None
                reusable.add(view)
            decoded_mesh = done[key]
            for semantic, unique_id in ids.items():
                if semantic not in attributes:
                    continue
                attr = decoded_mesh.get_attribute_by_unique_id(int(unique_id))
                if attr is None:
                    raise BakerError(doc.path, f"{ptr}/attributes/{semantic}: no Draco attribute {unique_id}")
                _fill_accessor(doc, attributes[semantic], np.asarray(attr["data"]), TARGET_ARRAY_BUFFER, reusable,
                               filled, f"{ptr}/attributes/{semantic}")
            faces = np.asarray(getattr(decoded_mesh, "faces", np.zeros((0, 3))), dtype=np.int64).reshape(-1)
            if "indices" in prim:
                _fill_accessor(doc, prim["indices"], faces, TARGET_ELEMENT_ARRAY_BUFFER, reusable, filled,
                               f"{ptr}/indices")
            elif len(faces):
                prim["indices"] = doc.add_accessor(faces.astype(np.uint32), target=TARGET_ELEMENT_ARRAY_BUFFER)
            _drop_extension(prim, DRACO)
            decoded.append(pointer("meshes", m, "primitives", p))
    return decoded, filled


def _fill_accessor(doc, index: int, values: np.ndarray, target: int, reusable: set, filled: set,
                   ptr: str) -> None:
    """Write ``values`` into accessor ``index`` (its componentType and type kept) as a tightly packed bufferView:
    the slot of a compressed one when one is free, else a new one."""
    if index in filled:
        return
    filled.add(index)
    acc = doc.json["accessors"][index]
    dtype = np.dtype(COMPONENT_DTYPES[acc["componentType"]])
    ncomp = TYPE_SIZES[acc["type"]]
    values = values.reshape(len(values), -1) if values.ndim > 1 else values.reshape(-1, 1)
    if values.shape[1] != ncomp:
        raise BakerError(doc.path, f"{ptr}: decoded {values.shape[1]} components, the accessor declares {ncomp}")
    if dtype.kind != "f" and values.dtype.kind == "f":
        if not acc.get("normalized"):
            raise BakerError(doc.path, f"{ptr}: decoded floats for an integer accessor that is not normalized")
        top = np.iinfo(dtype).max
        values = np.round(np.clip(values, -1.0 if dtype.kind == "i" else 0.0, 1.0) * top)
    if target == TARGET_ELEMENT_ARRAY_BUFFER and len(values) and values.max() > np.iinfo(dtype).max:
        dtype = np.dtype(np.uint32)
        acc["componentType"] = 5125
    values = values.astype(dtype.newbyteorder("<"))
    elem = dtype.itemsize * ncomp
    stride = None
    data = values.tobytes()
    if target == TARGET_ARRAY_BUFFER and elem % 4:
        stride = (elem + 3) // 4 * 4
        padded = np.zeros((len(values), stride), np.uint8)
        padded[:, :elem] = np.frombuffer(data, np.uint8).reshape(len(values), elem)
        data = padded.tobytes()
    offset = _append(doc, data)
    view = {"buffer": 0, "byteOffset": offset, "byteLength": len(data)}
    if stride:
        view["byteStride"] = stride
    view["target"] = target
    views = doc.json.setdefault("bufferViews", [])
    slot = min(reusable) if reusable else None
    if slot is not None:
        reusable.discard(slot)
        old = views[slot]
        keep = {k: v for k, v in old.items() if k in ("name", "extras", "extensions")}
        views[slot] = {**view, **keep}
        acc["bufferView"] = slot
    else:
        views.append(view)
        acc["bufferView"] = len(views) - 1
    acc.pop("byteOffset", None)
    acc["count"] = int(len(values))
    if "min" in acc or "max" in acc or target == TARGET_ARRAY_BUFFER and ptr.endswith("/POSITION"):
        cast = float if dtype.kind == "f" else int
        acc["min"] = [cast(v) for v in values.min(axis=0)] if len(values) else acc.get("min", [])
        acc["max"] = [cast(v) for v in values.max(axis=0)] if len(values) else acc.get("max", [])


# ---------------------------------------------------------------------------------------------- helpers
def _import(doc, module: str, extension: str):
    try:
        return __import__(module)
    except ImportError:
        raise BakerError(doc.path, f"{extension} geometry needs the Python package '{module}' to decode it: "
                                   f"pip install {module} (a dependency of baker)") from None


def _version(module: str) -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return f"{module} {version(module)}"
    except PackageNotFoundError:
        return module


def _view_bytes(doc, index, ptr: str) -> bytes:
    views = doc.json.get("bufferViews") or []
    if not isinstance(index, int) or not 0 <= index < len(views):
        raise BakerError(doc.path, f"{ptr}/bufferView: no bufferView {index!r}")
    view = views[index]
    start = int(view.get("byteOffset", 0))
    end = start + int(view.get("byteLength", 0))
    if end > len(doc.bin):
        raise BakerError(doc.path, f"{ptr}/bufferView: bufferView {index} runs past the end of its buffer")
    return bytes(doc.bin[start:end])


def _append(doc, data: bytes) -> int:
    doc.bin.extend(b"\0" * (-len(doc.bin) % 16))
    offset = len(doc.bin)
    doc.bin.extend(data)
    return offset


def _drop_extension(obj: dict, name: str) -> None:
    exts = obj.get("extensions")
    if isinstance(exts, dict) and name in exts:
        del exts[name]
        if not exts:
            del obj["extensions"]


def _unuse(gltf: dict, name: str) -> None:
    for key in ("extensionsUsed", "extensionsRequired"):
        names = gltf.get(key)
        if isinstance(names, list) and name in names:
            names.remove(name)
            if not names:
                del gltf[key]


def _compact(doc) -> None:
    """Drop the bytes of ``doc.bin`` no bufferView covers; each kept run keeps its offset modulo 16 (so every
    accessor stays aligned). Only bufferViews point into the merged buffer once nothing is compressed."""
    views = doc.json.get("bufferViews") or []
    spans = sorted((int(v.get("byteOffset", 0)), int(v.get("byteOffset", 0)) + int(v.get("byteLength", 0)))
                   for v in views)
    runs: list[list[int]] = []
    for start, end in spans:
        if runs and start <= runs[-1][1]:
            runs[-1][1] = max(runs[-1][1], end)
        else:
            runs.append([start, end])
    out = bytearray()
    moves = []  # (old start, old end, new start)
    for start, end in runs:
        new = len(out) + (start % 16 - len(out) % 16) % 16
        out.extend(b"\0" * (new - len(out)))
        out.extend(doc.bin[start:end])
        moves.append((start, end, new))
    for view in views:
        off = int(view.get("byteOffset", 0))
        for start, end, new in moves:
            if start <= off <= end:
                view["byteOffset"] = off - start + new
                break
    doc.bin = out
