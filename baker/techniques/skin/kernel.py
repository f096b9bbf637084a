"""Pre-integrated skin: Penner's diffusion LUT, the shadow-penumbra LUT, and the blur kernels of texture-space
and screen-space diffusion, all from one sum-of-Gaussians diffusion profile.

- **Diffusion LUT** (Penner & Borshukov, "Pre-Integrated Skin Shading", GPU Pro 2, 2011; RTR4 section 14.6.3):
  a ring of radius r lit from one side; the light reaching a point at angle theta from the light, after diffusing
  along the ring with profile R, is

      D(theta, r) = int saturate(cos(theta + x)) R(2 r sin(x / 2)) dx / int R(2 r sin(x / 2)) dx,   x in [-pi, pi]

  per RGB channel. Axes: u = N.L * 0.5 + 0.5 (N.L = cos theta), v linear in the curvature 1/r.
  R on the ring is by default the profile integrated across it (``ring="line"``): light that varies only along the
  ring (a cylinder lit across its axis; a sphere near its terminator) diffuses with the 2D profile's line integral,
  a sum of 1D Gaussians with the same weights and variances, as the penumbra LUT below does. Penner's text puts
  the radial 2D profile itself on the ring (``ring="radial"``), which divides each Gaussian's weight by its
  sigma: d'Eon's broad red lobes lose most of their weight, and at 1/r = 0.26/mm, N.L = 0 red - green is 0.012
  against 0.070 with the line profile.
- **Penumbra LUT** (same source): a shadow edge whose filtered shadow value s ramps linearly across a penumbra of
  width w; the light that diffuses across it, S(s, w) = int ramp(x(s) - y) R1(y) dy / int R1(y) dy, with R1 the
  profile integrated along the edge (a 2D Gaussian of variance v integrates to a 1D one of the same variance) and the
  ramp optionally sharpened (the filtered shadow is already blurred; sharpening gives the LUT a crisper edge to
  re-blur). A clamped ramp convolved with a Gaussian has a closed form, so this LUT is exact.
- **Jimenez separable SSS kernel** (Jimenez et al., "Separable Subsurface Scattering", CGF 2015): the taps and RGB
  weights of the reference implementation's ``calculateKernel`` (strength and falloff per channel).
- **d'Eon Gaussian weights** (d'Eon & Luebke, "Advanced Techniques for Realistic Real-Time Skin Rendering", GPU Gems
  3, ch. 14): per Gaussian its variance, the incremental variance of the successive blur, RGB weights, and the
  7-tap separable blur weights.

Profiles are sums of normalized 2D Gaussians G(v, r) = exp(-r^2 / (2 v)) / (2 pi v); variances in mm^2, so radii
and curvatures are in mm and 1/mm. The default is d'Eon & Luebke's three-layer skin fit.

The Penner integral is evaluated per Gaussian on its own grid: the integration range shrinks to where that Gaussian
is non-negligible (|2 r sin(x/2)| < 7 sigma), so a 0.08 mm Gaussian on a 10 cm ring (0.0008 rad wide) gets as many
samples as a 2.7 mm one on a 1 mm ring. Composite trapezoid rule, ``samples`` nodes per Gaussian and LUT row; the
integrand's kinks (where cos changes sign) keep the error O(h^2), well under 1e-4 at the default 256.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numba
import numpy as np

from baker.techniques.skin.options import (DEFAULT_RADII, FIT_PERCENTILES, JIMENEZ_FALLOFF, JIMENEZ_STRENGTH,
                                           MAX_RADIUS_RATIO, SkinOptions)
from baker.diffusion_profile import DEON_SKIN, Profile, load_profile
from baker.texels.color import linear_to_srgb

GAUSSIAN_CUTOFF = 7.0  # standard deviations beyond which a Gaussian is treated as zero (exp(-24.5) ~ 2e-11)


# ---------------------------------------------------------------------------------------------------- Penner LUT
@numba.njit(cache=True, nogil=True, parallel=True)
def _penner_components(cos_theta, curvature, variances, samples, num, den):
    """num[c, row, col] = int f(theta + x) G_c dx and den[c, row] = int G_c dx, G_c = G(v_c, 2 r sin(x / 2))."""
    rows = curvature.shape[0]
    cols = cos_theta.shape[0]
    sin_theta = np.sqrt(np.maximum(0.0, 1.0 - cos_theta * cos_theta))
    for row in numba.prange(rows):
        k = curvature[row]
        cx = np.empty(samples)
        sx = np.empty(samples)
        wx = np.empty(samples)
        for c in range(variances.shape[0]):
            v = variances[c]
            sigma = math.sqrt(v)
            if k <= 0.0:  # a flat surface: the kernel is a delta, D = saturate(N.L)
                for j in range(cols):
                    num[c, row, j] = max(cos_theta[j], 0.0)
                den[c, row] = 1.0
                continue
            r = 1.0 / k
            reach = GAUSSIAN_CUTOFF * sigma / (2.0 * r)
            x_max = math.pi if reach >= 1.0 else 2.0 * math.asin(reach)
            h = 2.0 * x_max / (samples - 1)
            total = 0.0
            for m in range(samples):
                x = -x_max + m * h
                d = 2.0 * r * math.sin(0.5 * x)
                g = math.exp(-d * d / (2.0 * v)) / (2.0 * math.pi * v)
                w = h * (0.5 if m == 0 or m == samples - 1 else 1.0) * g
                cx[m] = math.cos(x)
                sx[m] = math.sin(x)
                wx[m] = w
                total += w
            den[c, row] = total
            for j in range(cols):
                ct, st = cos_theta[j], sin_theta[j]
                acc = 0.0
                for m in range(samples):
                    f = ct * cx[m] - st * sx[m]  # cos(theta + x)
                    if f > 0.0:
                        acc += f * wx[m]
                num[c, row, j] = acc


RING_PROFILES = ("line", "radial")  # R on Penner's ring: the 2D profile integrated across the ring, or radial


def penner_integral(cos_theta, curvature, profile: Profile = DEON_SKIN, samples: int = 256,
                    ring: str = "line") -> np.ndarray:
    """Penner's pre-integrated diffuse D(theta, r) on the grid ``curvature`` x ``cos_theta``.

    Parameters
    ----------
    cos_theta : (cols,) array
        N.L values in [-1, 1].
    curvature : (rows,) array
        Curvatures 1/r in 1/mm (>= 0; 0 is flat).
    profile : Profile
        The diffusion profile (mm).
    samples : int
        Trapezoid nodes per Gaussian and row (>= 3).
    ring : str
        "line": R is the profile integrated across the ring (each 2D Gaussian becomes the 1D Gaussian of the same
        variance and weight); "radial": the 2D profile R(d) itself, as Penner & Borshukov write it.

    Returns
    -------
    (rows, cols, 3) float64 in [0, 1], linear.
    """
    cos_theta = np.clip(np.ascontiguousarray(cos_theta, np.float64).reshape(-1), -1.0, 1.0)
    curvature = np.ascontiguousarray(curvature, np.float64).reshape(-1)
    if ring not in RING_PROFILES:
        raise ValueError(f"ring must be one of {RING_PROFILES}, not {ring!r}")
    variances, weights = profile.arrays()
    if ring == "line":  # G1D(v, d) = G2D(v, d) * sqrt(2 pi v): the kernel integrates G2D, so reweight per Gaussian
        weights = weights * np.sqrt(2.0 * math.pi * np.asarray(variances, np.float64))[None, :]
    num = np.empty((len(variances), len(curvature), len(cos_theta)))
    den = np.empty((len(variances), len(curvature)))
    _penner_components(cos_theta, curvature, np.ascontiguousarray(variances), int(max(3, samples)), num, den)
    numerator = np.einsum("kc,crj->rjk", weights, num)
    denominator = np.einsum("kc,cr->rk", weights, den)
    return np.clip(numerator / denominator[:, None, :], 0.0, 1.0)


@dataclass
class LutAxes:
    """Where texel (row, col) of a LUT sits. Endpoint-aligned: column 0 is exactly N.L = -1 and the last column
    N.L = +1; row 0 is exactly ``curvature_range[0]`` and the last row ``curvature_range[1]`` (1/mm)."""

    width: int
    height: int
    curvature_range: tuple  # (1/r_max, 1/r_min) in 1/mm

    @property
    def ndotl(self) -> np.ndarray:
        return np.linspace(-1.0, 1.0, self.width)

    @property
    def curvature(self) -> np.ndarray:
        return np.linspace(self.curvature_range[0], self.curvature_range[1], self.height)


def diffusion_lut(width: int = 256, height: int = 256, min_radius: float = 1.0, max_radius: float = 100.0,
                  profile: Profile = DEON_SKIN, samples: int = 256, ring: str = "line") -> tuple[np.ndarray, LutAxes]:
    """Penner's 2D LUT: (height, width, 3) linear RGB, row 0 = the flattest curvature 1/max_radius (radii in mm)."""
    axes = LutAxes(int(width), int(height), (1.0 / max_radius, 1.0 / min_radius))
    return penner_integral(axes.ndotl, axes.curvature, profile, samples, ring), axes


# ---------------------------------------------------------------------------------------------------- penumbra LUT
def _phi(t):
    return np.exp(-0.5 * t * t) / math.sqrt(2.0 * math.pi)


def _big_phi(t):
    from scipy.special import ndtr

    return ndtr(t)


def _ramp_convolved(x, half: float, sigma: np.ndarray) -> np.ndarray:
    """int saturate((x - y) / (2 half) + 0.5) N(y; 0, sigma^2) dy, closed form (integral of Phi)."""
    def psi(t):
        return t * _big_phi(t / sigma) + sigma * _phi(t / sigma)

    return (psi(x + half) - psi(x - half)) / (2.0 * half)


def penumbra_lut(size: int = 128, min_width: float = 1.0, max_width: float = 100.0, sharpening: float = 1.0,
                 profile: Profile = DEON_SKIN) -> tuple[np.ndarray, tuple]:
    """Penner's shadow-penumbra LUT: (size, size, 3) linear RGB.

    Column i: the filtered shadow value s = i / (size - 1) (0 = shadowed, 1 = lit). Row j: 1 / w linear from
    1 / max_width (row 0) to 1 / min_width (last row), w the penumbra width in mm. A point with shadow s lies at
    x = (s - 0.5) w across the penumbra; the sharpened shadow ramps over w / sharpening; the value is that ramp
    diffused with the profile integrated along the edge. Returns (lut, (1/max_width, 1/min_width)).
    """
    variances, weights = profile.arrays()
    s = np.linspace(0.0, 1.0, size)
    inv_w = np.linspace(1.0 / max_width, 1.0 / min_width, size)
    width = 1.0 / inv_w
    x = (s[None, :] - 0.5) * width[:, None]  # (rows, cols) mm
    half = 0.5 * width[:, None, None] / sharpening
    sigma = np.sqrt(variances)
    per_gaussian = _ramp_convolved(x[..., None], half, sigma[None, None, :])  # (rows, cols, k)
    out = per_gaussian @ weights.T / weights.sum(axis=1)
    return np.clip(out, 0.0, 1.0), (float(inv_w[0]), float(inv_w[-1]))




def jimenez_kernel(taps: int = 17, strength=JIMENEZ_STRENGTH, falloff=JIMENEZ_FALLOFF) -> np.ndarray:
    """Separable SSS kernel of Jimenez et al. 2015: (taps, 4) rows (r, g, b weight, offset), centre tap first.

    As in the reference ``SeparableSSS::calculateKernel``: offsets span +-2 (+-3 above 20 taps) with quadratic
    spacing (dense near the centre); weights are the area of each tap times the profile, which is d'Eon's skin fit
    without its narrowest Gaussian (that one is the directly bounced light, kept by ``strength``) and stretched per
    channel by ``falloff``; normalized per channel, then the centre tap is lerp(1, w0, strength) and the others
    w * strength. Offsets are in units of the runtime's kernel width (sssWidth times the pixel footprint).
    """
    if taps < 3:
        raise ValueError("taps must be >= 3")
    strength = np.asarray(strength, np.float64)
    falloff = np.asarray(falloff, np.float64)
    extent = 3.0 if taps > 20 else 2.0
    exponent = 2.0
    o = -extent + np.arange(taps) * (2.0 * extent / (taps - 1))
    offsets = extent * np.sign(o) * np.abs(o) ** exponent / extent ** exponent
    w0 = np.abs(np.diff(offsets, prepend=np.nan))
    w1 = np.abs(np.diff(offsets, append=np.nan))
    area = (np.nan_to_num(w0) + np.nan_to_num(w1)) / 2.0

    def profile(r):
        rr = r[:, None] / (0.001 + falloff[None, :])
        out = np.zeros_like(rr)
        for weight, variance in ((0.100, 0.0484), (0.118, 0.187), (0.113, 0.567), (0.358, 1.99), (0.078, 7.41)):
            out += weight * np.exp(-rr * rr / (2.0 * variance)) / (2.0 * 3.14 * variance)
        return out

    rgb = area[:, None] * profile(offsets)
    kernel = np.concatenate([rgb, offsets[:, None]], axis=1)
    centre = taps // 2
    kernel = np.concatenate([kernel[centre:centre + 1], kernel[:centre], kernel[centre + 1:]])
    kernel[:, :3] /= kernel[:, :3].sum(axis=0)
    kernel[0, :3] = (1.0 - strength) + strength * kernel[0, :3]
    kernel[1:, :3] *= strength
    return kernel


def deon_gaussians(profile: Profile = DEON_SKIN) -> list[dict]:
    """Texture-space diffusion as successive Gaussian blurs (d'Eon & Luebke 2007): one entry per Gaussian.

    ``incrementalVariance`` is what blurring the previous result adds (variances add under convolution), ``weights``
    the RGB weights normalized per channel, ``taps7`` the 7-tap separable blur over +-3 sigma (each tap the Gaussian's
    mass over its interval, renormalized: 0.006, 0.061, 0.242, 0.382, ...).
    """
    from scipy.special import ndtr

    variances, weights = profile.arrays()
    order = np.argsort(variances, kind="stable")
    norm = weights / weights.sum(axis=1, keepdims=True)
    edges = np.arange(-3.5, 4.5, 1.0)
    mass = np.diff(ndtr(edges))
    taps = mass / mass.sum()
    out, previous = [], 0.0
    for i in order:
        v = float(variances[i])
        out.append({"variance": v, "incrementalVariance": v - previous, "sigma": math.sqrt(v),
                    "weights": [float(norm[c, i]) for c in range(3)],
                    "taps7": {"offsets": [float(k) for k in range(-3, 4)], "weights": [float(t) for t in taps]}})
        previous = v
    return out




def default_normal_blend(profile: Profile) -> np.ndarray:
    rms = profile.rms_radius()
    return rms / rms.max()


@dataclass
class SkinTables:
    """Everything ``baker skin-lut`` and ``--bakes skin`` write, in linear float."""

    lut: np.ndarray  # (height, width, 3)
    axes: LutAxes
    penumbra: np.ndarray | None  # (size, size, 3)
    penumbra_range: tuple | None  # (1/max_width, 1/min_width), 1/mm
    profile: Profile
    jimenez: np.ndarray  # (taps, 4)
    gaussians: list
    normal_blend: np.ndarray  # (3,)
    # percentiles of the asset's |mean curvature| that the curvature axis spans (None: options or fixed defaults)
    curvature_percentiles: tuple | None = None


def lut_radii(options: SkinOptions, curvature: np.ndarray | None = None) -> tuple[float, float, bool]:
    """Radii (mm) of the LUT's last and first rows: the options' where given, else spanning the asset's curvature.

    ``curvature`` is the asset's baked mean curvature in 1/mm (|H| x the curvature scale, convex and concave alike);
    the axis runs from its 1st to its 99th percentile (``FIT_PERCENTILES``) so the rows go to the curvatures the
    asset has instead of a fixed 1-100 mm (a 15 mm figure would clamp at the 1 mm row, a building would read row 0
    only). At most ``MAX_RADIUS_RATIO`` between the ends (the 1st percentile of a mostly flat asset is ~0); an
    asset of one curvature (a sphere) gets a factor 1.5 either side. No curvature: ``DEFAULT_RADII``. The flag says
    whether the asset's curvature set an end."""
    fitted, from_asset = DEFAULT_RADII, False
    k = np.abs(np.asarray(curvature, np.float64).reshape(-1)) if curvature is not None else np.zeros(0)
    k = k[np.isfinite(k)]
    if len(k):
        k_lo, k_hi = np.percentile(k, FIT_PERCENTILES)
        if k_hi > 0:
            k_lo = max(float(k_lo), float(k_hi) / MAX_RADIUS_RATIO)
            if k_lo > k_hi / 1.01:
                k_lo, k_hi = k_lo / 1.5, k_hi * 1.5
            fitted, from_asset = (1.0 / float(k_hi), 1.0 / float(k_lo)), True
    lo = options.min_radius if options.min_radius is not None else fitted[0]
    hi = options.max_radius if options.max_radius is not None else fitted[1]
    if lo >= hi:  # one radius given, the other fitted on the wrong side of it: keep the given one's decade ratio
        lo, hi = (lo, lo * 100.0) if options.min_radius is not None else (hi / 100.0, hi)
    from_asset = from_asset and (options.min_radius is None or options.max_radius is None)
    return float(lo), float(hi), from_asset


def skin_tables(options: SkinOptions, curvature: np.ndarray | None = None) -> SkinTables:
    """The LUTs and kernels of ``options``; the LUT's curvature axis spans ``curvature`` (1/mm, see
    :func:`lut_radii`) where the options leave the radii unset."""
    options.check()
    min_radius, max_radius, from_asset = lut_radii(options, curvature)
    options = replace(options, min_radius=min_radius, max_radius=max_radius)
    profile = load_profile(options.profile) if options.profile else DEON_SKIN
    lut, axes = diffusion_lut(options.width, options.height, options.min_radius, options.max_radius, profile,
                              options.samples, options.ring_profile)
    penumbra = penumbra_range = None
    if options.penumbra:
        penumbra, penumbra_range = penumbra_lut(options.penumbra_size, options.penumbra_min_width,
                                                options.penumbra_max_width, options.sharpening, profile)
    blend = np.asarray(options.normal_blend, np.float64)
    blend = np.where(blend < 0.0, default_normal_blend(profile), blend)
    return SkinTables(lut, axes, penumbra, penumbra_range, profile,
                      jimenez_kernel(options.jimenez_taps, options.jimenez_strength, options.jimenez_falloff),
                      deon_gaussians(profile), blend, FIT_PERCENTILES if from_asset else None)


def quantize(values: np.ndarray, bits: int, encoding: str = "linear") -> np.ndarray:
    """Linear [0, 1] floats -> uint8/uint16 (optionally sRGB-encoded), round to nearest."""
    if encoding == "srgb":
        values = linear_to_srgb(values)
    scale = (1 << bits) - 1
    return np.clip(np.rint(values * scale), 0, scale).astype(np.uint16 if bits == 16 else np.uint8)
