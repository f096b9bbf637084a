"""Wire the caustics generator to an Asset: one frame sequence, ``BAKER_caustics`` on every material."""
from __future__ import annotations

import numpy as np

from baker.geometry.asset import Asset
from baker.gltf.document import world_nodes
from baker.progress import QUIET, Progress
from baker.techniques.caustics import extension as ext
from baker.techniques.caustics.options import CausticsOptions, at_scale


def run(asset: Asset, options: CausticsOptions, seed: int = 0, progress: Progress = QUIET) -> None:
    from baker.techniques.caustics.kernel import caustic_frames, check_options

    try:
        check_options(options)
    except ValueError as exc:
        from baker.errors import BakerError

        raise BakerError(None, str(exc)) from None
    options, water_scale = at_scale(options, world_diagonal(asset))
    materials = list(asset.material_groups())
    frames = caustic_frames(options, seed=seed)
    textures, scale = ext.write_frame_textures(asset.doc, frames)
    for material in materials:
        ext.write_caustics(asset.doc, material, options, frames, textures, scale, water_scale)


def world_diagonal(asset: Asset) -> float:
    """The diagonal of the bounding box of every triangle mesh as the default scene places it (world units); the
    meshes' own positions when no node places them."""
    gltf = asset.doc.json
    nodes = gltf.get("nodes", [])
    placed = [(nodes[i]["mesh"], world) for i, world in world_nodes(gltf) if "mesh" in nodes[i]]
    if not placed:
        placed = [(m, np.eye(4)) for m in range(len(asset.meshes()))]
    points = [asset.primitive(m, p).positions @ world[:3, :3].T + world[:3, 3]
              for m, world in placed for p in asset.triangle_primitives(m)]
    points = np.concatenate(points) if points else np.zeros((0, 3))
    return float(np.linalg.norm(points.max(0) - points.min(0))) if len(points) else 0.0
