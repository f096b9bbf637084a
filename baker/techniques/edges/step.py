"""Wire the edge kernel to an Asset: per glTF mesh, gather its triangle primitives, analyze, write per primitive.

All triangle primitives of a mesh are analyzed together (edges between primitives are material edges and shells
close across them); each primitive then gets its own data in its own vertex indices. The EXT bitfield covers every
triangle of the primitive in glTF order, so triangles with a repeated index (which the kernel skips) get code 0.
"""
from __future__ import annotations

import numpy as np

from baker.geometry.asset import Asset
from baker.techniques.edges.options import EdgesOptions
from baker.geometry.edges import analyze_mesh, primitive_edges
from baker.texels.targets import made_by_unwrap
from baker.techniques.edges import extension as ext
from baker.progress import QUIET, Progress


def is_fin_primitive(prim: dict) -> bool:
    return "finsOf" in ((prim.get("extensions") or {}).get(ext.NAME) or {})


def _corner_attribute(asset: Asset, prim: dict, key: str, faces: np.ndarray, width: int) -> np.ndarray:
    from baker.gltf.accessors import to_float

    acc = (prim.get("attributes") or {}).get(key)
    if acc is None:
        return np.full((len(faces), 3, width), np.nan)
    return to_float(asset.doc, acc)[faces][..., :width]


def run(asset: Asset, options: EdgesOptions, seed: int = 0, progress: Progress = QUIET) -> None:
    doc = asset.doc
    for m, mesh in enumerate(asset.meshes()):
        prims = mesh.get("primitives", [])
        if options.fins:  # a re-bake replaces the fins of an earlier one (they are appended at the end)
            while prims and is_fin_primitive(prims[-1]):
                prims.pop()
        members = []  # (primitive index, positions, all triangles, kept mask)
        for p in asset.triangle_primitives(m):
            prim = prims[p]
            if is_fin_primitive(prim):
                continue
            positions = asset.primitive(m, p).positions
            indices = doc.accessor(prim["indices"]).astype(np.int64) if "indices" in prim else \
                np.arange(len(positions))
            triangles = ext.all_triangles(indices, prim.get("mode", 4))
            keep = ((triangles[:, 0] != triangles[:, 1]) & (triangles[:, 1] != triangles[:, 2])
                    & (triangles[:, 0] != triangles[:, 2]))
            if keep.any():
                members.append((p, positions, triangles, keep))
        if not members:
            continue
        v_off = np.cumsum([0] + [len(x[1]) for x in members])
        f_off = np.cumsum([0] + [int(x[3].sum()) for x in members])
        if len(members) == 1:  # the common large case: no copies, and no material edges to look for
            positions = members[0][1]
            faces = members[0][2] if members[0][3].all() else members[0][2][members[0][3]]
            group = None
        else:
            positions = np.concatenate([x[1] for x in members])
            faces = np.concatenate([x[2][x[3]] + v_off[i] for i, x in enumerate(members)])
            # a face's group: its primitive, so faces drawn by different primitives (materials) meet at material
            # edges
            group = np.repeat(np.arange(len(members)), np.diff(f_off))
        # per-corner attributes only where a primitive has them: no seam work on a mesh without UVs or normals
        # a layout baker made (an unwrap for a texture bake that ran first) is not the mesh's: its seams are not
        # UV seams of the asset, and the edges baked alone would not see them
        has_uv = any("TEXCOORD_0" in (prims[p].get("attributes") or {}) and not made_by_unwrap(asset, m, p, 0)
                     for p, *_ in members)
        has_normals = all("NORMAL" in (prims[p].get("attributes") or {}) for p, *_ in members)
        uv = np.concatenate([_corner_attribute(asset, prims[p], "TEXCOORD_0", t[k], 2) for p, _, t, k in members]) \
            if has_uv else None
        normals = np.concatenate([_corner_attribute(asset, prims[p], "NORMAL", t[k], 3) for p, _, t, k in members]) \
            if has_normals else None
        with progress.task(f"edges mesh {m}", 1) as advance:
            analysis = analyze_mesh(positions, faces, face_group=group, corner_uv=uv, corner_normals=normals,
                                    options=options)
            advance(1)
        del uv, normals, positions, faces, group
        for i, (p, pos, triangles, keep) in enumerate(members):
            pe = primitive_edges(analysis, (int(f_off[i]), int(f_off[i + 1])), (int(v_off[i]), int(v_off[i + 1])),
                                 options, fins=options.fins)
            # back to every triangle of the primitive (repeated-index triangles: hidden, not in the wireframe)
            codes = np.zeros((len(triangles), 3), np.uint8)
            codes[keep] = pe.visibility_codes
            wire = np.zeros(len(triangles), np.uint8)
            wire[keep] = pe.wireframe_mask
            pe.visibility_codes, pe.wireframe_mask = codes, wire
            written = None
            if options.visibility:
                written = ext.write_edge_visibility(doc, m, p, codes, pe.silhouette_mates, len(pos))
            if options.outline_normals:
                ext.write_outline_normals(doc, m, p, pe.outline_normals)
            fins = ext.write_fin_primitive(doc, m, p, pe) if options.fins and len(pe.edges) else None
            ext.write_primitive_edges(doc, m, p, pe, options=options, vertex_count=len(pos), fins=fins, outline=options.outline_normals,
                                      visibility=written is not None)
