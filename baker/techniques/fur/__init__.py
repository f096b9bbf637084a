"""Fur shells and fins (Lengyel et al. 2001; RTR4 14.7.3)."""
from baker.technique import Technique
from baker.techniques.fur.options import FurOptions

TECHNIQUE = Technique(
    name='fur',
    summary='fur shell + fin textures and fin primitives on every material (BAKER_fur)',
    options=FurOptions,
    run="baker.techniques.fur.step:run",
    extensions=("baker.techniques.fur.extension",),
    panels="baker.techniques.fur.panel:PANELS",
)
