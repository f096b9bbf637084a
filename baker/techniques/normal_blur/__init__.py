"""Diffuse normal maps blurred on the surface with a diffusion profile, and texture-space diffusion data (RTR4 14.6.2, 14.6.4)."""
from baker.technique import Technique
from baker.techniques.normal_blur.options import NormalBlurOptions

TECHNIQUE = Technique(
    name='normal-blur',
    summary="per-channel diffuse normal maps convolved on the surface with the skin profile, UV stretch map "
            "(BAKER_normal_blur)",
    options=NormalBlurOptions,
    run="baker.techniques.normal_blur.step:run",
    extensions=("baker.techniques.normal_blur.extension",),
    panels="baker.techniques.normal_blur.panel:PANELS",
)
