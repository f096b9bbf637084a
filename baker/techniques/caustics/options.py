"""Options of the caustics technique: one frozen dataclass feeds the CLI flags, recipe keys and the Python API."""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

from baker.options import opt

# The water of the default scale (scale 1): a 2 m tile over a floor 1.5 m down, 3 m/s wind, 1.2 cm RMS waves. At
# another scale s every length is s times these and the wind sqrt(s) times (Phillips' and JONSWAP's length scale
# is V^2 / g), so the water is geometrically similar: the same rays, the same caustic pattern relative to the tile.
REFERENCE = {"tile_size": 2.0, "depth": 1.5, "fade_distance": 1.0, "amplitude": 0.012, "wind_speed": 3.0}
TILE_PER_DIAGONAL = 0.5  # default tile: half the asset's bounding-box diagonal (world units, metres in glTF)


@dataclass(frozen=True)
class CausticsOptions:
    """Options of the offline caustics generator (``baker caustics`` and ``--bakes caustics``)."""

    spectrum: str = opt("phillips", "wave spectrum of the water: Phillips (Tessendorf 2001) or JONSWAP",
                        choices=("phillips", "jonswap"))
    wind_speed: float | None = opt(None, "wind speed in m/s (sets the dominant wavelength; default: 3 x "
                                         "sqrt(scale), so the wavelengths follow the tile)", min=0.1, max=60.0)
    wind_direction: float = opt(30.0, "wind direction in degrees, from +x towards +y of the tile", min=-360.0,
                                max=360.0)
    amplitude: float | None = opt(None, "RMS wave height in metres (0 = flat water; default: 0.012 x scale)",
                                  min=0.0, max=10.0)
    choppiness: float = opt(0.5, "horizontal displacement towards the crests (0 = pure height field)", min=0.0,
                            max=2.0)
    jonswap_gamma: float = opt(3.3, "JONSWAP peak enhancement factor", min=1.0, max=10.0)
    tile_size: float | None = opt(None, "side of the square, periodic tile in metres (default: half the asset's "
                                        "bounding-box diagonal; 2 for baker caustics). scale = tile / 2 m sets "
                                        "every other unset length", min=1e-6, max=1e4)
    depth: float | None = opt(None, "depth of the receiving floor below the mean water level, in metres "
                                    "(default: 1.5 x scale)", min=0.0, max=1e4)
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
    fade_distance: float | None = opt(None, "runtime: distance in metres from the baked depth over which the "
                                            "caustic fades (default: 1 x scale; with the default water level at "
                                            "least the asset's height, so its top and bottom keep half the "
                                            "caustic)", min=0.0, max=1e4)
    water_level: float | None = opt(None, "runtime: world height (glTF +Y) of the mean water surface, in metres "
                                          "(default: the baked depth above the middle of the asset's bounding "
                                          "box, so the whole asset is under water and lit by the caustics; 0 "
                                          "without an asset)", min=-1e6, max=1e6)


def at_scale(options: CausticsOptions, extent: float | None = None,
             heights: tuple[float, float] | None = None) -> tuple[CausticsOptions, float]:
    """``options`` with every unset length filled at the water's scale, and that scale. The scale is the tile's
    (tile / 2 m) when the tile is given, else half of ``extent`` (the asset's bounding-box diagonal) / 2 m, else 1.
    ``heights``: the asset's lowest and highest world height (glTF +Y), which place the default water
    (:func:`water_over`); without them the water level defaults to 0. Values the user gave are kept exactly."""
    if options.tile_size is not None:
        scale = options.tile_size / REFERENCE["tile_size"]
    elif extent is not None and extent > 0.0:
        scale = TILE_PER_DIAGONAL * extent / REFERENCE["tile_size"]
    else:
        scale = 1.0
    filled = {name: REFERENCE[name] * scale for name in ("tile_size", "depth", "fade_distance", "amplitude")}
    filled["wind_speed"] = REFERENCE["wind_speed"] * math.sqrt(scale)
    fade_given = options.fade_distance is not None
    options = replace(options, **{k: v for k, v in filled.items() if getattr(options, k) is None})
    if options.water_level is None:
        if heights is None:
            options = replace(options, water_level=0.0)
        else:
            # the default water covers the asset: the fade (unless given) reaches all of it at half strength or more
            level, reach = water_over(heights, options.depth)
            fade = options.fade_distance if fade_given else max(options.fade_distance, 2.0 * reach)
            options = replace(options, water_level=level, fade_distance=fade)
    return options, float(scale)


def water_over(heights: tuple[float, float], depth: float) -> tuple[float, float]:
    """The default water level over an asset spanning world heights ``heights`` (lowest, highest), and the largest
    distance of the asset from the baked depth under it. The level puts the baked floor (``depth`` below the water)
    through the middle of the asset's height, so the sharpest caustics fall on it (a runtime fades them out away
    from that depth and above the water, runtime-shaders/baker_caustics.glsl); when that would leave the asset's top
    less than a tenth of its height under water (depth < 0.6 x height), the level is raised to that, so all of it is
    under water."""
    bottom, top = (float(h) for h in heights)
    height = max(top - bottom, 0.0)
    level = max(0.5 * (bottom + top) + depth, top + 0.1 * height)
    reach = max(abs(level - top - depth), abs(level - bottom - depth))
    return float(level), float(reach)
