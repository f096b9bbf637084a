"""The structure of a glTF document, checked before any data is read: GLB container, buffer sizes, byte ranges of
bufferViews and accessors, component types, and references between objects. Only what baker must trust before it
reads a byte; the full core-spec check is Khronos glTF-Validator's job. ``baker validate`` reports these problems
with the extension checks (:mod:`baker.validate`)."""
from __future__ import annotations

import base64
import json
import urllib.parse
from pathlib import Path

import numpy as np

from baker.checks import Issues, is_count, is_index, pointer
from baker.errors import BakerError
from baker.gltf.document import COMPONENT_DTYPES, TYPE_SIZES, GltfDocument, parse_glb


TRIANGLE_MODES = (4, 5, 6)


# structural errors after which accessor data can still be read safely
NON_BLOCKING = {"MESH_PRIMITIVE_UNEQUAL_ACCESSOR_COUNT"}


# where an object sits in the document -> its kind, as in Khronos' extension schema file names
COLLECTION_KINDS = {
    "accessors": "accessor", "animations": "animation", "buffers": "buffer", "bufferViews": "bufferView",
    "cameras": "camera", "images": "image", "materials": "material", "meshes": "mesh", "nodes": "node",
    "samplers": "sampler", "scenes": "scene", "skins": "skin", "textures": "texture",
}


def _buffer_sizes(gltf: dict, path: Path, glb_bin: bytes | None, issues: Issues) -> list:
    """Bytes actually available to each buffer (None when unknown, e.g. a compression fallback buffer)."""
    sizes = []
    for i, buf in enumerate(gltf.get("buffers") or []):
        ptr = pointer("buffers", i)
        if not isinstance(buf, dict):
            issues.error("TYPE_MISMATCH", "buffer must be an object", ptr)
            sizes.append(0)
            continue
        declared = buf.get("byteLength")
        if not is_count(declared, 1):
            issues.error("BUFFER_BYTE_LENGTH", f"byteLength must be an integer >= 1, got {declared!r}", ptr)
        uri = buf.get("uri")
        if uri is None:
            if i == 0 and glb_bin is not None:
                available = len(glb_bin)
            else:
                sizes.append(None)
                continue
        elif not isinstance(uri, str):
            issues.error("TYPE_MISMATCH", "uri must be a string", ptr + "/uri")
            available = 0
        elif uri.startswith("data:"):
            header, _, payload = uri.partition(",")
            try:
                available = len(base64.b64decode(payload, validate=True)) if ";base64" in header else \
                    len(urllib.parse.unquote_to_bytes(payload))
            except ValueError as exc:
                issues.error("INVALID_URI", f"broken data URI: {exc}", ptr + "/uri")
                available = 0
        else:
            target = path.parent / urllib.parse.unquote(uri)
            if not target.is_file():
                issues.error("IO_ERROR", f"buffer file '{uri}' not found", ptr + "/uri")
                available = 0
            else:
                available = target.stat().st_size
        if is_count(declared) and available < declared:
            issues.error("BUFFER_BYTE_LENGTH_MISMATCH",
                         f"byteLength is {declared} but only {available} bytes are available", ptr)
        sizes.append(min(available, declared) if is_count(declared) else available)
    return sizes


def check_structure(gltf: dict, path: Path, glb_bin: bytes | None, issues: Issues) -> None:
    """References and byte ranges baker relies on when it reads accessors, meshes, materials and images."""
    buffers = gltf.get("buffers") or []
    views = gltf.get("bufferViews") or []
    accessors = gltf.get("accessors") or []
    sizes = _buffer_sizes(gltf, path, glb_bin, issues)

    for i, view in enumerate(views):
        ptr = pointer("bufferViews", i)
        if not isinstance(view, dict):
            issues.error("TYPE_MISMATCH", "bufferView must be an object", ptr)
            continue
        b, offset, length = view.get("buffer"), view.get("byteOffset", 0), view.get("byteLength")
        if not is_index(b, buffers):
            issues.error("UNRESOLVED_REFERENCE", f"buffer {b!r} does not exist", ptr + "/buffer")
            continue
        if not is_count(offset) or not is_count(length, 1):
            issues.error("BUFFER_VIEW_RANGE", f"byteOffset {offset!r} / byteLength {length!r} must be integers "
                         "(>= 0 and >= 1)", ptr)
            continue
        stride = view.get("byteStride")
        if stride is not None and not (is_count(stride, 4) and stride <= 252 and stride % 4 == 0):
            issues.error("BUFFER_VIEW_INVALID_BYTE_STRIDE", f"byteStride {stride!r} must be a multiple of 4 in "
                         "4..252", ptr + "/byteStride")
        if sizes[b] is not None and offset + length > sizes[b]:
            issues.error("BUFFER_VIEW_TOO_LONG", f"bytes {offset}..{offset + length} run past the end of buffer {b} "
                         f"({sizes[b]} bytes)", ptr)

    def view_range(v):
        view = views[v]
        return view.get("byteOffset", 0), view.get("byteLength", 0), view.get("byteStride") or 0

    for i, acc in enumerate(accessors):
        ptr = pointer("accessors", i)
        if not isinstance(acc, dict):
            issues.error("TYPE_MISMATCH", "accessor must be an object", ptr)
            continue
        ctype, atype, count = acc.get("componentType"), acc.get("type"), acc.get("count")
        ok = True
        if ctype not in COMPONENT_DTYPES or isinstance(ctype, bool):
            issues.error("VALUE_NOT_IN_LIST", f"componentType {ctype!r} is not one of "
                         f"{', '.join(map(str, COMPONENT_DTYPES))}", ptr + "/componentType")
            ok = False
        if atype not in TYPE_SIZES:
            issues.error("VALUE_NOT_IN_LIST", f"type {atype!r} is not one of {', '.join(TYPE_SIZES)}", ptr + "/type")
            ok = False
        if not is_count(count, 1):
            issues.error("VALUE_NOT_IN_RANGE", f"count must be an integer >= 1, got {count!r}", ptr + "/count")
            ok = False
        if not ok:
            continue
        elem = np.dtype(COMPONENT_DTYPES[ctype]).itemsize * TYPE_SIZES[atype]
        if "bufferView" in acc:
            v = acc["bufferView"]
            offset = acc.get("byteOffset", 0)
            if not is_index(v, views) or not isinstance(views[v], dict):
                issues.error("UNRESOLVED_REFERENCE", f"bufferView {v!r} does not exist", ptr + "/bufferView")
            elif not is_count(offset):
                issues.error("VALUE_NOT_IN_RANGE", f"byteOffset must be an integer >= 0, got {offset!r}",
                             ptr + "/byteOffset")
            else:
                _, length, stride = view_range(v)
                stride = stride if is_count(stride, 1) else elem
                end = offset + stride * (count - 1) + elem
                if is_count(length) and end > length:
                    issues.error("ACCESSOR_OUT_OF_BOUNDS", f"{count} x {atype} {np.dtype(COMPONENT_DTYPES[ctype])} "
                                 f"(stride {stride}) from byteOffset {offset} need {end} bytes; bufferView {v} has "
                                 f"{length}", ptr)
        sparse = acc.get("sparse")
        if sparse is not None:
            _check_sparse(sparse, acc, views, ptr + "/sparse", issues, view_range)

    _check_references(gltf, issues)


def _check_sparse(sparse, acc, views, ptr, issues, view_range) -> None:
    if not isinstance(sparse, dict):
        issues.error("TYPE_MISMATCH", "sparse must be an object", ptr)
        return
    n = sparse.get("count")
    if not is_count(n, 1) or n > acc["count"]:
        issues.error("VALUE_NOT_IN_RANGE", f"sparse count {n!r} must be in 1..{acc['count']}", ptr + "/count")
        return
    for key, size in (("indices", None), ("values", np.dtype(COMPONENT_DTYPES[acc["componentType"]]).itemsize
                                                    * TYPE_SIZES[acc["type"]])):
        part = sparse.get(key)
        sub = f"{ptr}/{key}"
        if not isinstance(part, dict):
            issues.error("TYPE_MISMATCH", f"sparse.{key} must be an object", sub)
            continue
        if key == "indices":
            if part.get("componentType") not in (5121, 5123, 5125):
                issues.error("VALUE_NOT_IN_LIST", "sparse index componentType must be 5121, 5123 or 5125",
                             sub + "/componentType")
                continue
            size = np.dtype(COMPONENT_DTYPES[part["componentType"]]).itemsize
        v, offset = part.get("bufferView"), part.get("byteOffset", 0)
        if not is_index(v, views) or not isinstance(views[v], dict):
            issues.error("UNRESOLVED_REFERENCE", f"bufferView {v!r} does not exist", sub + "/bufferView")
        elif is_count(offset) and offset + size * n > view_range(v)[1]:
            issues.error("ACCESSOR_OUT_OF_BOUNDS", f"sparse {key} need {offset + size * n} bytes; bufferView {v} "
                         f"has {view_range(v)[1]}", sub)


def _texture_infos(material: dict, parts: tuple):
    """Yield (path parts, textureInfo) for every ``*Texture`` object in a material, extensions included."""
    for key, value in material.items():
        if key == "extras":
            continue
        if isinstance(value, dict):
            if key.endswith("Texture") and "index" in value:
                yield parts + (key,), value
            else:
                yield from _texture_infos(value, parts + (key,))


def _check_references(gltf: dict, issues: Issues) -> None:
    def ref(value, collection_name, ptr):
        collection = gltf.get(collection_name) or []
        if not is_index(value, collection):
            issues.error("UNRESOLVED_REFERENCE", f"{collection_name[:-1]} {value!r} does not exist", ptr)
            return False
        return True

    def items(name):
        for i, obj in enumerate(gltf.get(name) or []):
            if isinstance(obj, dict):
                yield i, obj
            else:
                issues.error("TYPE_MISMATCH", f"{COLLECTION_KINDS.get(name, name)} must be an object",
                             pointer(name, i))

    accessors = gltf.get("accessors") or []
    for m, mesh in items("meshes"):
        prims = mesh.get("primitives")
        if not isinstance(prims, list) or not prims:
            issues.error("MESH_PRIMITIVES", "a mesh needs a non-empty primitives array", pointer("meshes", m))
            continue
        for p, prim in enumerate(prims):
            ptr = pointer("meshes", m, "primitives", p)
            if not isinstance(prim, dict) or not isinstance(prim.get("attributes"), dict):
                issues.error("TYPE_MISMATCH", "a primitive needs an attributes object", ptr)
                continue
            counts = {}
            for name, a in prim["attributes"].items():
                if ref(a, "accessors", f"{ptr}/attributes/{name}") and isinstance(accessors[a], dict):
                    counts[name] = accessors[a].get("count")
            if len(set(map(str, counts.values()))) > 1:
                issues.error("MESH_PRIMITIVE_UNEQUAL_ACCESSOR_COUNT",
                             "attributes have different counts: " + ", ".join(f"{k} {v}" for k, v in counts.items()),
                             ptr + "/attributes")
            if "indices" in prim:
                ref(prim["indices"], "accessors", ptr + "/indices")
            if "material" in prim:
                ref(prim["material"], "materials", ptr + "/material")
            for t, target in enumerate(prim.get("targets") or []):
                for name, a in (target.items() if isinstance(target, dict) else ()):
                    ref(a, "accessors", f"{ptr}/targets/{t}/{name}")
    for n, node in items("nodes"):
        ptr = pointer("nodes", n)
        if "mesh" in node:
            ref(node["mesh"], "meshes", ptr + "/mesh")
        if "skin" in node:
            ref(node["skin"], "skins", ptr + "/skin")
        if "camera" in node:
            ref(node["camera"], "cameras", ptr + "/camera")
        for c, child in enumerate(node.get("children") or []):
            ref(child, "nodes", f"{ptr}/children/{c}")
    for s, scene in items("scenes"):
        for k, root in enumerate(scene.get("nodes") or []):
            ref(root, "nodes", pointer("scenes", s, "nodes", k))
    if "scene" in gltf:
        ref(gltf["scene"], "scenes", "/scene")
    for t, tex in items("textures"):
        ptr = pointer("textures", t)
        if "source" in tex:
            ref(tex["source"], "images", ptr + "/source")
        if "sampler" in tex:
            ref(tex["sampler"], "samplers", ptr + "/sampler")
    for i, image in items("images"):
        if "bufferView" in image:
            ref(image["bufferView"], "bufferViews", pointer("images", i, "bufferView"))
    for m, material in items("materials"):
        for parts, info in _texture_infos(material, ("materials", m)):
            ref(info.get("index"), "textures", pointer(*parts, "index"))
            tc = info.get("texCoord", 0)
            if not is_count(tc):
                issues.error("VALUE_NOT_IN_RANGE", f"texCoord must be an integer >= 0, got {tc!r}",
                             pointer(*parts, "texCoord"))


def check_indices(doc: GltfDocument, issues: Issues) -> None:
    """Every index of every primitive must address a vertex (baker indexes arrays with them)."""
    for m, mesh in enumerate(doc.json.get("meshes") or []):
        for p, prim in enumerate(mesh.get("primitives") or []):
            attrs = prim.get("attributes") or {}
            if "indices" not in prim or "POSITION" not in attrs:
                continue
            vertex_count = doc.json["accessors"][attrs["POSITION"]]["count"]
            indices = doc.accessor(prim["indices"])
            if len(indices) and int(indices.max()) >= vertex_count:
                bad = int(np.count_nonzero(indices >= vertex_count))
                issues.error("ACCESSOR_INDEX_OOB", f"{bad} indices are >= the vertex count {vertex_count} "
                             f"(largest {int(indices.max())})", pointer("meshes", m, "primitives", p, "indices"))


# ---------------------------------------------------------------------------------------------------- entry points
def read_container(path: Path, issues: Issues) -> tuple[dict | None, bytes | None, str]:
    """The JSON and binary chunk of a .gltf/.glb (GLB header and chunk lengths checked against the file) and its
    mime type; (None, None, mime) with an error in ``issues`` when the container cannot be read."""
    data = path.read_bytes()
    is_glb = path.suffix.lower() == ".glb" or data[:4] == b"glTF"
    mime = "model/gltf-binary" if is_glb else "model/gltf+json"
    try:
        if is_glb:
            gltf, glb_bin = parse_glb(path, data)
        else:
            gltf, glb_bin = json.loads(data.decode("utf-8")), None
    except BakerError as exc:
        issues.error("INVALID_GLB", exc.message)
        return None, None, mime
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        issues.error("INVALID_JSON", f"broken JSON: {exc}")
        return None, None, mime
    if not isinstance(gltf, dict):
        issues.error("TYPE_MISMATCH", "the document must be a JSON object", "")
        return None, None, mime
    if not isinstance(gltf.get("asset"), dict) or not str(gltf["asset"].get("version", "")).startswith("2."):
        issues.error("UNSUPPORTED_VERSION", "not a glTF 2.x document (asset.version)", "/asset")
        return None, None, mime
    return gltf, glb_bin, mime
