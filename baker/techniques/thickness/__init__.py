"""Local thickness for translucency: AO of the inverted normals (Barré-Brisebois & Bouchard, GDC 2011; RTR4 eq. 14.30)."""
from baker.technique import Technique
from baker.techniques.thickness.options import ThicknessOptions

TECHNIQUE = Technique(
    name='thickness',
    summary='local thickness per vertex and texel (KHR_materials_volume + BAKER_thickness)',
    options=ThicknessOptions,
    run="baker.techniques.thickness.step:run",
    extensions=("baker.techniques.thickness.extension",),
    panels="baker.techniques.thickness.panel:PANELS",
    transfers=True,
)
