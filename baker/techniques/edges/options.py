"""Options of the edges technique: one frozen dataclass feeds the CLI flags, recipe keys and the Python API."""
from __future__ import annotations

from dataclasses import dataclass

from baker.options import opt


@dataclass(frozen=True)
class EdgesOptions:
    """Options of the edge-adjacency bake (``--bakes edges``)."""

    crease_angle: float = opt(60.0, "angle between face normals above which an edge is a crease, in degrees",
                              min=0.0, max=180.0)
    planar_angle: float = opt(0.01, "angle between face normals below which an edge is planar (never a contour), "
                                    "in degrees", min=0.0, max=180.0)
    weld_tolerance: float = opt(1e-6, "vertices closer than this x the bounding-box diagonal are one position",
                                min=0.0)
    quad_angle: float = opt(30.0, "largest angle between face normals of a quad diagonal hidden in the wireframe "
                                  "mask, in degrees", min=0.0, max=180.0)
    hard_uv_seams: bool = opt(False, "draw UV seams as hard edges in EXT_mesh_primitive_edge_visibility")
    visibility: bool = opt(True, "write EXT_mesh_primitive_edge_visibility (2 bits per triangle edge)")
    edge_list: bool = opt(True, "write the BAKER_edges edge list: vertex pairs, flags, angles")
    # off by default (compact files): v2, v3 are the third vertices of the faces holding (v0, v1) and (v1, v0), so a
    # reader rebuilds them from the triangles and the edge list; stored they are as large as the edge list itself
    opposite_vertices: bool = opt(False, "also write BAKER_edges oppositeVertices (each edge's two opposite vertices, "
                                         "derivable from the triangles and the edge list)")
    # off by default (compact files, issue 48): no runtime reads them and the positions, triangles and edge list give
    # them (the angle between the two faces' normals); stored they are 4 bytes per edge
    dihedral_angles: bool = opt(False, "also write BAKER_edges dihedralAngles (each edge's signed angle between its "
                                       "face normals, derivable from the positions and the triangles)")
    outline_normals: bool = opt(True, "write _OUTLINE_NORMAL: one averaged normal per welded position")
    wireframe: str = opt("quad-diagonals", "edges the wireframe mask hides", choices=("quad-diagonals", "planar",
                                                                                      "none", "off"))
    fins: bool = opt(False, "add a fin primitive per primitive (4 vertices per edge, McGuire & Hughes 2004)")
