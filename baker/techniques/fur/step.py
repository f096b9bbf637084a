"""Wire the fur kernel to an Asset: bake the shell/fin textures once, attach them to every material, and build fin
primitives from the edge adjacency (:mod:`baker.geometry.edges`). The shells tile along TEXCOORD_0, so any layout
works, overlapping or not; a primitive without one is unwrapped with xatlas into a new TEXCOORD_0 (as ``tam`` and
the texture bakes do)."""
from __future__ import annotations

import math

import numpy as np

from baker.geometry.asset import Asset
from baker.techniques.fur.options import FurOptions
from baker.techniques.fur.kernel import bake_fur_textures
from baker.techniques.fur import extension as ext
from baker.progress import QUIET, Progress
from baker.texels.texture_space import unwrap
from baker.texels.targets import reindex_primitive, unwrap_material


def _fins(asset: Asset, m: int, prims: list, tile_size: float):
    """Fin corners, extrusion normals, fin u and edge vertices for each primitive in ``prims`` of mesh ``m``."""
    from baker.geometry.edges import analyze_mesh, primitive_edges

    geoms = [asset.primitive(m, p) for p in asset.triangle_primitives(m)]
    order = asset.triangle_primitives(m)
    positions = np.concatenate([g.positions for g in geoms])
    v_off = np.cumsum([0] + [len(g.positions) for g in geoms])
    f_off = np.cumsum([0] + [len(g.faces) for g in geoms])
    faces = np.concatenate([g.faces + v_off[i] for i, g in enumerate(geoms)])
    group = np.repeat(np.arange(len(geoms)), [len(g.faces) for g in geoms])
    analysis = analyze_mesh(positions, faces, face_group=group)
    out = {}
    for i, p in enumerate(order):
        if p not in prims:
            continue
        pe = primitive_edges(analysis, (int(f_off[i]), int(f_off[i + 1])), (int(v_off[i]), int(v_off[i + 1])))
        normals = pe.outline_normals[pe.edges]  # (E, 2, 3): extrude along the crack-free outline normals
        length = np.linalg.norm(pe.fin_corners[:, 1] - pe.fin_corners[:, 0], axis=1)
        # fin u in tiles: each fin starts at a random-looking but deterministic offset (its edge index), so
        # neighbouring fins do not repeat the same hairs side by side
        start = (np.arange(len(length)) * 0.618034) % 1.0
        fin_u = np.stack([start, start + length / tile_size], axis=1)
        out[p] = (pe.fin_corners, normals, fin_u, pe.edges)
    return out


def run(asset: Asset, options: FurOptions, seed: int = 0, progress: Progress = QUIET) -> None:
    doc = asset.doc
    groups = asset.material_groups()
    furred = {}
    for material, members in groups.items():
        members = [(m, p) for m, p in members if len(asset.primitive(m, p).faces)]
        bare = [(m, p) for m, p in members if 0 not in asset.primitive(m, p).texcoords]
        if bare and len(bare) == len(members):
            # no UVs to tile along: the layout the texture bakes and tam share (once per asset, whichever bake runs
            # first), so fur's output does not depend on which other bakes ran; with no UVs at all it is TEXCOORD_0
            unwrap_material(asset, material, members, seed)
        elif bare:  # some primitives of the material have UVs: only the others get a TEXCOORD_0 of their own
            geoms = [asset.primitive(m, p) for m, p in bare]
            layouts = unwrap([(g.positions, g.faces) for g in geoms], resolution=512, seed=seed)
            for (m, p), (vmap, faces, uv) in zip(bare, layouts):
                reindex_primitive(asset, m, p, vmap, faces, uv, 0)
        if members:
            furred[material] = (members, [asset.primitive(m, p) for m, p in members])
    all_pos = np.concatenate([asset.mesh_triangles(m)[0] for m in range(len(asset.meshes()))])
    diag = float(np.linalg.norm(all_pos.max(0) - all_pos.min(0))) or 1.0
    length = options.length if options.length else 0.02 * diag
    with progress.task("fur textures", 1) as advance:
        textures = bake_fur_textures(options, seed)
        advance(1)
    with progress.task("fur coverage mips", 1) as advance:
        shell_tex, fin_tex, mips = ext.write_fur_textures(
            doc, textures.shells, textures.fin if options.fins else None,
            options.alpha_cutoff if options.coverage_mips else None)
        advance(1)
    for material, (members, geoms) in furred.items():
        # world size of one tile: sqrt(surface area / UV area) / tiling
        area = uv_area = 0.0
        for g in geoms:
            v = g.positions[g.faces]
            area += 0.5 * np.linalg.norm(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), axis=1).sum()
            t = g.texcoords[0][g.faces]
            e1, e2 = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
            uv_area += 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).sum()
        tile_size = float(np.sqrt(area / max(uv_area, 1e-30)) / options.tiling)
        if not (math.isfinite(tile_size) and tile_size > 0):  # zero-area surface or UVs: one tile per bbox diagonal
            tile_size = (diag if diag > 0 else 1.0) / options.tiling
        fins = []
        if options.fins:
            by_mesh = {}
            for m, p in members:
                by_mesh.setdefault(m, []).append(p)
            for m, prims in sorted(by_mesh.items()):
                for p, (corners, normals, fin_u, edges) in sorted(_fins(asset, m, prims, tile_size).items()):
                    fins.append((m, ext.write_fin_primitive(doc, m, p, corners, normals, fin_u, edges)))
        ext.write_material(doc, material, options=options, length=length, shell_textures=shell_tex,
                           fin_texture=fin_tex, fins=fins, coverage=textures.coverage, tile_size=tile_size,
                           coverage_mips=mips)
