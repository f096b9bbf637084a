"""Offline caustics: looping, tileable caustic textures from a physical water surface (RTR4 14.5.3)."""
from baker.technique import Technique
from baker.techniques.caustics.options import CausticsOptions

TECHNIQUE = Technique(
    name='caustics',
    summary='looping, tileable water caustic frames projected on every material (BAKER_caustics)',
    options=CausticsOptions,
    run="baker.techniques.caustics.step:run",
    extensions=("baker.techniques.caustics.extension",),
    panels="baker.techniques.caustics.panel:PANELS",
    commands=('baker.techniques.caustics.command',),
)
