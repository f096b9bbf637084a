"""The far-field hair fibre scattering model of Chiang et al. 2016 ("A Practical and Controllable Hair and Fur Model
for Production Path Tracing"), as pbrt-v3/v4's ``HairBxDF`` formulates it (Pharr, Jakob & Humphreys, Physically
Based Rendering, 3rd ed., 9.9), with d'Eon et al. 2011's energy-conserving longitudinal lobe and melanin absorption:
the truth the baked tables (:mod:`baker.techniques.hair_shading.tables`) and ``baker.api.hair_bsdf`` are measured
against (RTR4 14.7.2).

Frame: the fibre tangent is +x; theta is the longitudinal angle (sin theta = w.x), phi the azimuth in the normal
plane (atan2(w.z, w.y)). ``S(wo, wi) = sum_p M_p(theta_i, theta_o') A_p N_p(phi) + M_pmax A_pmax / (2 pi)``,
p = R, TT, TRT, and the residual p >= 3; the integral over the sphere of light directions (d omega, no cosine) of
S is the fibre's albedo (1 for non-absorbing hair). Averaged over the fibre offset h in [-1, 1] (far field).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

P_MAX = 3
SQRT_PI_OVER_8 = math.sqrt(math.pi / 8.0)

# d'Eon et al. 2011 absorption coefficients per unit concentration (pbrt's, per fibre radius; red, green, blue)
EUMELANIN_SIGMA_A = (0.419, 0.697, 1.37)
PHEOMELANIN_SIGMA_A = (0.187, 0.4, 1.05)


def sigma_a_from_melanin(eumelanin: float, pheomelanin: float = 0.0) -> np.ndarray:
    """Absorption (per fibre radius, RGB) of hair with these melanin concentrations (d'Eon et al. 2011)."""
    return eumelanin * np.asarray(EUMELANIN_SIGMA_A) + pheomelanin * np.asarray(PHEOMELANIN_SIGMA_A)


def sigma_a_from_color(color, beta_n: float) -> np.ndarray:
    """Chiang et al. 2016's inversion: the absorption whose multiply scattered colour is ``color`` (linear RGB)."""
    c = np.clip(np.asarray(color, float), 1e-4, 1.0)
    b = beta_n
    denom = 5.969 - 0.215 * b + 2.532 * b ** 2 - 10.73 * b ** 3 + 5.574 * b ** 4 + 0.245 * b ** 5
    return (np.log(c) / denom) ** 2


def longitudinal_variances(beta_m: float) -> np.ndarray:
    """Chiang's map from longitudinal roughness to the variance v of M_p, per p (R, TT, TRT, residual)."""
    v0 = (0.726 * beta_m + 0.812 * beta_m ** 2 + 3.7 * beta_m ** 20) ** 2
    return np.array([v0, 0.25 * v0, 4.0 * v0, 4.0 * v0])


def azimuthal_scale(beta_n: float) -> float:
    """Chiang's map from azimuthal roughness to the logistic scale s of N_p."""
    return SQRT_PI_OVER_8 * (0.265 * beta_n + 1.194 * beta_n ** 2 + 5.372 * beta_n ** 22)


def tilt_terms(alpha_degrees: float) -> tuple[np.ndarray, np.ndarray]:
    """sin and cos of 2^k alpha, k = 0, 1, 2 (the cuticle tilt shifts R by -2 alpha, TT by alpha, TRT by 4 alpha)."""
    s = np.zeros(3)
    c = np.zeros(3)
    s[0] = math.sin(math.radians(alpha_degrees))
    c[0] = math.sqrt(max(0.0, 1.0 - s[0] ** 2))
    for i in range(1, 3):
        s[i] = 2.0 * c[i - 1] * s[i - 1]
        c[i] = c[i - 1] ** 2 - s[i - 1] ** 2
    return s, c


@njit(cache=True)
def bessel_i0(x):
    """Modified Bessel function of the first kind, order 0: its power series until the terms no longer count
    (pbrt stops at 10 terms, 0.3% low at x = 10; the small-v branch below needs x up to 12 here)."""
    term = 1.0
    total = 1.0
    q = 0.25 * x * x
    for i in range(1, 200):
        term *= q / (i * i)
        total += term
        if term < 1e-17 * total:
            break
    return total


@njit(cache=True)
def log_bessel_i0(x):
    """log I0(x); above 12 the asymptotic series to 1/x^3 (relative error < 1e-5 there)."""
    if x > 12.0:
        r = 1.0 / x
        return x - 0.5 * math.log(2.0 * math.pi * x) + math.log(1.0 + r / 8.0 + 9.0 * r * r / 128.0
                                                                  + 225.0 * r * r * r / 3072.0)
    return math.log(bessel_i0(x))


@njit(cache=True)
def longitudinal(cos_i, cos_o, sin_i, sin_o, v):
    """d'Eon et al. 2011's M_p; the log-I0 form below v = 0.1 avoids overflow (pbrt; csch(1/v) ~ 2 exp(-1/v))."""
    a = cos_i * cos_o / v
    b = sin_i * sin_o / v
    if v <= 0.1:
        return math.exp(log_bessel_i0(a) - b - 1.0 / v + math.log(2.0) + math.log(1.0 / (2.0 * v)))
    return math.exp(-b) * bessel_i0(a) / (math.sinh(1.0 / v) * 2.0 * v)


@njit(cache=True)
def fresnel_dielectric(cos_i, eta):
    """Unpolarised Fresnel reflectance from outside (index 1) into index ``eta``."""
    cos_i = min(max(cos_i, -1.0), 1.0)
    if cos_i < 0.0:
        eta = 1.0 / eta
        cos_i = -cos_i
    sin_i = math.sqrt(max(0.0, 1.0 - cos_i * cos_i))
    sin_t = sin_i / eta
    if sin_t >= 1.0:
        return 1.0
    cos_t = math.sqrt(max(0.0, 1.0 - sin_t * sin_t))
    r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    return 0.5 * (r_par * r_par + r_perp * r_perp)


@njit(cache=True)
def logistic(x, s):
    x = abs(x)
    e = math.exp(-x / s)
    return e / (s * (1.0 + e) * (1.0 + e))


@njit(cache=True)
def logistic_cdf(x, s):
    return 1.0 / (1.0 + math.exp(-x / s))


@njit(cache=True)
def azimuthal(phi, p, s, gamma_o, gamma_t):
    """N_p: the logistic, trimmed to [-pi, pi], about the exit azimuth Phi = 2 p gamma_t - 2 gamma_o + p pi."""
    dphi = phi - (2.0 * p * gamma_t - 2.0 * gamma_o + p * math.pi)
    dphi = dphi - 2.0 * math.pi * math.floor((dphi + math.pi) / (2.0 * math.pi))  # into [-pi, pi)
    return logistic(dphi, s) / (logistic_cdf(math.pi, s) - logistic_cdf(-math.pi, s))


@njit(cache=True)
def attenuations(cos_theta_o, eta, h, transmittance, out):
    """A_p for p = R, TT, TRT and the residual sum p >= 3 (out[3]) of one channel."""
    cos_gamma_o = math.sqrt(max(0.0, 1.0 - h * h))
    f = fresnel_dielectric(cos_theta_o * cos_gamma_o, eta)
    out[0] = f
    out[1] = (1.0 - f) * (1.0 - f) * transmittance
    out[2] = out[1] * transmittance * f
    denom = 1.0 - transmittance * f
    out[3] = out[2] * f * transmittance / denom if denom > 1e-12 else 0.0


@njit(cache=True)
def fibre_geometry(sin_theta_o, eta, h):
    """gamma_o, gamma_t and the internal path length per unit sigma_a (2 cos gamma_t / cos theta_t) at offset h."""
    cos_theta_o = math.sqrt(max(0.0, 1.0 - sin_theta_o * sin_theta_o))
    sin_theta_t = sin_theta_o / eta
    cos_theta_t = math.sqrt(max(0.0, 1.0 - sin_theta_t * sin_theta_t))
    etap = math.sqrt(max(0.0, eta * eta - sin_theta_o * sin_theta_o)) / max(cos_theta_o, 1e-12)
    sin_gamma_t = min(max(h / etap, -1.0), 1.0)
    cos_gamma_t = math.sqrt(max(0.0, 1.0 - sin_gamma_t * sin_gamma_t))
    gamma_o = math.asin(min(max(h, -1.0), 1.0))
    return gamma_o, math.asin(sin_gamma_t), 2.0 * cos_gamma_t / cos_theta_t


@njit(cache=True)
def tilted(sin_o, cos_o, p, sin2k, cos2k):
    """sin and |cos| of theta_o shifted by the cuticle tilt for lobe p (pbrt's rotation by 2^k alpha)."""
    if p == 0:
        s = sin_o * cos2k[1] - cos_o * sin2k[1]
        c = cos_o * cos2k[1] + sin_o * sin2k[1]
    elif p == 1:
        s = sin_o * cos2k[0] + cos_o * sin2k[0]
        c = cos_o * cos2k[0] - sin_o * sin2k[0]
    else:
        s = sin_o * cos2k[2] + cos_o * sin2k[2]
        c = cos_o * cos2k[2] - sin_o * sin2k[2]
    return s, abs(c)


@njit(cache=True)
def scattering_at_offset(wo, wi, h, sigma_a, eta, v, s, sin2k, cos2k, out):
    """S(wo, wi) at fibre offset h, per channel (pbrt's HairBxDF::f times |cos theta_i|: no cosine), into out[3]."""
    sin_o = wo[0]
    cos_o = math.sqrt(max(0.0, 1.0 - sin_o * sin_o))
    sin_i = wi[0]
    cos_i = math.sqrt(max(0.0, 1.0 - sin_i * sin_i))
    phi = math.atan2(wi[2], wi[1]) - math.atan2(wo[2], wo[1])
    gamma_o, gamma_t, path = fibre_geometry(sin_o, eta, h)
    m = np.empty(P_MAX + 1)
    n = np.empty(P_MAX)
    for p in range(P_MAX):
        so, co = tilted(sin_o, cos_o, p, sin2k, cos2k)
        m[p] = longitudinal(cos_i, co, sin_i, so, v[p])
        n[p] = azimuthal(phi, p, s, gamma_o, gamma_t)
    m[P_MAX] = longitudinal(cos_i, cos_o, sin_i, sin_o, v[P_MAX])
    a = np.empty(P_MAX + 1)
    for c in range(3):
        attenuations(cos_o, eta, h, math.exp(-sigma_a[c] * path), a)
        total = m[P_MAX] * a[P_MAX] / (2.0 * math.pi)
        for p in range(P_MAX):
            total += m[p] * a[p] * n[p]
        out[c] = total


@njit(cache=True)
def scattering(wo, wi, sigma_a, eta, v, s, sin2k, cos2k, offsets, weights):
    """S(wo, wi) averaged over h (quadrature ``offsets``/``weights`` over [-1, 1], weights summing to 1): (n, 3)."""
    n = wo.shape[0]
    result = np.zeros((n, 3))
    tmp = np.empty(3)
    for k in range(n):
        for j in range(offsets.shape[0]):
            scattering_at_offset(wo[k], wi[k], offsets[j], sigma_a, eta, v, s, sin2k, cos2k, tmp)
            for c in range(3):
                result[k, c] += weights[j] * tmp[c]
    return result


def offset_quadrature(count: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes over h in [-1, 1], weights normalised to 1 (the average over the fibre's width)."""
    x, w = np.polynomial.legendre.leggauss(count)
    return x, w / 2.0


class FibreModel:
    """One fibre's parameters, pbrt's names: ``sigma_a`` (RGB, per fibre radius), ``beta_m``, ``beta_n`` (0..1),
    ``alpha`` (cuticle tilt, degrees), ``eta`` (index of refraction)."""

    def __init__(self, sigma_a, beta_m: float = 0.3, beta_n: float = 0.3, alpha: float = 2.0, eta: float = 1.55,
                 offsets: int = 64):
        self.sigma_a = np.asarray(sigma_a, float).reshape(3)
        self.beta_m, self.beta_n, self.alpha, self.eta = float(beta_m), float(beta_n), float(alpha), float(eta)
        self.v = longitudinal_variances(self.beta_m)
        self.s = azimuthal_scale(self.beta_n)
        self.sin2k, self.cos2k = tilt_terms(self.alpha)
        self.offsets, self.weights = offset_quadrature(offsets)

    def __call__(self, wo, wi) -> np.ndarray:
        """S(wo, wi) per channel, shape (n, 3), for unit directions in the fibre frame (tangent +x)."""
        wo = np.ascontiguousarray(np.atleast_2d(wo), float)
        wi = np.ascontiguousarray(np.atleast_2d(wi), float)
        wo, wi = np.broadcast_arrays(wo, wi)
        return scattering(np.ascontiguousarray(wo), np.ascontiguousarray(wi), self.sigma_a, self.eta, self.v,
                          self.s, self.sin2k, self.cos2k, self.offsets, self.weights)

    def at_offset(self, wo, wi, h: float) -> np.ndarray:
        """S(wo, wi) at one fibre offset h (not averaged), shape (3,)."""
        out = np.empty(3)
        scattering_at_offset(np.asarray(wo, float), np.asarray(wi, float), float(h), self.sigma_a, self.eta, self.v,
                             self.s, self.sin2k, self.cos2k, out)
        return out


@njit(cache=True)
def albedo_grid(wo, sigma_a, eta, v, s, sin2k, cos2k, offsets, weights, n_theta, n_phi):
    """The integral of S(wo, .) over the sphere of light directions by the midpoint rule in (sin theta_i, phi_i)
    (d omega = d sin theta d phi), per channel."""
    total = np.zeros(3)
    tmp = np.empty(3)
    wi = np.empty(3)
    d_sin = 2.0 / n_theta
    d_phi = 2.0 * math.pi / n_phi
    for a in range(n_theta):
        sin_i = -1.0 + (a + 0.5) * d_sin
        cos_i = math.sqrt(1.0 - sin_i * sin_i)
        for b in range(n_phi):
            phi = -math.pi + (b + 0.5) * d_phi
            wi[0] = sin_i
            wi[1] = cos_i * math.cos(phi)
            wi[2] = cos_i * math.sin(phi)
            for j in range(offsets.shape[0]):
                scattering_at_offset(wo, wi, offsets[j], sigma_a, eta, v, s, sin2k, cos2k, tmp)
                for c in range(3):
                    total[c] += weights[j] * tmp[c] * d_sin * d_phi
    return total
