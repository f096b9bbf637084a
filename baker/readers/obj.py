"""A direct, vectorized reader for the common Wavefront OBJ (what DCC tools and scanners write): ``v``/``vt``/``vn``
lines and polygon ``f`` lines, grouped by ``usemtl``. The file is read once; its lines are classified by their first
bytes and every number is converted in one ``numpy.fromstring`` per kind, so no Python work is done per line and no
trimesh (nor scipy) is imported.

The result is what trimesh's OBJ reader (``process=False``) gives for the same file, so the document built from it
is the one the trimesh path builds: one mesh per ``usemtl`` material in trimesh's order (the reverse of first use)
and with its names, vertices split where the (v, vt, vn) index triples differ and ordered as trimesh orders them
(the unique triples sorted by vn, vt, v, then by v), quads split as trimesh splits them, UVs and the file's normals
as they are, and, when the faces reference none, angle-weighted vertex normals (trimesh's arithmetic) computed
over all groups welded by position (:func:`seamless_vertex_normals`; the trimesh path of
:mod:`baker.geometry.asset` computes the same), split only between ``s`` smoothing groups, which trimesh ignores.

**What falls back to trimesh** (:func:`read_obj_groups` returns None; decided by the same scan, before any number
is converted): a line whose first word is anything but ``v vt vn f usemtl mtllib o g s`` or a comment (``l``, ``p``,
``vp``, free-form ``curv``/``surf``/``cstype``..., indented lines, tab after the keyword); ``v`` lines that are not
exactly 3 numbers (vertex colours, ``w``); ``vt`` lines not all 2 or all 3 numbers; ``vn`` lines not 3 numbers; face
corners written in more than one form (``v``, ``v/vt``, ``v//vn``, ``v/vt/vn``) or a face of fewer than 3 corners;
a number that does not parse (a trailing comment, ``1.5`` as an index); line continuations (``\\``), a lone
``\\r``; an ``s`` line other than one non-negative integer or ``off`` in a file without normals; ``usemtl``
anywhere but at the start of a line; no faces at all (points only: trimesh's error); text that is not UTF-8 in a
name.

**Where it is stricter than trimesh**: a face index (v, vt or vn) of 0 or out of range is refused naming the line
(trimesh raises for positions but silently drops out-of-range UVs or normals); negative indices count back from the
line's position as the OBJ specification says (trimesh counts them from the end of the file, the same thing only
when every vertex is written before the first face; the vertex order then differs from trimesh's). Mesh names
use the file's name where trimesh writes the path as given (an unnamed usemtl group of a multi-mesh file), so the
output does not depend on the folder; a group without an MTL material gets the dielectric even when the MTL
defines trimesh's placeholder name ``material_0``. Past 2^20 distinct indices (v/vt/vn faces) trimesh orders the
split vertices by their bytes; this reader keeps the numeric order, so such a mesh matches it up to vertex order.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from baker import memory
from baker.errors import BakerError
from baker.geometry.angle_normals import seamless_vertex_normals, unit_normals, unitize
from baker.gltf.accessors import MODE_TRIANGLES
from baker.gltf.document import GltfDocument
from baker.readers.finite import is_bad, refuse_non_finite
from baker.readers.mtl import MissingFileWarning, assign_materials, read_obj_materials

# line kinds: v/vt/vn/f numbers are converted in bulk; usemtl and o names (few) are read one by one
BLANK, COMMENT, V, VT, VN, F, USEMTL, MTLLIB, OBJECT, GROUP, SMOOTH = range(11)
KEYWORDS = ((b"v ", V), (b"vt ", VT), (b"vn ", VN), (b"f ", F), (b"usemtl ", USEMTL), (b"mtllib ", MTLLIB),
            (b"o ", OBJECT), (b"g ", GROUP), (b"s ", SMOOTH), (b"#", COMMENT))
PREFIX = max(len(k) for k, _ in KEYWORDS)
SPACE, TAB, NEWLINE, SLASH = 32, 9, 10, 47


@dataclass
class ObjGroup:
    """The faces of one ``usemtl`` material as one triangle mesh (trimesh's per-material mesh)."""

    name: str  # the mesh and node name trimesh gives it
    material: str | None  # the ``usemtl`` name, None before any
    positions: np.ndarray  # (n, 3) float64
    faces: np.ndarray  # (m, 3) int64
    texcoords: np.ndarray | None  # (n, 2) float64, OBJ's v (up)
    normals: np.ndarray | None  # (n, 3) float64: the file's (as written), or None when the faces reference none
    # (n,) int64 smoothing set of each vertex when the faces reference no normals and the file's ``s`` lines make
    # more than one set (faces under ``s off`` / ``s 0`` each make their own); None: one set, smooth everywhere
    smoothing: np.ndarray | None = None


def read(path: Path, allow_outside=None, max_memory: int | None = None) -> GltfDocument:
    """An OBJ and its MTL materials as a glTF document: read directly when the file is plain (:func:`read_direct`),
    else by trimesh. ``max_memory``: bytes the reading may need (:func:`baker.memory.check_file`; None: no limit)."""
    memory.check_file(path, max_memory)
    # the MTL files are read once for both readers (a missing one is one warning)
    materials, libraries = read_obj_materials(path, allow_outside)
    doc = read_direct(path, materials)
    if doc is None:
        from baker.readers.trimesh_scene import LibraryResolver, doc_from_trimesh_scene, load_trimesh

        loaded = load_trimesh(path, resolver=LibraryResolver(libraries))
        doc = doc_from_trimesh_scene(path, loaded, materials, non_finite_location)
    return doc


def references(path: Path, allow_outside=None) -> list[Path]:
    """The files the OBJ's result depends on: its .mtl files and the textures they name, as :func:`read` resolves
    them. A missing file or an MTL error is the bake's to report, not this listing's."""
    import warnings

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", MissingFileWarning)
            materials, libraries = read_obj_materials(path, allow_outside)
    except BakerError:
        return []
    return libraries + [t.path for m in materials.values() for t in m.textures.values()]


def read_obj_groups(path, material_names) -> list[ObjGroup] | None:
    """The OBJ at ``path`` as :class:`ObjGroup` s in trimesh's order, or None when the file needs trimesh (module
    docstring). ``material_names`` are the materials its ``mtllib`` files define (they decide the mesh names, as
    in trimesh). Bad face indices raise :class:`BakerError` naming the line."""
    path = Path(path)
    data = path.read_bytes()
    if b"\r" in data:
        data = data.replace(b"\r\n", b"\n")
        if b"\r" in data:
            return None
    if b"\\\n" in data or data.rstrip().endswith(b"\\"):
        return None
    lines = _Lines(data)
    if lines.kind is None or not (lines.kind == F).any():
        return None
    if data.count(b"usemtl") != int((lines.kind == USEMTL).sum()):
        return None  # trimesh splits at 'usemtl ' anywhere (a comment, a name): leave those files to it
    try:
        v = lines.numbers(V, np.float64, (3,))
        vt = lines.numbers(VT, np.float64, (2, 3))
        vn = lines.numbers(VN, np.float64, (3,))
        corners = lines.face_corners()
    except ValueError:
        return None
    if v is None or corners is None:
        return None
    names = lines.names()
    if names is None:
        return None
    smoothing = None
    if vn is None:
        smoothing = lines.smoothing_sets()
        if smoothing is False:
            return None
    return _groups(path, lines, v, vt, vn, corners, names, set(material_names), smoothing)


class _Lines:
    """The file's lines as offsets into one byte array, each classified by its first word."""

    def __init__(self, data: bytes):
        self.data = data
        buf = np.frombuffer(data + b"\n", np.uint8)
        ends = np.flatnonzero(buf == NEWLINE)
        starts = np.concatenate([[0], ends[:-1] + 1])
        if data.endswith(b"\n"):  # the appended newline made an empty last line
            ends, starts = ends[:-1], starts[:-1]
        self.starts, self.ends = starts, ends
        head = np.zeros((len(starts), PREFIX), np.uint8)
        for j in range(PREFIX):
            inside = starts + j < ends
            head[inside, j] = buf[starts[inside] + j]
        kind = np.full(len(starts), -1, np.int8)
        for keyword, code in KEYWORDS:
            match = np.ones(len(starts), bool)
            for j, byte in enumerate(keyword):
                match &= head[:, j] == byte
            kind[match & (kind < 0)] = code
        kind[(starts == ends) & (kind < 0)] = BLANK
        for row in np.flatnonzero(kind < 0):  # spaces and tabs only are blank too; anything else: not ours
            if data[starts[row]:ends[row]].strip(b" \t"):
                break
            kind[row] = BLANK
        self.kind = None if (kind < 0).any() else kind
        # the bytes with each data line's keyword blanked, so the numbers of a kind are one selection away
        self.work = buf.copy()
        for keyword, code in KEYWORDS[:4]:
            first = starts[kind == code]
            for j in range(len(keyword)):
                self.work[first + j] = SPACE
        self.span = ends - starts + 1  # with the newline

    def rows(self, code: int) -> np.ndarray:
        return np.flatnonzero(self.kind == code)

    def _bytes(self, code: int) -> np.ndarray:
        """The bytes of every line of ``code`` (keyword blanked), each ending in its newline."""
        mask = np.zeros(len(self.work), bool)
        mask[:int(self.span.sum())] = np.repeat(self.kind == code, self.span)
        return self.work[mask]

    def numbers(self, code: int, dtype, widths: tuple) -> np.ndarray | None:
        """The numbers of every ``code`` line as an (n, width) array, width one of ``widths`` for every line; None
        without such lines. ValueError when a line holds another count or something else."""
        count = int((self.kind == code).sum())
        if not count:
            return None
        picked = self._bytes(code)
        counts = _tokens_per_line(picked, count)
        width = int(counts[0])
        if width not in widths or (counts != width).any():
            raise ValueError("ragged")
        values = np.fromstring(picked.tobytes(), dtype=dtype, sep=" ")
        if len(values) != width * count:
            raise ValueError("unparsed")
        return values.reshape(count, width)

    def face_corners(self) -> dict | None:
        """Every face corner's indices as written and the faces' sizes: ``{"v"/"vt"/"vn": (c,) int64, "sizes":
        corners per face line, "rows": the face lines}``; None when the corner forms are mixed or a face has fewer
        than 3 corners. ValueError when an index does not parse."""
        rows = self.rows(F)
        picked = self._bytes(F)
        sizes = _tokens_per_line(picked, len(rows))
        if (sizes < 3).any():
            return None
        newlines = np.flatnonzero(picked == NEWLINE)
        slash = picked == SLASH
        slashes = np.bincount(np.searchsorted(newlines, np.flatnonzero(slash)), minlength=len(rows))
        doubled = np.flatnonzero(slash[:-1] & slash[1:])
        double = np.bincount(np.searchsorted(newlines, doubled), minlength=len(rows))
        per = slashes // sizes
        if (slashes != per * sizes).any() or (per != per[0]).any() or per[0] > 2:
            return None
        form = int(per[0])  # 0: v, 1: v/vt, 2: v/vt/vn; -2: v//vn
        if form == 2 and (double == sizes).all():
            form = -2
        elif double.any():
            return None
        picked[slash] = SPACE
        named = {0: ("v",), 1: ("v", "vt"), 2: ("v", "vt", "vn"), -2: ("v", "vn")}[form]
        values = np.fromstring(picked.tobytes(), dtype=np.int64, sep=" ")
        if len(values) != len(named) * int(sizes.sum()):
            raise ValueError("unparsed")
        values = values.reshape(-1, len(named))
        out = {name: values[:, i] for i, name in enumerate(named)}
        out.update(sizes=sizes, rows=rows)
        return out

    def names(self) -> dict | None:
        """The text after the keyword of every usemtl and o line, by line index (None: not UTF-8)."""
        found = {}
        for code, strip in ((USEMTL, 6), (OBJECT, 1)):
            for row in self.rows(code):
                try:
                    found[int(row)] = self.data[self.starts[row] + strip:self.ends[row]].decode("utf-8").strip()
                except UnicodeDecodeError:
                    return None
        return found


    def smoothing_sets(self):
        """The smoothing set of every face line (``s N`` lines, OBJ spec B1.5): faces after ``s N`` (N > 0) share
        set N, faces after ``s off`` / ``s 0`` are each a set of their own (flat), faces before any ``s`` line share
        one set. Dense int64 ids per face line; None when that makes one set (no ``s`` lines, or one group
        throughout); False for an ``s`` line that is not one non-negative integer or ``off`` (trimesh reads it)."""
        rows = self.rows(SMOOTH)
        if not len(rows):
            return None
        values = [-1]  # before any s line
        for row in rows:
            word = self.data[self.starts[row] + 2:self.ends[row]].strip(b" \t")
            if word == b"off":
                values.append(0)
            elif word.isdigit() and len(word) < 19:
                values.append(int(word))
            else:
                return False
        faces = self.rows(F)
        key = np.asarray(values, np.int64)[np.searchsorted(rows, faces, side="right")]
        flat = key == 0
        key[flat] = -2 - np.flatnonzero(flat)  # each flat face its own set
        ids, dense = np.unique(key, return_inverse=True)
        return None if len(ids) == 1 else dense.reshape(-1)


def _tokens_per_line(picked: np.ndarray, count: int) -> np.ndarray:
    """Whitespace-separated words in each of the ``count`` newline-terminated lines of ``picked``."""
    space = (picked == SPACE) | (picked == TAB) | (picked == NEWLINE)
    starts = np.flatnonzero(~space & np.concatenate([[True], space[:-1]]))
    return np.bincount(np.searchsorted(np.flatnonzero(picked == NEWLINE), starts), minlength=count)


def _resolve(path: Path, raw: np.ndarray, defined_before: np.ndarray, total: int, line: np.ndarray,
             what: str) -> np.ndarray:
    """OBJ indices (1-based; negative counts back from the ``what`` lines above the face) as 0-based, checked
    against the ``total`` the file defines."""
    index = np.where(raw < 0, defined_before + raw, raw - 1)
    bad = (raw == 0) | (index < 0) | (index >= total)
    if bad.any():
        at = int(np.argmax(bad))
        count, where = (int(defined_before[at]), " above it") if raw[at] < 0 else (total, "")
        raise BakerError(path, f"line {int(line[at]) + 1}: face index {int(raw[at])} is out of range ({count} "
                               f"'{what}' lines{where}; indices start at 1)")
    return index


def _groups(path: Path, lines: _Lines, v, vt, vn, corners: dict, names: dict, materials: set,
            smoothing: np.ndarray | None) -> list[ObjGroup]:
    sizes, rows = corners["sizes"], corners["rows"]
    corner_line = np.repeat(rows, sizes)  # the file line of each corner, for errors and relative indices
    columns = {}
    if smoothing is not None:  # a vertex used by faces of two smoothing sets needs a normal for each
        columns["s"] = np.repeat(smoothing, sizes)
    for key, values, code in (("v", v, V), ("vt", vt, VT), ("vn", vn, VN)):
        if key in corners:
            before = np.searchsorted(lines.rows(code), corner_line)  # lines of that kind above each corner
            columns[key] = _resolve(path, corners[key], before, 0 if values is None else len(values), corner_line,
                                    key)

    # a face belongs to the last usemtl above it; trimesh groups the faces by material in order of first use and
    # makes its meshes in the reverse order
    usemtl_rows = lines.rows(USEMTL)
    section = np.searchsorted(usemtl_rows, rows, side="right") - 1  # -1: before any usemtl
    material_of_section = [None] + [names[int(r)] for r in usemtl_rows]
    order, group_of_face, seen = [], np.empty(len(rows), np.int64), {}
    for s in np.unique(section):  # a few sections; their faces are assigned in bulk
        material = material_of_section[s + 1]
        if material not in seen:
            seen[material] = len(order)
            order.append(material)
        group_of_face[section == s] = seen[material]
    # trimesh names its meshes after the object only when the first of these statements is an 'o'
    directives = np.flatnonzero(np.isin(lines.kind, (F, USEMTL, OBJECT, GROUP, SMOOTH)))
    object_name = names.get(int(directives[0])) if lines.kind[directives[0]] == OBJECT else None

    corner_start = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    groups, taken = [], set()
    for g in reversed(range(len(order))):
        material = order[g]
        faces_here = np.flatnonzero(group_of_face == g)
        group_sizes = sizes[faces_here]
        local_start = np.concatenate([[0], np.cumsum(group_sizes)[:-1]])
        within = np.arange(int(group_sizes.sum())) - np.repeat(local_start, group_sizes)
        group_corners = np.repeat(corner_start[faces_here], group_sizes) + within
        keys = [k for k in ("v", "vt", "vn", "s") if k in columns]
        faces, picked = _split_vertices([columns[k][group_corners] for k in keys],
                                        _triangulate(local_start, group_sizes))
        picked = dict(zip(keys, picked))
        if len(order) == 1:
            name = path.name  # trimesh.load names a single mesh after the file
        elif len(materials) > 1 and material is not None:
            name = material
        else:  # trimesh would write the path as given (a folder name in the output): the file name only
            name = object_name if object_name is not None else path.name
        name = _unique_name(name, taken)
        taken.add(name)
        groups.append(ObjGroup(name, material, v[picked["v"]], faces,
                               vt[picked["vt"], :2] if "vt" in picked else None,
                               vn[picked["vn"]] if "vn" in picked else None, picked.get("s")))
    return groups


def _triangulate(first: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """(m, 3) corner indices of the faces starting at corners ``first`` with ``sizes`` corners, split as trimesh
    splits them: a section of quads only as every (0, 1, 2) then every (2, 3, 0); otherwise face by face, quads as
    (0, 1, 2), (2, 3, 0) and larger polygons as fans (0, i, i + 1)."""
    if (sizes == 4).all():
        quads = first[:, None] + np.arange(4)
        return np.concatenate([quads[:, [0, 1, 2]], quads[:, [2, 3, 0]]])
    count = sizes - 2
    face = np.repeat(np.arange(len(sizes)), count)
    step = np.arange(int(count.sum())) - np.repeat(np.cumsum(count) - count, count)
    base = first[face]
    triangles = np.column_stack([base, base + step + 1, base + step + 2])
    second_of_quad = (sizes[face] == 4) & (step == 1)
    triangles[second_of_quad] = triangles[second_of_quad][:, [1, 2, 0]]
    return triangles


def _split_vertices(columns: list, triangles: np.ndarray) -> tuple[np.ndarray, list]:
    """One vertex per distinct (v[, vt][, vn]) tuple of the corners ``columns`` hold, in trimesh's order: the tuples
    sorted with the last index most significant, then (numpy's default sort, as trimesh's) by position index.
    Returns ``triangles`` (corner numbers) on the new vertices and, per column, the index each new vertex takes."""
    stack = np.column_stack(columns)
    bits = [max(int(c.max()), 1).bit_length() for c in columns]
    if sum(bits) <= 62:  # one integer per tuple, the last index in the highest bits
        key = np.zeros(len(stack), np.int64)
        shift = 0
        for column, width in zip(columns, bits):
            key |= column << shift
            shift += width
        _, first, inverse = np.unique(key, return_index=True, return_inverse=True)
    else:
        _, first, inverse = np.unique(stack[:, ::-1], axis=0, return_index=True, return_inverse=True)
    tuples = stack[first]
    order = tuples[:, 0].argsort()
    remap = np.empty(len(order), np.int64)
    remap[order] = np.arange(len(order))
    return remap[inverse.reshape(-1)][triangles], list(tuples[order].T)


def _unique_name(name: str, taken: set) -> str:
    """``name``, or ``name_1``, ``name_2``... when taken (trimesh's rule for geometry names)."""
    if name and name not in taken:
        return name
    i = 1
    while f"{name}_{i}" in taken:
        i += 1
    return f"{name}_{i}"


def read_direct(path: Path, materials: dict) -> GltfDocument | None:
    """An OBJ the direct reader takes, as the document :func:`baker.readers.trimesh_scene.doc_from_trimesh_scene`
    makes of trimesh's reading:
    one mesh and node per usemtl group, accessors laid out as trimesh's glTF exporter lays them out (identical
    arrays share a bufferView or an accessor), vertex normals made unit by :func:`unit_normals`, then as trimesh's
    exporter does; None when the file needs trimesh. ``materials``: the file's MTL materials by name
    (:func:`baker.readers.mtl.read_obj_materials`)."""
    groups = read_obj_groups(path, materials)
    if groups is None:
        return None
    doc = GltfDocument(json={"scene": 0, "scenes": [{"nodes": list(range(len(groups)))}],
                             "asset": {"version": "2.0", "generator": "baker (converted from obj)"}}, path=path)
    views: dict = {}
    accessors: dict = {}

    def add(array, role: str) -> int:
        data = array.tobytes()
        target = 34963 if role == "indices" else 34962
        if (data, target) not in views:
            views[data, target] = doc.add_buffer_view(data, target=target)
        if (data, role) not in accessors:
            blob = {"componentType": 5125 if role == "indices" else 5126}
            if role == "normal":
                blob["count"] = len(array)
            blob["type"] = {"indices": "SCALAR", "uv": "VEC2"}.get(role, "VEC3")
            if role != "indices":
                blob["byteOffset"] = 0
            blob["bufferView"] = views[data, target]
            blob["count"] = len(array)
            flat = array.reshape(len(array), -1)
            blob["max"] = flat.max(axis=0).tolist()
            blob["min"] = flat.min(axis=0).tolist()
            doc.json.setdefault("accessors", []).append(blob)
            accessors[data, role] = len(doc.json["accessors"]) - 1
        return accessors[data, role]

    for group in groups:
        check_finite(path, group)
    computed = {}
    without_normals = [i for i, group in enumerate(groups) if group.normals is None]
    if without_normals:  # the file has no normals: one smooth surface across its material groups and UV seams
        with np.errstate(all="ignore"):
            parts = [(groups[i].positions, groups[i].faces, groups[i].smoothing) for i in without_normals]
            computed = dict(zip(without_normals, seamless_vertex_normals(parts)))
    meshes, by_mesh = [], {}
    for index, group in enumerate(groups):
        normals = group.normals if group.normals is not None else computed[index]
        primitive = {"attributes": {}, "indices": add(group.faces.astype(np.uint32).reshape(-1), "indices"),
                     "mode": MODE_TRIANGLES}
        primitive["attributes"]["POSITION"] = add(group.positions.astype(np.float32), "position")
        mtl = materials.get(group.material)
        if group.texcoords is not None:
            uv = group.texcoords.copy()
            uv[:, 1] = 1.0 - uv[:, 1]  # OBJ's v runs up, glTF's down
            primitive["attributes"]["TEXCOORD_0"] = add(uv.astype(np.float32), "uv")
        # trimesh's exporter unitizes the normals once more (a last-bit change on some)
        primitive["attributes"]["NORMAL"] = add(unitize(unit_normals(normals)).astype(np.float32), "normal")
        by_mesh[len(meshes)] = mtl
        meshes.append({"name": group.name, "extras": {}, "primitives": [primitive]})
    doc.json["meshes"] = meshes
    doc.json["nodes"] = [{"name": m["name"], "mesh": i} for i, m in enumerate(meshes)]
    # the converted GLB's key order, so the output's bytes are the trimesh path's
    layout = ("scene", "scenes", "asset", "accessors", "meshes", "nodes", "buffers", "bufferViews")
    ordered = {key: doc.json.pop(key) for key in layout}
    doc.json.update(ordered)
    assign_materials(doc, by_mesh)
    return doc


def check_finite(path: Path, group: ObjGroup) -> None:
    """Refuse NaN, infinite or beyond-float32 positions, UVs or normals, naming the line."""
    for name, values in (("POSITION", group.positions), ("TEXCOORD_0", group.texcoords), ("NORMAL", group.normals)):
        if values is not None:
            refuse_non_finite(path, values, name, non_finite_location)


# ---------------------------------------------------------------------------------------------------------- numbers
OBJ_KEYS = {b"v": "vertex position", b"vn": "normal", b"vt": "texture coordinate", b"vp": "parameter value"}
# a token float() could read as non-finite or beyond float32: nan, inf(inity), or an exponent of 39 or more digits
_SUSPECT = re.compile(rb"(?i)nan|inf|e\+?0*(?:39|[4-9]\d|\d{3,})")


def non_finite_location(path: Path) -> str | None:
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
            if is_bad(value):
                return f"line {number}: {OBJ_KEYS[words[0]]} {word.decode(errors='replace')!r} is not a finite " \
                       "float32 number"
    return None
