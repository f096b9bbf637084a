"""Hair fibre tables (``baker hair-lut``) vs the fibre model they are baked from, and their sizes.

    python benchmarks/hair_lut.py

Truth: Chiang et al. 2016's far field (``baker.techniques.hair_shading.kernel``) averaged over the fibre offset h by
a 512-node midpoint rule. Tables: M and N at three sizes, half float, sampled by the twin (``baker.api.hair_bsdf``'s
bilinear lookups). Error: relative L1 over the sphere of light directions (48 x 96 equal-area midpoints), per view
direction (theta_o in -70..80 degrees, 7 views) and channel; the worst and the mean over views and channels, for
blond, brown and black hair (eumelanin 0.3, 1.3, 8) at beta_m = beta_n = 0.2 and 0.4 (alpha 2 degrees, eta 1.55).
Also white hair's albedo (the integral of S over light directions) at theta_o 0..85 from the tables.
"""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baker.techniques.hair_shading import kernel as K  # noqa: E402
from baker.techniques.hair_shading.extension import lut_files  # noqa: E402
from baker.techniques.hair_shading.options import HairShadingOptions  # noqa: E402
from baker.techniques.hair_shading.tables import as_half, bake_tables, evaluate, sphere_directions  # noqa: E402

SIZES = {"small (M 64, N 32x16x8)": (64, 32, 16, 8), "default (M 128, N 64x32x16)": (128, 64, 32, 16),
         "large (M 256, N 128x64x32)": (256, 128, 64, 32)}




def view(theta_deg):
    t = math.radians(theta_deg)
    return np.array([math.sin(t), math.cos(t) * math.cos(0.3), math.cos(t) * math.sin(0.3)])


def main() -> None:
    lights = sphere_directions(48, 96)
    h = -1 + (np.arange(512) + 0.5) * 2 / 512
    w = np.full(512, 1 / 512)
    views = (-70, -40, -10, 0, 20, 50, 80)
    print("| tables | files (EXR half) | beta | blond worst / mean | brown worst / mean | black worst / mean |")
    print("|---|---|---|---|---|---|")
    for beta in (0.2, 0.4):
        truths = {}
        for eu in (0.3, 1.3, 8.0):
            m = K.FibreModel(K.sigma_a_from_melanin(eu), beta, beta, 2.0, 1.55)
            truths[eu] = [K.scattering(np.ascontiguousarray(np.broadcast_to(view(t), lights.shape)), lights,
                                       m.sigma_a, m.eta, m.v, m.s, m.sin2k, m.cos2k, h, w) for t in views]
        for name, (m_size, n_phi, n_theta, slices) in SIZES.items():
            start = time.perf_counter()
            raw = bake_tables(beta, beta, 1.55, m_size, n_phi, n_theta, slices)
            seconds = time.perf_counter() - start
            tables = as_half(raw)
            files = lut_files(raw, HairShadingOptions(beta_m=beta, beta_n=beta))
            kib = sum(len(d) for _, d in files) / 1024
            cells = []
            for eu in (0.3, 1.3, 8.0):
                errors = []
                for t, truth in zip(views, truths[eu]):
                    got = evaluate(tables, [1, 0, 0], lights, view(t), K.sigma_a_from_melanin(eu), 2.0)
                    errors.append(np.abs(got - truth).sum(0) / truth.sum(0))
                errors = np.array(errors)
                cells.append(f"{100 * errors.max():.2f}% / {100 * errors.mean():.2f}%")
            print(f"| {name} | {kib:.0f} KiB, baked in {seconds:.2f} s | {beta} | " + " | ".join(cells) + " |")
    tables = as_half(bake_tables(0.3, 0.3, 1.55))
    dense = sphere_directions(200, 400)
    albedo = [evaluate(tables, [1, 0, 0], dense, view(t), [0.0, 0.0, 0.0], 2.0)[:, 0].sum() * 4 * math.pi
              / len(dense) for t in (0, 30, 60, 85)]
    print("white hair albedo from the default tables (beta 0.3), theta_o 0/30/60/85:",
          " ".join(f"{a:.4f}" for a in albedo))


if __name__ == "__main__":
    main()
