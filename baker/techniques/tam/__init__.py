"""Tonal art maps for real-time hatching (Praun et al. 2001; volume TAM, Webb et al. 2002; RTR4 15.3)."""
from baker.technique import Technique
from baker.techniques.tam.options import TamOptions

TECHNIQUE = Technique(
    name='tam',
    summary='tonal art map for real-time hatching on every material (BAKER_tonal_art_map)',
    options=TamOptions,
    run="baker.techniques.tam.step:run",
    extensions=("baker.techniques.tam.extension",),
    panels="baker.techniques.tam.panel:PANELS",
    commands=('baker.techniques.tam.command',),
    requires=('curvature',),  # reads its principal directions when both are baked
    splits_vertices=True,  # the stroke TEXCOORD set (--tam-strokes field)
)
