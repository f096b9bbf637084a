"""Per-vertex curvature by adjacent-normal cubic fitting (Goldfeather & Interrante 2004) with tensor smoothing (Rusinkiewicz 2004)."""
from baker.technique import Technique
from baker.techniques.curvature.options import CurvatureOptions

TECHNIQUE = Technique(
    name='curvature',
    summary='per-vertex mean/principal curvature by quadric fitting (_CURVATURE + BAKER_curvature)',
    options=CurvatureOptions,
    run="baker.techniques.curvature.step:run",
    extensions=("baker.techniques.curvature.extension",),
    transfers=True,
)
