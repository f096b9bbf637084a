"""Dual scattering (``baker.api.hair_shade``) against a path tracer of explicit fibres, and what single scattering
misses.

    python benchmarks/hair_shading.py

Truth: :mod:`baker.techniques.hair_shading.slab_tracer`, slabs of parallel unit-radius fibres (rows ``spacing``
apart centre to centre, ``gap`` between rows, each row shifted by the golden ratio of the spacing) of blond hair
(eumelanin 0.3, beta_m = beta_n = 0.3, alpha 2 degrees, eta 1.55) traced with every bounce (Russian roulette),
80 000 camera rays per figure. ``hair_shade`` is evaluated at each camera ray's first fibre with the number of
fibres its shadow ray crosses (what a baked count or a deep opacity map gives a renderer), with Zinke's density
factors d = 1 (the default) and 0.7 (Zinke's for human hair). Also: the path tracer with at most two bounces, and
single scattering alone (``hair_bsdf`` where the light reaches the fibre unblocked). Radiance toward the viewer per
unit irradiance, averaged over the slab (gaps count as 0), per channel R, G, B.
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import baker.api  # noqa: E402
from baker.techniques.hair_shading import kernel as K  # noqa: E402
from baker.techniques.hair_shading.slab_tracer import Slab  # noqa: E402

VIEW = np.array([0.3, 0.1, 1.0]) / np.linalg.norm([0.3, 0.1, 1.0])
LIGHTS = {"front": (np.array([-0.2, 0.5, 1.0]) / np.linalg.norm([-0.2, 0.5, 1.0]), 8),
          "back": (np.array([-0.2, 0.4, -1.0]) / np.linalg.norm([-0.2, 0.4, -1.0]), 4)}
GEOMETRIES = ((3.0, 2.0), (2.5, 2.0), (4.0, 2.0))
BLOND = dict(eumelanin=0.3, beta_m=0.3, beta_n=0.3, alpha=2.0, eta=1.55)
PATHS = 80000


def rgb(values) -> str:
    return " / ".join(f"{v:.3f}" for v in values)


def main() -> None:
    model = K.FibreModel(K.sigma_a_from_melanin(0.3), 0.3, 0.3, 2.0, 1.55)
    print("| slab (spacing, row gap; rows) | light | path traced R / G / B | hair_shade / traced (d = 1) "
          "| (d = 0.7) | <= 2 bounces / traced | single scattering / traced | trace s |")
    print("|---|---|---|---|---|---|---|---|")
    for spacing, gap in GEOMETRIES:
        for name, (light, layers) in LIGHTS.items():
            slab = Slab(layers, spacing, gap)
            start = time.perf_counter()
            traced, crossed = slab.trace(model, VIEW, light, paths=PATHS)
            seconds = time.perf_counter() - start
            two, _ = slab.trace(model, VIEW, light, paths=PATHS, max_bounces=2)
            hit = crossed >= 0
            ratios = []
            for density in (1.0, 0.7):
                shade = np.zeros_like(traced)
                shade[hit] = baker.api.hair_shade([1, 0, 0], light, VIEW, crossed[hit], density_forward=density,
                                                  density_back=density, **BLOND)
                ratios.append(shade.mean(0) / traced.mean(0))
            single = baker.api.hair_bsdf([1, 0, 0], light, VIEW, **BLOND)[0] * (crossed == 0).mean()
            error = traced.std(0) / np.sqrt(len(traced)) / traced.mean(0)
            print(f"| {spacing:g}, {gap:g}; {layers} | {name} | {rgb(traced.mean(0))} (+- {100 * error.max():.1f}%) "
                  f"| {rgb(ratios[0])} | {rgb(ratios[1])} | {rgb(two.mean(0) / traced.mean(0))} "
                  f"| {rgb(single / traced.mean(0))} | {seconds:.1f} |")


if __name__ == "__main__":
    main()
