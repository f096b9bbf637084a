"""The structure of a glTF document, checked before any data is read: GLB container, JSON types of every object baker
reads, references between objects, buffer sizes, byte ranges of bufferViews and accessors, the formats of the vertex
attributes baker decodes, and the external resources (URIs) it may open. Only what baker must trust before it reads a
byte; the full core-spec check is Khronos glTF-Validator's job.

One implementation for every command: :meth:`baker.gltf.document.GltfDocument.load` (bake, inspect, preview, build)
raises the first error as ``BakerError(path, "<JSON pointer>: <problem>")``, and ``baker validate``
(:mod:`baker.validate`) reports every one of them.

URI policy: a buffer or image URI is either a ``data:`` URI (decoded, its length checked against ``byteLength``) or a
relative path, percent-decoded, that stays inside the folder of the file naming it (or inside an ``allow_outside``
root). Absolute paths, ``..`` leaving the folder, symbolic links out of it, ``file:``, ``http(s):`` and every other
scheme are refused before anything is opened.
"""
from __future__ import annotations

import base64
import json
import math
import os
import re
import struct
import urllib.parse
from pathlib import Path

import numpy as np

from baker.checks import Issues, is_count, is_index, pointer
from baker.errors import BakerError

GLB_MAGIC = 0x46546C67  # b"glTF"
CHUNK_JSON = 0x4E4F534A
CHUNK_BIN = 0x004E4942

COMPONENT_DTYPES = {
    5120: np.int8,
    5121: np.uint8,
    5122: np.int16,
    5123: np.uint16,
    5125: np.uint32,
    5126: np.float32,
}
TYPE_SIZES = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
TRIANGLE_MODES = (4, 5, 6)
FLOAT = 5126

# structural errors after which accessor data can still be read safely (validate reads on; a bake does not)
NON_BLOCKING = {"MESH_PRIMITIVE_UNEQUAL_ACCESSOR_COUNT"}

# where an object sits in the document -> its kind, as in Khronos' extension schema file names
COLLECTION_KINDS = {
    "accessors": "accessor", "animations": "animation", "buffers": "buffer", "bufferViews": "bufferView",
    "cameras": "camera", "images": "image", "materials": "material", "meshes": "mesh", "nodes": "node",
    "samplers": "sampler", "scenes": "scene", "skins": "skin", "textures": "texture",
}

# vertex attributes baker decodes: accepted (type, componentTypes, normalized-only componentTypes)
# (float, or the integer forms KHR_mesh_quantization allows)
ATTRIBUTE_FORMATS = {
    "POSITION": (("VEC3",), {5126, 5120, 5121, 5122, 5123}),
    "NORMAL": (("VEC3",), {5126, 5120, 5122}),
    "TEXCOORD": (("VEC2",), {5126, 5120, 5121, 5122, 5123}),
    "COLOR": (("VEC3", "VEC4"), {5126, 5121, 5123}),
}
INDEX_COMPONENTS = (5121, 5123, 5125)
# bufferView compression: the ratified KHR_meshopt_compression keeps EXT_meshopt_compression's JSON (and adds the
# vertex codec's version 1 and the COLOR filter to what the data may hold)
MESHOPT_EXTENSIONS = ("EXT_meshopt_compression", "KHR_meshopt_compression")
# float attributes a bake reads: NaN or infinity there is an error
FINITE_ATTRIBUTES = ("POSITION", "NORMAL", "TEXCOORD")

_SCHEME = re.compile(r"^[A-Za-z][A-Za-z0-9+.\-]*:")
_DRIVE = re.compile(r"^[A-Za-z]:")


def align(n: int, a: int = 4) -> int:
    return (n + a - 1) // a * a


def attribute_semantic(name: str) -> str:
    """``TEXCOORD_1`` -> ``TEXCOORD``, ``COLOR_0`` -> ``COLOR``; other names as they are."""
    for prefix in ("TEXCOORD_", "COLOR_", "JOINTS_", "WEIGHTS_"):
        if name.startswith(prefix):
            return prefix[:-1]
    return name


def extension(obj, name: str):
    """``obj["extensions"][name]`` when both are objects, else None."""
    exts = obj.get("extensions") if isinstance(obj, dict) else None
    value = exts.get(name) if isinstance(exts, dict) else None
    return value if isinstance(value, dict) else None


def meshopt_extension(view) -> tuple[str, dict] | tuple[None, None]:
    """The meshopt extension of a bufferView as (name, object), or (None, None) when it has none."""
    for name in MESHOPT_EXTENSIONS:
        ext = extension(view, name)
        if isinstance(ext, dict):
            return name, ext
    return None, None


def one_of(value, allowed) -> bool:
    """``value in allowed`` for JSON values (a list or an object is never in it; true/false are not 1/0)."""
    return isinstance(value, (int, str)) and not isinstance(value, bool) and value in allowed


def json_type(value) -> str:
    """The JSON name of a Python value's type, for messages."""
    if isinstance(value, bool):
        return "boolean"
    if isinstance(value, int):
        return "integer"
    if isinstance(value, float):
        return "number"
    return {dict: "object", list: "array", str: "string", type(None): "null"}.get(type(value), type(value).__name__)


def first_error(issues: Issues) -> str | None:
    """The first error of ``issues`` as ``"<pointer>: <message>"`` (or the message alone), or None."""
    for m in issues.messages:
        if m["severity"] == 0:
            return f"{m['pointer']}: {m['message']}" if m.get("pointer") else m["message"]
    return None


# ---------------------------------------------------------------------------------------------------- container
def parse_glb(path: Path, data: bytes) -> tuple[dict, bytes | None]:
    """The JSON and BIN chunks of a GLB; magic, version, total length and every chunk length are checked against the
    real size of ``data``."""
    if len(data) < 20:
        raise BakerError(path, f"truncated GLB ({len(data)} bytes)")
    magic, version, length = struct.unpack_from("<III", data, 0)
    if magic != GLB_MAGIC:
        raise BakerError(path, "not a GLB file (bad magic)")
    if version != 2:
        raise BakerError(path, f"unsupported GLB container version {version}")
    if length > len(data):
        raise BakerError(path, f"truncated GLB: header says {length} bytes, file has {len(data)}")
    offset = 12
    gltf = None
    bin_chunk = None
    first = True
    while offset < length:
        if offset + 8 > length:
            raise BakerError(path, f"truncated GLB: a chunk header at byte {offset} runs past the end of the file")
        chunk_len, chunk_type = struct.unpack_from("<II", data, offset)
        offset += 8
        if offset + chunk_len > length:
            raise BakerError(path, f"truncated GLB: a chunk of {chunk_len} bytes at byte {offset - 8} runs past the "
                                   f"end of the file ({length} bytes)")
        if first and chunk_type != CHUNK_JSON:
            raise BakerError(path, "GLB: the first chunk is not the JSON chunk")
        first = False
        chunk = data[offset: offset + chunk_len]
        if chunk_type == CHUNK_JSON and gltf is None:
            try:
                gltf = json.loads(chunk.decode("utf-8"))
            except (UnicodeDecodeError, json.JSONDecodeError, RecursionError) as exc:
                raise BakerError(path, f"broken JSON chunk: {exc}") from None
        elif chunk_type == CHUNK_BIN and bin_chunk is None:
            bin_chunk = chunk
        offset += align(chunk_len)
    if gltf is None:
        raise BakerError(path, "GLB has no JSON chunk")
    return gltf, bin_chunk


def read_container(path: Path, issues: Issues) -> tuple[dict | None, bytes | None, str]:
    """The JSON and binary chunk of a .gltf/.glb (GLB header and chunk lengths checked against the file) and its
    mime type, integer-valued floats in index and count properties made integers (:func:`normalise_integers`);
    (None, None, mime) with an error in ``issues`` when the container cannot be read."""
    data = path.read_bytes()
    is_glb = path.suffix.lower() == ".glb" or data[:4] == b"glTF"
    mime = "model/gltf-binary" if is_glb else "model/gltf+json"
    try:
        if is_glb:
            gltf, glb_bin = parse_glb(path, data)
        else:
            text = data.decode("utf-8")
            gltf, glb_bin = json.loads(text[1:] if text.startswith("\ufeff") else text), None
    except BakerError as exc:
        issues.error("INVALID_GLB", exc.message)
        return None, None, mime
    except json.JSONDecodeError as exc:
        where = f"line {exc.lineno} column {exc.colno} (char {exc.pos})"
        if not exc.doc[exc.pos:].strip():  # nothing but white space after the place the parser stopped
            issues.error("INVALID_JSON", f"truncated JSON: the file ends at {where} inside the document ({exc.msg})")
        else:
            issues.error("INVALID_JSON", f"broken JSON at {where}: {exc.msg}")
        return None, None, mime
    except (UnicodeDecodeError, RecursionError) as exc:
        issues.error("INVALID_JSON", f"broken JSON: {exc}")
        return None, None, mime
    if not isinstance(gltf, dict):
        issues.error("TYPE_MISMATCH", f"the document must be a JSON object, not {json_type(gltf)}", "")
        return None, None, mime
    if not isinstance(gltf.get("asset"), dict):
        issues.error("UNSUPPORTED_VERSION", "not a glTF document (no 'asset' object)", "/asset")
        return None, None, mime
    version = gltf["asset"].get("version")
    if not isinstance(version, str) or not version.startswith("2."):
        issues.error("UNSUPPORTED_VERSION", f"unsupported glTF version {version!r} (baker reads glTF 2.x)",
                     "/asset/version")
        return None, None, mime
    if is_glb and struct.unpack_from("<I", data, 8)[0] < len(data):
        issues.warning("GLB_EXTRA_DATA", f"{len(data) - struct.unpack_from('<I', data, 8)[0]} bytes after the "
                       "length the GLB header gives are ignored")
    normalise_integers(gltf)
    return gltf, glb_bin, mime


# ---------------------------------------------------------------------------------------------------- integers
def _int(value):
    if isinstance(value, float) and value.is_integer():
        return int(value)
    return value


def _fix(obj, *keys) -> None:
    if isinstance(obj, dict):
        for key in keys:
            if key in obj:
                obj[key] = _int(obj[key])


def _fix_values(obj, key=None) -> None:
    """Every value of a dict (or of ``obj[key]``, a list or a dict) made an int where it is an integral float."""
    target = obj.get(key) if key is not None and isinstance(obj, dict) else obj
    if isinstance(target, list):
        target[:] = [_int(v) for v in target]
    elif isinstance(target, dict):
        for k in list(target):
            target[k] = _int(target[k])


def _dicts(gltf: dict, name: str):
    value = gltf.get(name)
    return [v for v in value if isinstance(v, dict)] if isinstance(value, list) else []


def texture_infos(material: dict, parts: tuple):
    """Yield (path parts, textureInfo) for every ``*Texture`` object in a material, extensions included."""
    for key, value in material.items():
        if key == "extras":
            continue
        if isinstance(value, dict):
            if key.endswith("Texture") and "index" in value:
                yield parts + (key,), value
            else:
                yield from texture_infos(value, parts + (key,))


def normalise_integers(gltf: dict) -> None:
    """JSON numbers such as ``3.0`` where glTF expects an integer (indices, counts, offsets, enums) become ints, in
    place: they are valid JSON and common in files written by JavaScript tools. Other floats stay as they are."""
    _fix(gltf, "scene")
    for acc in _dicts(gltf, "accessors"):
        _fix(acc, "bufferView", "byteOffset", "componentType", "count")
        sparse = acc.get("sparse")
        if isinstance(sparse, dict):
            _fix(sparse, "count")
            _fix(sparse.get("indices"), "bufferView", "byteOffset", "componentType")
            _fix(sparse.get("values"), "bufferView", "byteOffset")
    for buf in _dicts(gltf, "buffers"):
        _fix(buf, "byteLength")
    for view in _dicts(gltf, "bufferViews"):
        _fix(view, "buffer", "byteOffset", "byteLength", "byteStride", "target")
        exts = view.get("extensions")
        if isinstance(exts, dict):
            for name in MESHOPT_EXTENSIONS:
                _fix(exts.get(name), "buffer", "byteOffset", "byteLength", "byteStride", "count")
    for image in _dicts(gltf, "images"):
        _fix(image, "bufferView")
    for mesh in _dicts(gltf, "meshes"):
        for prim in mesh.get("primitives") if isinstance(mesh.get("primitives"), list) else []:
            if not isinstance(prim, dict):
                continue
            _fix(prim, "indices", "material", "mode")
            _fix_values(prim, "attributes")
            for target in prim.get("targets") if isinstance(prim.get("targets"), list) else []:
                _fix_values(target)
            exts = prim.get("extensions")
            if isinstance(exts, dict) and isinstance(exts.get("KHR_draco_mesh_compression"), dict):
                _fix(exts["KHR_draco_mesh_compression"], "bufferView")
                _fix_values(exts["KHR_draco_mesh_compression"], "attributes")
    for node in _dicts(gltf, "nodes"):
        _fix(node, "camera", "mesh", "skin")
        _fix_values(node, "children")
    for scene in _dicts(gltf, "scenes"):
        _fix_values(scene, "nodes")
    for skin in _dicts(gltf, "skins"):
        _fix(skin, "inverseBindMatrices", "skeleton")
        _fix_values(skin, "joints")
    for tex in _dicts(gltf, "textures"):
        _fix(tex, "sampler", "source")
        if isinstance(tex.get("extensions"), dict):
            for ext in tex["extensions"].values():
                _fix(ext, "source")
    for sampler in _dicts(gltf, "samplers"):
        _fix(sampler, "magFilter", "minFilter", "wrapS", "wrapT")
    for m, material in enumerate(gltf.get("materials") if isinstance(gltf.get("materials"), list) else []):
        if isinstance(material, dict):
            for _, info in texture_infos(material, ("materials", m)):
                _fix(info, "index", "texCoord")
                exts = info.get("extensions")
                if isinstance(exts, dict):
                    _fix(exts.get("KHR_texture_transform"), "texCoord")
    for anim in _dicts(gltf, "animations"):
        for channel in anim.get("channels") if isinstance(anim.get("channels"), list) else []:
            if isinstance(channel, dict):
                _fix(channel, "sampler")
                _fix(channel.get("target"), "node")
        for sampler in anim.get("samplers") if isinstance(anim.get("samplers"), list) else []:
            _fix(sampler, "input", "output")


# ---------------------------------------------------------------------------------------------------- URIs
def uri_roots(base: Path, allow_outside=None) -> list[Path]:
    """The folders a URI may resolve into: ``base`` (the folder of the file naming it) and every ``allow_outside``
    path (one path or a list)."""
    extra = [] if allow_outside is None else \
        list(allow_outside) if isinstance(allow_outside, (list, tuple, set, frozenset)) else [allow_outside]
    return [Path(base)] + [Path(p) for p in extra]


def _inside(path: str, root: str) -> bool:
    return path == root or path.startswith(root.rstrip(os.sep) + os.sep)


def decode_data_uri(uri: str) -> tuple[bytes, str | None]:
    """The bytes and mime type of a ``data:`` URI; ValueError when it is malformed."""
    header, sep, payload = uri.partition(",")
    if not sep:
        raise ValueError("a data: URI needs a ',' before its payload")
    mime = header[5:].split(";")[0] or None
    if header.lower().endswith(";base64"):
        return base64.b64decode(payload, validate=True), mime
    return urllib.parse.unquote_to_bytes(payload), mime


def local_file(uri: str, base: Path, allow_outside=None) -> Path:
    """The file a relative URI names under ``base`` (the folder of the file naming it) or an ``allow_outside`` root.
    Raises ValueError saying why the URI is refused; nothing is opened (only symbolic links are followed, to check
    where they lead)."""
    scheme = _SCHEME.match(uri)
    if scheme and not _DRIVE.match(uri):
        name = scheme.group(0)[:-1].lower()
        raise ValueError(f"URI {uri!r}: the '{name}:' scheme is refused (baker reads only data: URIs and relative "
                         "paths inside the asset's folder)")
    decoded = urllib.parse.unquote(uri).replace("\\", "/")
    if "\0" in decoded:
        raise ValueError(f"URI {uri!r} holds a NUL character")
    if decoded.startswith("/") or _DRIVE.match(decoded):
        raise ValueError(f"URI {uri!r} is an absolute path (refused: only relative paths inside the asset's folder "
                         "are read; --allow-outside PATH widens it)")
    target = os.path.normpath(os.path.join(os.path.abspath(base), decoded))
    for root in uri_roots(base, allow_outside):
        lexical = os.path.normpath(os.path.abspath(root))
        if _inside(target, lexical) and _inside(os.path.realpath(target), os.path.realpath(lexical)):
            return Path(target)
    raise ValueError(f"URI {uri!r} leaves the asset's folder (refused; --allow-outside PATH widens it)")


# ---------------------------------------------------------------------------------------------------- the check
class _Checker:
    """One walk over the JSON, reporting into ``issues``; the methods run in the order of :func:`check_structure`."""

    def __init__(self, gltf: dict, path: Path, issues: Issues, allow_outside=None, glb: bool = False):
        self.gltf, self.path, self.issues, self.allow_outside, self.glb = gltf, path, issues, allow_outside, glb

    # ------------------------------------------------------------------ helpers
    def error(self, code, message, ptr):
        self.issues.error(code, message, ptr)

    def collection(self, name) -> list:
        value = self.gltf.get(name)
        return value if isinstance(value, list) else []

    def items(self, name):
        for i, obj in enumerate(self.collection(name)):
            if isinstance(obj, dict):
                yield i, obj

    def ref(self, value, collection, ptr, what=None) -> bool:
        """``value`` is an index into the top-level array ``collection`` (or into the list ``collection``)."""
        items = self.collection(collection) if isinstance(collection, str) else collection
        what = what or (COLLECTION_KINDS.get(collection, collection) if isinstance(collection, str) else "item")
        if not isinstance(value, int) or isinstance(value, bool):
            self.error("TYPE_MISMATCH", f"must be an integer index ({what}), not {json_type(value)} {value!r}", ptr)
            return False
        if not is_index(value, items):
            self.error("UNRESOLVED_REFERENCE", f"{what} {value} does not exist ({len(items)} in the document)", ptr)
            return False
        if not isinstance(items[value], dict):
            return False  # reported where it sits
        return True

    def obj(self, value, ptr, what) -> bool:
        if not isinstance(value, dict):
            self.error("TYPE_MISMATCH", f"{what} must be an object, not {json_type(value)}", ptr)
            return False
        return True

    def array(self, value, ptr, what, minimum=0) -> bool:
        if not isinstance(value, list):
            self.error("TYPE_MISMATCH", f"{what} must be an array, not {json_type(value)}", ptr)
            return False
        if len(value) < minimum:
            self.error("EMPTY_ENTITY", f"{what} must not be empty", ptr)
            return False
        return True

    def integer(self, obj, key, ptr, minimum=0, default=None):
        """``obj[key]`` as an int >= minimum (``default`` when absent), or None with an error."""
        value = obj.get(key, default)
        if value is None and default is None and key not in obj:
            return None
        if not is_count(value, minimum):
            if not isinstance(value, int) or isinstance(value, bool):
                self.error("TYPE_MISMATCH", f"{key} must be an integer, not {json_type(value)} {value!r}",
                           f"{ptr}/{key}")
            else:
                self.error("VALUE_NOT_IN_RANGE", f"{key} must be >= {minimum}, got {value}", f"{ptr}/{key}")
            return None
        return value

    def numbers(self, obj, key, ptr, length) -> None:
        if key not in obj:
            return
        value = obj[key]
        if not isinstance(value, list) or len(value) != length or not all(
                isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in value):
            self.error("TYPE_MISMATCH", f"{key} must be an array of {length} finite numbers", f"{ptr}/{key}")

    def of_type(self, obj, key, types, ptr, what) -> None:
        if key not in obj:
            return
        value = obj[key]
        types = types if isinstance(types, tuple) else (types,)
        if not isinstance(value, types) or (isinstance(value, bool) and bool not in types):
            self.error("TYPE_MISMATCH", f"{key} must be {what}, not {json_type(obj[key])}", f"{ptr}/{key}")

    # ------------------------------------------------------------------ root
    def root(self) -> None:
        for name, kind in COLLECTION_KINDS.items():
            if name not in self.gltf:
                continue
            value = self.gltf[name]
            if not isinstance(value, list):
                self.error("TYPE_MISMATCH", f"{name} must be an array, not {json_type(value)}", pointer(name))
                continue
            for i, obj in enumerate(value):
                if not isinstance(obj, dict):
                    self.error("TYPE_MISMATCH", f"{kind} must be an object, not {json_type(obj)}", pointer(name, i))
        if "scene" in self.gltf:
            self.ref(self.gltf["scene"], "scenes", "/scene")
        for key in ("extensionsUsed", "extensionsRequired"):
            if key in self.gltf:
                value = self.gltf[key]
                if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
                    self.error("TYPE_MISMATCH", f"{key} must be an array of strings", pointer(key))
        self.extension_objects(self.gltf, ())

    def extension_objects(self, node, parts) -> None:
        """Every ``extensions`` property is an object of objects (code reads ``obj["extensions"].get(name)``)."""
        if isinstance(node, dict):
            exts = node.get("extensions")
            if "extensions" in node:
                ptr = pointer(*parts, "extensions")
                if not isinstance(exts, dict):
                    self.error("TYPE_MISMATCH", f"extensions must be an object, not {json_type(exts)}", ptr)
                else:
                    for name, value in exts.items():
                        if not isinstance(value, dict):
                            self.error("TYPE_MISMATCH", f"extension '{name}' must be an object, not "
                                                        f"{json_type(value)}", pointer(*parts, "extensions", name))
            for key, value in node.items():
                if key != "extras" and isinstance(value, (dict, list)):
                    self.extension_objects(value, parts + (key,))
        elif isinstance(node, list):
            for i, value in enumerate(node):
                if isinstance(value, (dict, list)):
                    self.extension_objects(value, parts + (i,))

    # ------------------------------------------------------------------ buffers
    def buffers(self, glb_bin: bytes | None) -> tuple[list, dict]:
        """Per buffer: the bytes available (its declared byteLength when it holds no data); and {buffer: why it
        holds no data} for the buffers without data."""
        sizes, empty = [], {}
        for i, buf in enumerate(self.collection("buffers")):
            ptr = pointer("buffers", i)
            if not isinstance(buf, dict):
                sizes.append(0)
                continue
            declared = buf.get("byteLength")
            if not is_count(declared, 1):
                self.error("BUFFER_BYTE_LENGTH" if not isinstance(declared, int) or isinstance(declared, bool)
                           else "VALUE_NOT_IN_RANGE",
                           f"byteLength must be an integer >= 1, got {declared!r}", ptr + "/byteLength")
                declared = None
            uri = buf.get("uri")
            if uri is None:
                if i == 0 and glb_bin is not None:
                    available = len(glb_bin)
                else:
                    empty[i] = "has no uri" + (" and the GLB has no BIN chunk" if i == 0 and self.glb else "")
                    sizes.append(declared)
                    continue
            elif not isinstance(uri, str):
                self.error("TYPE_MISMATCH", f"uri must be a string, not {json_type(uri)}", ptr + "/uri")
                available = 0
            else:
                available = self.uri_size(uri, ptr + "/uri", "buffer")
                if available is None:
                    sizes.append(None)
                    continue
            if declared is not None and available < declared:
                self.error("BUFFER_BYTE_LENGTH_MISMATCH",
                           f"byteLength is {declared} but only {available} bytes are available", ptr)
            sizes.append(min(available, declared) if declared is not None else available)
        return sizes, empty

    def uri_size(self, uri: str, ptr: str, what: str) -> int | None:
        """Bytes behind a URI (checked by the URI policy), or None with an error when it cannot be read."""
        if uri[:5].lower() == "data:":
            try:
                return len(decode_data_uri(uri)[0])
            except ValueError as exc:
                self.error("INVALID_URI", f"broken data URI: {exc}", ptr)
                return None
        try:
            target = local_file(uri, self.path.parent, self.allow_outside)
        except ValueError as exc:
            self.error("URI_REFUSED", str(exc), ptr)
            return None
        try:
            if not target.is_file():
                self.error("IO_ERROR", f"{what} file '{uri}' not found", ptr)
                return None
            return target.stat().st_size
        except OSError as exc:
            self.error("IO_ERROR", f"{what} file '{uri}' cannot be read: {exc.strerror or exc}", ptr)
            return None

    def buffer_views(self, sizes: list) -> list:
        """Checks every bufferView; returns per view (byteLength, byteStride or 0), None for a broken view."""
        ranges = []
        buffers = self.collection("buffers")
        for i, view in enumerate(self.collection("bufferViews")):
            ptr = pointer("bufferViews", i)
            ranges.append(None)
            if not isinstance(view, dict):
                continue
            b = view.get("buffer")
            if not self.ref(b, buffers, ptr + "/buffer", "buffer"):
                continue
            offset, length = view.get("byteOffset", 0), view.get("byteLength")
            if not is_count(offset) or not is_count(length, 1):
                self.error("BUFFER_VIEW_RANGE", f"byteOffset {offset!r} / byteLength {length!r} must be integers "
                           "(>= 0 and >= 1)", ptr)
                continue
            stride = view.get("byteStride")
            if stride is not None and not (is_count(stride, 4) and stride <= 252 and stride % 4 == 0):
                self.error("BUFFER_VIEW_INVALID_BYTE_STRIDE", f"byteStride {stride!r} must be a multiple of 4 in "
                           "4..252", ptr + "/byteStride")
                continue
            if b < len(sizes) and sizes[b] is not None and offset + length > sizes[b]:
                self.error("BUFFER_VIEW_TOO_LONG", f"bytes {offset}..{offset + length} run past the end of buffer "
                           f"{b} ({sizes[b]} bytes)", ptr)
                continue
            name, meshopt = meshopt_extension(view)
            if sum(isinstance(extension(view, n), dict) for n in MESHOPT_EXTENSIONS) > 1:
                self.error("BUFFER_VIEW_MESHOPT_TWICE", "a bufferView may use only one of "
                           f"{' and '.join(MESHOPT_EXTENSIONS)}", ptr + "/extensions")
                continue
            if isinstance(meshopt, dict):
                mp = ptr + "/extensions/" + name
                mb = meshopt.get("buffer")
                if not self.ref(mb, buffers, mp + "/buffer", "buffer"):
                    continue
                mo, ml = meshopt.get("byteOffset", 0), meshopt.get("byteLength")
                if not is_count(mo) or not is_count(ml, 1):
                    self.error("BUFFER_VIEW_RANGE", f"byteOffset {mo!r} / byteLength {ml!r} must be integers", mp)
                    continue
                if mb < len(sizes) and sizes[mb] is not None and mo + ml > sizes[mb]:
                    self.error("BUFFER_VIEW_TOO_LONG", f"bytes {mo}..{mo + ml} run past the end of buffer {mb}", mp)
                    continue
            ranges[i] = (length, stride or 0)
        return ranges

    # ------------------------------------------------------------------ accessors
    def accessors(self, ranges: list) -> None:
        for i, acc in enumerate(self.collection("accessors")):
            ptr = pointer("accessors", i)
            if not isinstance(acc, dict):
                continue
            ctype, atype, count = acc.get("componentType"), acc.get("type"), acc.get("count")
            ok = True
            if not one_of(ctype, COMPONENT_DTYPES):
                self.error("VALUE_NOT_IN_LIST", f"componentType {ctype!r} is not one of "
                           f"{', '.join(map(str, COMPONENT_DTYPES))}", ptr + "/componentType")
                ok = False
            if not one_of(atype, TYPE_SIZES):
                # a warning, as in Khronos' validator (a later glTF may add types); an error where baker reads it
                report = self.issues.warning if isinstance(atype, str) else self.issues.error
                report("VALUE_NOT_IN_LIST", f"type {atype!r} is not one of {', '.join(TYPE_SIZES)}", ptr + "/type")
                ok = False
            if not is_count(count, 1):
                self.error("VALUE_NOT_IN_RANGE", f"count must be an integer >= 1, got {count!r}", ptr + "/count")
                ok = False
            if "normalized" in acc and not isinstance(acc["normalized"], bool):
                self.error("TYPE_MISMATCH", f"normalized must be a boolean, not {json_type(acc['normalized'])}",
                           ptr + "/normalized")
            if not ok:
                continue
            elem = np.dtype(COMPONENT_DTYPES[ctype]).itemsize * TYPE_SIZES[atype]
            if "bufferView" in acc:
                v = acc["bufferView"]
                offset = acc.get("byteOffset", 0)
                if not self.ref(v, "bufferViews", ptr + "/bufferView") or ranges[v] is None:
                    pass
                elif not is_count(offset):
                    self.error("VALUE_NOT_IN_RANGE", f"byteOffset must be an integer >= 0, got {offset!r}",
                               ptr + "/byteOffset")
                else:
                    length, stride = ranges[v]
                    if stride and stride < elem:
                        self.error("ACCESSOR_BYTE_STRIDE", f"bufferView {v} has byteStride {stride}, less than "
                                   f"one {atype} element ({elem} bytes)", ptr)
                        continue
                    stride = stride or elem
                    end = offset + stride * (count - 1) + elem
                    if end > length:
                        self.error("ACCESSOR_OUT_OF_BOUNDS", f"{count} x {atype} "
                                   f"{np.dtype(COMPONENT_DTYPES[ctype])} (stride {stride}) from byteOffset {offset} "
                                   f"need {end} bytes; bufferView {v} has {length}", ptr)
            elif "byteOffset" in acc:
                self.error("ACCESSOR_BYTE_OFFSET_WITHOUT_BUFFER_VIEW", "byteOffset is set but bufferView is not",
                           ptr + "/byteOffset")
            if "sparse" in acc:
                self.sparse(acc["sparse"], acc, ranges, elem, ptr + "/sparse")

    def sparse(self, sparse, acc, ranges, elem, ptr) -> None:
        if not self.obj(sparse, ptr, "sparse"):
            return
        n = sparse.get("count")
        if not is_count(n, 1) or n > acc["count"]:
            self.error("VALUE_NOT_IN_RANGE", f"sparse count {n!r} must be an integer in 1..{acc['count']}",
                       ptr + "/count")
            return
        for key in ("indices", "values"):
            part, sub = sparse.get(key), f"{ptr}/{key}"
            if not self.obj(part, sub, f"sparse.{key}"):
                continue
            size = elem
            if key == "indices":
                if part.get("componentType") not in INDEX_COMPONENTS or isinstance(part.get("componentType"), bool):
                    self.error("VALUE_NOT_IN_LIST", "sparse index componentType must be 5121, 5123 or 5125",
                               sub + "/componentType")
                    continue
                size = np.dtype(COMPONENT_DTYPES[part["componentType"]]).itemsize
            v, offset = part.get("bufferView"), part.get("byteOffset", 0)
            if not self.ref(v, "bufferViews", sub + "/bufferView") or ranges[v] is None:
                continue
            if not is_count(offset):
                self.error("VALUE_NOT_IN_RANGE", f"byteOffset must be an integer >= 0, got {offset!r}",
                           sub + "/byteOffset")
            elif offset + size * n > ranges[v][0]:
                self.error("ACCESSOR_OUT_OF_BOUNDS", f"sparse {key} need {offset + size * n} bytes; bufferView {v} "
                           f"has {ranges[v][0]}", sub)

    # ------------------------------------------------------------------ images, textures, samplers, materials
    def images(self) -> None:
        for i, image in self.items("images"):
            ptr = pointer("images", i)
            has_uri, has_view = "uri" in image, "bufferView" in image
            if has_uri and has_view:
                self.error("IMAGE_URI_AND_BUFFER_VIEW", "an image has a uri or a bufferView, not both", ptr)
            elif not has_uri and not has_view:
                self.error("IMAGE_DATA_MISSING", "an image needs a uri or a bufferView", ptr)
            if "mimeType" in image and not isinstance(image["mimeType"], str):
                self.error("TYPE_MISMATCH", f"mimeType must be a string, not {json_type(image['mimeType'])}",
                           ptr + "/mimeType")
            if has_view:
                self.ref(image["bufferView"], "bufferViews", ptr + "/bufferView")
            if has_uri:
                if not isinstance(image["uri"], str):
                    self.error("TYPE_MISMATCH", f"uri must be a string, not {json_type(image['uri'])}", ptr + "/uri")
                else:
                    self.uri_size(image["uri"], ptr + "/uri", "image")

    def textures(self) -> None:
        for t, tex in self.items("textures"):
            ptr = pointer("textures", t)
            if "source" in tex:
                self.ref(tex["source"], "images", ptr + "/source")
            if "sampler" in tex:
                self.ref(tex["sampler"], "samplers", ptr + "/sampler")
            for name, ext in (tex["extensions"].items() if isinstance(tex.get("extensions"), dict) else ()):
                if isinstance(ext, dict) and "source" in ext:
                    self.ref(ext["source"], "images", f"{ptr}/extensions/{name}/source")
        for s, sampler in self.items("samplers"):
            for key in ("magFilter", "minFilter", "wrapS", "wrapT"):
                if key in sampler:
                    self.integer(sampler, key, pointer("samplers", s))

    def materials(self) -> None:
        for m, material in self.items("materials"):
            ptr = pointer("materials", m)
            for key in ("pbrMetallicRoughness", "normalTexture", "occlusionTexture", "emissiveTexture"):
                if key in material:
                    self.obj(material[key], f"{ptr}/{key}", key)
            pbr = material.get("pbrMetallicRoughness")
            if isinstance(pbr, dict):
                self.numbers(pbr, "baseColorFactor", ptr + "/pbrMetallicRoughness", 4)
                for key in ("metallicFactor", "roughnessFactor"):
                    self.of_type(pbr, key, (int, float), ptr + "/pbrMetallicRoughness", "a number")
                if "baseColorTexture" in pbr:
                    self.obj(pbr["baseColorTexture"], ptr + "/pbrMetallicRoughness/baseColorTexture",
                             "baseColorTexture")
                if "metallicRoughnessTexture" in pbr:
                    self.obj(pbr["metallicRoughnessTexture"], ptr + "/pbrMetallicRoughness/metallicRoughnessTexture",
                             "metallicRoughnessTexture")
            self.numbers(material, "emissiveFactor", ptr, 3)
            self.of_type(material, "alphaMode", str, ptr, "a string")
            self.of_type(material, "alphaCutoff", (int, float), ptr, "a number")
            self.of_type(material, "doubleSided", bool, ptr, "a boolean")
            for parts, info in texture_infos(material, ("materials", m)):
                self.ref(info.get("index"), "textures", pointer(*parts, "index"))
                if "texCoord" in info:
                    self.integer(info, "texCoord", pointer(*parts))

    # ------------------------------------------------------------------ meshes
    def meshes(self) -> None:
        accessors = self.collection("accessors")
        for m, mesh in self.items("meshes"):
            mptr = pointer("meshes", m)
            prims = mesh.get("primitives")
            if not isinstance(prims, list) or not prims:
                self.error("MESH_PRIMITIVES", "a mesh needs a non-empty primitives array"
                           + ("" if prims is None else f", not {json_type(prims)}"
                              + (" (empty)" if prims == [] else "")), mptr + ("/primitives" if prims is not None
                                                                              else ""))
                continue
            for p, prim in enumerate(prims):
                ptr = pointer("meshes", m, "primitives", p)
                if not self.obj(prim, ptr, "a primitive"):
                    continue
                attrs = prim.get("attributes")
                if not isinstance(attrs, dict):
                    self.error("TYPE_MISMATCH", "a primitive needs an attributes object"
                               + ("" if attrs is None else f", not {json_type(attrs)}"),
                               ptr + ("/attributes" if attrs is not None else ""))
                    continue
                counts = {}
                for name, a in attrs.items():
                    aptr = f"{ptr}/attributes/{name}"
                    if self.ref(a, accessors, aptr, "accessor") and isinstance(accessors[a], dict):
                        counts[name] = accessors[a].get("count")
                        self.attribute_format(name, a, accessors[a], aptr)
                if "indices" in prim and self.ref(prim["indices"], accessors, ptr + "/indices", "accessor"):
                    acc = accessors[prim["indices"]]
                    if acc.get("type") != "SCALAR" or acc.get("componentType") not in INDEX_COMPONENTS \
                            or isinstance(acc.get("componentType"), bool) or acc.get("normalized"):
                        self.error("MESH_PRIMITIVE_INDICES_ACCESSOR_INVALID_FORMAT",
                                   f"indices must be SCALAR 5121/5123/5125, not {acc.get('type')} "
                                   f"{acc.get('componentType')}" + (" normalized" * bool(acc.get("normalized"))),
                                   ptr + "/indices")
                if "material" in prim:
                    self.ref(prim["material"], "materials", ptr + "/material")
                if "mode" in prim and (not isinstance(prim["mode"], int) or isinstance(prim["mode"], bool)
                                       or not 0 <= prim["mode"] <= 6):
                    self.error("VALUE_NOT_IN_LIST", f"mode must be an integer in 0..6, got {prim['mode']!r}",
                               ptr + "/mode")
                if "targets" in prim and self.array(prim["targets"], ptr + "/targets", "targets", 1):
                    for t, target in enumerate(prim["targets"]):
                        tptr = f"{ptr}/targets/{t}"
                        if self.obj(target, tptr, "a morph target"):
                            for name, a in target.items():
                                if self.ref(a, accessors, f"{tptr}/{name}", "accessor") and \
                                        isinstance(accessors[a], dict):
                                    self.attribute_format(name, a, accessors[a], f"{tptr}/{name}")
                if len(set(map(str, counts.values()))) > 1:
                    self.error("MESH_PRIMITIVE_UNEQUAL_ACCESSOR_COUNT", "attributes have different counts: "
                               + ", ".join(f"{k} {v}" for k, v in counts.items()), ptr + "/attributes")
            if "weights" in mesh and (not isinstance(mesh["weights"], list) or not all(
                    isinstance(w, (int, float)) and not isinstance(w, bool) for w in mesh["weights"])):
                self.error("TYPE_MISMATCH", "weights must be an array of numbers", mptr + "/weights")

    def attribute_format(self, name: str, a: int, acc: dict, ptr: str) -> None:
        atype, ctype = acc.get("type"), acc.get("componentType")
        if not one_of(atype, TYPE_SIZES) or not one_of(ctype, COMPONENT_DTYPES):
            self.error("MESH_PRIMITIVE_ATTRIBUTES_ACCESSOR_INVALID_FORMAT", f"{name} names accessor {a}, whose type "
                       f"{atype!r} / componentType {ctype!r} baker cannot read", ptr)
            return
        semantic = attribute_semantic(name)
        if semantic not in ATTRIBUTE_FORMATS:
            return
        types, components = ATTRIBUTE_FORMATS[semantic]
        if atype not in types or ctype not in components:
            self.error("MESH_PRIMITIVE_ATTRIBUTES_ACCESSOR_INVALID_FORMAT",
                       f"{name} must be {' or '.join(types)} with componentType "
                       f"{' / '.join(map(str, sorted(components)))}, but accessor {a} is {atype} {ctype}", ptr)

    # ------------------------------------------------------------------ nodes, scenes, skins, cameras, animations
    def nodes(self) -> None:
        nodes = self.collection("nodes")
        parent = {}
        for n, node in self.items("nodes"):
            ptr = pointer("nodes", n)
            for key, collection in (("mesh", "meshes"), ("skin", "skins"), ("camera", "cameras")):
                if key in node:
                    self.ref(node[key], collection, f"{ptr}/{key}")
            if "children" in node and self.array(node["children"], ptr + "/children", "children"):
                for c, child in enumerate(node["children"]):
                    cptr = f"{ptr}/children/{c}"
                    if self.ref(child, nodes, cptr, "node"):
                        if child in parent:
                            self.error("NODE_PARENT_OVERRIDE", f"node {child} is already a child of node "
                                       f"{parent[child]}", cptr)
                        else:
                            parent[child] = n
            self.numbers(node, "matrix", ptr, 16)
            self.numbers(node, "translation", ptr, 3)
            self.numbers(node, "rotation", ptr, 4)
            self.numbers(node, "scale", ptr, 3)
        for start in list(parent):  # every node has at most one parent: a loop is a parent chain back to itself
            seen, n = {start}, parent[start]
            while n in parent:
                if n in seen:
                    self.error("NODE_LOOP", f"node {n} is its own ancestor", pointer("nodes", n))
                    return
                seen.add(n)
                n = parent[n]
        for s, scene in self.items("scenes"):
            if "nodes" in scene and self.array(scene["nodes"], pointer("scenes", s, "nodes"), "nodes"):
                for k, root in enumerate(scene["nodes"]):
                    self.ref(root, nodes, pointer("scenes", s, "nodes", k), "node")

    def skins(self) -> None:
        for s, skin in self.items("skins"):
            ptr = pointer("skins", s)
            if "inverseBindMatrices" in skin:
                self.ref(skin["inverseBindMatrices"], "accessors", ptr + "/inverseBindMatrices")
            if "skeleton" in skin:
                self.ref(skin["skeleton"], "nodes", ptr + "/skeleton")
            if self.array(skin.get("joints"), ptr + "/joints", "joints", 1):
                for j, joint in enumerate(skin["joints"]):
                    self.ref(joint, "nodes", f"{ptr}/joints/{j}")

    def cameras(self) -> None:
        for c, camera in self.items("cameras"):
            ptr = pointer("cameras", c)
            kind = camera.get("type")
            if kind not in ("perspective", "orthographic"):
                self.error("VALUE_NOT_IN_LIST", f"type must be 'perspective' or 'orthographic', got {kind!r}",
                           ptr + "/type")
                continue
            if self.obj(camera.get(kind), f"{ptr}/{kind}", kind):
                for key, value in camera[kind].items():
                    if key in ("yfov", "znear", "zfar", "aspectRatio", "xmag", "ymag") and (
                            not isinstance(value, (int, float)) or isinstance(value, bool)):
                        self.error("TYPE_MISMATCH", f"{key} must be a number, not {json_type(value)}",
                                   f"{ptr}/{kind}/{key}")

    def animations(self) -> None:
        for a, anim in self.items("animations"):
            ptr = pointer("animations", a)
            samplers = anim.get("samplers")
            if self.array(samplers, ptr + "/samplers", "samplers", 1):
                for s, sampler in enumerate(samplers):
                    sptr = f"{ptr}/samplers/{s}"
                    if self.obj(sampler, sptr, "an animation sampler"):
                        for key in ("input", "output"):
                            self.ref(sampler.get(key), "accessors", f"{sptr}/{key}")
            else:
                samplers = []
            if self.array(anim.get("channels"), ptr + "/channels", "channels", 1):
                for c, channel in enumerate(anim["channels"]):
                    cptr = f"{ptr}/channels/{c}"
                    if not self.obj(channel, cptr, "an animation channel"):
                        continue
                    self.ref(channel.get("sampler"), samplers, cptr + "/sampler", "animation sampler")
                    if self.obj(channel.get("target"), cptr + "/target", "target") and "node" in channel["target"]:
                        self.ref(channel["target"]["node"], "nodes", cptr + "/target/node")

    # ------------------------------------------------------------------ data a read needs
    def missing_data(self, empty: dict) -> None:
        """A buffer without data is an error when something reads it: an accessor (directly or sparse), an image or
        a Draco primitive through one of its bufferViews, or a meshopt-compressed view's source. A bufferView
        decoded by EXT_ or KHR_meshopt_compression reads no bytes of its own buffer (a fallback buffer)."""
        if not empty:
            return
        views = self.collection("bufferViews")
        used = {}

        def use(v, ptr):
            if is_index(v, views) and isinstance(views[v], dict):
                used.setdefault(v, ptr)

        for i, acc in self.items("accessors"):
            use(acc.get("bufferView"), pointer("accessors", i))
            sparse = acc.get("sparse")
            if isinstance(sparse, dict):
                for key in ("indices", "values"):
                    if isinstance(sparse.get(key), dict):
                        use(sparse[key].get("bufferView"), pointer("accessors", i, "sparse", key))
        for i, image in self.items("images"):
            use(image.get("bufferView"), pointer("images", i))
        for m, mesh in self.items("meshes"):
            for p, prim in enumerate(mesh.get("primitives") if isinstance(mesh.get("primitives"), list) else []):
                draco = extension(prim, "KHR_draco_mesh_compression")
                if isinstance(draco, dict):
                    use(draco.get("bufferView"), pointer("meshes", m, "primitives", p))
        needed = {}
        for v, view in enumerate(views):
            if not isinstance(view, dict):
                continue
            _, meshopt = meshopt_extension(view)
            if isinstance(meshopt, dict):
                if v in used and one_of(meshopt.get("buffer"), empty):
                    needed.setdefault(meshopt["buffer"], used[v])
            elif v in used and one_of(view.get("buffer"), empty):
                needed.setdefault(view["buffer"], used[v])
        for b in sorted(needed):
            self.error("BUFFER_DATA_MISSING", f"buffer {b} {empty[b]}, but {needed[b]} reads its data (baker does "
                       "not make up zeros)", pointer("buffers", b))


def check_structure(gltf: dict, path: Path, glb_bin: bytes | None, issues: Issues, allow_outside=None) -> None:
    """Everything baker relies on before it reads a byte: JSON types, references, buffer sizes, byte ranges, the
    formats of the attributes it decodes, and external resources under the URI policy (:func:`local_file`)."""
    glb = glb_bin is not None or Path(path).suffix.lower() == ".glb"
    c = _Checker(gltf, Path(path), issues, allow_outside, glb=glb)
    c.root()
    sizes, empty = c.buffers(glb_bin)
    ranges = c.buffer_views(sizes)
    c.accessors(ranges)
    c.images()
    c.textures()
    c.materials()
    c.meshes()
    c.nodes()
    c.skins()
    c.cameras()
    c.animations()
    c.missing_data(empty)


# ---------------------------------------------------------------------------------------------------- data
def check_data(doc, issues: Issues) -> None:
    """What only the data can tell, on a structurally valid document (a :class:`~baker.gltf.document.GltfDocument`):
    every index of every primitive addresses a vertex, sparse indices address an element, and the float POSITION,
    NORMAL and TEXCOORD_n values a bake reads are finite."""
    accessors = doc.json.get("accessors") or []
    finite_checked = set()
    for a, acc in enumerate(accessors):
        if isinstance(acc.get("sparse"), dict) and one_of(acc.get("type"), TYPE_SIZES):
            try:
                doc.accessor(a)
            except BakerError as exc:
                issues.error("ACCESSOR_SPARSE_INDEX_OOB", exc.message.split(": ", 1)[-1], pointer("accessors", a))
                finite_checked.add(a)
    check_finite_attributes(doc, issues, skip=finite_checked)
    for m, mesh in enumerate(doc.json.get("meshes") or []):
        for p, prim in enumerate(mesh.get("primitives") or []):
            attrs = prim.get("attributes") or {}
            if "indices" not in prim or "POSITION" not in attrs:
                continue
            vertex_count = accessors[attrs["POSITION"]]["count"]
            indices = doc.accessor(prim["indices"])
            if len(indices) and int(indices.max()) >= vertex_count:
                bad = int(np.count_nonzero(indices >= vertex_count))
                issues.error("ACCESSOR_INDEX_OOB", f"{bad} indices are >= the vertex count {vertex_count} "
                             f"(largest {int(indices.max())})", pointer("meshes", m, "primitives", p, "indices"))



def check_finite_attributes(doc, issues: Issues, only=None, skip=(), decoded: str = "") -> None:
    """The float POSITION, NORMAL and TEXCOORD_n accessors of every primitive hold no NaN or infinity: each accessor
    once, those in ``only`` when it is given (the ones a decoder just filled), none in ``skip``. ``decoded`` names
    where the values came from, for the message."""
    accessors = doc.json.get("accessors") or []
    checked = set(skip)
    for mesh in doc.json.get("meshes") or []:
        for prim in mesh.get("primitives") or []:
            for name, a in (prim.get("attributes") or {}).items():
                if attribute_semantic(name) not in FINITE_ATTRIBUTES or a in checked or (only is not None
                                                                                         and a not in only):
                    continue
                checked.add(a)
                if accessors[a].get("componentType") != FLOAT:
                    continue
                values = doc.accessor(a)
                bad = ~np.isfinite(values)
                if bad.any():
                    row = int(np.argwhere(bad)[0][0])
                    issues.error("ACCESSOR_INVALID_FLOAT", f"{int(bad.sum())} of {values.size} values of {name}"
                                 f"{decoded} are NaN or infinite (first at element {row}); no bake may read or write "
                                 "them", pointer("accessors", a))
