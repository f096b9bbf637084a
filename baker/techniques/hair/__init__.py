"""Hair guide strands and children (RTR4 14.7): `baker hair`, glTF LINES + BAKER_hair, USD BasisCurves, TressFX."""
from baker.technique import Technique

TECHNIQUE = Technique(
    name='hair',
    summary='hair guide strands and interpolated children grown on an emitter (BAKER_hair)',
    extensions=("baker.techniques.hair.extension",),
    panels="baker.techniques.hair.panel:PANELS",
    commands=('baker.techniques.hair.command',),
)
