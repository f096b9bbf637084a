"""The scalp (emitter) mesh of a hair file: ``baker hair`` writes its emitter beside the strands, and ``baker guides``
and ``baker cards`` carry it to their outputs from here (or from ``--scalp MESH``)."""
from __future__ import annotations

import numpy as np

from baker.errors import BakerError
def read_scalp(path, max_memory: int | None = None, required: bool = False):
    """The scalp (emitter) mesh a file holds, as a one-mesh glTF document in world space (its node has no
    transform, like the groom's curves): the triangles of the first mesh with any, primitives merged, positions and
    (when every primitive has them) normals. None when the file has no triangles (a groom of curves only); with
    ``required`` a file that cannot be read as a mesh is an error.

    A ``baker hair`` output holds its emitter mesh beside the strands; ``baker guides`` and ``baker cards`` carry it
    to their outputs from here (or from ``--scalp MESH``)."""
    from pathlib import Path

    from baker import readers
    from baker.gltf.document import GltfDocument, world_nodes

    if Path(path).suffix.lower() not in readers.READERS:  # TressFX: strands only
        return None
    try:
        asset = readers.read(path, max_memory=max_memory, require_triangles=False)
    except BakerError:
        if required:
            raise
        return None  # a groom of curves only (the USD reader finds no mesh): no scalp
    gltf = asset.doc.json
    drawn = {}
    for node, matrix in world_nodes(gltf):  # the first node drawing a mesh places it
        mesh = gltf["nodes"][node].get("mesh")
        if mesh is not None:
            drawn.setdefault(mesh, matrix)
    for mesh in sorted(drawn):
        prims = [asset.primitive(mesh, p) for p in asset.triangle_primitives(mesh)]
        prims = [g for g in prims if len(g.faces)]
        if not prims:
            continue
        matrix = drawn[mesh]
        if abs(np.linalg.det(matrix[:3, :3])) < 1e-300:
            raise BakerError(path, f"the node drawing the scalp mesh {mesh} has a singular transform")
        offsets = np.cumsum([0] + [len(g.positions) for g in prims])
        positions = np.concatenate([g.positions for g in prims]) @ matrix[:3, :3].T + matrix[:3, 3]
        faces = np.concatenate([g.faces + offsets[i] for i, g in enumerate(prims)])
        if np.linalg.det(matrix[:3, :3]) < 0:  # a mirroring node: keep the triangles facing out
            faces = faces[:, ::-1]
        attributes = {"POSITION": positions.astype(np.float32)}
        if all(g.normals is not None for g in prims):
            normals = np.concatenate([g.normals for g in prims]) @ np.linalg.inv(matrix[:3, :3])
            normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)
            attributes["NORMAL"] = normals.astype(np.float32)
        name = (gltf.get("meshes") or [{}])[mesh].get("name") or "scalp"
        return GltfDocument.from_triangles(path, name, attributes, faces.reshape(-1).astype(np.uint32), "baker")
    return None
