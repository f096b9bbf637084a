"""Checks on OBJ, PLY and STL files that run before (and after) trimesh reads them, and a direct reader for the
common large case (a binary PLY of triangles: scans, sculpts, subdivided meshes).

Before: a count written in a header is not trusted. A PLY header's element counts and a binary STL's triangle count
are compared with the size of the file; a count the file cannot hold (``element vertex 1000000000000`` in a 200-byte
file, a binary STL whose count disagrees with its length, a binary PLY cut short) is refused before any array is
allocated. Only the header is read (a few hundred bytes), so a 10^12-vertex claim is refused in microseconds.

After: the numbers read are numbers. :func:`non_finite_location` names where a NaN, an infinity or a value beyond
float32 (what glTF stores; it would become an infinity there) sits in the file: the OBJ line, the PLY element index,
the STL triangle.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from baker.errors import BakerError

PLY_TYPES = {"char": 1, "int8": 1, "uchar": 1, "uint8": 1, "short": 2, "int16": 2, "ushort": 2, "uint16": 2,
             "int": 4, "int32": 4, "uint": 4, "uint32": 4, "float": 4, "float32": 4, "double": 8, "float64": 8}
PLY_HEADER_LIMIT = 1 << 20  # a header longer than 1 MiB is not a PLY header
STL_HEADER = 84  # 80 bytes of text + uint32 triangle count
STL_RECORD = 50  # normal, 3 vertices (12 float32) + uint16 attribute
FLOAT32_MAX = 3.4028234663852886e38


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


def check_mesh_file(path) -> dict:
    """Refuse an OBJ/PLY/STL whose header promises more than the file holds. Returns the counts the header gives
    (``{"vertices": n, "faces": m}`` for PLY and binary STL, ``{}`` otherwise) for the memory estimate."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".ply":
        header = check_ply(path)
        counts = {e.name: e.count for e in header.elements}
        return {"vertices": counts.get("vertex", 0), "faces": counts.get("face", 0) + counts.get("tristrips", 0)}
    if suffix == ".stl":
        return check_stl(path)
    return {}


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


def check_stl(path: Path) -> dict:
    """A binary STL's triangle count against its size; ASCII STL (starting with ``solid``) has no count."""
    size = path.stat().st_size
    with open(path, "rb") as f:
        head = f.read(STL_HEADER)
    if len(head) == STL_HEADER:
        count = int.from_bytes(head[80:84], "little")
        if STL_HEADER + STL_RECORD * count == size:
            return {"vertices": 3 * count, "faces": count}
    if head.lstrip().lower().startswith(b"solid"):
        return {}  # ASCII (or a binary file with a 'solid' header and a wrong count: trimesh tries both)
    if len(head) < STL_HEADER:
        raise BakerError(path, f"binary STL shorter than its {STL_HEADER}-byte header ({size} bytes)")
    needed = STL_HEADER + STL_RECORD * count
    problem = "truncated file or a corrupt count" if needed > size else "trailing data or a corrupt count"
    raise BakerError(path, f"binary STL header says {count} triangles ({needed} bytes) but the file has {size} "
                           f"bytes: {problem}")


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
    import numpy as np

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


# ---------------------------------------------------------------------------------------------------------- numbers
def _bad(value: float) -> bool:
    return not math.isfinite(value) or abs(value) > FLOAT32_MAX


OBJ_KEYS = {b"v": "vertex position", b"vn": "normal", b"vt": "texture coordinate", b"vp": "parameter value"}
# a token float() could read as non-finite or beyond float32: nan, inf(inity), or an exponent of 39 or more digits
_SUSPECT = re.compile(rb"(?i)nan|inf|e\+?0*(?:39|[4-9]\d|\d{3,})")


def non_finite_location(path) -> str | None:
    """Where the first non-finite number of an OBJ/PLY/STL file is (``line 12: vertex position 'nan'``), or None."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".obj":
        return _obj_location(path)
    if suffix == ".ply":
        return _ply_location(path)
    if suffix == ".stl":
        return _stl_location(path)
    return None


def _obj_location(path: Path) -> str | None:
    data = path.read_bytes()
    if not _SUSPECT.search(data):  # one C-speed pass; only a suspect file is walked line by line
        return None
    for number, line in enumerate(data.split(b"\n"), start=1):
        words = line.split()
        if not words or words[0] not in OBJ_KEYS or not _SUSPECT.search(line):
            continue
        for word in words[1:]:
            try:
                value = float(word)
            except ValueError:
                continue
            if _bad(value):
                return f"line {number}: {OBJ_KEYS[words[0]]} {word.decode(errors='replace')!r} is not a finite " \
                       "float32 number"
    return None


def _ply_location(path: Path) -> str | None:
    import numpy as np

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


def _stl_location(path: Path) -> str | None:
    import numpy as np
    import trimesh

    loaded = trimesh.load(str(path), process=False)
    vertices = np.asarray(getattr(loaded, "vertices", np.zeros((0, 3))), np.float64)
    with np.errstate(invalid="ignore"):
        bad = ~np.isfinite(vertices).all(axis=1) | (np.abs(vertices) > FLOAT32_MAX).any(axis=1)
    if bad.any():
        return f"triangle {int(np.argmax(bad)) // 3}: a vertex coordinate is not a finite float32 number"
    return None
