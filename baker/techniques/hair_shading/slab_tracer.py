"""A small path tracer of explicit fibres: the multiple-scattering truth ``baker.api.hair_shade`` (dual scattering) is
measured against (issue 49's fidelity check; ``benchmarks/hair_shading.py``, ``tests/techniques/test_hair_shading.py``).

The scene is a slab of parallel cylinders of unit radius along +x (the fibre tangent): ``layers`` rows at depths
z = -l * layer_gap, each row periodic in y with ``spacing`` and its own offset, lit by a directional light of unit
irradiance. A camera ray (orthographic, from +z) enters at a random y; at every fibre it meets, the fibre scatters
with the far-field model of :mod:`baker.techniques.hair_shading.kernel` (Chiang et al. 2016 as pbrt's HairBxDF),
which is the h-average of the model at offset h: each event draws h uniformly and uses the model at that h, an
unbiased estimate of the average. Light is gathered by next-event estimation (a shadow ray to the directional light;
any other fibre blocks it) and the path continues in a direction drawn by pbrt's importance sampling of HairBxDF
(lobe by A_p, d'Eon's M_p and the trimmed logistic N_p sampled exactly), weighted by S / pdf, with Russian
roulette after a few bounces. A scattered ray leaves from the fibre's axis and ignores that fibre (the far field:
the fibre is a line scatterer, its own cross-section is inside the model).

Also recorded per camera ray: the fibre it sees first and the number of fibres its shadow ray crosses toward the
light, which is what a renderer with a fibre count (deep opacity map or a baked count) hands ``hair_shade``.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from baker.techniques.hair_shading.kernel import (
    P_MAX, attenuations, fibre_geometry, logistic_cdf, longitudinal, scattering_at_offset, tilted)

NO_HIT = -1


@njit(cache=True)
def intersect(origin, direction, offsets, spacing, layer_gap, skip_layer, skip_index, max_t):
    """The nearest fibre the ray meets before ``max_t`` (skipping fibre (skip_layer, skip_index)): (t, layer, index),
    layer -1 when none. Each layer's circles (centre y = index * spacing + offset, z = -layer * layer_gap) are
    visited in the order the ray passes them within the layer's band |z - z_c| <= 1."""
    best_t = max_t
    best_layer = NO_HIT
    best_index = 0
    dy, dz = direction[1], direction[2]
    a = dy * dy + dz * dz
    if a < 1e-14:
        return best_t, best_layer, best_index
    for layer in range(offsets.shape[0]):
        zc = -layer * layer_gap
        # the ray's t-interval inside the band
        if abs(dz) > 1e-12:
            t0 = (zc - 1.0 - origin[2]) / dz
            t1 = (zc + 1.0 - origin[2]) / dz
            if t0 > t1:
                t0, t1 = t1, t0
        else:
            if abs(origin[2] - zc) > 1.0:
                continue
            t0, t1 = -1e30, 1e30
        t0 = max(t0, 0.0)
        t1 = min(t1, best_t)
        if t0 >= t1:
            continue
        y0 = origin[1] + t0 * dy
        y1 = origin[1] + t1 * dy
        off = offsets[layer]
        step = 1 if dy >= 0.0 else -1
        k = int(math.floor((y0 - off) / spacing)) - step  # from one circle behind the entry
        k_end = int(math.floor((y1 - off) / spacing)) + 2 * step
        for _ in range(100000):
            if layer == skip_layer and k == skip_index:
                k += step
                if (k - k_end) * step > 0:
                    break
                continue
            yc = k * spacing + off
            oy = origin[1] - yc
            oz = origin[2] - zc
            b = oy * dy + oz * dz
            c = oy * oy + oz * oz - 1.0
            disc = b * b - a * c
            if disc > 0.0:
                root = math.sqrt(disc)
                t = (-b - root) / a  # rays start outside every fibre they may meet: the entry is the hit
                if t > 1e-9 and t < best_t:
                    best_t, best_layer, best_index = t, layer, k
                    break  # circles of one row are passed in order
            k += step
            if (k - k_end) * step > 0:
                break
    return best_t, best_layer, best_index


@njit(cache=True)
def count_crossed(origin, direction, offsets, spacing, layer_gap, skip_layer, skip_index):
    """How many fibres the ray from ``origin`` crosses (leaving the slab), the fibre (skip_layer, skip_index)
    excluded."""
    count = 0
    p = origin.copy()
    last_layer, last_index = skip_layer, skip_index
    for _ in range(10000):
        t, layer, index = intersect(p, direction, offsets, spacing, layer_gap, last_layer, last_index, 1e30)
        if layer == NO_HIT:
            break
        count += 1
        p = fibre_axis_point(p + t * direction, layer, index, offsets, spacing, layer_gap)
        last_layer, last_index = layer, index
    return count


@njit(cache=True)
def fibre_axis_point(hit, layer, index, offsets, spacing, layer_gap):
    """The point of the fibre's axis beside ``hit``: where a far-field scattering event leaves from."""
    out = hit.copy()
    out[1] = index * spacing + offsets[layer]
    out[2] = -layer * layer_gap
    return out


@njit(cache=True)
def sample_trimmed_logistic(u, s, a, b):
    """pbrt's SampleTrimmedLogistic: the logistic of scale s restricted to [a, b], by inverting its CDF."""
    k = logistic_cdf(b, s) - logistic_cdf(a, s)
    x = -s * math.log(1.0 / (u * k + logistic_cdf(a, s)) - 1.0)
    return min(max(x, a), b)


@njit(cache=True)
def trimmed_logistic(x, s, a, b):
    e = math.exp(-abs(x) / s)
    return e / (s * (1.0 + e) * (1.0 + e)) / (logistic_cdf(b, s) - logistic_cdf(a, s))


@njit(cache=True)
def lobe_pdf(wo, wi, h, sigma_a, eta, v, s, sin2k, cos2k):
    """The solid-angle density of :func:`sample_lobes` (pbrt's HairBxDF::Pdf): sum_p P(p) M_p N_p."""
    sin_o = wo[0]
    cos_o = math.sqrt(max(0.0, 1.0 - sin_o * sin_o))
    sin_i = wi[0]
    cos_i = math.sqrt(max(0.0, 1.0 - sin_i * sin_i))
    gamma_o, gamma_t, path = fibre_geometry(sin_o, eta, h)
    weights = lobe_weights(cos_o, eta, h, sigma_a, path)
    phi = math.atan2(wi[2], wi[1]) - math.atan2(wo[2], wo[1])
    pdf = 0.0
    for p in range(P_MAX):
        so, co = tilted(sin_o, cos_o, p, sin2k, cos2k)
        dphi = phi - (2.0 * p * gamma_t - 2.0 * gamma_o + p * math.pi)
        dphi = dphi - 2.0 * math.pi * math.floor((dphi + math.pi) / (2.0 * math.pi))
        pdf += weights[p] * longitudinal(cos_i, co, sin_i, so, v[p]) * trimmed_logistic(dphi, s, -math.pi, math.pi)
    pdf += weights[P_MAX] * longitudinal(cos_i, cos_o, sin_i, sin_o, v[P_MAX]) / (2.0 * math.pi)
    return pdf


@njit(cache=True)
def lobe_weights(cos_o, eta, h, sigma_a, path):
    """pbrt's lobe choice: A_p (mean of the channels) normalised."""
    a = np.empty(P_MAX + 1)
    total = np.zeros(P_MAX + 1)
    for c in range(3):
        attenuations(cos_o, eta, h, math.exp(-sigma_a[c] * path), a)
        for p in range(P_MAX + 1):
            total[p] += a[p]
    norm = total.sum()
    return total / norm if norm > 0.0 else total


@njit(cache=True)
def sample_lobes(wo, h, sigma_a, eta, v, s, sin2k, cos2k, u0, u1, u2, u3):
    """A light direction drawn by pbrt's HairBxDF::Sample_f at offset h: the lobe by its A_p, theta by d'Eon's M_p
    (exactly), phi by the trimmed logistic about the lobe's exit azimuth (uniform for the residual)."""
    sin_o = wo[0]
    cos_o = math.sqrt(max(0.0, 1.0 - sin_o * sin_o))
    gamma_o, gamma_t, path = fibre_geometry(sin_o, eta, h)
    weights = lobe_weights(cos_o, eta, h, sigma_a, path)
    p = 0
    acc = weights[0]
    while p < P_MAX and u0 >= acc:
        p += 1
        acc += weights[p]
    if p < P_MAX:
        so, co = tilted(sin_o, cos_o, p, sin2k, cos2k)
    else:
        so, co = sin_o, cos_o
    vp = v[p]
    u1 = max(u1, 1e-5)
    cos_theta = 1.0 + vp * math.log(u1 + (1.0 - u1) * math.exp(-2.0 / vp))
    sin_theta = math.sqrt(max(0.0, 1.0 - cos_theta * cos_theta))
    sin_i = -cos_theta * so + sin_theta * math.cos(2.0 * math.pi * u2) * co
    sin_i = min(max(sin_i, -1.0), 1.0)
    cos_i = math.sqrt(max(0.0, 1.0 - sin_i * sin_i))
    if p < P_MAX:
        dphi = 2.0 * p * gamma_t - 2.0 * gamma_o + p * math.pi + sample_trimmed_logistic(u3, s, -math.pi, math.pi)
    else:
        dphi = 2.0 * math.pi * u3
    phi = math.atan2(wo[2], wo[1]) + dphi
    wi = np.empty(3)
    wi[0] = sin_i
    wi[1] = cos_i * math.cos(phi)
    wi[2] = cos_i * math.sin(phi)
    return wi


@njit(cache=True)
def trace_slab(view, light, offsets, spacing, layer_gap, sigma_a, eta, v, s, sin2k, cos2k, paths, max_bounces,
               seed):
    """Per camera ray (``paths`` of them, y uniform over one period): the radiance toward ``view`` per unit
    irradiance from ``light`` with at most ``max_bounces`` scattering events (RGB), the fibre count of its first
    hit's shadow ray (-1 when the ray misses every fibre), and its first hit's fibre (layer, index)."""
    np.random.seed(seed)
    radiance = np.zeros((paths, 3))
    crossed = np.full(paths, -1, np.int64)
    d0 = -view
    top = 2.0
    tmp = np.empty(3)
    for k in range(paths):
        # enter at z = top moving along -view: y uniform over one period
        origin = np.empty(3)
        origin[0] = 0.0
        origin[1] = np.random.random() * spacing
        origin[2] = top
        direction = d0.copy()
        throughput = np.ones(3)
        skip_layer, skip_index = NO_HIT, 0
        for bounce in range(max_bounces):
            t, layer, index = intersect(origin, direction, offsets, spacing, layer_gap, skip_layer, skip_index, 1e30)
            if layer == NO_HIT:
                break
            axis = fibre_axis_point(origin + t * direction, layer, index, offsets, spacing, layer_gap)
            wo = -direction
            h = 2.0 * np.random.random() - 1.0
            # next event: the directional light, blocked by any other fibre
            blocker_t, blocker, _ = intersect(axis, light, offsets, spacing, layer_gap, layer, index, 1e30)
            if bounce == 0:
                crossed[k] = count_crossed(axis, light, offsets, spacing, layer_gap, layer, index)
            if blocker == NO_HIT:
                scattering_at_offset(wo, light, h, sigma_a, eta, v, s, sin2k, cos2k, tmp)
                for c in range(3):
                    radiance[k, c] += throughput[c] * tmp[c]
            # continue by pbrt's sampling of the lobes at this h
            wi = sample_lobes(wo, h, sigma_a, eta, v, s, sin2k, cos2k, np.random.random(), np.random.random(),
                              np.random.random(), np.random.random())
            pdf = lobe_pdf(wo, wi, h, sigma_a, eta, v, s, sin2k, cos2k)
            if not pdf > 0.0:
                break
            scattering_at_offset(wo, wi, h, sigma_a, eta, v, s, sin2k, cos2k, tmp)
            for c in range(3):
                throughput[c] *= tmp[c] / pdf
            if bounce >= 3:  # Russian roulette, unbiased: survivors carry 1 / q
                q = min(0.95, max(throughput[0], max(throughput[1], throughput[2])))
                if np.random.random() >= q:
                    break
                for c in range(3):
                    throughput[c] /= q
            origin = axis
            direction = wi
            skip_layer, skip_index = layer, index
    return radiance, crossed


class Slab:
    """A slab of ``layers`` rows of parallel unit-radius fibres along +x, ``spacing`` apart within a row (centre to
    centre, in fibre radii) and ``layer_gap`` between rows; each row is shifted by the golden ratio of the spacing
    against the one above, so no channel runs straight through."""

    def __init__(self, layers: int = 8, spacing: float = 3.0, layer_gap: float = 2.0):
        self.layers, self.spacing, self.layer_gap = int(layers), float(spacing), float(layer_gap)
        golden = (math.sqrt(5.0) - 1.0) / 2.0
        self.offsets = np.array([(l * golden % 1.0) * spacing for l in range(layers)])

    def trace(self, model, view, light, paths: int = 20000, max_bounces: int = 1000, seed: int = 1):
        """(radiance (paths, 3), fibres crossed by each first hit's shadow ray (paths,), -1 for a miss)."""
        view = np.asarray(view, float) / np.linalg.norm(view)
        light = np.asarray(light, float) / np.linalg.norm(light)
        return trace_slab(view, light, self.offsets, self.spacing, self.layer_gap, model.sigma_a, model.eta, model.v,
                          model.s, model.sin2k, model.cos2k, int(paths), int(max_bounces), int(seed))


@njit(cache=True)
def sampled_albedo(wo, sigma_a, eta, v, s, sin2k, cos2k, count, seed):
    """The mean of S / pdf over ``count`` draws of :func:`sample_lobes` (h uniform): an unbiased estimate of the
    fibre's albedo toward ``wo`` if the sampler's density is the one :func:`lobe_pdf` states."""
    np.random.seed(seed)
    total = np.zeros(3)
    tmp = np.empty(3)
    for _ in range(count):
        h = 2.0 * np.random.random() - 1.0
        wi = sample_lobes(wo, h, sigma_a, eta, v, s, sin2k, cos2k, np.random.random(), np.random.random(),
                          np.random.random(), np.random.random())
        pdf = lobe_pdf(wo, wi, h, sigma_a, eta, v, s, sin2k, cos2k)
        scattering_at_offset(wo, wi, h, sigma_a, eta, v, s, sin2k, cos2k, tmp)
        for c in range(3):
            total[c] += tmp[c] / pdf
    return total / count
