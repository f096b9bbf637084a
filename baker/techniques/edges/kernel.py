"""The edges bake's kernel: one glTF mesh's triangle primitives -> each primitive's edge data.

Edge topology and classes are mesh geometry (:mod:`baker.geometry.edges`: adjacency over welded positions, dihedral
angles, creases, seams, outline normals, fin corners), shared with the fur bake's fins; this module is what the
edges bake adds on top: all triangle primitives of a mesh analyzed together (edges between primitives are material
edges, and shells close across them), then each primitive's own data in its own vertex indices, with the
``EXT_mesh_primitive_edge_visibility`` codes and the wireframe mask covering every triangle of the primitive in glTF
order (a triangle with a repeated index, which the analysis skips, gets code 0 and no wireframe edge).
"""
from __future__ import annotations

import numpy as np

from baker.geometry.edge_codes import EdgeSettings
from baker.geometry.edges import PrimitiveEdges, analyze_mesh, primitive_edges


def mesh_edges(parts: list, corner_uv, corner_normals,
               settings: EdgeSettings, fins: bool) -> list[PrimitiveEdges]:
    """Edge data of one mesh's triangle primitives, in their order.

    ``parts``: per primitive ``(positions (n, 3), triangles (t, 3) in its own vertex indices, keep (t,) bool: the
    triangles without a repeated index)``; ``corner_uv`` / ``corner_normals``: the kept triangles' per-corner UVs
    (f, 3, 2) and normals (f, 3, 3) over all parts in order, or functions returning them (called only when some
    position is held by several vertices: no seam is possible otherwise), or None where no seam is looked for.
    ``settings``: the crease, planar and seam thresholds (the edges bake's options fit, by name); ``fins``: build fin
    corners."""
    v_off = np.cumsum([0] + [len(positions) for positions, _, _ in parts])
    f_off = np.cumsum([0] + [int(keep.sum()) for _, _, keep in parts])
    if len(parts) == 1:  # the common large case: no copies, and no material edges to look for
        positions, triangles, keep = parts[0]
        faces = triangles if keep.all() else triangles[keep]
        group = None
    else:
        positions = np.concatenate([p for p, _, _ in parts])
        faces = np.concatenate([t[k] + v_off[i] for i, (_, t, k) in enumerate(parts)])
        # a face's group: its primitive, so faces drawn by different primitives (materials) meet at material edges
        group = np.repeat(np.arange(len(parts)), np.diff(f_off))
    analysis = analyze_mesh(positions, faces, face_group=group, corner_uv=corner_uv, corner_normals=corner_normals,
                            options=settings)
    del corner_uv, corner_normals, positions, faces, group  # the analysis holds what the primitives need
    found = []
    for i, (_, triangles, keep) in enumerate(parts):
        pe = primitive_edges(analysis, (int(f_off[i]), int(f_off[i + 1])), (int(v_off[i]), int(v_off[i + 1])),
                             settings, fins=fins)
        codes = np.zeros((len(triangles), 3), np.uint8)
        codes[keep] = pe.visibility_codes
        wire = np.zeros(len(triangles), np.uint8)
        wire[keep] = pe.wireframe_mask
        pe.visibility_codes, pe.wireframe_mask = codes, wire
        found.append(pe)
    return found
