"""Pre-integrated skin LUTs (Penner 2011, RTR4 14.6.3) and `baker skin-lut`; reads curvature's attribute when both are baked."""
from baker.technique import Technique
from baker.techniques.skin.options import SkinOptions

TECHNIQUE = Technique(
    name='skin',
    summary="Penner's pre-integrated skin LUTs on every material (BAKER_skin_lut)",
    options=SkinOptions,
    run="baker.techniques.skin.step:run",
    extensions=("baker.techniques.skin.extension",),
    panels="baker.techniques.skin.panel:PANELS",
    commands=('baker.techniques.skin.command',),
    requires=('curvature',),
)
