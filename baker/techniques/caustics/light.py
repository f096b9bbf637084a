"""The light: sunlight refracted at the water surface (Snell's law, Fresnel transmittance) and traced to a flat floor,
its irradiance gathered on a periodic texel grid.

Two estimators of the floor irradiance, both periodic and both normalised so that flat water under the same sun gives
exactly 1:

- **photons**: every surface sample carries the flux through its parameter cell, T (s . A) du dv, to where its
  refracted ray meets the floor, and deposits it on the four nearest texel centres with bilinear weights. The flux
  is conserved exactly (the splat weights sum to 1), and flat water gives exactly 1: the bilinear tent is a
  partition of unity on any integer lattice, and s x s samples per texel form s^2 such lattices.
- **jacobian**: the sampled surface is a triangle mesh whose vertices move to their floor points; each floor
  triangle receives its surface triangle's flux spread uniformly over its area (irradiance = flux / floor area,
  the inverse of the map's Jacobian, as Evan Wallace's WebGL Water rasterises it), point-sampled at texel centres
  and summed over overlapping sheets.

Coordinates: x, y horizontal, z up; the sun direction s points from the water towards the sun.
"""
from __future__ import annotations

import numpy as np


def sun_direction(elevation_degrees: float, azimuth_degrees: float) -> np.ndarray:
    """Unit vector towards the sun: azimuth from +x towards +y, elevation above the horizon."""
    e, a = np.radians(elevation_degrees), np.radians(azimuth_degrees)
    return np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])


def fresnel_transmittance(cos_incident: np.ndarray, cos_transmitted: np.ndarray, ior: float) -> np.ndarray:
    """Unpolarised Fresnel transmittance 1 - (R_s + R_p) / 2 from air (n = 1) into a medium of index ``ior``."""
    rs = (cos_incident - ior * cos_transmitted) / (cos_incident + ior * cos_transmitted)
    rp = (ior * cos_incident - cos_transmitted) / (ior * cos_incident + cos_transmitted)
    return 1.0 - 0.5 * (rs * rs + rp * rp)


def refract(normal: np.ndarray, sun: np.ndarray, ior: float):
    """Refract the sunlight (travelling along -sun) at unit normals (..., 3) into water of index ``ior``.

    Returns the transmitted unit directions (..., 3), cos of the incidence angle (clipped at 0: a facet facing
    away from the sun gets no light) and the Fresnel transmittance (0 where unlit)."""
    eta = 1.0 / ior
    cos_i = np.clip(normal @ sun, 0.0, 1.0)
    cos_t = np.sqrt(1.0 - eta * eta * (1.0 - cos_i * cos_i))  # never total reflection going into a denser medium
    direction = -eta * sun + (eta * cos_i - cos_t)[..., None] * normal
    transmittance = np.where(cos_i > 0, fresnel_transmittance(cos_i, cos_t, ior), 0.0)
    return direction, cos_i, transmittance


def flat_direction(sun: np.ndarray, ior: float) -> np.ndarray:
    """The refracted sun direction under flat water (unit, pointing down): the runtime's projection direction."""
    direction, _, _ = refract(np.array([0.0, 0.0, 1.0]), sun, ior)
    return direction


def floor_hits(surface, sun: np.ndarray, ior: float, depth: float):
    """Where each surface sample's refracted ray meets the floor z = -depth, and the flux it carries.

    Returns (floor_xy (N, N, 2) in metres, not wrapped; weight (N, N)): the flux through the sample's parameter
    cell relative to the flux through the same cell of flat water under the same sun, T (s . A) / (T_flat s_z).
    """
    area = surface.area
    length = np.linalg.norm(area, axis=-1)
    normal = area / length[..., None]
    direction, cos_i, transmittance = refract(normal, sun, ior)
    travel = (-depth - surface.position[..., 2]) / direction[..., 2]
    floor_xy = surface.position[..., :2] + travel[..., None] * direction[..., :2]
    flat_cos = sun[2]
    flat_t = fresnel_transmittance(flat_cos, np.sqrt(1.0 - (1.0 - flat_cos ** 2) / ior ** 2), ior)
    weight = transmittance * cos_i * length / (flat_t * flat_cos)
    return floor_xy, weight


def splat_photons(floor_xy: np.ndarray, weight: np.ndarray, tile_size: float, size: int) -> np.ndarray:
    """Bilinear splat of photons (floor positions in metres, flux weights) onto a periodic size x size grid.

    Returns irradiance (size, size) relative to flat water: the deposited flux per texel divided by the number of
    photons per texel. Texel (row j, column i) is centred at ((i + 0.5), (j + 0.5)) L / size.
    """
    per_texel = weight.size / (size * size)
    texel = floor_xy.reshape(-1, 2) * (size / tile_size) - 0.5
    base = np.floor(texel)
    frac = texel - base
    base = base.astype(np.int64)
    w = weight.reshape(-1)
    out = np.zeros(size * size)
    for dx, dy in ((0, 0), (1, 0), (0, 1), (1, 1)):
        wx = frac[:, 0] if dx else 1.0 - frac[:, 0]
        wy = frac[:, 1] if dy else 1.0 - frac[:, 1]
        index = ((base[:, 1] + dy) % size) * size + (base[:, 0] + dx) % size
        out += np.bincount(index, weights=w * wx * wy, minlength=size * size)
    return (out / per_texel).reshape(size, size)


def rasterise_jacobian(floor_xy: np.ndarray, weight: np.ndarray, tile_size: float, size: int) -> np.ndarray:
    """Irradiance (size, size) relative to flat water from the surface-to-floor map's Jacobian (periodic).

    The (N, N) sample grid is split into two triangles per cell; a floor triangle's irradiance is its surface
    triangle's flux (mean vertex weight times its parameter area) over its floor area, added to every texel whose
    centre it covers, wherever the map folds (every sheet counts).
    """
    n = floor_xy.shape[0]
    scale = size / tile_size
    p = floor_xy * scale  # texel units
    cell = size / n  # parameter spacing in texels
    # the corners of each cell, unwrapped across the tile edges so that every triangle is contiguous
    right = np.roll(p, -1, axis=1)
    right[:, -1, 0] += size
    down = np.roll(p, -1, axis=0)
    down[-1, :, 1] += size
    diagonal = np.roll(right, -1, axis=0)
    diagonal[-1, :, 1] += size
    w = weight
    w_right, w_down, w_diagonal = np.roll(w, -1, 1), np.roll(w, -1, 0), np.roll(np.roll(w, -1, 0), -1, 1)
    out = np.zeros(size * size)
    for a, b, c, wa, wb, wc in ((p, right, diagonal, w, w_right, w_diagonal),
                                (p, diagonal, down, w, w_diagonal, w_down)):
        a, b, c = a.reshape(-1, 2), b.reshape(-1, 2), c.reshape(-1, 2)
        flux = (wa + wb + wc).reshape(-1) / 3.0 * (0.5 * cell * cell)
        signed = 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1]))
        keep = np.abs(signed) > 1e-12
        a, b, c, flux, signed = a[keep], b[keep], c[keep], flux[keep], signed[keep]
        density = flux / np.abs(signed)
        orient = np.sign(signed)
        low = np.minimum(np.minimum(a, b), c)
        high = np.maximum(np.maximum(a, b), c)
        first = np.ceil(low - 0.5)  # first texel whose centre (i + 0.5) is >= the box's low corner
        count = (np.floor(high - 0.5) - first + 1).astype(np.int64)
        for oy in range(int(count[:, 1].max(initial=0))):
            for ox in range(int(count[:, 0].max(initial=0))):
                live = (count[:, 0] > ox) & (count[:, 1] > oy)
                centre = first[live] + np.array([ox, oy]) + 0.5
                o = orient[live]
                inside = (covers(a[live], b[live], centre, o) & covers(b[live], c[live], centre, o)
                          & covers(c[live], a[live], centre, o))
                texel = (centre[inside] - 0.5).astype(np.int64) % size
                out += np.bincount(texel[:, 1] * size + texel[:, 0], weights=density[live][inside],
                                   minlength=size * size)
    return out.reshape(size, size)


def covers(a: np.ndarray, b: np.ndarray, point: np.ndarray, orient: np.ndarray) -> np.ndarray:
    """Whether ``point`` is on the inner side of edge a -> b of a triangle of orientation ``orient`` (+1 counter-
    clockwise, -1 clockwise), points on the edge counted by the top-left rule: two triangles sharing an edge never
    both count a texel centre on it."""
    dx, dy = (b[:, 0] - a[:, 0]) * orient, (b[:, 1] - a[:, 1]) * orient  # the edge as the CCW triangle runs it
    side = (b[:, 0] - a[:, 0]) * (point[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (point[:, 0] - a[:, 0])
    side = side * orient
    top_left = (dy < 0) | ((dy == 0) & (dx < 0))
    return (side > 0) | ((side == 0) & top_left)
