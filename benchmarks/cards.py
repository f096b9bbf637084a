"""Hair cards (issue 30): coverage per mip level of alpha-tested textures, with and without the coverage-preserving
chain (Castaño 2010; RTR4 14.7.1). (The cards-vs-strands silhouette section belongs to the cards branch.)

    python benchmarks/cards.py [--repeat 3]

coverage_per_mip(): for baker's fur shells (the defaults: 16 shells of 128^2; the innermost, a middle and an outer
shell), the fur fin texture and a synthetic hair-card texture (60 antialiased strands 0.6-1.2 texels wide on 256^2),
the fraction of texels whose alpha passes the cutoff (0.5) at every level, for the chain baker ships
(baker.gltf.alpha_mips.alpha_mip_chain) and for the plain box chain (the same area filter, alpha not scaled: what
mipmapping the PNG gives), plus the same levels' coverage under bilinear sampling (4 x 4 samples per texel,
baker.gltf.alpha_mips.bilinear_coverage: what a GPU's LINEAR filter sees). Time: building the chain against
building the box chain (the same filter without the binary search), best of --repeat.
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baker.gltf.alpha_mips import (alpha_mip_chain, bilinear_coverage, level_sizes,  # noqa: E402
                                   levels_off_coverage)
from baker.techniques.fur.kernel import bake_fur_textures  # noqa: E402
from baker.techniques.fur.options import FurOptions  # noqa: E402
from common import best_of  # noqa: E402

CUTOFF = 0.5


def hair_card_texture(size: int = 256, strands: int = 60, seed: int = 3) -> np.ndarray:
    """Antialiased strands along gentle random curves, 0.6-1.2 texels wide: a hair card atlas region."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:size, 0:size] + 0.5
    alpha = np.zeros((size, size))
    for _ in range(strands):
        x0, amp, freq, phase = rng.uniform(0, size), rng.uniform(2, 12), rng.uniform(1, 3), rng.uniform(0, 2 * math.pi)
        width = rng.uniform(0.6, 1.2)
        centre = x0 + amp * np.sin(freq * 2 * math.pi * y / size + phase)
        alpha = np.maximum(alpha, np.clip(width / 2 - np.abs(x - centre) + 0.5, 0, 1) * (y < rng.uniform(0.5, 1) * size))
    out = np.zeros((size, size, 4), np.uint8)
    out[..., :3] = (89, 56, 31)
    out[..., 3] = np.rint(alpha * 255)
    return out


def textures() -> list[tuple[str, np.ndarray, str]]:
    fur = bake_fur_textures(FurOptions(), seed=0)
    return [(f"fur shell {i} of 16 (128^2)", fur.shells[i], "gamma2.2") for i in (0, 7, 12)] + \
        [(f"fur fin ({fur.fin.shape[1]} x {fur.fin.shape[0]})", fur.fin, "gamma2.2"),
         ("hair card texture (256^2)", hair_card_texture(), "srgb")]


def coverage_per_mip(repeat: int = 3) -> list[dict]:
    """One row per texture: coverage per level (texel fraction and bilinear) of the preserving and the box chain,
    the levels (down to 8 x 8) more than 10% (or one texel) off level 0's, and the build times."""
    rows = []
    for name, rgba, transfer in textures():
        sizes = level_sizes(*rgba.shape[:2])
        t_chain, chain = best_of(repeat, lambda: alpha_mip_chain(rgba, CUTOFF, transfer=transfer))
        t_box, box = best_of(repeat, lambda: alpha_mip_chain(rgba, CUTOFF, transfer=transfer, preserve_coverage=False))
        rows.append({
            "name": name, "sizes": sizes, "chain": chain.coverage, "box": box.coverage, "scales": chain.scales,
            "chain_bilinear": [bilinear_coverage(lv[..., 3], CUTOFF) for lv in chain.levels],
            "box_bilinear": [bilinear_coverage(lv[..., 3], CUTOFF) for lv in box.levels],
            "chain_off": levels_off_coverage(chain.coverage, sizes), "box_off": levels_off_coverage(box.coverage, sizes),
            "seconds_chain": t_chain, "seconds_box": t_box})
    return rows


def _percent(values, sizes, down_to=2):
    return " / ".join(f"{100 * v:.1f}" for v, (h, w) in zip(values, sizes) if min(h, w) >= down_to)


def print_coverage_table(rows, repeat: int) -> None:
    """The RESULTS.md table of :func:`coverage_per_mip`'s rows."""
    print(f"alpha cutoff {CUTOFF}; coverage in % of texels per level, level 0 first, down to 2 texels on the short "
          f"side; 'off': levels down to 8 x 8 more than 10% (or one texel) from level 0; best of {repeat}, "
          "2 cores\n")
    print("| texture | chain | texel coverage per level (%) | levels off | bilinear coverage per level (%) | "
          "build (ms) |")
    print("|---|---|---|---|---|---:|")
    for r in rows:
        for kind in ("chain", "box"):
            label = "coverage-preserving" if kind == "chain" else "box (plain mips)"
            print(f"| {r['name']} | {label} | {_percent(r[kind], r['sizes'])} | "
                  f"{len(r[kind + '_off'])} {r[kind + '_off'] or ''} | {_percent(r[kind + '_bilinear'], r['sizes'])} | "
                  f"{1000 * r['seconds_' + kind]:.1f} |", flush=True)
    print()
    for r in rows:
        print(f"{r['name']}: chain build {r['seconds_chain'] / r['seconds_box']:.1f}x the box chain's time; "
              f"alpha scales {' '.join(f'{s:.2f}' for s in r['scales'])}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print_coverage_table(coverage_per_mip(args.repeat), args.repeat)


if __name__ == "__main__":
    main()
