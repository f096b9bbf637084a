"""Zinke et al. 2008's dual scattering ("Dual Scattering Approximation for Fast Multiple Scattering in Hair", RTR4
14.7.2) on the baked tables, in numpy: what ``runtime-shaders/baker_hair_shading.glsl`` computes and the twin
``baker.api.hair_shade`` calls.

At a fibre whose light crosses ``n`` parallel fibres first, the light splits into what arrives unscattered (the
direct fraction, 1 - n clamped to [0, 1], so a count interpolated between fibres fades) and what arrives after n
forward scatterings (global multiple scattering Psi_G): its transmittance T_f = a_f(theta_i)^max(n, 1) (a_f: the fraction
one fibre scatters into the forward half, from the dual-scattering table), its incidence shifted by n alpha_f and
spread by the variance n beta_f^2 (TT's tilt and variance), and its azimuth spread uniformly over the forward half.
Around the fibre, the neighbours scatter part of it back (local multiple scattering Psi_L): Zinke's series of one
and three backward events among forward ones, A_b = A_1 + A_3, A_1 = a_b a_f^2 / (1 - a_f^2),
A_3 = a_b^3 a_f^2 / (1 - a_f^2)^3, shifted by Delta_b (Zinke's Eq.) and of width sigma_b.

    F = direct (S(wo, wi) + d_b S_back) + (1 - direct) T_f d_f (S_G + d_b S_back,G)

- S: the single-scattering sum from the M and N tables (:func:`baker.techniques.hair_shading.tables.evaluate`);
- S_G = sum_p M_p(theta_i + n alpha_f, theta_o'; v_p + n beta_f^2) N_G,p(phi): d'Eon's lobe with the spread
  added (evaluated analytically: the M table holds one variance), and N_G,p the N table averaged over the forward
  half of incoming azimuths (four taps at phi + (-3, -1, 1, 3) pi / 8);
- S_back = A_b M(theta_i [+ n alpha_f], theta_o + Delta_b; sigma_b^2 [+ n beta_f^2]) B(phi), B = 1/pi on the
  backward half |phi| < pi/2 for direct light, (pi - |phi|) / pi^2 for light already spread over the forward half:
  normalised so that integrated over light directions it returns A_b (Zinke's f_back carries the same energy);
- d_f, d_b: Zinke's density factors, 1 by default (see DENSITY_FORWARD).

All angles are in the tables' convention: theta = asin(w . tangent), theta_o' the view tilted per lobe (R by
-2 alpha, TT by +alpha, TRT by +4 alpha), phi the angle between light and view about the fibre.
"""
from __future__ import annotations

import math

import numpy as np

from baker.techniques.hair_shading.tables import (
    DualScatteringTable, HairTables, absorption_coordinate, bilinear, evaluate)

# Zinke et al. 2008's density factors d_f, d_b: they chose 0.7 for human hair, whose fibre count comes from a deep
# opacity map; with the count of the fibres actually crossed (a baked count, the path-traced slab) 1 matches the
# path tracer (benchmarks/hair_shading.py: 0.7 leaves the slab 20-45% dark)
DENSITY_FORWARD = 1.0
DENSITY_BACK = 1.0
FORWARD_TAPS = (np.arange(4) - 1.5) * (math.pi / 4.0)  # midpoints of [-pi/2, pi/2]


def log_bessel_i0(x):
    """log I0(x) by Abramowitz & Stegun 9.8.1-2 (relative error < 2e-7): the polynomial the shader evaluates."""
    x = np.asarray(x, float)
    small = x <= 3.75
    t = np.where(small, x / 3.75, 1.0)
    t2 = t * t
    series = 1 + t2 * (3.5156229 + t2 * (3.0899424 + t2 * (1.2067492 + t2 * (0.2659732 + t2 * (0.0360768
                                                                                               + t2 * 0.0045813)))))
    r = np.where(small, 1.0, 3.75 / np.maximum(x, 3.75))
    tail = (0.39894228 + r * (0.01328592 + r * (0.00225319 + r * (-0.00157565 + r * (0.00916281 + r * (
        -0.02057706 + r * (0.02635537 + r * (-0.01647633 + r * 0.00392377))))))))
    return np.where(small, np.log(series), x - 0.5 * np.log(np.maximum(x, 3.75)) + np.log(tail))


def longitudinal_lobe(theta_i, theta_o, v):
    """d'Eon et al. 2011's M (unit integral of M cos theta_i over theta_i) in the log domain, any v > 0."""
    cos_i, sin_i = np.cos(theta_i), np.sin(theta_i)
    cos_o, sin_o = np.cos(theta_o), np.sin(theta_o)
    a = np.abs(cos_i * cos_o) / v
    b = sin_i * sin_o / v
    log_sinh = 1.0 / v + np.log((1.0 - np.exp(-2.0 / v)) * 0.5)
    return np.exp(log_bessel_i0(a) - b - np.log(2.0 * v) - log_sinh)


def clamp_angle(theta):
    return np.clip(theta, -0.5 * math.pi, 0.5 * math.pi)


def dual_lookup(dual: DualScatteringTable, theta, x):
    """(a_f, a_b, alpha_b, beta_b) at |theta| and absorption coordinate x (per channel): one bilinear fetch."""
    return bilinear(dual.table, np.abs(theta) / (0.5 * math.pi), x)


def forward_azimuthal(tables: HairTables, phi, theta_o, x):
    """N_G,p: the h-averaged A_p N_p averaged over light azimuths phi + psi, psi uniform in [-pi/2, pi/2] (the
    forward spread), by four taps; (n, 4) for one channel's absorption x."""
    slices, n_theta = tables.slices, tables.n_theta
    s = x * (slices - 1)
    k0 = np.minimum(np.floor(s).astype(int), slices - 2)
    fk = (s - k0)[:, None]
    v_o = np.abs(theta_o) / (0.5 * math.pi)
    total = 0.0
    for psi in FORWARD_TAPS:
        tap = np.abs(np.mod(phi + psi + math.pi, 2.0 * math.pi) - math.pi) / math.pi
        lo = bilinear(tables.azimuthal, tap, v_o, k0 * n_theta, n_theta)
        hi = bilinear(tables.azimuthal, tap, v_o, (k0 + 1) * n_theta, n_theta)
        total = total + lo * (1 - fk) + hi * fk
    return total / len(FORWARD_TAPS)


def shade(tables: HairTables, dual: DualScatteringTable, tangent, light, view, fibres_crossed, sigma_a,
          alpha: float = 2.0, density_forward: float = DENSITY_FORWARD, density_back: float = DENSITY_BACK,
          variances=None):
    """Zinke's F per channel, (n, 3): the radiance toward ``view`` per unit irradiance from ``light`` at a fibre
    behind ``fibres_crossed`` fibres (scalar or (n,)) parallel to ``tangent``; ``variances``: d'Eon's v per lobe
    (default: Chiang's map of the tables' beta_m)."""
    t = np.atleast_2d(np.asarray(tangent, float))
    wi = np.atleast_2d(np.asarray(light, float))
    wo = np.atleast_2d(np.asarray(view, float))
    counts = np.atleast_1d(np.asarray(fibres_crossed, float))
    t, wi, wo = (np.ascontiguousarray(np.broadcast_to(a, (max(len(t), len(wi), len(wo), len(counts)), 3)))
                 for a in (t, wi, wo))
    count = len(t)
    single = evaluate(tables, t, wi, wo, sigma_a, alpha)
    t = t / np.linalg.norm(t, axis=-1, keepdims=True)
    sin_i = np.clip(np.sum(wi * t, -1), -1.0, 1.0)
    sin_o = np.clip(np.sum(wo * t, -1), -1.0, 1.0)
    theta_i, theta_o = np.arcsin(sin_i), np.arcsin(sin_o)
    pi_ = wi - sin_i[:, None] * t
    po = wo - sin_o[:, None] * t
    norm = np.linalg.norm(pi_, axis=-1) * np.linalg.norm(po, axis=-1)
    cos_phi = np.where(norm > 1e-12, np.sum(pi_ * po, -1) / np.maximum(norm, 1e-12), 1.0)
    phi = np.arccos(np.clip(cos_phi, -1.0, 1.0))
    n = np.broadcast_to(np.maximum(counts, 0.0), (count,))
    direct = np.clip(1.0 - n, 0.0, 1.0)
    crossed = np.maximum(n, 1.0)  # what does not arrive directly crossed at least one fibre
    sigma = np.broadcast_to(np.asarray(sigma_a, float), (count, 3)) if np.ndim(sigma_a) < 2 \
        else np.asarray(sigma_a, float)
    x = absorption_coordinate(sigma)
    v = np.asarray(tables_variances(tables) if variances is None else variances, float)
    spread = crossed * dual.beta_f ** 2
    theta_g = clamp_angle(theta_i + crossed * dual.alpha_f)  # where forward-scattered light comes from, on average
    tilt = np.radians([-2.0 * alpha, alpha, 4.0 * alpha, 0.0])
    m_g = np.stack([longitudinal_lobe(theta_g, clamp_angle(theta_o + tilt[p]), v[p] + spread) for p in range(4)], -1)
    theta_d = 0.5 * (theta_o - theta_i)
    back_direct = np.where(phi < 0.5 * math.pi, 1.0 / math.pi, 0.0)
    back_spread = (math.pi - phi) / math.pi ** 2
    out = np.empty((count, 3))
    for c in range(3):
        a_f = dual_lookup(dual, theta_i, x[:, c])[:, 0]
        scattered = (1.0 - direct) * np.maximum(a_f, 0.0) ** crossed  # T_f of what crossed fibres
        a_f_d, a_b, alpha_b, beta_b = dual_lookup(dual, theta_d, x[:, c]).T
        a_f2 = np.minimum(a_f_d * a_f_d, 0.999)
        one = 1.0 - a_f2
        a1 = a_b * a_f2 / one
        a3 = a_b ** 3 * a_f2 / one ** 3
        a_back = a1 + a3
        shift_b = alpha_b * (1.0 - 2.0 * a_b * a_b / (one * one)) \
            + dual.alpha_f * (2.0 * one * one + 4.0 * a_f2 * a_b * a_b) / one ** 3
        width_1 = np.sqrt(2.0 * dual.beta_f ** 2 + beta_b ** 2)
        width_3 = np.sqrt(2.0 * dual.beta_f ** 2 + 3.0 * beta_b ** 2)
        sigma_b = (1.0 + density_back * a_f2) * (a1 * width_1 + a3 * width_3) / np.maximum(a_back, 1e-12)
        var_b = np.maximum(sigma_b * sigma_b, 1e-4)  # no zero-width lobe where a fibre backscatters nothing
        theta_back = clamp_angle(theta_o + shift_b)
        s_back = a_back * longitudinal_lobe(theta_i, theta_back, var_b) * back_direct
        s_back_g = a_back * longitudinal_lobe(theta_g, theta_back, var_b + spread) * back_spread
        n_g = forward_azimuthal(tables, phi, theta_o, x[:, c])
        s_g = np.sum(m_g * n_g, -1)
        out[:, c] = direct * (single[:, c] + density_back * s_back) \
            + scattered * density_forward * (s_g + density_back * s_back_g)
    return out


def tables_variances(tables: HairTables):
    from baker.techniques.hair_shading.kernel import longitudinal_variances

    return longitudinal_variances(tables.beta_m)


_DUAL: dict = {}  # (beta_m, beta_n, eta, alpha) -> the dual-scattering table, half float, baked once per setting


def dual_table_for(beta_m: float, beta_n: float, eta: float, alpha: float) -> DualScatteringTable:
    from baker.techniques.hair_shading.tables import dual_scattering_table

    key = (float(beta_m), float(beta_n), float(eta), float(alpha))
    if key not in _DUAL:
        dual = dual_scattering_table(*key)
        _DUAL[key] = DualScatteringTable(dual.table.astype(np.float16).astype(np.float32), dual.alpha_f, dual.beta_f)
    return _DUAL[key]


def shade_from_tables(tangent, light, view, fibres_crossed, *, eumelanin: float = 1.3, pheomelanin: float = 0.0,
                      beta_m: float = 0.3, beta_n: float = 0.3, alpha: float = 2.0, eta: float = 1.55, sigma_a=None,
                      color=None, tables: HairTables | None = None, dual: DualScatteringTable | None = None,
                      density_forward: float = DENSITY_FORWARD, density_back: float = DENSITY_BACK) -> np.ndarray:
    """``baker.api.hair_shade``: :func:`shade` on the default half-float tables (or ``tables`` and ``dual``)."""
    from baker.techniques.hair_shading.tables import resolve_parameters

    tables, sigma = resolve_parameters(eumelanin, pheomelanin, beta_m, beta_n, alpha, eta, sigma_a, color, tables)
    if dual is None:
        dual = dual_table_for(tables.beta_m, tables.beta_n, tables.eta, alpha)
    counts = np.asarray(fibres_crossed, float)
    if not np.all(np.isfinite(counts)) or np.any(counts < 0):
        raise ValueError("hair_shade: fibres_crossed must be finite and >= 0")
    return shade(tables, dual, tangent, light, view, counts, sigma, alpha, density_forward, density_back)
