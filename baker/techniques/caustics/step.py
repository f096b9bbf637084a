"""Wire the caustics generator to an Asset: one frame sequence, ``BAKER_caustics`` on every material; and to a
folder, for the standalone ``baker caustics -o DIR`` (:func:`run_caustics`)."""
from __future__ import annotations

import sys

import numpy as np

from baker.errors import BakerError
from baker.geometry.asset import Asset
from baker.gltf.document import world_nodes
from baker.options import from_args
from baker.progress import QUIET, Progress
from baker.techniques.caustics import extension as ext
from baker.techniques.caustics.options import CausticsOptions, at_scale


def run(asset: Asset, options: CausticsOptions, seed: int = 0, progress: Progress = QUIET) -> None:
    from baker.techniques.caustics.kernel import caustic_frames, check_options

    try:
        check_options(options)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    lo, hi = world_bounds(asset)
    options, water_scale = at_scale(options, float(np.linalg.norm(hi - lo)), (float(lo[1]), float(hi[1])))
    materials = list(asset.material_groups())
    frames = caustic_frames(options, seed=seed)
    textures, scale = ext.write_frame_textures(asset.doc, frames)
    for material in materials:
        ext.write_caustics(asset.doc, material, options, frames, textures, scale, water_scale)


def world_bounds(asset: Asset) -> tuple[np.ndarray, np.ndarray]:
    """The corners (lowest, highest) of the bounding box of every triangle mesh as the default scene places it
    (world units); the meshes' own positions when no node places them; zeros without a triangle."""
    gltf = asset.doc.json
    nodes = gltf.get("nodes", [])
    placed = [(nodes[i]["mesh"], world) for i, world in world_nodes(gltf) if "mesh" in nodes[i]]
    if not placed:
        placed = [(m, np.eye(4)) for m in range(len(asset.meshes()))]
    points = [asset.primitive(m, p).positions @ world[:3, :3].T + world[:3, 3]
              for m, world in placed for p in asset.triangle_primitives(m)]
    points = np.concatenate(points) if points else np.zeros((0, 3))
    if not len(points):
        return np.zeros(3), np.zeros(3)
    return points.min(0), points.max(0)


def run_caustics(args) -> int:
    """``baker caustics -o DIR``: the frames and ``caustics.json`` (optionally ``caustics.ktx2``) in a folder."""
    from baker.gltf.atomic import output_folder
    from baker.techniques.caustics.kernel import caustic_frames, check_options

    folder = output_folder(args.output)
    try:
        options = at_scale(from_args(CausticsOptions, "caustics", args))[0]  # no asset: the tile's scale, else 1
        check_options(options)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    if args.seed < 0:
        raise BakerError(None, f"--seed must be >= 0, got {args.seed}")
    frames = caustic_frames(options, seed=args.seed)
    manifest = ext.write_caustics_directory(options, frames, folder, seed=args.seed, ktx2=args.ktx2)
    if not args.quiet:
        e = frames.irradiance
        print(f"caustics: {manifest['frameCount']} frames of {options.size} x {options.size}, irradiance mean "
              f"{e.mean():.3f} max {e.max():.2f} -> {folder}/caustics.json", file=sys.stderr)
    return 0
