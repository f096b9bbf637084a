"""Options of the caustics technique: one frozen dataclass feeds the CLI flags, recipe keys and the Python API."""
from __future__ import annotations

from dataclasses import dataclass

from baker.options import opt


@dataclass(frozen=True)
class CausticsOptions:
    """Options of the offline caustics generator (``baker caustics`` and ``--bakes caustics``)."""

    spectrum: str = opt("phillips", "wave spectrum of the water: Phillips (Tessendorf 2001) or JONSWAP",
                        choices=("phillips", "jonswap"))
    wind_speed: float = opt(3.0, "wind speed in m/s (sets the dominant wavelength)", min=0.1, max=60.0)
    wind_direction: float = opt(30.0, "wind direction in degrees, from +x towards +y of the tile", min=-360.0,
                                max=360.0)
    amplitude: float = opt(0.012, "RMS wave height in metres (0 = flat water)", min=0.0, max=10.0)
    choppiness: float = opt(0.5, "horizontal displacement towards the crests (0 = pure height field)", min=0.0,
                            max=2.0)
    jonswap_gamma: float = opt(3.3, "JONSWAP peak enhancement factor", min=1.0, max=10.0)
    tile_size: float = opt(2.0, "side of the square, periodic tile in metres", min=0.01, max=1e4)
    depth: float = opt(1.5, "depth of the receiving floor below the mean water level, in metres", min=0.0, max=1e4)
    period: float = opt(4.0, "loop period in seconds (wave frequencies are multiples of 2 pi / period)",
                        min=0.05, max=1e4)
    sun_elevation: float = opt(70.0, "sun elevation above the horizon in degrees", min=5.0, max=90.0)
    sun_azimuth: float = opt(0.0, "sun azimuth in degrees, from +x towards +y of the tile", min=-360.0, max=360.0)
    ior: float = opt(1.333, "index of refraction of the water", min=1.0, max=3.0)
    ior_rgb: tuple = opt((0.0, 0.0, 0.0), "per-channel IOR r,g,b for dispersion (RGB frames); 0,0,0 = one channel "
                                          "at --ior", min=0.0, max=3.0)
    frames: int = opt(32, "frames per loop", min=1, max=1024)
    size: int = opt(256, "frame width and height in texels (a power of two)", min=8, max=4096)
    waves: int = opt(32, "wave lattice per side: wave vectors 2 pi n / tile for |n_x|, |n_y| < waves / 2",
                     min=4, max=1024)
    method: str = opt("photons", "irradiance estimator: photon splatting (bilinear) or the Jacobian of the "
                                 "surface-to-floor map (Wallace's WebGL Water)", choices=("photons", "jacobian"))
    samples: int = opt(3, "surface samples per texel side (photons, or Jacobian mesh vertices)", min=1, max=16)
    strength: float = opt(1.0, "runtime: scale of the caustic modulation (0 = off, 1 = physical)", min=0.0, max=10.0)
    fade_distance: float = opt(1.0, "runtime: distance in metres from the baked depth over which the caustic fades",
                               min=0.0, max=1e4)
    water_level: float = opt(0.0, "runtime: world height (glTF +Y) of the mean water surface, in metres")
