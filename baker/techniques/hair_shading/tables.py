"""The fibre model of :mod:`baker.techniques.hair_shading.kernel` as two tables a shader samples with bilinear filtering
(the factorisation of Nguyen & Donnelly 2005 / Karis 2016 applied to Chiang et al. 2016, RTR4 14.7.2), and the
lookup a shader does, in numpy (the twin ``baker.api.hair_bsdf`` calls).

pbrt's far field factors exactly: M_p depends only on (theta_i, theta_o tilted by the cuticle), and the h-averaged
A_p N_p only on (phi, theta_o, sigma_a), so the tables lose only what sampling and 16-bit floats lose:

- **M table** (one per beta_m): RGB = M_p for p = R, TT, TRT over (theta_i, theta_o'), both in [-pi/2, pi/2]
  (u = theta_i / pi + 0.5, v = theta_o' / pi + 0.5); the shader applies the tilt to theta_o per lobe, and the
  residual lobe reads the TRT channel (same variance) at the untilted theta_o.
- **N table** (one per beta_n and eta): RGBA = the h-averaged A_p N_p for R, TT, TRT and A_residual / (2 pi), over
  (|phi| / pi, |theta_o| / (pi / 2)) in a stack of slices along the absorption sigma_a (per fibre radius), slice k at
  x = k / (slices - 1), x = 1 - exp(-sigma_a / 2) (transmittance through one diameter, so TT is nearly linear in
  x and black hair, x -> 1, is the last slice). A shader looks up each colour channel's own sigma_a: colour and
  melanin can vary per strand with one table.
Both are endpoint-aligned (texel i is at coordinate i / (size - 1)).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit, prange

from baker.techniques.hair_shading.kernel import (
    P_MAX, attenuations, azimuthal, azimuthal_scale, fibre_geometry, longitudinal, longitudinal_variances,
    offset_quadrature, tilt_terms)


@dataclass(frozen=True)
class HairTables:
    """The baked tables of one fibre setting (linear float32; written as half-float EXR)."""

    longitudinal: np.ndarray  # (m_size, m_size, 3): [row = theta_o', column = theta_i, lobe]
    azimuthal: np.ndarray  # (slices * n_theta, n_phi, 4): slice-major rows (|theta_o|), columns |phi|
    beta_m: float
    beta_n: float
    eta: float
    slices: int

    @property
    def n_theta(self) -> int:
        return self.azimuthal.shape[0] // self.slices


def absorption_coordinate(sigma_a):
    """x in [0, 1] of the N table's absorption axis for sigma_a (per fibre radius)."""
    return 1.0 - np.exp(-np.asarray(sigma_a, float) / 2.0)


@njit(cache=True, parallel=True)
def longitudinal_table(size, v):
    out = np.zeros((size, size, 3), np.float32)
    for row in prange(size):
        theta_o = (row / (size - 1) - 0.5) * math.pi
        for col in range(size):
            theta_i = (col / (size - 1) - 0.5) * math.pi
            for p in range(3):
                out[row, col, p] = longitudinal(abs(math.cos(theta_i)), abs(math.cos(theta_o)), math.sin(theta_i),
                                                math.sin(theta_o), v[p])
    return out


@njit(cache=True, parallel=True)
def azimuthal_table(n_phi, n_theta, slices, s, eta, offsets, weights):
    out = np.zeros((slices * n_theta, n_phi, 4), np.float32)
    for row in prange(slices * n_theta):
        k = row // n_theta
        x = k / (slices - 1)
        sigma = -2.0 * math.log(1.0 - x) if x < 1.0 else np.inf
        theta_o = min((row % n_theta) / (n_theta - 1), 0.999) * 0.5 * math.pi  # grazing: the limit, not 1 / 0
        sin_o = math.sin(theta_o)
        cos_o = math.cos(theta_o)
        a = np.empty(P_MAX + 1)
        for j in range(offsets.shape[0]):
            h = offsets[j]
            gamma_o, gamma_t, path = fibre_geometry(sin_o, eta, h)
            transmittance = math.exp(-sigma * path) if sigma < np.inf else 0.0
            attenuations(cos_o, eta, h, transmittance, a)
            out[row, 0, 3] += weights[j] * a[P_MAX] / (2.0 * math.pi)
            for col in range(n_phi):
                phi = col / (n_phi - 1) * math.pi
                for p in range(P_MAX):
                    out[row, col, p] += weights[j] * a[p] * azimuthal(phi, p, s, gamma_o, gamma_t)
        for col in range(1, n_phi):
            out[row, col, 3] = out[row, 0, 3]
    return out


def bake_tables(beta_m: float = 0.3, beta_n: float = 0.3, eta: float = 1.55, m_size: int = 128, n_phi: int = 64,
                n_theta: int = 32, slices: int = 16, offsets: int = 64) -> HairTables:
    """Both tables for one (beta_m, beta_n, eta); absorption and tilt stay free for the shader."""
    h, w = offset_quadrature(offsets)
    m = longitudinal_table(int(m_size), longitudinal_variances(beta_m))
    n = azimuthal_table(int(n_phi), int(n_theta), int(slices), azimuthal_scale(beta_n), float(eta), h, w)
    return HairTables(m, n, float(beta_m), float(beta_n), float(eta), int(slices))


def as_half(tables: HairTables) -> HairTables:
    """The tables as a half-float image stores them (what a shader samples)."""
    return HairTables(tables.longitudinal.astype(np.float16).astype(np.float32),
                      tables.azimuthal.astype(np.float16).astype(np.float32),
                      tables.beta_m, tables.beta_n, tables.eta, tables.slices)


def sphere_directions(n_theta: int, n_phi: int) -> np.ndarray:
    """(n_theta n_phi, 3) unit directions at the midpoints of an (sin theta, phi) grid, x along the fibre: each
    stands for the same solid angle 4 pi / (n_theta n_phi), so a mean over them is an integral over the sphere."""
    s = -1 + (np.arange(n_theta) + 0.5) * 2 / n_theta
    p = -math.pi + (np.arange(n_phi) + 0.5) * 2 * math.pi / n_phi
    s, p = np.meshgrid(s, p, indexing="ij")
    c = np.sqrt(1 - s ** 2)
    return np.stack([s.ravel(), (c * np.cos(p)).ravel(), (c * np.sin(p)).ravel()], -1)


def bilinear(image: np.ndarray, u, v, row0=0, rows=None) -> np.ndarray:
    """Linear filtering of an endpoint-aligned image at (u, v) in [0, 1] (clamped), within rows [row0, row0+rows):
    what a GPU's bilinear fetch at texel centre ((t * (size - 1) + 0.5) / size) returns."""
    rows = image.shape[0] if rows is None else rows
    width = image.shape[1]
    x = np.clip(np.asarray(u, float), 0.0, 1.0) * (width - 1)
    y = np.clip(np.asarray(v, float), 0.0, 1.0) * (rows - 1)
    x0 = np.minimum(np.floor(x).astype(int), width - 2)
    y0 = np.minimum(np.floor(y).astype(int), rows - 2)
    fx = (x - x0)[..., None]
    fy = (y - y0)[..., None]
    r = np.asarray(row0) + y0
    top = image[r, x0] * (1 - fx) + image[r, x0 + 1] * fx
    bottom = image[r + 1, x0] * (1 - fx) + image[r + 1, x0 + 1] * fx
    return top * (1 - fy) + bottom * fy


def evaluate(tables: HairTables, tangent, light, view, sigma_a, alpha: float = 2.0) -> np.ndarray:
    """sum_p M_p A_p N_p from the tables, per channel, (n, 3): the radiance toward ``view`` per unit irradiance-free
    light from ``light`` (unit vectors away from the fibre), as a shader computes it."""
    t = np.atleast_2d(np.asarray(tangent, float))
    wi = np.atleast_2d(np.asarray(light, float))
    wo = np.atleast_2d(np.asarray(view, float))
    t, wi, wo = np.broadcast_arrays(t, wi, wo)
    t = t / np.linalg.norm(t, axis=-1, keepdims=True)
    sin_i = np.clip(np.sum(wi * t, -1), -1.0, 1.0)
    sin_o = np.clip(np.sum(wo * t, -1), -1.0, 1.0)
    cos_o = np.sqrt(1.0 - sin_o * sin_o)
    pi_ = wi - sin_i[:, None] * t
    po = wo - sin_o[:, None] * t
    norm = np.linalg.norm(pi_, axis=-1) * np.linalg.norm(po, axis=-1)
    cos_phi = np.where(norm > 1e-12, np.sum(pi_ * po, -1) / np.maximum(norm, 1e-12), 1.0)
    phi = np.arccos(np.clip(cos_phi, -1.0, 1.0))
    sin2k, cos2k = tilt_terms(alpha)
    u_i = np.arcsin(sin_i) / math.pi + 0.5
    # per lobe: theta_o rotated by the tilt (pbrt: R by -2 alpha, TT by +alpha, TRT by +4 alpha)
    signs = {0: (1, -1), 1: (0, 1), 2: (2, 1)}
    m = np.empty((len(sin_i), P_MAX + 1))
    for p, (k, sign) in signs.items():
        s_p = sin_o * cos2k[k] + sign * cos_o * sin2k[k]
        m[:, p] = bilinear(tables.longitudinal, u_i, np.arcsin(np.clip(s_p, -1, 1)) / math.pi + 0.5)[:, p]
    m[:, P_MAX] = bilinear(tables.longitudinal, u_i, np.arcsin(sin_o) / math.pi + 0.5)[:, 2]
    sigma = np.broadcast_to(np.asarray(sigma_a, float), (len(sin_i), 3)) if np.ndim(sigma_a) < 2 \
        else np.asarray(sigma_a, float)
    x = absorption_coordinate(sigma) * (tables.slices - 1)
    k0 = np.minimum(np.floor(x).astype(int), tables.slices - 2)
    fk = x - k0
    out = np.empty((len(sin_i), 3))
    n_theta = tables.n_theta
    v_o = np.abs(np.arcsin(sin_o)) / (0.5 * math.pi)
    for c in range(3):
        lo = bilinear(tables.azimuthal, phi / math.pi, v_o, k0[:, c] * n_theta, n_theta)
        hi = bilinear(tables.azimuthal, phi / math.pi, v_o, (k0[:, c] + 1) * n_theta, n_theta)
        n = lo * (1 - fk[:, c, None]) + hi * fk[:, c, None]
        out[:, c] = np.sum(m * n, -1)
    return out


_BAKED: dict = {}  # (beta_m, beta_n, eta) -> tables: a shader's tables are baked once per setting


def shade_from_tables(tangent, light, view, *, eumelanin: float = 1.3, pheomelanin: float = 0.0, beta_m: float = 0.3,
                      beta_n: float = 0.3, alpha: float = 2.0, eta: float = 1.55, sigma_a=None,
                      color=None, tables: HairTables | None = None) -> np.ndarray:
    """``baker.api.hair_bsdf``: the tables (default size, half float, baked once per (beta_m, beta_n, eta), or
    ``tables``) sampled as the runtime samples them; ``sigma_a`` (RGB per fibre radius), or ``color`` (linear RGB,
    through Chiang et al. 2016's inversion), overrides the melanin."""
    tables, sigma = resolve_parameters(eumelanin, pheomelanin, beta_m, beta_n, alpha, eta, sigma_a, color, tables)
    return evaluate(tables, tangent, light, view, sigma, alpha)


def resolve_parameters(eumelanin, pheomelanin, beta_m, beta_n, alpha, eta, sigma_a, color, tables):
    """The checked parameters of ``hair_bsdf`` / ``hair_shade``: (tables, sigma_a per channel)."""
    from baker.techniques.hair_shading.kernel import sigma_a_from_color, sigma_a_from_melanin

    for name, value, lo, hi in (("eumelanin", eumelanin, 0.0, 50.0), ("pheomelanin", pheomelanin, 0.0, 50.0),
                                ("beta_m", beta_m, 0.05, 1.0), ("beta_n", beta_n, 0.05, 1.0),
                                ("alpha", alpha, -10.0, 10.0), ("eta", eta, 1.01, 3.0)):
        if not (lo <= value <= hi):
            raise ValueError(f"hair_bsdf: {name} must be in [{lo}, {hi}], got {value}")
    if tables is None:
        key = (float(beta_m), float(beta_n), float(eta))
        if key not in _BAKED:
            _BAKED[key] = as_half(bake_tables(*key))
        tables = _BAKED[key]
    if sigma_a is not None:
        sigma = np.asarray(sigma_a, float)
    elif color is not None:
        sigma = sigma_a_from_color(color, beta_n)
    else:
        sigma = sigma_a_from_melanin(eumelanin, pheomelanin)
    return tables, sigma


@dataclass(frozen=True)
class DualScatteringTable:
    """Zinke et al. 2008's per-fibre averages for dual scattering, over (|theta|, absorption slice): RGBA = a_f, a_b
    (the fraction of light a fibre scatters into the forward, |phi| > pi/2, and backward half), alpha_b, beta_b
    (radians: the a_b-weighted longitudinal shift and width of R and TRT); forward shift and width are TT's."""

    table: np.ndarray  # (slices, n_theta, 4)
    alpha_f: float
    beta_f: float


def dual_scattering_table(beta_m: float = 0.3, beta_n: float = 0.3, eta: float = 1.55, alpha: float = 2.0,
                          n_theta: int = 32, slices: int = 16, offsets: int = 64, n_phi: int = 361):
    """The averages of :class:`DualScatteringTable` from the h-averaged A_p N_p (M_p integrates to 1 over theta_i
    with its cosine, so the halves are integrals of A_p N_p over phi; the residual splits evenly)."""
    h, w = offset_quadrature(offsets)
    n = azimuthal_table(int(n_phi), int(n_theta), int(slices), azimuthal_scale(beta_n), float(eta), h, w)
    n = n.astype(np.float64).reshape(slices, n_theta, n_phi, 4)
    phi = np.linspace(0.0, math.pi, n_phi)
    back = phi <= math.pi / 2
    # 2 x the integral over [0, pi] (N is even in phi); trapezoid weights split at pi / 2 (n_phi odd: a node there)
    weights = np.full(n_phi, phi[1]) * 2.0
    weights[[0, -1]] *= 0.5
    half = (n_phi - 1) // 2
    wb = np.where(back, weights, 0.0)
    wf = np.where(~back, weights, 0.0)
    wb[half] *= 0.5
    wf[half] = wb[half]
    lobe_b = np.einsum("stpl,p->stl", n[..., :3], wb)
    lobe_f = np.einsum("stpl,p->stl", n[..., :3], wf)
    residual = n[:, :, 0, 3] * 2.0 * math.pi
    a_f = lobe_f.sum(-1) + 0.5 * residual
    a_b = lobe_b.sum(-1) + 0.5 * residual
    v = longitudinal_variances(beta_m)
    shift = np.radians([-2.0 * alpha, alpha, 4.0 * alpha])
    weight = np.maximum(lobe_b[..., 0] + lobe_b[..., 2], 1e-30)
    alpha_b = (lobe_b[..., 0] * shift[0] + lobe_b[..., 2] * shift[2]) / weight
    beta_b = np.sqrt((lobe_b[..., 0] * v[0] + lobe_b[..., 2] * v[2]) / weight)
    table = np.stack([a_f, a_b, alpha_b, beta_b], -1).astype(np.float32)
    return DualScatteringTable(table, float(shift[1]), float(math.sqrt(v[1])))
