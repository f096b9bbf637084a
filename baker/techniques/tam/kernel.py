"""Tonal art maps (TAMs): nested stroke textures for real-time hatching.

Praun, Hoppe, Webb & Finkelstein, "Real-Time Hatching", SIGGRAPH 2001 (RTR4 section 15.3, figure 15.21). A TAM is a
set of tones (darkness targets, lightest first) each with its own, hand-drawn-looking mip levels. The strokes are
*nested*: every stroke of a tone appears in all darker tones, and every stroke of a mip level appears in all finer
levels with the same width in pixels. That nesting is what lets the runtime blend two tones, and two mip levels,
without strokes popping, while the stroke width stays constant on screen.

Construction (Praun et al. 2001, section 4.2), followed here:

- the tones are filled lightest first; each tone starts as a copy of the previous one;
- within a tone the levels are filled coarsest first; a stroke added at a level is added to every finer level, at
  the same position in texture space, scaled length, and the *same width in pixels*;
- a stroke is the best of K random candidates (random position, length, a small angle jitter, optional curvature),
  scored by how much it moves *every* level of the current tone toward the tone's darkness target, the error being
  measured on an image pyramid of each level (2 x 2 blocks up to the whole tile), so that candidates falling into
  empty regions win and the strokes spread evenly;
- a level is done when the next stroke would not bring its mean darkness closer to the target.

Strokes are anti-aliased capsules (coverage = clamp(r + 1/2 - distance, 0, 1), a box-filtered edge) composited as
ink over paper, darkness d <- d + c (1 - d); every position is wrapped toroidally, so each texture tiles.
Styles: ``hatching`` (one direction), ``cross-hatching`` (tones darker than ``cross_threshold`` also draw strokes in
a second direction) and ``stippling`` (dots of a fixed pixel diameter).

Webb, Praun, Finkelstein & Hoppe, "Fine Tone Control in Hardware Hatching", NPAR 2002: the *volume TAM* stores many
tones as the third axis of a texture whose mips are spatial only. The generation is the same with more tones; only
the packing differs (``layout="volume"``, see :mod:`baker.techniques.tam.extension`).

The whole fill of one (tone, level) runs in one compiled loop (:func:`_fill_level`): candidates, rasterization of
each candidate at every affected level, pyramid scoring, and the update; Python only loops over tones x levels.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from baker.techniques.tam.options import STYLES, TamOptions

# columns of the stroke table (TonalArtMap.strokes)
STROKE_FIELDS = ("x", "y", "angle", "length", "sagitta", "width", "tone", "level")




@dataclass
class TonalArtMap:
    """A generated TAM.

    Attributes
    ----------
    targets : (tones,) float64
        Darkness targets, lightest first (0 = white paper, 1 = black).
    darkness : list of (tones, R, R) float64
        One array per level, **finest first** (level 0 = ``size`` pixels, level i = ``size >> i``); darkness of
        each pixel (0 paper .. 1 ink). Brightness, what the images store, is ``1 - darkness``.
    strokes : dict of arrays
        The stroke table, one row per stroke in drawing order, columns :data:`STROKE_FIELDS`: centre ``x, y`` in
        tile units [0, 1), ``angle`` (radians), ``length`` (tile units), ``sagitta`` (bend, fraction of the
        length, signed), ``width`` (pixels), ``tone`` (first tone that has it) and ``level`` (coarsest level, in
        the finest-first numbering, that has it; it is in every finer level too).
    options : TamOptions
    seed : int
    """

    targets: np.ndarray
    darkness: list
    strokes: dict
    options: TamOptions
    seed: int

    @property
    def sizes(self) -> list[int]:
        return [int(d.shape[-1]) for d in self.darkness]

    def stroke_set(self, tone: int, level: int) -> np.ndarray:
        """Indices of the strokes present at (tone, level): introduced at a lighter-or-equal tone and a
        coarser-or-equal level."""
        s = self.strokes
        return np.flatnonzero((s["tone"] <= tone) & (s["level"] >= level))

    def brightness_u8(self, level: int) -> np.ndarray:
        """(tones, R, R) uint8 brightness of one level (255 = paper), as written to the images."""
        return np.rint((1.0 - self.darkness[level]) * 255.0).astype(np.uint8)


def tone_targets(tones: int, darkest: float) -> np.ndarray:
    """Evenly spaced darkness targets ``darkest * (i + 1) / tones``, lightest first."""
    return darkest * np.arange(1, tones + 1, dtype=np.float64) / tones


def check_options(options: TamOptions) -> None:
    """Raise ValueError for combinations the dataclass bounds cannot express."""
    size = options.size
    if size & (size - 1):
        raise ValueError(f"tam size must be a power of two, got {size}")
    if size >> (options.levels - 1) < 4:
        raise ValueError(f"{options.levels} levels of a {size}-pixel TAM go below 4 pixels")
    lo, hi = options.stroke_length
    if lo > hi:
        raise ValueError(f"stroke_length min {lo} exceeds max {hi}")
    if options.layout == "packed" and options.tones != 6:
        raise ValueError(f"the packed layout holds exactly 6 tones (two RGB textures, Praun et al.), got "
                         f"{options.tones}; use layout volume for other counts")


# ---------------------------------------------------------------------------------------------------------- raster
@numba.njit(cache=True, nogil=True, inline="always")
def _segment_distance(px, py, ax, ay, bx, by):
    dx, dy = bx - ax, by - ay
    ll = dx * dx + dy * dy
    t = 0.0
    if ll > 0.0:
        t = ((px - ax) * dx + (py - ay) * dy) / ll
        t = min(1.0, max(0.0, t))
    ex, ey = px - (ax + t * dx), py - (ay + t * dy)
    return math.sqrt(ex * ex + ey * ey)


@numba.njit(cache=True, nogil=True)
def _stamp(x, y, angle, length, sagitta, width, size, scratch, touched, count):
    """Rasterize one stroke at a level of ``size`` pixels into ``scratch`` (flat size*size, max-combined, wrapped).

    ``x, y, length`` are in tile units, ``width`` in pixels. Pixel (i, j) has its centre at ((j + .5), (i + .5))
    pixels, with row i along +v. Newly touched pixels are appended to ``touched``; returns the new count.
    The stroke is a quadratic Bezier (a straight segment when ``sagitta`` is 0) drawn as a polyline of capsules.
    """
    r = 0.5 * width
    reach = r + 0.5  # coverage is zero beyond r + 1/2 from the centre line
    cx, cy = x * size, y * size
    ux, uy = math.cos(angle), math.sin(angle)
    half = 0.5 * length * size
    ax, ay = cx - ux * half, cy - uy * half
    bx, by = cx + ux * half, cy + uy * half
    # control point: the curve's largest deviation from the chord (at t = 1/2) is sagitta * length
    ox, oy = -uy * 2.0 * sagitta * length * size, ux * 2.0 * sagitta * length * size
    segments = 1 if sagitta == 0.0 else 6
    px0, py0 = ax, ay
    for k in range(1, segments + 1):
        t = k / segments
        if segments == 1:
            px1, py1 = bx, by
        else:
            w0, w1, w2 = (1 - t) * (1 - t), 2 * t * (1 - t), t * t
            px1 = w0 * ax + w1 * (cx + ox) + w2 * bx
            py1 = w0 * ay + w1 * (cy + oy) + w2 * by
        dx, dy = px1 - px0, py1 - py0
        seg_len = math.sqrt(dx * dx + dy * dy)
        major_x = abs(dx) >= abs(dy)
        # band half-height around the centre line along the minor axis (cap pixels are within `reach` of an end)
        if seg_len > 0.0:
            cosine = (abs(dx) if major_x else abs(dy)) / seg_len
        else:
            cosine = 1.0
        band = reach / cosine + 1.0
        if major_x:
            lo_m, hi_m = min(px0, px1), max(px0, px1)
        else:
            lo_m, hi_m = min(py0, py1), max(py0, py1)
        m0 = int(math.floor(lo_m - reach - 0.5))
        m1 = int(math.ceil(hi_m + reach - 0.5))
        for m in range(m0, m1 + 1):
            mc = m + 0.5
            # centre line's minor coordinate at this major coordinate (clamped to the segment)
            if major_x:
                tt = (mc - px0) / dx if dx != 0.0 else 0.0
                tt = min(1.0, max(0.0, tt))
                centre = py0 + tt * dy
            else:
                tt = (mc - py0) / dy if dy != 0.0 else 0.0
                tt = min(1.0, max(0.0, tt))
                centre = px0 + tt * dx
            n0 = int(math.floor(centre - band - 0.5))
            n1 = int(math.ceil(centre + band - 0.5))
            for n in range(n0, n1 + 1):
                nc = n + 0.5
                if major_x:
                    d = _segment_distance(mc, nc, px0, py0, px1, py1)
                    col, row = m, n
                else:
                    d = _segment_distance(nc, mc, px0, py0, px1, py1)
                    col, row = n, m
                c = reach - d
                if c <= 0.0:
                    continue
                if c > 1.0:
                    c = 1.0
                p = (row % size) * size + (col % size)  # toroidal wrap: the tile repeats seamlessly
                old = scratch[p]
                if old == 0.0:
                    touched[count] = p
                    count += 1
                if c > old:
                    scratch[p] = c
        px0, py0 = px1, py1
    return count


def rasterize_stroke(x: float, y: float, angle: float, length: float, sagitta: float, width: float,
                     size: int) -> np.ndarray:
    """Anti-aliased coverage (size, size) float64 of one stroke (tile units; width in pixels), wrapped."""
    scratch = np.zeros(size * size, np.float64)
    touched = np.empty(size * size, np.int64)
    _stamp(float(x), float(y), float(angle), float(length), float(sagitta), float(width), size, scratch, touched, 0)
    return scratch.reshape(size, size)


# ---------------------------------------------------------------------------------------------------------- fill
@numba.njit(cache=True, nogil=True)
def _fill_level(dark, dark_off, sizes, pyr, pyr_off, pyr_count, level, target, seed, style, width, len_lo, len_hi,
                angle, jitter, curvature, cross, cross_angle, candidates, out, out_count, max_strokes):
    """Add strokes at ``level`` (internal numbering, 0 = coarsest) until its mean darkness is closest to ``target``.

    ``dark`` holds every level's darkness (flat, level ``i`` at ``dark_off[i]``); ``pyr`` every level's pyramid of
    block means (2x2 blocks up to the whole tile; level i, pyramid step p >= 1 at ``pyr_off[i, p]``). Each accepted
    stroke is drawn into levels ``level .. finest`` and appended to ``out`` (rows of x, y, angle, length, sagitta).
    Returns the new row count of ``out``.
    """
    np.random.seed(seed)
    nlev = sizes.shape[0]
    finest = sizes[nlev - 1]
    scratch = np.zeros(finest * finest, np.float64)
    touched = np.empty(finest * finest, np.int64)
    # per pyramid step: accumulated delta per block and the touched blocks
    max_steps = pyr_count.max()
    bscratch = np.zeros((max_steps + 1, (finest // 2) * (finest // 2)), np.float64)
    btouched = np.empty((max_steps + 1, finest * finest), np.int64)  # a block may repeat (zero deltas)
    bcount = np.zeros(max_steps + 1, np.int64)
    cand = np.empty((candidates, 5))
    size_here = sizes[level]
    area_here = float(size_here * size_here)
    added = 0
    stalls = 0
    while added < max_strokes:
        mean_here = pyr[pyr_off[level, pyr_count[level]]]  # the 1x1 block: the level's mean darkness
        deficit = target - mean_here
        if deficit <= 0.0:
            break
        best, best_score, best_gain_here = -1, -1e300, 0.0
        for k in range(candidates):
            x, y = np.random.random(), np.random.random()
            a = angle + (2.0 * np.random.random() - 1.0) * jitter
            if cross and np.random.random() < 0.5:
                a += cross_angle
            if style == 2:  # stippling: a dot, `width` pixels across
                length, sag = 0.0, 0.0
            else:
                length = len_lo + (len_hi - len_lo) * np.random.random()
                # the last strokes of a level are shortened so it can land on its target, not overshoot by a stroke
                fit = deficit * area_here / (width * max(1.0 - mean_here, 1e-3)) / size_here
                length = max(min(length, fit), 2.0 * width / size_here)
                sag = curvature * (2.0 * np.random.random() - 1.0)
            cand[k, 0], cand[k, 1], cand[k, 2], cand[k, 3], cand[k, 4] = x, y, a, length, sag
            score, gain_here = 0.0, 0.0
            for lv in range(level, nlev):
                s = sizes[lv]
                steps = pyr_count[lv]
                base = dark_off[lv]
                count = _stamp(x, y, a, length, sag, width, s, scratch, touched, 0)
                for b in range(1, steps + 1):
                    bcount[b] = 0
                total = 0.0
                for q in range(count):
                    p = touched[q]
                    delta = scratch[p] * (1.0 - dark[base + p])  # ink over paper: d + c (1 - d)
                    scratch[p] = 0.0
                    total += delta
                    row, col = p // s, p % s
                    for b in range(1, steps + 1):
                        bs = s >> b
                        blk = (row >> b) * bs + (col >> b)
                        if bscratch[b, blk] == 0.0:
                            btouched[b, bcount[b]] = blk
                            bcount[b] += 1
                        bscratch[b, blk] += delta
                # squared-error reduction of every pyramid step, each step weighted as a mean over its blocks
                for b in range(1, steps + 1):
                    bs = s >> b
                    inv_area = 1.0 / float(1 << (2 * b))
                    weight = 1.0 / float(bs * bs)
                    off = pyr_off[lv, b]
                    gain = 0.0
                    for q in range(bcount[b]):
                        blk = btouched[b, q]
                        dmean = bscratch[b, blk] * inv_area
                        bscratch[b, blk] = 0.0
                        err = target - pyr[off + blk]
                        gain += dmean * (2.0 * err - dmean)
                    score += gain * weight
                if lv == level:
                    gain_here = total / float(s * s)
            if score > best_score:
                best, best_score, best_gain_here = k, score, gain_here
        if best_gain_here <= 0.0:  # it fell on solid ink: no progress, draw new candidates (a bounded number)
            stalls += 1
            if stalls > 1000:
                break
            continue
        stalls = 0
        # stop when the best stroke would overshoot: leave the mean farther from the target than it is now
        if best_gain_here >= 2.0 * deficit:
            break
        x, y, a, length, sag = cand[best, 0], cand[best, 1], cand[best, 2], cand[best, 3], cand[best, 4]
        for lv in range(level, nlev):
            s = sizes[lv]
            steps = pyr_count[lv]
            base = dark_off[lv]
            count = _stamp(x, y, a, length, sag, width, s, scratch, touched, 0)
            for q in range(count):
                p = touched[q]
                delta = scratch[p] * (1.0 - dark[base + p])
                scratch[p] = 0.0
                dark[base + p] += delta
                row, col = p // s, p % s
                for b in range(1, steps + 1):
                    bs = s >> b
                    pyr[pyr_off[lv, b] + (row >> b) * bs + (col >> b)] += delta / float(1 << (2 * b))
        out[out_count, 0], out[out_count, 1], out[out_count, 2] = x, y, a
        out[out_count, 3], out[out_count, 4] = length, sag
        out_count += 1
        added += 1
        if out_count >= out.shape[0]:
            break
    return out_count


def _mix_seed(seed: int, tone: int, level: int) -> int:
    """A 31-bit seed per (seed, tone, level), so each fill has its own reproducible random stream."""
    h = (seed * 0x9E3779B1 + tone * 0x85EBCA77 + level * 0xC2B2AE3D + 0x27D4EB2F) & 0xFFFFFFFF
    h ^= h >> 15
    h = (h * 0x2C1B3C6D) & 0xFFFFFFFF
    h ^= h >> 12
    return h & 0x7FFFFFFF


def generate_tam(options: TamOptions = TamOptions(), seed: int = 0) -> TonalArtMap:
    """Generate a tonal art map (Praun et al. 2001); see the module docstring for the algorithm.

    Parameters
    ----------
    options : TamOptions
        Tones, levels, size (pixels of the finest level), style and stroke parameters.
    seed : int
        The same seed and options give the same TAM, bit for bit.

    Returns
    -------
    TonalArtMap, levels finest first.
    """
    check_options(options)
    tones, nlev = options.tones, options.levels
    targets = tone_targets(tones, options.darkest)
    # internal numbering: 0 = coarsest (filled first), nlev - 1 = finest
    sizes = np.array([options.size >> (nlev - 1 - i) for i in range(nlev)], np.int64)
    dark_off = np.concatenate([[0], np.cumsum(sizes * sizes)])[:-1].astype(np.int64)
    dark = np.zeros(int((sizes * sizes).sum()), np.float64)
    pyr_count = np.array([int(round(math.log2(s))) for s in sizes], np.int64)
    pyr_off = np.zeros((nlev, pyr_count.max() + 1), np.int64)
    offset = 0
    for i, s in enumerate(sizes):
        for b in range(1, pyr_count[i] + 1):
            pyr_off[i, b] = offset
            offset += int(s >> b) ** 2
    pyr = np.zeros(offset, np.float64)

    style = STYLES.index(options.style)
    width = float(options.stroke_width)
    len_lo, len_hi = (float(v) for v in options.stroke_length)
    angle = math.radians(options.stroke_angle)
    jitter = math.radians(options.angle_jitter)
    cross_angle = math.radians(options.cross_angle)
    out = np.empty((4096, 5), np.float64)  # the stroke table; doubled whenever a fill runs out of rows
    tone_col, level_col = [], []
    count = 0
    images = [np.empty((tones, int(s), int(s)), np.float64) for s in sizes[::-1]]
    for t in range(tones):
        cross = options.style == "cross-hatching" and targets[t] > options.cross_threshold
        for lv in range(nlev):
            before = count
            for attempt in range(64):
                count = _fill_level(dark, dark_off, sizes, pyr, pyr_off, pyr_count, lv, float(targets[t]),
                                    _mix_seed(seed, t, lv + 1000 * attempt), style, width, len_lo, len_hi, angle,
                                    jitter, float(options.curvature), cross, cross_angle, options.candidates, out,
                                    count, 1 << 40)
                if count < len(out):
                    break  # the level reached its target
                out = np.concatenate([out, np.empty_like(out)])  # full: grow and go on filling this level
            tone_col += [t] * (count - before)
            level_col += [nlev - 1 - lv] * (count - before)  # finest-first numbering
        for lv in range(nlev):
            s = int(sizes[lv])
            images[nlev - 1 - lv][t] = dark[dark_off[lv]: dark_off[lv] + s * s].reshape(s, s)
    strokes = {
        "x": out[:count, 0].copy(), "y": out[:count, 1].copy(), "angle": out[:count, 2].copy(),
        "length": out[:count, 3].copy(), "sagitta": out[:count, 4].copy(),
        "width": np.full(count, width), "tone": np.array(tone_col, np.int64), "level": np.array(level_col, np.int64),
    }
    return TonalArtMap(targets=targets, darkness=images, strokes=strokes, options=options, seed=seed)


# ---------------------------------------------------------------------------------------------------------- packing
def pack_rgb(tam: TonalArtMap, level: int) -> list[np.ndarray]:
    """Praun's packing: tones 0-2 in the RGB of a first texture, 3-5 in a second; (R, R, 3) uint8 brightness each."""
    bright = tam.brightness_u8(level)
    if len(bright) != 6:
        raise ValueError(f"the packed layout needs 6 tones, got {len(bright)}")
    textures = [np.ascontiguousarray(np.moveaxis(bright[first: first + 3], 0, -1)) for first in (0, 3)]
    return textures


def pack_volume(tam: TonalArtMap, level: int) -> np.ndarray:
    """Webb's volume TAM for one level: the tone slices stacked vertically, (tones * R, R) uint8, lightest on top."""
    bright = tam.brightness_u8(level)
    return bright.reshape(-1, bright.shape[-1])
