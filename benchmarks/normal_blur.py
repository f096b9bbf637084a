"""Surface normal blur: time per channel at 1024^2 and 2048^2 against a UV-space Gaussian filter of the same kernels
(the naive floor), and both's error against a brute-force surface convolution on a small case.

    python benchmarks/normal_blur.py [--repeat 1] [--sizes 1024,2048] [--small 96] [--radius 0.08]

Timing: a torus of radii --radius and half that (0.08 m: 0.126 m^2, a head's area; both UV directions wrap) sampled
at every texel centre, analytically (positions, texel areas |dP/du x dP/dv| / texels, tangent frames), carrying a
4 mm plane-wave bump along u and v. Error: a UV sphere (u = longitude, v = colatitude, one seam, poles), bump of 4 mm
along the meridians and 47 waves around each latitude circle. Profile: d'Eon & Luebke's
skin (6 Gaussians, mm -> m).

- baker: :func:`baker.techniques.normal_blur.kernel.blur_normals` (direct gather for Gaussians up to 1.5 texel
  spacings, sparse lattice of one sigma above; the error table also shows a lattice of 0.5 sigma) for all three
  channels; per channel = total / 3 (the Gaussians are shared).
- peer: ``scipy.ndimage.gaussian_filter`` of the tangent-space map, per channel the sum of its Gaussians (sigma in
  texels from the mean texel size sqrt(area) / size, wrap in u, nearest in v), renormalized; per channel as timed.
- error: RMS and max angle (degrees) between each method's three maps and the brute-force surface convolution
  (every texel pair, no cut-off, same area weights) on a --small^2 sphere of radius 0.02 m.
Wall clock, best of --repeat, 2 shared cores.
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baker.techniques.normal_blur.kernel import TangentFrames, blur_normals  # noqa: E402
from baker.diffusion_profile import DEON_SKIN  # noqa: E402
from common import best_of  # noqa: E402


def sphere_texels(size: int, radius: float):
    """Texel-centre samples of a UV sphere: positions, areas, frames, the bump's tangent-space normals (n, 3) and
    the same normals as a (size, size, 3) image."""
    centres = (np.arange(size) + 0.5) / size
    u, v = np.meshgrid(centres, centres)
    phi, theta = 2 * np.pi * u, np.pi * v
    normal = np.stack([np.sin(theta) * np.cos(phi), np.cos(theta), -np.sin(theta) * np.sin(phi)], -1)
    tangent = np.stack([-np.sin(phi), np.zeros_like(phi), -np.cos(phi)], -1)
    areas = (2 * np.pi * radius * np.sin(theta)) * (np.pi * radius) / size ** 2
    slope_u = 0.15 * np.sin(47 * phi)
    slope_v = 0.15 * np.sin(2 * np.pi / 0.004 * radius * theta)
    local = np.stack([-slope_u, -slope_v, np.ones_like(u)], -1)
    local /= np.linalg.norm(local, axis=-1, keepdims=True)
    flat = lambda a: a.reshape(-1, a.shape[-1]) if a.ndim == 3 else a.reshape(-1)  # noqa: E731
    frames = TangentFrames.from_tangents(flat(normal), np.concatenate([flat(tangent), np.ones((size * size, 1))], 1))
    return radius * flat(normal), flat(areas), frames, flat(local), local


def torus_texels(size: int, major: float, minor: float):
    """Texel-centre samples of a torus (u around the major circle, v around the tube; both wrap: two seams), whose
    texel density varies only 3:1 (a UV sphere's grows without bound at the poles): positions, areas, frames and a
    bump of 4 mm waves along u and v, as :func:`sphere_texels`."""
    centres = (np.arange(size) + 0.5) / size
    u, v = np.meshgrid(centres, centres)
    phi, theta = 2 * np.pi * u, 2 * np.pi * v
    ring = major + minor * np.cos(theta)
    normal = np.stack([np.cos(theta) * np.cos(phi), np.sin(theta), np.cos(theta) * np.sin(phi)], -1)
    position = np.stack([ring * np.cos(phi), minor * np.sin(theta), ring * np.sin(phi)], -1)
    tangent = np.stack([-np.sin(phi), np.zeros_like(phi), np.cos(phi)], -1)
    areas = (2 * np.pi * ring) * (2 * np.pi * minor) / size ** 2
    slope_u = 0.15 * np.sin(2 * np.pi * np.round(2 * np.pi * major / 0.004) * u)
    slope_v = 0.15 * np.sin(2 * np.pi * np.round(2 * np.pi * minor / 0.004) * v)
    local = np.stack([-slope_u, -slope_v, np.ones_like(u)], -1)
    local /= np.linalg.norm(local, axis=-1, keepdims=True)
    flat = lambda a: a.reshape(-1, a.shape[-1]) if a.ndim == 3 else a.reshape(-1)  # noqa: E731
    # the frame's handedness does not matter to the timing; w = +1
    frames = TangentFrames.from_tangents(flat(normal), np.concatenate([flat(tangent), np.ones((size * size, 1))], 1))
    return flat(position), flat(areas), frames, flat(local), local


def profile_in_metres():
    variances, weights = DEON_SKIN.arrays()
    return variances * 1e-6, weights / weights.sum(axis=1, keepdims=True)


def uv_filter(image: np.ndarray, area: float, channels=(0, 1, 2)) -> list:
    """The naive floor: per channel scipy's Gaussian filter of the map in UV space, sigma in texels from the mean
    texel size sqrt(area) / size (metres)."""
    from scipy.ndimage import gaussian_filter

    variances, weights = profile_in_metres()
    size = image.shape[0]
    texel = math.sqrt(area) / size
    out = []
    for c in channels:
        blurred = sum(w * gaussian_filter(image, sigma=(math.sqrt(v) / texel, math.sqrt(v) / texel, 0),
                                          mode=("nearest", "wrap", "nearest"))
                      for v, w in zip(variances, weights[c]) if w > 0)
        out.append((blurred / np.linalg.norm(blurred, axis=-1, keepdims=True)).reshape(-1, 3))
    return out


def brute_force(positions, areas, frames, local, chunk: int = 256) -> np.ndarray:
    """(3, n, 3): every texel pair, exp(-d^2 / 2v) a_j, no cut-off; per Gaussian the weighted mean, then channels."""
    variances, weights = profile_in_metres()
    mesh = frames.to_mesh(local)
    per_gaussian = np.zeros((len(variances), len(positions), 3))
    for start in range(0, len(positions), chunk):
        d2 = ((positions[start:start + chunk, None, :] - positions[None, :, :]) ** 2).sum(-1)
        for k, v in enumerate(variances):
            w = np.exp(-d2 / (2 * v)) * areas[None, :]
            per_gaussian[k, start:start + chunk] = (w @ mesh) / w.sum(1, keepdims=True)
    out = []
    for c in range(3):
        n = frames.to_local(np.einsum("k,kij->ij", weights[c], per_gaussian))
        out.append(n / np.linalg.norm(n, axis=1, keepdims=True))
    return np.stack(out)


def angles(a: np.ndarray, b: np.ndarray) -> tuple[float, float]:
    cos = np.clip((a * b).sum(-1), -1, 1)
    degrees = np.degrees(np.arccos(cos))
    return float(np.sqrt((degrees ** 2).mean())), float(degrees.max())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--sizes", default="1024,2048")
    parser.add_argument("--small", type=int, default=96)
    parser.add_argument("--radius", type=float, default=0.08)
    args = parser.parse_args()
    variances, weights = profile_in_metres()

    print(f"torus of radii {args.radius} and {args.radius / 2} m (area {4 * math.pi ** 2 * args.radius ** 2 / 2:.3f} m^2, a "
          f"head's), d'Eon & Luebke skin profile; 2 cores; best of {args.repeat}\n")
    print("| size | texels | baker s (3 channels) | baker s / channel | scipy UV filter s / channel | ratio |")
    print("|---:|---:|---:|---:|---:|---:|")
    for size in map(int, args.sizes.split(",")):
        positions, areas, frames, local, image = torus_texels(size, args.radius, args.radius / 2)
        ours, _ = best_of(args.repeat, lambda: blur_normals(positions, areas, frames, local, variances, weights))
        peer = [best_of(args.repeat, lambda c=c: uv_filter(image, 2 * math.pi ** 2 * args.radius ** 2, (c,)))[0] for c in range(3)]
        per_channel = ours / 3
        print(f"| {size}^2 | {len(positions)} | {ours:.2f} | {per_channel:.2f} | {np.mean(peer):.2f} | "
              f"{per_channel / np.mean(peer):.1f}x |", flush=True)

    small_radius = 0.02
    positions, areas, frames, local, image = sphere_texels(args.small, small_radius)
    reference = brute_force(positions, areas, frames, local)
    ours = blur_normals(positions, areas, frames, local, variances, weights).diffuse
    finer = blur_normals(positions, areas, frames, local, variances, weights, cell_fraction=0.5).diffuse
    naive = uv_filter(image, 2 * math.pi ** 2 * small_radius ** 2)  # the sphere's |dP/du| |dP/dv| at the equator
    print(f"\nerror against the brute-force surface convolution, {args.small}^2 texels on a {small_radius} m sphere "
          "(degrees, RMS / max over texels)\n")
    print("| channel | baker RMS | baker max | baker cell 0.5 sigma RMS | max | UV filter RMS | UV filter max |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for c, name in enumerate(("red", "green", "blue")):
        a, f, b = angles(ours[c], reference[c]), angles(finer[c], reference[c]), angles(naive[c], reference[c])
        print(f"| {name} | {a[0]:.3f} | {a[1]:.3f} | {f[0]:.3f} | {f[1]:.3f} | {b[0]:.3f} | {b[1]:.3f} |")


if __name__ == "__main__":
    main()
