"""glTF and GLB files: the container and JSON checked and read by :class:`baker.gltf.document.GltfDocument` (byte
ranges, URIs kept inside the asset's folder), Draco / meshopt geometry decompressed into plain accessors; or, as a
groom, the strands of its line primitives."""
from __future__ import annotations

import json
import urllib.parse
from pathlib import Path

import numpy as np

from baker.errors import BakerError
from baker.gltf.compression import decompress
from baker.gltf.document import GltfDocument, world_nodes
from baker.readers.groom import Groom, concat_curves

MODE_LINES, MODE_LINE_STRIP = 1, 3


def read(path: Path, allow_outside=None, max_memory: int | None = None) -> GltfDocument:
    """The document as it is (buffers are read as they are: no memory estimate before it), decompressed
    (``asset.extras.baker.decompressed`` says what was)."""
    doc = GltfDocument.load(path, allow_outside=allow_outside)
    decompress(doc)
    return doc


def references(path: Path, allow_outside=None) -> list[Path]:
    """The external buffers and images a .gltf names (``data:`` URIs are inside it), as paths beside it; a file
    that does not parse references nothing (the bake reports it)."""
    try:
        gltf = json.loads(path.read_text())
    except (ValueError, UnicodeDecodeError):
        return []
    found = []
    for item in gltf.get("buffers", []) + gltf.get("images", []):
        uri = item.get("uri") if isinstance(item, dict) else None
        if uri and not uri.startswith("data:"):
            found.append(path.parent / urllib.parse.unquote(uri))
    return found


def line_chains(segments: np.ndarray, vertex_count: int) -> list[np.ndarray]:
    """Polylines (vertex index arrays, first vertex = the one no segment enters) of a LINES segment list in which
    every vertex starts at most one segment and ends at most one; raises ValueError otherwise."""
    a, b = segments[:, 0], segments[:, 1]
    if len(a) == 0:
        return []
    if (np.bincount(a, minlength=vertex_count) > 1).any() or (np.bincount(b, minlength=vertex_count) > 1).any():
        raise ValueError("LINES segments branch (a vertex starts or ends two segments): not a set of strands")
    following = np.full(vertex_count, -1, np.int64)
    following[a] = b
    entered = np.zeros(vertex_count, bool)
    entered[b] = True
    roots = np.flatnonzero((following >= 0) & ~entered)
    chains = [[r] for r in roots.tolist()]
    current = roots.copy()
    alive = np.arange(len(roots))
    steps = 0
    while len(alive):
        current = following[current]
        keep = current >= 0
        alive, current = alive[keep], current[keep]
        for i, c in zip(alive.tolist(), current.tolist()):
            chains[i].append(c)
        steps += 1
        if steps > vertex_count:
            raise ValueError("LINES segments form a cycle")
    return [np.asarray(c, np.int64) for c in chains]


def read_groom(path) -> Groom:
    """The strands of every ``LINES``/``LINE_STRIP`` primitive drawn by a node of the default scene, in world space.
    A mesh with ``BAKER_hair`` children contributes its children only (its guides are a subset of what they show)."""
    doc = GltfDocument.load(path)
    gltf = doc.json
    meshes = gltf.get("meshes") or []
    parts = []
    for node, matrix in world_nodes(gltf):
        m = (gltf["nodes"][node]).get("mesh")
        if m is None or not (0 <= m < len(meshes)):
            continue
        prims = meshes[m].get("primitives") or []
        hair = [(prim.get("extensions") or {}).get("BAKER_hair") for prim in prims]
        has_children = any(isinstance(h, dict) and h.get("strandSet") == "children" for h in hair)
        scale = abs(float(np.linalg.det(matrix[:3, :3]))) ** (1.0 / 3.0)
        for p, prim in enumerate(prims):
            mode = prim.get("mode", 4)
            if mode not in (MODE_LINES, MODE_LINE_STRIP):
                continue
            ext = hair[p] if isinstance(hair[p], dict) else None
            if ext is not None and has_children and ext.get("strandSet") != "children":
                continue
            where = f"/meshes/{m}/primitives/{p}"
            if "POSITION" not in prim.get("attributes", {}):
                raise BakerError(path, f"{where}/attributes: a line primitive without POSITION")
            positions = np.asarray(doc.accessor(prim["attributes"]["POSITION"]), np.float64).reshape(-1, 3)
            positions = positions @ matrix[:3, :3].T + matrix[:3, 3]
            n = len(positions)
            if ext is not None:
                s, v = ext.get("strandCount"), ext.get("verticesPerStrand")
                if not (isinstance(s, int) and isinstance(v, int)) or s < 1 or v < 1 or s * v != n:
                    raise BakerError(path, f"{where}/extensions/BAKER_hair: strandCount x verticesPerStrand does "
                                           f"not match POSITION count {n}")
                scales = np.ones(s)
                if isinstance(ext.get("widthScale"), int) and 0 <= ext["widthScale"] < len(gltf["accessors"]):
                    scales = np.asarray(doc.accessor(ext["widthScale"]), np.float64).reshape(-1)
                    if len(scales) != s:
                        raise BakerError(path, f"{where}/extensions/BAKER_hair/widthScale: {len(scales)} values "
                                               f"for {s} strands")
                t = np.tile(np.linspace(0.0, 1.0, v), s)
                root, tip = float(ext.get("rootWidth", 0.0)), float(ext.get("tipWidth", 0.0))
                widths = (root + (tip - root) * t) * np.repeat(scales, v) * scale
                parts.append((positions, np.full(s, v, np.int64), widths))
                continue
            if "indices" in prim:
                index = np.asarray(doc.accessor(prim["indices"]), np.int64).reshape(-1)
                if len(index) and (index.min() < 0 or index.max() >= n):
                    raise BakerError(path, f"{where}/indices: index out of range of POSITION ({n})")
            else:
                index = np.arange(n, dtype=np.int64)
            if mode == MODE_LINE_STRIP:
                chains = [index] if len(index) else []
            else:
                try:
                    chains = line_chains(index[: len(index) // 2 * 2].reshape(-1, 2), n)
                except ValueError as exc:
                    raise BakerError(path, f"{where}/indices: {exc}") from None
            if chains:
                order = np.concatenate(chains)
                parts.append((positions[order], np.array([len(c) for c in chains], np.int64), None))
    return concat_curves(parts, path)
