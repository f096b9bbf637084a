"""A lossless glTF 2.0 document: the JSON as parsed, plus the binary data it points to.

baker keeps the source JSON as a plain ``dict`` so that every node, material, animation, skin, extension and extra
it does not touch is written back unchanged (pygltflib and trimesh rebuild the document from their own classes,
which reorders or drops what they do not model). Binary data is merged into a single buffer at load time: the
accessor data stays byte-identical, only ``bufferView.buffer``/``byteOffset`` change, which is what a GLB needs
anyway and makes appending new accessors trivial.
"""
from __future__ import annotations

import copy
import json
import mimetypes
import struct
import urllib.parse
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from baker.checks import Issues, pointer
from baker.errors import BakerError
from baker.gltf.atomic import write_files_atomic
from baker.gltf.vertex_attributes import AttributeLayout
from baker.gltf.structure import (CHUNK_BIN, CHUNK_JSON, COMPONENT_DTYPES, GLB_MAGIC, TYPE_SIZES, align,
                                  check_data, check_structure, decode_data_uri, first_error, local_file,
                                  meshopt_extension, parse_glb, read_container)

__all__ = ["GltfDocument", "node_matrix", "world_nodes", "sniff_mime", "parse_glb", "COMPONENT_DTYPES", "TYPE_SIZES",
           "DTYPE_COMPONENTS", "SIZE_TYPES", "GLB_MAGIC", "CHUNK_JSON", "CHUNK_BIN", "TARGET_ARRAY_BUFFER",
           "TARGET_ELEMENT_ARRAY_BUFFER"]

DTYPE_COMPONENTS = {np.dtype(v): k for k, v in COMPONENT_DTYPES.items()}
SIZE_TYPES = {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4"}

TARGET_ARRAY_BUFFER = 34962
TARGET_ELEMENT_ARRAY_BUFFER = 34963

_align = align


@dataclass
class GltfDocument:
    """A glTF document held losslessly.

    Attributes
    ----------
    json : dict
        The glTF JSON, exactly as read (plus what baker adds).
    bin : bytearray
        The single merged binary buffer (``buffers[0]``), or empty when the asset has no binary data.
    path : Path or None
        Where it was read from (for error messages and external resources).
    image_files : dict[int, bytes]
        Bytes of images referenced by an external ``uri``, read at load time so outputs can embed or copy them.
    """

    json: dict = field(default_factory=lambda: {"asset": {"version": "2.0", "generator": "baker"}})
    bin: bytearray = field(default_factory=bytearray)
    path: Path | None = None
    image_files: dict = field(default_factory=dict)
    # images baker adds: index -> (bytes, mimeType, file stem); written as bufferViews (GLB) or files (.gltf)
    new_images: dict = field(default_factory=dict)
    # extra folders external URIs may resolve into (see baker.gltf.structure.local_file)
    allow_outside: object = field(default=None, repr=False, compare=False)
    # how extension writers lay out custom vertex attributes (baker.gltf.vertex_attributes), set by the bake
    attribute_layout: AttributeLayout = field(default_factory=AttributeLayout, repr=False, compare=False)
    # primitive extension name -> its members that are accessors of vertex indices, renumbered when a bake splits
    # the vertices (baker.texels.targets.renumber_extension_vertices); the pipeline sets it from the registry
    vertex_index_members: dict = field(default_factory=dict, repr=False, compare=False)
    # gltf JSON -> the accessor indices something refers to, or None when that cannot be known
    # (baker.validate.referenced_accessors, set by the pipeline): lets a re-indexing bake reuse the slots of the
    # accessors it replaced instead of leaving them unused in the file; None: it leaves them
    accessor_references: object = field(default=None, repr=False, compare=False)

    # ------------------------------------------------------------------ reading
    @classmethod
    def load(cls, path, allow_outside=None) -> "GltfDocument":
        """Read a .gltf/.glb after the structural check of :mod:`baker.gltf.structure` (the one ``baker validate``
        reports): the first problem raises ``BakerError(path, "<JSON pointer>: <problem>")`` before any buffer is
        read. URIs resolve only inside the file's folder (or an ``allow_outside`` path, or a list of them)."""
        path = Path(path)
        if not path.is_file():
            raise BakerError(path, "file not found")
        issues = Issues()
        gltf, glb_bin, _ = read_container(path, issues)
        if gltf is not None:
            check_structure(gltf, path, glb_bin, issues, allow_outside)
        problem = first_error(issues)
        if problem:
            raise BakerError(path, problem)
        doc = cls.from_checked(path, gltf, glb_bin, allow_outside)
        check_data(doc, issues)
        problem = first_error(issues)
        if problem:
            raise BakerError(path, problem)
        return doc

    @classmethod
    def from_checked(cls, path, gltf: dict, glb_bin: bytes | None, allow_outside=None) -> "GltfDocument":
        """A document from JSON that passed :func:`~baker.gltf.structure.check_structure` (``gltf`` is taken over,
        not copied) and the GLB BIN chunk; buffers and images are read here, under the same URI policy."""
        doc = cls(json=gltf, path=Path(path), allow_outside=allow_outside)
        doc._merge_buffers(glb_bin)
        doc._read_external_images()
        return doc

    @classmethod
    def from_triangles(cls, path, name: str, attributes: dict, indices: np.ndarray, generator: str) -> "GltfDocument":
        """A one-mesh, one-node document holding a triangle primitive: ``attributes`` maps glTF attribute names to
        (n, k) arrays (float32 stays float32), ``indices`` is (3m,) uint32. Built straight from a mesh file's arrays:
        no exporter round trip, and nothing computed here (a reader passes the normals it wants written)."""
        doc = cls(json={"asset": {"version": "2.0", "generator": generator}, "scene": 0,
                        "scenes": [{"nodes": [0]}], "nodes": [{"name": name, "mesh": 0}]}, path=Path(path))
        prim = {"attributes": {}, "mode": 4}
        prim["indices"] = doc.add_accessor(np.asarray(indices, np.uint32), target=TARGET_ELEMENT_ARRAY_BUFFER,
                                           min_max=True)
        for key, values in attributes.items():
            prim["attributes"][key] = doc.add_accessor(values, min_max=key == "POSITION")
        doc.json["meshes"] = [{"name": name, "primitives": [prim]}]
        return doc

    def _resolve_uri(self, uri: str, ptr: str) -> bytes:
        if uri[:5].lower() == "data:":
            try:
                return decode_data_uri(uri)[0]
            except ValueError as exc:
                raise BakerError(self.path, f"{ptr}: broken data URI: {exc}") from None
        base = self.path.parent if self.path else Path(".")
        try:
            target = local_file(uri, base, self.allow_outside)
        except ValueError as exc:
            raise BakerError(self.path, f"{ptr}: {exc}") from None
        try:
            if not target.is_file():
                raise BakerError(self.path, f"{ptr}: referenced file '{uri}' not found")
            return target.read_bytes()
        except OSError as exc:
            raise BakerError(self.path, f"{ptr}: referenced file '{uri}' cannot be read: {exc.strerror or exc}") \
                from None

    def _merge_buffers(self, bin_chunk: bytes | None) -> None:
        buffers = self.json.get("buffers", [])
        merged = bytearray()
        offsets = []
        for i, buf in enumerate(buffers):
            length = int(buf.get("byteLength", 0))
            if "uri" in buf:
                data = self._resolve_uri(buf["uri"], pointer("buffers", i, "uri"))
            elif i == 0 and bin_chunk is not None:
                data = bin_chunk
            else:
                # nothing reads it (check_structure refuses a buffer without data that is read), e.g. the fallback
                # buffer of EXT_/KHR_meshopt_compression views: only a size
                data = b"\0" * length
            if len(data) < length:
                raise BakerError(self.path, f"{pointer('buffers', i)}: buffer is truncated ({len(data)} of {length} "
                                            "bytes)")
            merged.extend(b"\0" * (_align(len(merged), 16) - len(merged)))
            offsets.append(len(merged))
            merged.extend(data[:length])
        for view in self.json.get("bufferViews", []):
            b = view.get("buffer", 0)
            view["buffer"] = 0
            view["byteOffset"] = view.get("byteOffset", 0) + offsets[b]
            _, meshopt = meshopt_extension(view)
            if isinstance(meshopt, dict) and "buffer" in meshopt:
                meshopt["byteOffset"] = meshopt.get("byteOffset", 0) + offsets[meshopt["buffer"]]
                meshopt["buffer"] = 0
        # keep the first buffer's own keys (name, extras, extensions); its uri is set on save
        if buffers:
            first = {k: v for k, v in buffers[0].items() if k not in ("uri", "byteLength")}
            self.json["buffers"] = [first]
        self.bin = merged

    def _read_external_images(self) -> None:
        for i, image in enumerate(self.json.get("images", [])):
            uri = image.get("uri")
            if uri is not None and uri[:5].lower() != "data:":
                self.image_files[i] = self._resolve_uri(uri, pointer("images", i, "uri"))

    # ------------------------------------------------------------------ accessors
    def accessor(self, index: int, copy: bool = True) -> np.ndarray:
        """Read accessor ``index`` as an array of shape (count, n) (or (count,) for SCALAR), sparse applied.

        Normalized integer data is returned as stored (not converted to float). ``copy=False`` may return a
        read-only view of the binary buffer, for a caller that converts it at once and drops it: the buffer cannot
        grow (``add_buffer_view``) while such a view lives.
        """
        acc = self.json["accessors"][index]
        dtype = np.dtype(COMPONENT_DTYPES[acc["componentType"]])
        ncomp = TYPE_SIZES[acc["type"]]
        count = acc["count"]
        if "bufferView" in acc:
            view = self.json["bufferViews"][acc["bufferView"]]
            start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
            elem = dtype.itemsize * ncomp
            stride = view.get("byteStride", 0) or elem
            end = start + stride * (count - 1) + elem if count else start
            if end > view.get("byteOffset", 0) + view["byteLength"] or end > len(self.bin):
                raise BakerError(self.path, f"accessor {index} reads past the end of its bufferView")
            raw = np.frombuffer(self.bin, dtype=np.uint8, count=end - start, offset=start)
            if stride == elem:
                out = raw.view(dtype).reshape(count, ncomp)
                if copy or acc.get("sparse"):
                    out = out.copy()
                else:
                    out.flags.writeable = False
            else:
                rows = np.lib.stride_tricks.as_strided(raw, shape=(count, elem), strides=(stride, 1))
                out = np.ascontiguousarray(rows).view(dtype).reshape(count, ncomp)
        else:
            out = np.zeros((count, ncomp), dtype=dtype)
        sparse = acc.get("sparse")
        if sparse:
            n = sparse["count"]
            idx_info, val_info = sparse["indices"], sparse["values"]
            iview = self.json["bufferViews"][idx_info["bufferView"]]
            idx = np.frombuffer(self.bin, dtype=COMPONENT_DTYPES[idx_info["componentType"]], count=n,
                                offset=iview.get("byteOffset", 0) + idx_info.get("byteOffset", 0))
            if n and int(idx.max()) >= count:
                raise BakerError(self.path, f"{pointer('accessors', index, 'sparse', 'indices')}: sparse index "
                                            f"{int(idx.max())} is >= the accessor's count {count}")
            vview = self.json["bufferViews"][val_info["bufferView"]]
            vals = np.frombuffer(self.bin, dtype=dtype, count=n * ncomp,
                                 offset=vview.get("byteOffset", 0) + val_info.get("byteOffset", 0))
            out[idx.astype(np.int64)] = vals.reshape(n, ncomp)
        return out[:, 0] if acc["type"] == "SCALAR" else out

    def add_buffer_view(self, data: bytes, target: int | None = None, byte_stride: int | None = None) -> int:
        """Append ``data`` to the binary buffer (4-byte aligned) and return the new bufferView index."""
        self.bin.extend(b"\0" * (_align(len(self.bin)) - len(self.bin)))
        view = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if byte_stride:
            view["byteStride"] = byte_stride
        if target:
            view["target"] = target
        self.bin.extend(data)
        if not self.json.get("buffers"):
            self.json["buffers"] = [{}]
        views = self.json.setdefault("bufferViews", [])
        views.append(view)
        return len(views) - 1

    def add_accessor(self, array: np.ndarray, *, target: int | None = TARGET_ARRAY_BUFFER,
                     normalized: bool = False, min_max: bool = False, name: str | None = None) -> int:
        """Append ``array`` ((count,) or (count, n)) as a new tightly packed accessor; return its index."""
        array = np.ascontiguousarray(array)
        if array.dtype == np.float64:
            array = array.astype(np.float32)
        if array.dtype not in DTYPE_COMPONENTS:
            raise TypeError(f"no glTF component type for {array.dtype}")
        ncomp = 1 if array.ndim == 1 else array.shape[1]
        # the array's own bytes (a view, not a tobytes() copy): add_buffer_view copies them into the buffer once
        data = memoryview(array.astype(array.dtype.newbyteorder("<"), copy=False).reshape(-1).view(np.uint8))
        # vertex attributes must have a byteStride multiple of 4: pad small elements (e.g. 3 x uint8)
        stride = None
        if target == TARGET_ARRAY_BUFFER and (array.dtype.itemsize * ncomp) % 4:
            elem = array.dtype.itemsize * ncomp
            stride = _align(elem)
            padded = np.zeros((len(array), stride), np.uint8)
            padded[:, :elem] = np.frombuffer(data, np.uint8).reshape(len(array), elem)
            data = padded.tobytes()
        acc = {
            "bufferView": self.add_buffer_view(data, target=target, byte_stride=stride),
            "componentType": DTYPE_COMPONENTS[array.dtype],
            "count": int(len(array)),
            "type": SIZE_TYPES[ncomp] if array.ndim > 1 else "SCALAR",
        }
        if normalized:
            acc["normalized"] = True
        if min_max and len(array):
            flat = array.reshape(len(array), -1)
            cast = float if array.dtype.kind == "f" else int
            # column by column: several times faster than numpy's axis-0 reduction of a (count, n) array, same values
            acc["min"] = [cast(flat[:, k].min()) for k in range(flat.shape[1])]
            acc["max"] = [cast(flat[:, k].max()) for k in range(flat.shape[1])]
        if name:
            acc["name"] = name
        accessors = self.json.setdefault("accessors", [])
        accessors.append(acc)
        return len(accessors) - 1

    # ------------------------------------------------------------------ images
    def add_image(self, data: bytes, mime_type: str, name: str) -> int:
        """Add an image; it becomes a bufferView in a GLB or a file ``<out-stem>_<name>.<ext>`` beside a .gltf."""
        images = self.json.setdefault("images", [])
        images.append({"name": name, "mimeType": mime_type})
        index = len(images) - 1
        self.new_images[index] = (data, mime_type, name)
        return index

    def add_texture(self, image: int, sampler: dict | None = None, name: str | None = None) -> int:
        tex = {"source": image}
        if sampler is not None:
            samplers = self.json.setdefault("samplers", [])
            if sampler in samplers:
                tex["sampler"] = samplers.index(sampler)
            else:
                samplers.append(dict(sampler))
                tex["sampler"] = len(samplers) - 1
        if name:
            tex["name"] = name
        textures = self.json.setdefault("textures", [])
        textures.append(tex)
        return len(textures) - 1

    def image_bytes(self, index: int) -> bytes:
        """The encoded bytes of image ``index`` wherever they live (bufferView, data URI, file, or new)."""
        if index in self.new_images:
            return self.new_images[index][0]
        image = self.json["images"][index]
        if "bufferView" in image:
            view = self.json["bufferViews"][image["bufferView"]]
            off = view.get("byteOffset", 0)
            return bytes(self.bin[off: off + view["byteLength"]])
        uri = image.get("uri", "")
        if uri[:5].lower() == "data:":
            return self._resolve_uri(uri, pointer("images", index, "uri"))
        return self.image_files[index]

    # ------------------------------------------------------------------ extensions
    def use_extension(self, name: str, required: bool = False) -> None:
        used = self.json.setdefault("extensionsUsed", [])
        if name not in used:
            used.append(name)
        if required:
            req = self.json.setdefault("extensionsRequired", [])
            if name not in req:
                req.append(name)

    def set_material_extension(self, material: int, name: str, data: dict) -> dict:
        """Put extension ``name`` with ``data`` on material ``material`` (replacing one of that name a bake wrote
        before) and list it in ``extensionsUsed``; returns ``data``."""
        self.json["materials"][material].setdefault("extensions", {})[name] = data
        self.use_extension(name)
        return data

    def set_primitive_extension(self, mesh: int, primitive: int, name: str, data: dict) -> dict:
        """Put extension ``name`` with ``data`` on primitive ``primitive`` of mesh ``mesh`` and list it in
        ``extensionsUsed``; returns ``data``."""
        self.json["meshes"][mesh]["primitives"][primitive].setdefault("extensions", {})[name] = data
        self.use_extension(name)
        return data

    # ------------------------------------------------------------------ writing
    def save(self, path, compress: str | None = None) -> list[Path]:
        """Write ``.glb`` or ``.gltf`` (+ ``.bin`` + images) atomically, chosen by the file extension.
        ``compress="meshopt"`` (or ``"meshopt-gzip"``): the bufferViews accessors read stored as
        EXT_meshopt_compression, each as small as it gets (or as small as it gets once gzipped), baked float vertex
        attributes through the EXPONENTIAL filter at a stated precision; ``"meshopt-lossless"`` without the filter
        (:mod:`baker.gltf.meshopt_encode`).

        Returns every file written (the main file last)."""
        path = Path(path)
        suffix = path.suffix.lower()
        if suffix not in (".glb", ".gltf"):
            raise BakerError(path, "output must end in .glb or .gltf")
        gltf = copy.deepcopy(self.json)
        binary = self.bin  # copied only when images are appended (a big mesh's buffer is most of the memory)
        side_files: dict[str, bytes] = {}

        def append_view(data: bytes) -> int:
            nonlocal binary
            if binary is self.bin:
                binary = bytearray(self.bin)
            binary.extend(b"\0" * (_align(len(binary)) - len(binary)))
            gltf.setdefault("bufferViews", []).append({"buffer": 0, "byteOffset": len(binary), "byteLength": len(data)})
            binary.extend(data)
            return len(gltf["bufferViews"]) - 1

        for i, image in enumerate(gltf.get("images", [])):
            if i in self.new_images:
                data, mime, name = self.new_images[i]
                if suffix == ".glb":
                    image["bufferView"] = append_view(data)
                else:
                    ext = mimetypes.guess_extension(mime) or ".bin"
                    uri = f"{path.stem}_{name}{ext}"
                    image["uri"] = uri
                    side_files[uri] = data
            elif "uri" in image and suffix == ".glb":
                data = self.image_bytes(i)
                mime = image.get("mimeType") or sniff_mime(data)
                del image["uri"]
                image["bufferView"] = append_view(data)
                image["mimeType"] = mime
            elif "uri" in image and image["uri"][:5].lower() != "data:":
                uri = image["uri"]
                rel = Path(urllib.parse.unquote(uri))
                if rel.is_absolute() or ".." in rel.parts:
                    rel = Path(f"{path.stem}_image{i}{Path(uri).suffix}")
                    image["uri"] = urllib.parse.quote(rel.as_posix())
                side_files[rel.as_posix()] = self.image_files[i]

        if compress in ("meshopt", "meshopt-gzip", "meshopt-lossless"):
            if binary:
                from baker.gltf.meshopt_encode import compress_meshopt

                gltf, binary, _ = compress_meshopt(gltf, binary, "gzip" if compress == "meshopt-gzip" else "size",
                                                   filters=compress != "meshopt-lossless")
        elif compress not in (None, "none"):
            raise BakerError(path, f"unknown compression {compress!r} (use meshopt, meshopt-gzip or meshopt-lossless)")
        if binary:
            if not gltf.get("buffers"):
                gltf["buffers"] = [{}]
            gltf["buffers"][0]["byteLength"] = len(binary)
            if suffix == ".gltf":
                gltf["buffers"][0]["uri"] = f"{path.stem}.bin"
                side_files[f"{path.stem}.bin"] = bytes(binary)
        elif "buffers" in gltf and not gltf["buffers"]:
            del gltf["buffers"]

        if suffix == ".glb":
            text = json.dumps(gltf, separators=(",", ":"), ensure_ascii=False).encode("utf-8")
            text += b" " * (_align(len(text)) - len(text))
            # assembled in one preallocated buffer: one copy of the binary chunk, not four
            bin_length = _align(len(binary)) if binary else 0
            total = 12 + 8 + len(text) + (8 + bin_length if binary else 0)
            blob = bytearray(total)
            struct.pack_into("<IIIII", blob, 0, GLB_MAGIC, 2, total, len(text), CHUNK_JSON)
            blob[20: 20 + len(text)] = text
            if binary:
                struct.pack_into("<II", blob, 20 + len(text), bin_length, CHUNK_BIN)
                blob[28 + len(text): 28 + len(text) + len(binary)] = binary  # the padding stays zero
        else:
            blob = (json.dumps(gltf, indent=2, ensure_ascii=False) + "\n").encode("utf-8")

        # one atomic group, side files renamed first and the main file last: a reader never sees a .gltf whose .bin
        # is missing, and a failed or killed run keeps every earlier file (never a new .bin beside the old .gltf)
        return write_files_atomic([(path.parent / rel, data) for rel, data in sorted(side_files.items())]
                                  + [(path, blob)])



def node_matrix(node: dict) -> np.ndarray:
    """The local 4x4 matrix (column-vector convention, ``p' = M @ p``) of a glTF node: ``matrix`` or T * R * S."""
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T  # glTF stores columns
    x, y, z, w = node.get("rotation", [0.0, 0.0, 0.0, 1.0])
    rotation = np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])
    out = np.eye(4)
    out[:3, :3] = rotation * np.array(node.get("scale", [1.0, 1.0, 1.0]), dtype=np.float64)[None, :]
    out[:3, 3] = node.get("translation", [0.0, 0.0, 0.0])
    return out


def world_nodes(gltf: dict) -> list[tuple[int, np.ndarray]]:
    """(node index, world matrix) of every node of the default scene, depth first (every root node when the
    document has no scene)."""
    nodes = gltf.get("nodes") or []
    scenes = gltf.get("scenes") or []
    if scenes:
        roots = scenes[gltf.get("scene", 0)].get("nodes", [])
    else:
        children = {c for n in nodes for c in n.get("children", [])}
        roots = [i for i in range(len(nodes)) if i not in children]
    out, stack = [], [(r, np.eye(4)) for r in reversed(roots)]
    while stack:
        i, parent = stack.pop()
        world = parent @ node_matrix(nodes[i])
        out.append((i, world))
        stack.extend((c, world) for c in reversed(nodes[i].get("children", [])))
    return out


def sniff_mime(data: bytes) -> str:
    if data[:8] == b"\x89PNG\r\n\x1a\n":
        return "image/png"
    if data[:3] == b"\xff\xd8\xff":
        return "image/jpeg"
    if data[:4] == b"RIFF" and data[8:12] == b"WEBP":
        return "image/webp"
    if data[4:12] == b"ftypavif":
        return "image/avif"
    if data[:12] == b"\xabKTX 20\xbb\r\n\x1a\n":
        return "image/ktx2"
    return "application/octet-stream"
