"""The water: a periodic, exactly looping height field from a wave spectrum (Tessendorf, "Simulating Ocean Water",
SIGGRAPH course notes 2001).

Wave vectors lie on the tile's lattice, k = 2 pi n / L with integer n = (n_x, n_y), |n_x|, |n_y| < waves / 2, so the
surface repeats every L metres in x and y. Each wave travels with the deep-water dispersion relation
omega = sqrt(g |k|), rounded to the nearest multiple of 2 pi / period, so the surface at t + period equals the surface
at t. The complex amplitude of wave k at time t is h(k, t) = h0(k) e^{i omega t} + conj(h0(-k)) e^{-i omega t}
(Hermitian in k, so the height is real); h0(k) is a complex normal draw scaled by the square root of the spectrum.
The choppy displacement D(k) = i lambda (k / |k|) h(k) moves surface points towards the crests.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from baker.techniques.caustics.options import at_scale

GRAVITY = 9.81  # m/s^2


@dataclass(frozen=True)
class WaveSpectrum:
    """Wave amplitudes on a tile's lattice: everything that fixes the surface at every time.

    ``n`` (2, m, m) integer lattice coordinates (x, y) of each wave; ``h0`` (m, m) complex amplitudes in metres;
    ``omega`` (m, m) angular frequencies in rad/s (multiples of 2 pi / period); ``tile_size`` L in metres.
    """

    n: np.ndarray
    h0: np.ndarray
    omega: np.ndarray
    tile_size: float

    def at(self, time: float) -> np.ndarray:
        """The Hermitian amplitudes h(k, t) (m, m), in metres."""
        phase = np.exp(1j * self.omega * time)
        opposite = np.conj(self.h0[::-1, ::-1])  # h0(-k): the lattice is symmetric about n = 0
        return self.h0 * phase + opposite * np.conj(phase)


def lattice(waves: int) -> np.ndarray:
    """Integer wave coordinates (2, m, m) with |n| < waves / 2 on each axis (m = 2 ceil(waves / 2) - 1)."""
    half = (waves + 1) // 2 - 1
    axis = np.arange(-half, half + 1)
    ny, nx = np.meshgrid(axis, axis, indexing="ij")
    return np.stack([nx, ny])


def quantised_omega(k: np.ndarray, period: float) -> np.ndarray:
    """Deep-water dispersion omega = sqrt(g k) rounded to a multiple of 2 pi / period (rad/s)."""
    base = 2.0 * np.pi / period
    return np.rint(np.sqrt(GRAVITY * k) / base) * base


def phillips(k: np.ndarray, kx: np.ndarray, ky: np.ndarray, wind_speed: float, wind_direction: float) -> np.ndarray:
    """Phillips spectrum (Tessendorf 2001) up to a constant: exp(-1 / (k L)^2) / k^4 |k_hat . w_hat|^2, with
    L = V^2 / g, and waves much shorter than L / 1000 damped."""
    big_l = wind_speed ** 2 / GRAVITY
    small_l = big_l / 1000.0
    safe = np.where(k > 0, k, 1.0)
    along = (kx * np.cos(wind_direction) + ky * np.sin(wind_direction)) / safe
    value = np.exp(-1.0 / (safe * big_l) ** 2) / safe ** 4 * along ** 2 * np.exp(-(safe * small_l) ** 2)
    return np.where(k > 0, value, 0.0)


def jonswap(k: np.ndarray, kx: np.ndarray, ky: np.ndarray, wind_speed: float, wind_direction: float,
            gamma: float = 3.3) -> np.ndarray:
    """JONSWAP (Hasselmann et al. 1973) up to a constant, moved from frequency to the wave-vector plane.

    S(omega) = g^2 / omega^5 exp(-5/4 (omega_p / omega)^4) gamma^r, r = exp(-(omega - omega_p)^2 / (2 sigma^2
    omega_p^2)), sigma = 0.07 below the peak and 0.09 above, omega_p = 0.855 g / U (fully developed sea). With
    omega = sqrt(g k): S(k) = S(omega) d omega / dk, spread over directions as |k_hat . w_hat|^2 / k (polar area).
    """
    safe = np.where(k > 0, k, 1.0)
    omega = np.sqrt(GRAVITY * safe)
    peak = 0.855 * GRAVITY / wind_speed
    sigma = np.where(omega <= peak, 0.07, 0.09)
    r = np.exp(-((omega - peak) ** 2) / (2.0 * sigma ** 2 * peak ** 2))
    s_omega = GRAVITY ** 2 / omega ** 5 * np.exp(-1.25 * (peak / omega) ** 4) * gamma ** r
    along = (kx * np.cos(wind_direction) + ky * np.sin(wind_direction)) / safe
    value = s_omega * GRAVITY / (2.0 * omega) / safe * along ** 2
    return np.where(k > 0, value, 0.0)


def wave_spectrum(options, seed: int = 0) -> WaveSpectrum:
    """The random wave field of ``options`` (a CausticsOptions), its RMS height scaled to ``options.amplitude``.

    The RMS is the time average sqrt(sum_k |h0(k)|^2 + |h0(-k)|^2), fixed by the draw, so the same seed and options
    give the same surface whatever ``amplitude`` is. Unset lengths are filled at the tile's scale (``at_scale``).
    """
    options = at_scale(options)[0]
    n = lattice(options.waves)
    kx, ky = 2.0 * np.pi * n / options.tile_size
    k = np.hypot(kx, ky)
    direction = np.radians(options.wind_direction)
    if options.spectrum == "jonswap":
        power = jonswap(k, kx, ky, options.wind_speed, direction, options.jonswap_gamma)
    else:
        power = phillips(k, kx, ky, options.wind_speed, direction)
    rng = np.random.default_rng(seed)
    draw = rng.standard_normal((2,) + k.shape)
    h0 = (draw[0] + 1j * draw[1]) * np.sqrt(power / 2.0)
    rms = np.sqrt(2.0 * np.sum(np.abs(h0) ** 2))
    h0 = h0 * (options.amplitude / rms) if rms > 0 else np.zeros_like(h0)
    return WaveSpectrum(n=n, h0=h0, omega=quantised_omega(k, options.period), tile_size=float(options.tile_size))


def single_wave(amplitude: float, cycles: int, tile_size: float, period: float = 1.0) -> WaveSpectrum:
    """h = amplitude cos(2 pi cycles x / tile_size - omega t), one wave along x: the analytic test case."""
    n = lattice(2 * cycles + 2)
    h0 = np.zeros(n.shape[1:], complex)
    centre = n.shape[1] // 2
    h0[centre, centre + cycles] = amplitude / 2.0  # h0(k) + conj(h0(-k)) = amplitude / 2 at +k (and at -k)
    k = 2.0 * np.pi * np.hypot(*n) / tile_size
    return WaveSpectrum(n=n, h0=h0, omega=quantised_omega(k, period), tile_size=float(tile_size))


@dataclass(frozen=True)
class Surface:
    """The water surface sampled on a regular (N, N) parameter grid over one tile.

    ``position`` (N, N, 3) in metres (x, y horizontal, z up, z = 0 the mean level); ``area`` (N, N, 3) the
    un-normalised normal dp/du x dp/dv per unit parameter area (its z is 1 for flat water); ``spacing`` the
    parameter spacing L / N in metres. Row j, column i is the parameter point (x, y) = (i, j) L / N.
    """

    position: np.ndarray
    area: np.ndarray
    spacing: float


def sample_surface(spectrum: WaveSpectrum, time: float, grid: int, choppiness: float = 0.0) -> Surface:
    """The surface at ``time`` (seconds) on a grid x grid lattice, by inverse FFT of the zero-padded spectrum, with
    exact spectral derivatives."""
    m = spectrum.n.shape[1]
    if m > grid:
        raise ValueError(f"a {grid} x {grid} grid cannot hold {m} waves per side")
    kx, ky = 2.0 * np.pi * spectrum.n / spectrum.tile_size
    k = np.hypot(kx, ky)
    ux = np.divide(kx, k, out=np.zeros_like(kx), where=k > 0)
    uy = np.divide(ky, k, out=np.zeros_like(ky), where=k > 0)
    h = spectrum.at(time)
    lam = choppiness
    # eight real fields as four complex inverse FFTs (a + i b transforms to field_a + i field_b when both are real)
    pairs = [(h, 1j * kx * h), (1j * ky * h, 1j * lam * ux * h), (1j * lam * uy * h, -lam * kx * ux * h),
             (-lam * ky * ux * h, -lam * ky * uy * h)]
    rows, cols = spectrum.n[1] % grid, spectrum.n[0] % grid
    fields = []
    for a, b in pairs:
        padded = np.zeros((grid, grid), complex)
        padded[rows, cols] = a + 1j * b
        value = np.fft.ifft2(padded) * (grid * grid)
        fields += [value.real, value.imag]
    height, hx, hy, dx, dy, dxx, dxy, dyy = fields
    coords = np.arange(grid) * (spectrum.tile_size / grid)
    y, x = np.meshgrid(coords, coords, indexing="ij")
    position = np.stack([x + dx, y + dy, height], axis=-1)
    # area vector (1 + Dxx, Dxy, hx) x (Dxy, 1 + Dyy, hy)
    area = np.stack([dxy * hy - hx * (1.0 + dyy), hx * dxy - (1.0 + dxx) * hy,
                     (1.0 + dxx) * (1.0 + dyy) - dxy * dxy], axis=-1)
    return Surface(position=position, area=area, spacing=spectrum.tile_size / grid)
