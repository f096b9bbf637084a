"""Hair shaded like hair (RTR4 14.7.2): Chiang et al. 2016's fibre model as truth, its baked tables and
``baker hair-lut``, ``BAKER_hair_shading`` on the hair materials of ``baker hair``/``guides``/``cards``, the strands'
rest-pose occlusion, the table lookup ``baker.api.hair_bsdf`` twins, Zinke et al. 2008's dual scattering on the
tables (``baker.api.hair_shade``, :mod:`.dual`; ``runtime-shaders/baker_hair_shading.glsl``/``.wgsl``) and the path
tracer of fibre slabs it is measured against (:mod:`.slab_tracer`)."""
from baker.technique import Technique

TECHNIQUE = Technique(
    name='hair-shading',
    summary="Chiang et al. 2016's hair fibre BSDF (pbrt's HairBxDF) baked into M and N tables (baker hair-lut)",
    extensions=("baker.techniques.hair_shading.extension",),
    commands=('baker.techniques.hair_shading.command',),
)
