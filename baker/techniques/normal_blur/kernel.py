"""Diffuse normal maps blurred on the surface with a diffusion profile (RTR4 14.6.2-14.6.4), from per-texel arrays.

- **Per-channel diffuse normals** (Ma et al. 2007, "Rapid acquisition of specular and diffuse normal maps";
  Penner 2011, GPU Pro 2, generating them by blurring with the profile): the input normal map, sampled at each
  texel (bilinear, the sampler's wrap), goes to mesh space through the texel's tangent frame, is convolved on the
  surface with each channel's sum of Gaussians (:mod:`.surface_convolution`: Euclidean 3D distances, area-weighted,
  across seams and charts), renormalized and brought back to the same tangent frame.
- **Penner's cheaper variant**: one smoothed map S (the channel with the narrowest profile) and per channel a blend
  factor t with n_c ~ normalize(lerp(S, vertex normal, t)); t by least squares on the tangent-plane part (exact for
  the linear term: S.xy (1 - t) ~ n_c.xy), the fit error the RMS length of the residual of the unit vectors.
- **Texture-space diffusion data** (Borshukov & Lewis 2003; d'Eon & Luebke 2007; Hable et al. 2009): the UV
  stretch |dP/du|, |dP/dv| per texel, with which a runtime scales its UV-space kernels to surface distances.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from baker.techniques.normal_blur.surface_convolution import surface_blur

REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT = 10497, 33071, 33648


def _wrap(index: np.ndarray, size: int, mode: int) -> np.ndarray:
    if mode == CLAMP_TO_EDGE:
        return np.clip(index, 0, size - 1)
    if mode == MIRRORED_REPEAT:
        period = np.mod(index, 2 * size)
        return np.where(period < size, period, 2 * size - 1 - period)
    return np.mod(index, size)


def sample_bilinear(image: np.ndarray, uv: np.ndarray, wrap_s: int = REPEAT, wrap_t: int = REPEAT) -> np.ndarray:
    """Bilinear samples of ``image`` (H, W, C) at glTF UVs (n, 2) (texel centres at (i + 0.5) / size), wrapped as a
    glTF sampler's wrapS / wrapT say."""
    height, width = image.shape[:2]
    x = uv[:, 0] * width - 0.5
    y = uv[:, 1] * height - 0.5
    x0, y0 = np.floor(x).astype(np.int64), np.floor(y).astype(np.int64)
    fx, fy = (x - x0)[:, None], (y - y0)[:, None]
    xa, xb = _wrap(x0, width, wrap_s), _wrap(x0 + 1, width, wrap_s)
    ya, yb = _wrap(y0, height, wrap_t), _wrap(y0 + 1, height, wrap_t)
    return ((1 - fy) * ((1 - fx) * image[ya, xa] + fx * image[ya, xb])
            + fy * ((1 - fx) * image[yb, xa] + fx * image[yb, xb]))


def decode_normal_pixels(pixels: np.ndarray, scale: float = 1.0) -> np.ndarray:
    """PNG pixels (H, W, >= 3) of a glTF normal texture -> float (H, W, 3) vectors, xy times ``scale``
    (normalTexture.scale), normalized."""
    top = float(np.iinfo(pixels.dtype).max) if pixels.dtype.kind in "ui" else 1.0
    if pixels.ndim == 2 or pixels.shape[2] < 3:
        raise ValueError("a normal texture needs three channels")
    n = pixels[..., :3].astype(np.float64) / top * 2.0 - 1.0
    n[..., :2] *= scale
    return n / np.maximum(np.linalg.norm(n, axis=-1, keepdims=True), 1e-12)


def encode_normal_pixels(normals: np.ndarray) -> np.ndarray:
    """Unit tangent-space vectors (H, W, 3) -> 8-bit RGB, c = round((n + 1) / 2 * 255)."""
    return np.clip(np.rint((normals + 1.0) * 127.5), 0, 255).astype(np.uint8)


@dataclass(frozen=True)
class TangentFrames:
    """Per-texel right-handed-or-mirrored tangent frames: tangent T, bitangent B = w cross(N, T), normal N."""

    tangent: np.ndarray  # (n, 3) unit, orthogonal to normal
    bitangent: np.ndarray  # (n, 3) unit
    normal: np.ndarray  # (n, 3) unit

    @staticmethod
    def from_tangents(normals: np.ndarray, tangents: np.ndarray) -> "TangentFrames":
        """Frames from interpolated glTF NORMAL and TANGENT (xyz, w) as a glTF viewer builds them per pixel."""
        n = normals / np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)
        t = tangents[:, :3] - n * np.einsum("ij,ij->i", tangents[:, :3], n)[:, None]
        t /= np.maximum(np.linalg.norm(t, axis=1, keepdims=True), 1e-300)
        w = np.where(tangents[:, 3] < 0.0, -1.0, 1.0)
        return TangentFrames(t, np.cross(n, t) * w[:, None], n)

    def to_mesh(self, local: np.ndarray) -> np.ndarray:
        return (local[:, 0:1] * self.tangent + local[:, 1:2] * self.bitangent + local[:, 2:3] * self.normal)

    def to_local(self, vectors: np.ndarray) -> np.ndarray:
        return np.stack([np.einsum("ij,ij->i", vectors, self.tangent), np.einsum("ij,ij->i", vectors, self.bitangent),
                         np.einsum("ij,ij->i", vectors, self.normal)], axis=1)


def unit(v: np.ndarray) -> np.ndarray:
    length = np.linalg.norm(v, axis=-1, keepdims=True)
    return np.where(length > 1e-12, v / np.maximum(length, 1e-300), np.array([0.0, 0.0, 1.0]))


@dataclass
class NormalBlurResult:
    """Per texel: the three diffuse normals (tangent space), Penner's smoothed map and blend factors."""

    diffuse: np.ndarray  # (3, n, 3) unit tangent-space normals, red, green, blue
    smoothed_channel: int  # which channel's map is the smoothed one
    channel_blend: np.ndarray  # (3,) t per channel: n_c ~ normalize(lerp(smoothed, (0, 0, 1), t))
    fit_error: np.ndarray  # (3,) RMS |normalize(lerp) - n_c| per channel


def blur_normals(positions: np.ndarray, areas: np.ndarray, frames: TangentFrames, local_normals: np.ndarray,
                 variances: np.ndarray, weights: np.ndarray, cell_fraction: float = 1.0) -> NormalBlurResult:
    """The per-channel diffuse normals of texels.

    Parameters
    ----------
    positions : (n, 3) texel surface points, mesh units.
    areas : (n,) surface area per texel, mesh units^2.
    frames : the texels' tangent frames.
    local_normals : (n, 3) unit tangent-space normals sampled from the input map.
    variances : (k,) Gaussian variances, mesh units^2.
    weights : (3, k) weights of each Gaussian per channel (normalized here per channel).
    """
    weights = np.asarray(weights, np.float64)
    weights = weights / weights.sum(axis=1, keepdims=True)
    mesh_normals = frames.to_mesh(local_normals)
    used = weights.sum(axis=0) > 0
    per_gaussian = np.zeros((len(variances), len(positions), 3))
    if used.any() and len(positions):
        blurred = surface_blur(positions, areas, mesh_normals, np.asarray(variances, np.float64)[used],
                               cell_fraction=cell_fraction)
        per_gaussian[used] = np.moveaxis(blurred, 1, 0)
    diffuse = np.stack([unit(frames.to_local(np.einsum("k,kij->ij", weights[c], per_gaussian)))
                        for c in range(3)])
    spread = (weights * np.asarray(variances)[None, :]).sum(axis=1)
    smoothed = int(np.argmin(spread))
    blend, error = fit_channel_blend(diffuse, smoothed)
    return NormalBlurResult(diffuse, smoothed, blend, error)


def fit_channel_blend(diffuse: np.ndarray, smoothed: int) -> tuple[np.ndarray, np.ndarray]:
    """Per channel t in [0, 1] with normalize(lerp(S, (0, 0, 1), t)) ~ n_c (S = ``diffuse[smoothed]``), by least
    squares on the tangent-plane components; returns (t, RMS residual length)."""
    s = diffuse[smoothed]
    sxy = s[:, :2]
    energy = float((sxy * sxy).sum())
    blend, error = np.zeros(3), np.zeros(3)
    for c in range(3):
        if energy > 0:
            t = 1.0 - float((diffuse[c][:, :2] * sxy).sum()) / energy
        else:
            t = 0.0
        t = min(1.0, max(0.0, t))
        fitted = unit((1.0 - t) * s + t * np.array([0.0, 0.0, 1.0]))
        blend[c] = t
        error[c] = math.sqrt(float(((fitted - diffuse[c]) ** 2).sum(axis=1).mean())) if len(s) else 0.0
    return blend, error


def texel_areas(dpdu: np.ndarray, dpdv: np.ndarray, size: int) -> np.ndarray:
    """Surface area per texel of a size x size texture: |dP/du x dP/dv| / size^2 (mesh units^2)."""
    return np.linalg.norm(np.cross(dpdu, dpdv), axis=1) / float(size * size)


def twelve_tap_kernel(variances: np.ndarray, weights: np.ndarray) -> dict:
    """A 12-tap texture-space kernel after Hable et al. (ShaderX7, 2009): two rings of six taps (the outer one
    turned by 30 degrees) plus the centre tap. The profile's mass is split into three annuli at the radii where
    the red channel's cumulative mass reaches 1/3 and 2/3; each tap sits at its annulus's mass-weighted mean radius
    and carries its annulus's mass per channel, shared by the ring's taps. Offsets in mesh units."""
    variances = np.asarray(variances, np.float64)
    weights = np.asarray(weights, np.float64)
    weights = weights / weights.sum(axis=1, keepdims=True)
    radius = np.linspace(0.0, 8.0 * math.sqrt(variances.max()), 4097)

    def mass_inside(r):  # a normalized 2D Gaussian's mass inside radius r is 1 - exp(-r^2 / (2 v)); (..., 3)
        r = np.asarray(r, np.float64)[..., None]
        return (1.0 - np.exp(-r * r / (2.0 * variances))) @ weights.T

    cumulative = mass_inside(radius)  # (r, 3)
    edges = [0.0] + [float(np.interp(q, cumulative[:, 0], radius)) for q in (1.0 / 3.0, 2.0 / 3.0)] + [radius[-1]]
    total = mass_inside(radius[-1])
    taps = []
    for ring in range(3):
        ring_mass = (mass_inside(edges[ring + 1]) - mass_inside(edges[ring])) / total
        inside = (radius >= edges[ring]) & (radius <= edges[ring + 1])
        r = radius[inside]
        density = np.gradient(cumulative[inside, 0], r) if len(r) > 1 else np.ones(1)
        mean_radius = _trapezoid(r * density, r) / max(_trapezoid(density, r), 1e-300) if len(r) > 1 else 0.0
        if ring == 0:
            taps.append({"offset": [0.0, 0.0], "weights": [float(x) for x in ring_mass]})
            continue
        turn = 0.0 if ring == 1 else math.pi / 6.0
        for i in range(6):
            angle = turn + i * math.pi / 3.0
            taps.append({"offset": [mean_radius * math.cos(angle), mean_radius * math.sin(angle)],
                         "weights": [float(x) / 6.0 for x in ring_mass]})
    return {"taps": taps, "ringRadii": [float(e) for e in edges[1:3]]}


def _trapezoid(y: np.ndarray, x: np.ndarray) -> float:
    return float(((y[1:] + y[:-1]) * np.diff(x)).sum() / 2.0)
