"""Tonal art map generation: baker (Praun et al. 2001, nested, best of K) vs a naive random fill, same run.

    python benchmarks/tam.py [--size 256] [--tones 6] [--levels 4] [--repeat 3] [--style hatching]

Rows (best of --repeat, wall clock, numba kernels compiled beforehand):
- baker generate_tam: the full algorithm, K = 16 candidates per stroke scored on every level's image pyramid,
  strokes nested across tones and levels;
- baker generate_tam, K = 1: the same code without the choice among candidates (each stroke is the first random
  one), to show what the scoring costs;
- naive random fill (peer): every (tone, level) filled on its own from blank paper with uniformly random strokes
  (same stroke shapes or dots, same anti-aliased rasterizer, compiled the same way) until its mean darkness reaches
  the same target (one stroke direction, for every style but stippling). It reaches the same tones but nothing is
  nested, so the runtime blend between tones and levels would make strokes pop; it is the cheapest way to get "a
  texture per tone".
End to end: ``baker tam`` (the command a user runs, process start to files written, same options), best of
--repeat, next to the kernel row, with its peak RSS and bytes per output texel (every tone of every level).
Quality columns: max |tone - target| over every (tone, level); nesting violations (share of tone t's inked pixels
not inked in tone t+1, same level); unevenness (std of the darkness of 16 x 16-pixel blocks at the finest level,
darkest tone; lower is more even).
"""
from __future__ import annotations

import argparse
import dataclasses
import math
import os
import sys
import tempfile
from pathlib import Path

import numba
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baker.techniques.tam.options import TamOptions
from baker.techniques.tam.kernel import _stamp, generate_tam  # noqa: E402
from common import baker_cli, best_of, run_command  # noqa: E402


@numba.njit(cache=True, nogil=True)
def _naive_fill(size, target, width, len_lo, len_hi, angle, jitter, curvature, dots, seed):
    """Random strokes on blank paper until the mean darkness reaches ``target`` (no scoring, no nesting)."""
    np.random.seed(seed)
    dark = np.zeros(size * size, np.float64)
    scratch = np.zeros(size * size, np.float64)
    touched = np.empty(size * size, np.int64)
    total = 0.0
    area = float(size * size)
    while total / area < target:
        x, y = np.random.random(), np.random.random()
        a = angle + (2.0 * np.random.random() - 1.0) * jitter
        length = 0.0 if dots else len_lo + (len_hi - len_lo) * np.random.random()
        sag = 0.0 if dots else curvature * (2.0 * np.random.random() - 1.0)
        count = _stamp(x, y, a, length, sag, width, size, scratch, touched, 0)
        gain = 0.0
        for q in range(count):
            p = touched[q]
            delta = scratch[p] * (1.0 - dark[p])
            scratch[p] = 0.0
            gain += delta
        if gain <= 0.0:
            continue  # fell on solid ink
        # stop on the stroke that lands closest to the target, like baker does
        if abs(target - (total + gain) / area) >= abs(target - total / area):
            break
        count = _stamp(x, y, a, length, sag, width, size, scratch, touched, 0)
        for q in range(count):
            p = touched[q]
            delta = scratch[p] * (1.0 - dark[p])
            scratch[p] = 0.0
            dark[p] += delta
            total += delta
    return dark.reshape(size, size)


def naive_tam(options: TamOptions, seed: int) -> list:
    """Darkness (tones, R, R) per level, finest first, each (tone, level) filled independently."""
    targets = options.darkest * np.arange(1, options.tones + 1) / options.tones
    out = []
    for lv in range(options.levels):
        size = options.size >> lv
        out.append(np.stack([_naive_fill(size, float(t), options.stroke_width, *map(float, options.stroke_length),
                                         math.radians(options.angle), math.radians(options.angle_jitter),
                                         options.curvature, options.style == "stippling", seed * 1000 + lv * 100 + i)
                             for i, t in enumerate(targets)]))
    return out


def quality(darkness: list, targets: np.ndarray) -> tuple[float, float, float]:
    quantized = [np.rint((1.0 - d) * 255.0) for d in darkness]
    means = np.array([[1.0 - q[t].mean() / 255.0 for t in range(len(targets))] for q in quantized])
    tone_error = float(np.abs(means - targets).max())
    inked, missing = 0, 0
    for q in quantized:
        for t in range(len(targets) - 1):
            light, dark = q[t] < 255, q[t + 1] < 255
            inked += int(light.sum())
            missing += int((light & ~dark).sum())
    finest = darkness[0][-1]
    blocks = finest.reshape(finest.shape[0] // 16, 16, -1, 16).mean(axis=(1, 3))
    return tone_error, missing / max(inked, 1), float(blocks.std())


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--tones", type=int, default=6)
    ap.add_argument("--levels", type=int, default=4)
    ap.add_argument("--style", default="hatching", choices=("hatching", "cross-hatching", "stippling"))
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    layout = "packed" if args.tones == 6 else "volume"
    options = TamOptions(tones=args.tones, levels=args.levels, size=args.size, style=args.style, layout=layout)
    small = dataclasses.replace(options, size=32, levels=2)
    generate_tam(small, seed=0)  # compile the kernels (numba cache) outside the timings
    naive_tam(small, seed=0)

    rows = []
    t_baker, tam = best_of(args.repeat, lambda: generate_tam(options, seed=0))
    rows.append(("baker generate_tam (K = 16, nested)", t_baker, quality(tam.darkness, tam.targets),
                 len(tam.strokes["x"])))
    k1 = dataclasses.replace(options, candidates=1)
    t_k1, tam1 = best_of(args.repeat, lambda: generate_tam(k1, seed=0))
    rows.append(("baker generate_tam (K = 1, nested)", t_k1, quality(tam1.darkness, tam1.targets),
                 len(tam1.strokes["x"])))
    t_naive, naive = best_of(args.repeat, lambda: naive_tam(options, seed=0))
    rows.append(("naive random fill per (tone, level), not nested", t_naive, quality(naive, tam.targets), None))

    print(f"{args.tones} tones x {args.levels} levels, {args.size} px finest, style {args.style}; "
          f"{os.cpu_count()} cores; best of {args.repeat}\n")
    print("| implementation | time (s) | time vs baker | max tone error | nesting violations | unevenness | strokes |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, seconds, (tone_error, violations, unevenness), strokes in rows:
        print(f"| {name} | {seconds:.3f} | {seconds / t_baker:.2f}x | {tone_error:.4f} | {violations:.1%} | "
              f"{unevenness:.4f} | {strokes if strokes is not None else '-'} |")
    print(f"\nbaker: {t_baker:.2f} s for {args.tones} x {args.levels} at {args.size} px (goal: a few seconds)")

    runs = []
    for _ in range(args.repeat):
        with tempfile.TemporaryDirectory() as out:
            runs.append(run_command(baker_cli("tam", "-o", out, "-q", "--seed", "0", "--tam-tones", args.tones,
                                              "--tam-levels", args.levels, "--tam-size", args.size,
                                              "--tam-style", args.style, "--tam-layout", layout)))
    best = min(runs, key=lambda r: r["wall"])
    texels = args.tones * sum((args.size >> level) ** 2 for level in range(args.levels))
    print("\n| end to end | time (s) | time vs kernel (generate_tam) | peak RSS (MB) | bytes per output texel |")
    print("|---|---:|---:|---:|---:|")
    print(f"| `baker tam -o DIR --tam-tones {args.tones} --tam-levels {args.levels} --tam-size {args.size} "
          f"--tam-style {args.style}` | {best['wall']:.3f} | {best['wall'] / t_baker:.2f}x | "
          f"{max(r['peak'] for r in runs) / 1e6:.0f} | {max(r['peak'] for r in runs) / texels:,.0f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
