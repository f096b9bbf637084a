"""Hair cards from a groom (RTR4 14.7.1): clumps -> alpha-tested quad ribbons + a strand atlas (BAKER_hair_cards)."""
from baker.technique import Technique

TECHNIQUE = Technique(
    name='cards',
    summary='hair cards from a groom: clump ribbons + strand atlas, alpha-tested (BAKER_hair_cards)',
    extensions=("baker.techniques.cards.extension",),
    panels="baker.techniques.cards.panel:PANELS",
    commands=('baker.techniques.cards.command',),
)
