"""Toon ramps and X-Toon maps (RTR4 15.1; Barla et al. 2006)."""
from baker.technique import Technique
from baker.techniques.toon.options import ToonOptions

TECHNIQUE = Technique(
    name='toon',
    summary='toon ramp or X-Toon map on every material (BAKER_toon_ramp)',
    options=ToonOptions,
    run="baker.techniques.toon.step:run",
    extensions=("baker.techniques.toon.extension",),
    panels="baker.techniques.toon.panel:PANELS",
    commands=('baker.techniques.toon.command',),
)
