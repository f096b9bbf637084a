"""Distance-field glyph atlases (Green 2007; Chlumsky 2015) and text labels: `baker glyphs`, `baker text`."""
from baker.technique import Technique

TECHNIQUE = Technique(
    name='glyphs',
    summary='SDF/PSDF/MSDF/MTSDF glyph atlases and distance-field text (BAKER_glyph_atlas + BAKER_text)',
    extensions=("baker.techniques.glyphs.extension:ATLAS", "baker.techniques.glyphs.extension:TEXT"),
    panels="baker.techniques.glyphs.panel:PANELS",
    commands=('baker.techniques.glyphs.command',),
)
