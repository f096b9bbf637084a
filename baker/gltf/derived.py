"""Primitives baker appends to a mesh (edge fins, fur fins) fitted to the rules the mesh's own primitives set.

glTF asks every primitive of a mesh to have the same number of morph targets (Khronos:
MESH_PRIMITIVES_UNEQUAL_TARGETS_COUNT). A derived primitive on a morphing mesh gets as many targets as its
siblings, each a POSITION delta of zeros held by one accessor with no bufferView (glTF reads it as zeros, so it costs
no bytes): the derived geometry stays where it was baked while the mesh morphs.

On a skinned mesh a derived primitive carries the ``JOINTS_n``/``WEIGHTS_n`` of the source vertices each of its
vertices was built from, so it deforms with the skin (and every primitive of the mesh has the same joint sets, as
Khronos asks: MESH_PRIMITIVES_UNEQUAL_JOINTS_COUNT).
"""
from __future__ import annotations

import numpy as np

from baker.gltf.document import GltfDocument


def match_morph_targets(doc: GltfDocument, mesh: int, primitive: dict, vertex_count: int) -> None:
    """Give ``primitive`` (about to be appended to ``mesh``) the morph target count of the mesh's primitives."""
    siblings = doc.json["meshes"][mesh].get("primitives", [])
    counts = [len(p.get("targets") or []) for p in siblings]
    count = max(counts, default=0)
    if not count or "targets" in primitive:
        return
    accessors = doc.json.setdefault("accessors", [])
    accessors.append({"componentType": 5126, "count": int(vertex_count), "type": "VEC3",
                      "min": [0.0, 0.0, 0.0], "max": [0.0, 0.0, 0.0]})
    zeros = len(accessors) - 1
    primitive["targets"] = [{"POSITION": zeros} for _ in range(count)]


def copy_skinning(doc: GltfDocument, mesh: int, source: int, primitive: dict, source_vertices: np.ndarray) -> None:
    """Give ``primitive`` (derived from primitive ``source`` of ``mesh``) the joint sets of the source: vertex ``k``
    gets the ``JOINTS_n`` and ``WEIGHTS_n`` of source vertex ``source_vertices[k]``, stored as the source stores them
    (component type, normalization)."""
    attributes = doc.json["meshes"][mesh]["primitives"][source].get("attributes") or {}
    accessors = doc.json["accessors"]
    for name in sorted(attributes):
        if name.startswith(("JOINTS_", "WEIGHTS_")):
            values = doc.accessor(attributes[name])[np.asarray(source_vertices, np.int64)]
            primitive["attributes"][name] = doc.add_accessor(
                values, normalized=bool(accessors[attributes[name]].get("normalized")))
