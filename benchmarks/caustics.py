"""Offline caustics: frames per second and error against cost, photon splatting vs the Jacobian (area ratio).

    python benchmarks/caustics.py [--repeat 2] [--error-size 128] [--reference-samples 16]

Rows: each estimator of :mod:`baker.techniques.caustics.light` at s x s surface samples per texel (photons: s^2
photons per texel splatted bilinearly; jacobian: the refracted surface mesh with s^2 quads per texel, each floor
triangle's flux over its area point-sampled at texel centres, as Wallace's WebGL Water rasterises it).
Columns:
- frames per second at 256^2 and 512^2 (one frame of the default water: spectrum synthesis, refraction, gather;
  best of --repeat, wall clock, 2 cores);
- error: relative RMS difference, over 4 frames of the loop at --error-size^2, from a converged reference, the
  photon estimator at --reference-samples per texel side (irradiance averaged under the texels' bilinear footprint,
  the quantity a LINEAR-filtered texture stands for), and from the same estimator's own reference at that density
  (self-convergence: the Jacobian converges to point values of an irradiance that is infinite on the caustic lines,
  so it converges slowly even to itself).
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baker.techniques.caustics.kernel import irradiance  # noqa: E402
from baker.techniques.caustics.light import sun_direction  # noqa: E402
from baker.techniques.caustics.options import CausticsOptions, at_scale  # noqa: E402
from baker.techniques.caustics.spectrum import wave_spectrum  # noqa: E402
from common import best_of  # noqa: E402

ROWS = [("photons", 1), ("photons", 2), ("photons", 3), ("photons", 4), ("photons", 6),
        ("jacobian", 1), ("jacobian", 2), ("jacobian", 3)]


def frame(options, spectrum, time, size, method, samples):
    return irradiance(spectrum, time, size=size, samples=samples, depth=options.depth,
                      sun=sun_direction(options.sun_elevation, options.sun_azimuth), ior=options.ior,
                      choppiness=options.choppiness, method=method)


def relative_rms(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)) / np.sqrt(np.mean(b ** 2)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--error-size", type=int, default=128)
    parser.add_argument("--reference-samples", type=int, default=16)
    args = parser.parse_args()

    options = at_scale(CausticsOptions())[0]  # the default water at scale 1 (tile 2 m)
    spectrum = wave_spectrum(options, seed=0)
    times = [f * options.period / 4 for f in range(4)]
    n = args.error_size
    references = {method: [frame(options, spectrum, t, n, method, args.reference_samples) for t in times]
                  for method in ("photons", "jacobian")}
    print(f"water: default options ({options.spectrum}, wind {options.wind_speed} m/s, RMS height "
          f"{options.amplitude} m, {options.waves} waves per side, tile {options.tile_size} m, depth "
          f"{options.depth} m, sun elevation {options.sun_elevation} deg); error over 4 frames at {n}^2 against "
          f"s = {args.reference_samples}; 2 cores; best of {args.repeat}\n")
    print("| estimator | samples per texel | fps 256^2 | fps 512^2 | error vs converged photons | "
          "error vs its own s = %d |" % args.reference_samples)
    print("|---|---:|---:|---:|---:|---:|")
    for method, samples in ROWS:
        fps = []
        for size in (256, 512):
            seconds, _ = best_of(args.repeat, lambda: frame(options, spectrum, 0.0, size, method, samples))
            fps.append(1.0 / seconds)
        estimates = [frame(options, spectrum, t, n, method, samples) for t in times]
        error = np.mean([relative_rms(e, r) for e, r in zip(estimates, references["photons"])])
        own = np.mean([relative_rms(e, r) for e, r in zip(estimates, references[method])])
        print(f"| {method} | {samples}x{samples} | {fps[0]:.1f} | {fps[1]:.2f} | {100 * error:.1f}% | "
              f"{100 * own:.1f}% |", flush=True)


if __name__ == "__main__":
    main()
