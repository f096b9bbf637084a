"""PLY files: the header checked once, a direct reader for the common large case (a binary PLY of triangles:
scans, sculpts, subdivided meshes), trimesh for the rest, ``tristrips`` (Stanford scans) made triangles.

Before reading: a count written in a header is not trusted. The header's element counts are compared with the size
of the file; a count the file cannot hold (``element vertex 1000000000000`` in a 200-byte file, a binary PLY cut
short) is refused before any array is allocated. Only the header is read (a few hundred bytes), so a 10^12-vertex
claim is refused in microseconds. The header read there is the one every later step uses.

After: the numbers read are numbers. :func:`non_finite_location` names the PLY element and property where a NaN,
an infinity or a value beyond float32 (what glTF stores) sits.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from baker import memory
from baker.errors import BakerError
from baker.geometry.angle_normals import seamless_vertex_normals
from baker.geometry.strips import triangles_from_strips
from baker.gltf.document import GltfDocument
from baker.readers.finite import FLOAT32_MAX, refuse_non_finite
from baker.readers.mtl import assign_materials

PLY_TYPES = {"char": 1, "int8": 1, "uchar": 1, "uint8": 1, "short": 2, "int16": 2, "ushort": 2, "uint16": 2,
             "int": 4, "int32": 4, "uint": 4, "uint32": 4, "float": 4, "float32": 4, "double": 8, "float64": 8}
PLY_HEADER_LIMIT = 1 << 20  # a header longer than 1 MiB is not a PLY header


@dataclass
class PlyElement:
    name: str
    count: int
    scalars: list = field(default_factory=list)  # (name, byte size)
    lists: list = field(default_factory=list)  # (name, count byte size, item byte size)
    types: dict = field(default_factory=dict)  # property name -> PLY type name, or (count type, item type) of a list

    def min_bytes(self, binary: bool) -> int:
        """The fewest bytes one element can take: every scalar, and every list empty (its count only). In ASCII,
        at least one character and one separator per value."""
        if binary:
            return sum(s for _, s in self.scalars) + sum(c for _, c, _ in self.lists)
        return 2 * (len(self.scalars) + len(self.lists))


@dataclass
class PlyHeader:
    format: str  # ascii, binary_little_endian, binary_big_endian
    elements: list
    header_bytes: int  # offset of the first data byte

    @property
    def binary(self) -> bool:
        return self.format != "ascii"


def read(path: Path, allow_outside=None, max_memory: int | None = None) -> GltfDocument:
    """A PLY as a glTF document: its header checked once (:func:`check_ply`) and against ``max_memory`` bytes
    (:func:`baker.memory.check_file`; None: no limit), then read directly (:func:`read_direct`) or by trimesh."""
    header = check_ply(path)
    counts = {e.name: e.count for e in header.elements}
    memory.check_file(path, max_memory, {"vertices": counts.get("vertex", 0),
                                         "faces": counts.get("face", 0) + counts.get("tristrips", 0)})
    doc = read_direct(path, header)
    if doc is None:
        import trimesh

        from baker.readers.trimesh_scene import doc_from_trimesh_scene, load_trimesh

        loaded = load_trimesh(path)
        if isinstance(loaded, trimesh.PointCloud):
            loaded = mesh_from_strips(path, loaded)
        doc = doc_from_trimesh_scene(path, loaded, None, non_finite_location)
    return doc


def read_direct(path: Path, header: PlyHeader) -> GltfDocument | None:
    """A binary PLY of triangles (:func:`read_ply_triangles`) straight into a document without trimesh; None for
    every other PLY (trimesh reads it). The positions, normals and UVs the file has are kept as float32; a file
    without normals gets the smooth ones the OBJ and ASCII PLY readers compute (angle-weighted, welded by position),
    so the output is not drawn faceted (glTF viewers flat-shade a primitive without NORMAL)."""
    arrays = read_ply_triangles(path, header)
    if arrays is None:
        return None
    indices = arrays.pop("indices")
    for name, values in arrays.items():
        # float32 already: a double beyond float32 became an infinity
        refuse_non_finite(path, values, name, non_finite_location)
    if "NORMAL" not in arrays:
        (arrays["NORMAL"],) = seamless_vertex_normals([(arrays["POSITION"], indices.reshape(-1, 3), None)],
                                                      np.float32)
    doc = GltfDocument.from_triangles(path, path.name, arrays, indices, "baker (converted from ply)")
    assign_materials(doc, {})
    return doc


def read_ply_header(path: Path) -> PlyHeader:
    with open(path, "rb") as f:
        head = f.read(PLY_HEADER_LIMIT)
    if not head.startswith(b"ply"):
        raise BakerError(path, "not a PLY file (it does not start with 'ply')")
    match = re.search(rb"end_header[ \t]*\r?\n", head)
    if match is None:
        if len(head) >= PLY_HEADER_LIMIT:
            raise BakerError(path, f"PLY header has no end_header in its first {PLY_HEADER_LIMIT} bytes")
        raise BakerError(path, "PLY header has no end_header (truncated file?)")
    text = head[:match.start()].decode("ascii", errors="replace")
    fmt = None
    elements: list[PlyElement] = []
    for number, line in enumerate(text.splitlines(), start=1):
        words = line.split()
        if not words or words[0] in ("ply", "comment", "obj_info"):
            continue
        where = f"PLY header line {number}"
        if words[0] == "format":
            if len(words) < 2 or words[1] not in ("ascii", "binary_little_endian", "binary_big_endian"):
                raise BakerError(path, f"{where}: unknown format {' '.join(words[1:])!r}")
            fmt = words[1]
        elif words[0] == "element":
            if len(words) != 3 or not words[2].isdigit():
                raise BakerError(path, f"{where}: expected 'element NAME COUNT', got {line.strip()!r}")
            elements.append(PlyElement(words[1], int(words[2])))
        elif words[0] == "property":
            if not elements:
                raise BakerError(path, f"{where}: property before any element")
            if len(words) == 5 and words[1] == "list":
                if words[2] not in PLY_TYPES or words[3] not in PLY_TYPES:
                    raise BakerError(path, f"{where}: unknown list type in {line.strip()!r}")
                elements[-1].lists.append((words[4], PLY_TYPES[words[2]], PLY_TYPES[words[3]]))
                elements[-1].types[words[4]] = (words[2], words[3])
            elif len(words) == 3 and words[1] in PLY_TYPES:
                elements[-1].scalars.append((words[2], PLY_TYPES[words[1]]))
                elements[-1].types[words[2]] = words[1]
            else:
                raise BakerError(path, f"{where}: cannot read property {line.strip()!r}")
    if fmt is None:
        raise BakerError(path, "PLY header has no format line")
    return PlyHeader(fmt, elements, match.end())


def check_ply(path: Path) -> PlyHeader:
    """The PLY header, refused when its element counts need more bytes than follow it."""
    header = read_ply_header(path)
    available = path.stat().st_size - header.header_bytes
    needed = 0
    for element in header.elements:
        needed += element.count * element.min_bytes(header.binary)
        if needed > available:
            kind = "binary" if header.binary else "ASCII"
            raise BakerError(path, f"PLY header claims {element.count} '{element.name}' elements, more than the "
                                   f"{available} bytes of {kind} data can hold (at least {needed} needed): a "
                                   "corrupt header or a truncated file")
    return header


# ---------------------------------------------------------------------------------------------------------- reading
PLY_DTYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
              "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
              "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}
PLY_VERTEX_GROUPS = {"POSITION": ("x", "y", "z"), "NORMAL": ("nx", "ny", "nz")}
PLY_UV_NAMES = (("s", "t"), ("u", "v"), ("texture_u", "texture_v"))
PLY_FACE_LISTS = ("vertex_indices", "vertex_index")


def read_ply_triangles(path, header: PlyHeader | None = None) -> dict | None:
    """A binary PLY holding only vertices (positions, optionally normals and one UV pair) and triangles, read with
    one ``numpy.frombuffer`` per element: ``{"POSITION": (n, 3) float32, "NORMAL": ..., "TEXCOORD_0": ...,
    "indices": (3m,) uint32}`` with only what the file has, or None when the file holds anything else (ASCII, other
    properties such as colors, polygons, strips, other elements): that file goes through trimesh, which keeps it.
    The header is checked (:func:`check_ply`) first; indices are checked against the vertex count here."""
    path = Path(path)
    header = header or check_ply(path)
    if not header.binary or [e.name for e in header.elements] != ["vertex", "face"]:
        return None
    vertex, face = header.elements
    if vertex.lists or face.scalars or len(face.lists) != 1 or face.lists[0][0] not in PLY_FACE_LISTS:
        return None
    names = [n for n, _ in vertex.scalars]
    wanted = {group: cols for group, cols in PLY_VERTEX_GROUPS.items() if all(c in names for c in cols)}
    uv = next((pair for pair in PLY_UV_NAMES if all(c in names for c in pair)), None)
    used = {c for cols in wanted.values() for c in cols} | set(uv or ())
    if "POSITION" not in wanted or used != set(names) or len(names) != len(set(names)):
        return None  # another vertex property (colors, quality, ...): trimesh keeps it
    order = ">" if header.format == "binary_big_endian" else "<"
    vertex_dtype = np.dtype([(n, order + PLY_DTYPES[vertex.types[n]]) for n in names])
    count_name, index_name = face.types[face.lists[0][0]]
    if PLY_DTYPES[index_name][0] == "f" or PLY_DTYPES[count_name][0] == "f":
        return None
    face_dtype = np.dtype([("n", order + PLY_DTYPES[count_name]), ("v", order + PLY_DTYPES[index_name], 3)])
    with open(path, "rb") as f:
        f.seek(header.header_bytes)
        vertex_data = f.read(vertex_dtype.itemsize * vertex.count)
        face_bytes = face_dtype.itemsize * face.count
        face_data = f.read(face_bytes)
    if len(vertex_data) < vertex_dtype.itemsize * vertex.count:
        raise BakerError(path, "binary PLY is truncated inside its vertex element")
    if len(face_data) < face_bytes:
        return None  # not all triangles (or truncated): trimesh's reader decides
    faces = np.frombuffer(face_data, face_dtype, count=face.count)
    if face.count and not (faces["n"] == 3).all():
        return None  # polygons: trimesh triangulates them
    vertices = np.frombuffer(vertex_data, vertex_dtype, count=vertex.count)
    with np.errstate(over="ignore"):  # a double beyond float32 becomes an infinity, which the caller refuses
        out = {group: np.column_stack([vertices[c] for c in cols]).astype(np.float32, copy=False)
               for group, cols in wanted.items()}
        if uv is not None:
            out["TEXCOORD_0"] = np.column_stack([vertices[uv[0]], 1.0 - vertices[uv[1]].astype(np.float64)]) \
                .astype(np.float32)  # PLY's t runs up, glTF's v runs down (as trimesh converts it)
    del vertices, vertex_data
    corners = faces["v"]  # (m, 3) strided view of the records: checked there, then copied once as uint32
    if len(corners) and (int(corners.min()) < 0 or int(corners.max()) >= vertex.count):
        indices = corners.reshape(-1)
        bad = int(np.argmax((indices < 0) | (indices >= vertex.count))) // 3
        raise BakerError(path, f"face {bad}: vertex index out of range ({vertex.count} vertices)")
    out["indices"] = corners.astype(np.uint32).reshape(-1)
    return out


# ---------------------------------------------------------------------------------------------------------- strips
def mesh_from_strips(path: Path, cloud):
    """A PLY whose surface is a ``tristrips`` element (Stanford scans such as igea.ply): trimesh reads only its
    vertices; build the triangles from the strips. Other point clouds are returned as they are."""
    import trimesh

    elements = cloud.metadata.get("_ply_raw") or {}
    strips = strip_indices(elements)
    if strips is None:
        return cloud
    vertices = np.asarray(cloud.vertices, dtype=np.float64)
    valid = strips[strips >= 0]
    if len(valid) and valid.max() >= len(vertices):
        raise BakerError(path, f"tristrips: vertex index {int(valid.max())} out of range ({len(vertices)} vertices)")
    if (strips < -1).any():
        raise BakerError(path, "tristrips: negative vertex index other than the -1 restart")
    faces = triangles_from_strips(strips)
    kwargs = {}
    data = elements["vertex"]["data"]
    names = data.keys() if isinstance(data, dict) else (data.dtype.names or ())
    if all(name in names for name in ("nx", "ny", "nz")):
        kwargs["vertex_normals"] = np.column_stack([data[name] for name in ("nx", "ny", "nz")])
    return trimesh.Trimesh(vertices=vertices, faces=faces, process=False, **kwargs)


def strip_indices(elements: dict) -> np.ndarray | None:
    """The concatenated ``vertex_indices`` of a PLY ``tristrips`` element as parsed by trimesh (its ``_ply_raw``
    metadata), strips separated by -1; None when the file has no such element."""
    strips = elements.get("tristrips")
    if not strips or not strips.get("length"):
        return None
    data = strips["data"]
    # binary files parse to a structured array, ASCII ones to a dict of columns
    names = data.keys() if isinstance(data, dict) else (data.dtype.names or ())
    name = next((n for n in ("vertex_indices", "vertex_index") if n in names), None)
    if name is None:
        return None
    parts = []
    for row in data[name]:
        # a binary list is stored as (count, values); an ASCII one as the values
        values = row["f1"] if getattr(row, "dtype", None) is not None and row.dtype.names else row
        parts.append(np.asarray(values, dtype=np.int64).reshape(-1))
        parts.append(np.array([-1], np.int64))
    return np.concatenate(parts)


# ---------------------------------------------------------------------------------------------------------- numbers
def non_finite_location(path: Path) -> str | None:
    header = read_ply_header(path)
    # trimesh keeps the raw elements; read them again only to name the first bad one
    import trimesh

    loaded = trimesh.load(str(path), process=False)
    raw = loaded.metadata.get("_ply_raw") or {}
    for element in header.elements:
        data = (raw.get(element.name) or {}).get("data")
        if data is None:
            continue
        names = list(data.keys()) if isinstance(data, dict) else list(data.dtype.names or ())
        for name in names:
            column = np.asarray(data[name])
            if column.dtype.kind != "f" or column.dtype.names or not column.size:
                continue
            column = column.reshape(len(column), -1)  # ASCII PLY reads (n, 1) columns, binary (n,)
            with np.errstate(invalid="ignore"):
                bad = (~np.isfinite(column) | (np.abs(column) > FLOAT32_MAX)).any(axis=1)
            if bad.any():
                index = int(np.argmax(bad))
                value = column[index][~np.isfinite(column[index]) | (np.abs(column[index]) > FLOAT32_MAX)][0]
                return f"{element.name} {index}: property '{name}' is {float(value)!r}, not a finite float32 number"
    return None
