"""numpy twins of ``runtime-shaders/baker_hair_shading.glsl``, one per GLSL function: the table lookups and Zinke's
dual scattering of :mod:`baker.techniques.hair_shading.tables` and :mod:`baker.techniques.hair_shading.dual`
(``baker.api.hair_bsdf`` / ``hair_shade``), called with the images the shader samples (numpy arrays, rows as
uploaded) and the fields of ``BakerHairShading`` as a dict."""
from __future__ import annotations

import math

import numpy as np

from baker.techniques.hair_shading import dual as D
from baker.techniques.hair_shading import tables as TB
from baker.techniques.hair_shading.kernel import sigma_a_from_melanin


def params(tables, dual_table, tilt_degrees=2.0, density_forward=1.0, density_back=1.0) -> dict:
    """The BakerHairShading fields of baked tables (what a host reads from hair_lut.json)."""
    from baker.techniques.hair_shading.kernel import longitudinal_variances

    return {"variances": longitudinal_variances(tables.beta_m), "tilt": math.radians(tilt_degrees),
            "slices": tables.slices, "alphaF": dual_table.alpha_f, "betaF": dual_table.beta_f,
            "densityForward": density_forward, "densityBack": density_back}


def _tables(m_image, n_image, h) -> TB.HairTables:
    return TB.HairTables(np.asarray(m_image, np.float32)[..., :3], np.asarray(n_image, np.float32), 0.0, 0.0, 0.0,
                         int(h["slices"]))


def _dual(dual_image, h) -> TB.DualScatteringTable:
    return TB.DualScatteringTable(np.asarray(dual_image, np.float32), float(h["alphaF"]), float(h["betaF"]))


def baker_hair_shading_melanin(eumelanin, pheomelanin):
    e, p = np.asarray(eumelanin, float), np.asarray(pheomelanin, float)
    return e[..., None] * sigma_a_from_melanin(1.0) + p[..., None] * sigma_a_from_melanin(0.0, 1.0)


def baker_hair_shading_absorption(sigma_a):
    return TB.absorption_coordinate(sigma_a)


def baker_hair_shading_angles(T, L, V):
    t = np.asarray(T, float)
    t = t / np.linalg.norm(t, axis=-1, keepdims=True)
    L, V = np.asarray(L, float), np.asarray(V, float)
    sin_i = np.clip((L * t).sum(-1), -1, 1)
    sin_o = np.clip((V * t).sum(-1), -1, 1)
    pl, pv = L - sin_i[..., None] * t, V - sin_o[..., None] * t
    norm = np.linalg.norm(pl, axis=-1) * np.linalg.norm(pv, axis=-1)
    cos_phi = np.where(norm > 1e-12, (pl * pv).sum(-1) / np.maximum(norm, 1e-12), 1.0)
    return np.stack([np.arcsin(sin_i), np.arcsin(sin_o), np.arccos(np.clip(cos_phi, -1, 1))], -1)


def baker_hair_shading_longitudinal(m_image, theta_i, theta_o, tilt):
    m_image = np.asarray(m_image, np.float32)[..., :3]
    theta_i, theta_o = np.asarray(theta_i, float), np.asarray(theta_o, float)
    u = theta_i / math.pi + 0.5
    out = []
    for p, shift in enumerate((-2 * tilt, tilt, 4 * tilt, 0.0)):
        theta_p = np.arcsin(np.clip(np.sin(theta_o) * math.cos(shift) + np.cos(theta_o) * math.sin(shift), -1, 1))
        out.append(TB.bilinear(m_image, u, theta_p / math.pi + 0.5)[..., min(p, 2)])
    return np.stack(out, -1)


def baker_hair_shading_azimuthal(n_image, slices, phi, theta_o, x):
    n_image = np.asarray(n_image, np.float32)
    n_theta = n_image.shape[0] // int(slices)
    s = np.clip(np.asarray(x, float), 0, 1) * (slices - 1)
    k0 = np.minimum(np.floor(s).astype(int), int(slices) - 2)
    fk = (s - k0)[..., None]
    u = np.abs(np.asarray(phi, float)) / math.pi
    v = np.abs(np.asarray(theta_o, float)) / (0.5 * math.pi)
    lo = TB.bilinear(n_image, u, v, k0 * n_theta, n_theta)
    hi = TB.bilinear(n_image, u, v, (k0 + 1) * n_theta, n_theta)
    return lo * (1 - fk) + hi * fk


def baker_hair_shading_single(m_image, n_image, h, T, L, V, sigma_a):
    return TB.evaluate(_tables(m_image, n_image, h), T, L, V, sigma_a, math.degrees(h["tilt"]))


def baker_hair_shading_log_i0(x):
    return D.log_bessel_i0(x)


def baker_hair_shading_lobe(theta_i, theta_o, v):
    return D.longitudinal_lobe(np.asarray(theta_i, float), np.asarray(theta_o, float), np.asarray(v, float))


def baker_hair_shading_dual(dual_image, theta, x):
    return D.dual_lookup(_dual(dual_image, {"alphaF": 0.0, "betaF": 0.0}), np.asarray(theta, float),
                         np.asarray(x, float))


def baker_hair_shading(m_image, n_image, dual_image, h, T, L, V, fibres_crossed, sigma_a):
    return D.shade(_tables(m_image, n_image, h), _dual(dual_image, h), T, L, V, fibres_crossed, sigma_a,
                   math.degrees(h["tilt"]), h["densityForward"], h["densityBack"], h["variances"])
