"""STL files, read by trimesh (:mod:`baker.readers.trimesh_scene`). A binary STL's triangle count is checked against
the file's size before anything is allocated; an STL's facets carry their normals, so the mesh stays faceted."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from baker import memory
from baker.errors import BakerError
from baker.gltf.document import GltfDocument
from baker.readers.finite import FLOAT32_MAX

STL_HEADER = 84  # 80 bytes of text + uint32 triangle count
STL_RECORD = 50  # normal, 3 vertices (12 float32) + uint16 attribute


def read(path: Path, allow_outside=None, max_memory: int | None = None) -> GltfDocument:
    """An STL as a glTF document: its triangle count checked (:func:`check_stl`) and against ``max_memory`` bytes
    (:func:`baker.memory.check_file`; None: no limit), then read by trimesh."""
    from baker.readers.trimesh_scene import doc_from_trimesh_scene, load_trimesh

    memory.check_file(path, max_memory, check_stl(path))
    return doc_from_trimesh_scene(path, load_trimesh(path), None, non_finite_location)


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


def non_finite_location(path: Path) -> str | None:
    """The STL triangle holding the first NaN, infinite or beyond-float32 coordinate, or None."""
    from baker.readers.trimesh_scene import load_trimesh

    loaded = load_trimesh(path)
    vertices = np.asarray(getattr(loaded, "vertices", np.zeros((0, 3))), np.float64)
    with np.errstate(invalid="ignore"):
        bad = ~np.isfinite(vertices).all(axis=1) | (np.abs(vertices) > FLOAT32_MAX).any(axis=1)
    if bad.any():
        return f"triangle {int(np.argmax(bad)) // 3}: a vertex coordinate is not a finite float32 number"
    return None
