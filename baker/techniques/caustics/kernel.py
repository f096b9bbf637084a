"""Offline caustics (RTR4 14.5.3): a looping, tileable sequence of floor irradiance under a wavy water surface.

"In order to generate caustics from water surfaces, one may apply an animated texture of caustics generated offline
as a light map applied on a surface" (RTR4 14.5.3, after CryEngine's water in Crysis 3). Each frame samples the
periodic surface of :mod:`.spectrum` at t = f period / frames, refracts the sun through it and gathers the
irradiance on the floor with :mod:`.light`. The surface tiles in space and loops in time exactly, so the frames do
too: frame ``frames`` would equal frame 0.

Steps: :func:`.spectrum.wave_spectrum` -> :func:`.spectrum.sample_surface` -> :func:`.light.floor_hits` ->
:func:`.light.splat_photons` or :func:`.light.rasterise_jacobian`.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from baker.techniques.caustics.light import (flat_direction, floor_hits, rasterise_jacobian, splat_photons,
                                             sun_direction)
from baker.techniques.caustics.options import CausticsOptions, at_scale
from baker.techniques.caustics.spectrum import WaveSpectrum, sample_surface, wave_spectrum

CODE_MAX = 65535  # 16-bit PNG


@dataclass(frozen=True)
class CausticFrames:
    """The baked sequence: ``irradiance`` (frames, size, size, channels) float64 relative to flat water (1 = the
    irradiance under flat water; channels 1, or 3 with per-channel IOR), and the refracted sun direction under flat
    water ``projection`` (3,) (x, y horizontal, z up; pointing down)."""

    irradiance: np.ndarray
    projection: np.ndarray

    @property
    def intensity_scale(self) -> float:
        """Irradiance of the largest 16-bit code: PNG value / 65535 x intensity_scale = irradiance."""
        return float(np.float32(max(float(self.irradiance.max()), 1e-6)))


def check_options(options: CausticsOptions) -> None:
    """Refuse combinations the dataclass bounds cannot express (ValueError with the option's name)."""
    if options.size & (options.size - 1):
        raise ValueError(f"option 'size' must be a power of two, got {options.size}")
    if options.waves > options.size * options.samples:
        raise ValueError(f"option 'waves' ({options.waves}) must not exceed size x samples "
                         f"({options.size * options.samples})")
    rgb = tuple(options.ior_rgb)
    if any(rgb) and min(rgb) < 1.0:
        raise ValueError(f"option 'ior_rgb' needs three indices >= 1 (or 0,0,0), got {','.join(map(str, rgb))}")


def channel_iors(options: CausticsOptions) -> tuple:
    return tuple(float(v) for v in options.ior_rgb) if any(options.ior_rgb) else (float(options.ior),)


def irradiance(spectrum: WaveSpectrum, time: float, *, size: int, samples: int = 3, depth: float = 1.5,
               sun: np.ndarray = np.array([0.0, 0.0, 1.0]), ior: float = 1.333, choppiness: float = 0.0,
               method: str = "photons") -> np.ndarray:
    """Floor irradiance (size, size) relative to flat water at ``time`` seconds, ``depth`` metres below the mean
    level, with ``samples`` x ``samples`` surface samples per texel."""
    surface = sample_surface(spectrum, time, size * samples, choppiness)
    floor_xy, weight = floor_hits(surface, sun, ior, depth)
    gather = rasterise_jacobian if method == "jacobian" else splat_photons
    return gather(floor_xy, weight, spectrum.tile_size, size)


def caustic_frames(options: CausticsOptions = CausticsOptions(), seed: int = 0) -> CausticFrames:
    """Every frame of the loop (see :class:`CausticFrames`); unset lengths at the tile's scale (scale 1 without a
    tile: :func:`~baker.techniques.caustics.options.at_scale`)."""
    options = at_scale(options)[0]
    check_options(options)
    spectrum = wave_spectrum(options, seed)
    sun = sun_direction(options.sun_elevation, options.sun_azimuth)
    iors = channel_iors(options)
    frames = np.empty((options.frames, options.size, options.size, len(iors)))
    for f in range(options.frames):
        time = f * options.period / options.frames
        surface = sample_surface(spectrum, time, options.size * options.samples, options.choppiness)
        for c, ior in enumerate(iors):
            floor_xy, weight = floor_hits(surface, sun, ior, options.depth)
            gather = rasterise_jacobian if options.method == "jacobian" else splat_photons
            frames[f, :, :, c] = gather(floor_xy, weight, options.tile_size, options.size)
    projection = flat_direction(sun, iors[len(iors) // 2])
    return CausticFrames(irradiance=frames, projection=projection)


def encode_u16(values: np.ndarray, scale: float) -> np.ndarray:
    """Irradiance -> 16-bit codes with value / 65535 x scale = irradiance (rounded, clipped at 0)."""
    return np.rint(np.clip(values / scale, 0.0, 1.0) * CODE_MAX).astype(np.uint16)


def mip_chain(layers: np.ndarray) -> list:
    """Box-filtered mip levels of (layers, H, W, C) images down to 1 x 1 (exact for periodic tiles: 2 x 2 means)."""
    levels = [layers]
    while levels[-1].shape[1] > 1:
        a = levels[-1]
        levels.append(0.25 * (a[:, 0::2, 0::2] + a[:, 1::2, 0::2] + a[:, 0::2, 1::2] + a[:, 1::2, 1::2]))
    return levels
