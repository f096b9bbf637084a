"""Edge adjacency, crease/contour classes, outline normals and fins (RTR4 15.2; McGuire & Hughes 2004), and `baker lines`."""
from baker.technique import Technique
from baker.techniques.edges.options import EdgesOptions

TECHNIQUE = Technique(
    name='edges',
    summary='edge adjacency, classes, outline normals, fins (BAKER_edges + EXT_mesh_primitive_edge_visibility)',
    options=EdgesOptions,
    run="baker.techniques.edges.step:run",
    extensions=("baker.techniques.edges.extension",),
    panels="baker.techniques.edges.panel:PANELS",
    commands=('baker.techniques.edges.command',),
)
