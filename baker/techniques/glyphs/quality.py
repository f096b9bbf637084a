"""The quality metric of a glyph atlas: what a shader draws when it magnifies the field, vs the exact outline.

For each glyph, its box of the atlas is drawn ``magnify`` times larger the way a runtime does: the texture sampled
bilinearly at each output pixel's centre (texel centres at half-integers, clamp to the atlas edge), the median of
the three channels taken (the single channel for SDF; RGB for MTSDF), and the result thresholded at 0.5. The truth is
an exact rasterization of the glyph's outline at the same resolution: the font's original contours (not baker's
normalized ones) flattened finely, filled with the **nonzero** rule by a supersampled scanline (``supersample`` x
``supersample`` samples per output pixel, a pixel is covered when at least half its samples are). The error of a
glyph is the fraction of its output pixels whose coverage differs.

This module shares nothing with the distance kernels except the outline reader, so it checks them independently.
It serves the tests and ``benchmarks/glyphs.py`` (which scores msdfgen's output with the same code).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from baker.techniques.glyphs.shape import Shape


def flatten(shape: Shape, steps: int = 64) -> np.ndarray:
    """(m, 2, 2) line pieces approximating every segment (curves: ``steps`` chords of equal parameter step)."""
    if shape.segment_count == 0:
        return np.zeros((0, 2, 2))
    t = np.linspace(0.0, 1.0, steps + 1)
    s = 1.0 - t
    basis = {
        1: np.stack([s, t], 1),
        2: np.stack([s * s, 2 * s * t, t * t], 1),
        3: np.stack([s ** 3, 3 * s * s * t, 3 * s * t * t, t ** 3], 1),
    }
    pieces = []
    for d in (1, 2, 3):
        rows = shape.degree == d
        if not rows.any():
            continue
        b = basis[d] if d > 1 else np.stack([np.array([1.0, 0.0]), np.array([0.0, 1.0])], 0)
        pts = np.einsum("tk,nkc->ntc", b, shape.points[rows, : d + 1])  # (n, steps + 1 or 2, 2)
        pieces.append(np.stack([pts[:, :-1], pts[:, 1:]], axis=2).reshape(-1, 2, 2))
    return np.concatenate(pieces)


def nonzero_raster(lines: np.ndarray, width: int, height: int) -> np.ndarray:
    """(height, width) bool: sample (r, c) at (c + .5, r + .5) is inside the closed polylines ``lines`` (units of
    samples, y up, row 0 at the bottom) by the nonzero winding rule (a ray to +x; half-open rows, no double
    counting at shared vertices)."""
    acc = np.zeros((height, width + 1), np.int32)
    if len(lines):
        x0, y0, x1, y1 = lines[:, 0, 0], lines[:, 0, 1], lines[:, 1, 0], lines[:, 1, 1]
        lo, hi = np.minimum(y0, y1), np.maximum(y0, y1)
        first = np.clip(np.ceil(lo - 0.5).astype(np.int64), 0, height)
        last = np.clip(np.ceil(hi - 0.5).astype(np.int64), 0, height)  # rows first..last-1 have lo <= y < hi
        count = last - first
        keep = count > 0
        idx = np.repeat(np.nonzero(keep)[0], count[keep])
        start = np.repeat(np.cumsum(count[keep]) - count[keep], count[keep])
        rows = np.repeat(first[keep], count[keep]) + (np.arange(len(idx)) - start)
        yr = rows + 0.5
        tt = (yr - y0[idx]) / (y1[idx] - y0[idx])
        xc = x0[idx] + tt * (x1[idx] - x0[idx])
        direction = np.where(y1[idx] > y0[idx], 1, -1).astype(np.int32)
        # the crossing counts for samples c with c + .5 < xc, i.e. c <= ceil(xc - .5) - 1
        col = np.clip(np.ceil(xc - 0.5).astype(np.int64) - 1, -1, width - 1) + 1
        np.add.at(acc, (rows, col), direction)
    winding = np.cumsum(acc[:, ::-1], axis=1)[:, ::-1][:, 1:]
    return winding != 0


def reference_coverage(shape: Shape, scale: float, left: float, bottom: float, width: int, height: int,
                       magnify: int = 8, supersample: int = 5) -> np.ndarray:
    """(height * magnify, width * magnify) bool coverage of the outline (font units, mapped by p * scale - (left,
    bottom) into a box of ``width`` x ``height`` pixels), row 0 at the bottom."""
    k = magnify * supersample
    lines = flatten(shape)
    lines = (lines * scale - np.array([left, bottom])) * k
    inside = nonzero_raster(lines, width * k, height * k)
    blocks = inside.reshape(height * magnify, supersample, width * magnify, supersample).sum(axis=(1, 3))
    return blocks * 2 >= supersample * supersample


def magnified_inside(values: np.ndarray, atlas_bounds: tuple, magnify: int = 8) -> np.ndarray:
    """Bilinear + median + threshold render of one glyph box. ``values`` (H, W, C) float in [0, 1], row 0 at the top;
    ``atlas_bounds`` (left, bottom, right, top) in pixels from the atlas bottom. Returns (h * magnify, w * magnify)
    bool, row 0 at the bottom."""
    H, W, C = values.shape
    l, b, r, t = atlas_bounds
    w, h = int(round(r - l)), int(round(t - b))
    u = l + (np.arange(w * magnify) + 0.5) / magnify  # atlas x of output pixel centres
    v = b + (np.arange(h * magnify) + 0.5) / magnify  # atlas y from the bottom
    fx = u - 0.5
    fy = (H - v) - 0.5  # image rows (top-down) of texel centres
    x0 = np.floor(fx).astype(np.int64)
    y0 = np.floor(fy).astype(np.int64)
    ax, ay = fx - x0, fy - y0
    xa, xb = np.clip(x0, 0, W - 1), np.clip(x0 + 1, 0, W - 1)
    ya, yb = np.clip(y0, 0, H - 1), np.clip(y0 + 1, 0, H - 1)
    ch = min(C, 3)
    v00 = values[ya][:, xa, :ch]
    v01 = values[ya][:, xb, :ch]
    v10 = values[yb][:, xa, :ch]
    v11 = values[yb][:, xb, :ch]
    axx, ayy = ax[None, :, None], ay[:, None, None]
    s = (1 - ayy) * ((1 - axx) * v00 + axx * v01) + ayy * ((1 - axx) * v10 + axx * v11)
    field = np.median(s, axis=2) if ch == 3 else s[..., 0]
    return field > 0.5


@dataclass
class GlyphError:
    codepoint: int
    error: float  # wrongly covered pixels / box pixels
    wrong: int
    pixels: int
    ink: int  # covered pixels of the reference
    components: tuple  # (reference, rendered) 8-connected ink components
    holes: tuple  # (reference, rendered) 4-connected background components (the outside included)
    ties: int = 0  # wrong pixels whose centre is within ``tie`` pixels of the outline (8-bit rounding decides them)


def _distance_to_lines(points: np.ndarray, lines: np.ndarray, chunk: int = 256) -> np.ndarray:
    """Distance from each point (n, 2) to the nearest line piece (m, 2, 2), brute force."""
    out = np.empty(len(points))
    a, ab = lines[:, 0], lines[:, 1] - lines[:, 0]
    l2 = np.maximum((ab * ab).sum(-1), 1e-300)
    for s in range(0, len(points), chunk):
        p = points[s: s + chunk, None, :]
        t = np.clip(((p - a) * ab).sum(-1) / l2, 0.0, 1.0)
        out[s: s + chunk] = np.linalg.norm(p - (a + t[..., None] * ab), axis=-1).min(axis=1)
    return out


def glyph_errors(values: np.ndarray, glyphs: list, magnify: int = 8, supersample: int = 5,
                 topology: bool = False, tie: float = 0.0) -> list:
    """Score every glyph with an outline. ``values`` (H, W, C) the decoded atlas in [0, 1] (row 0 at the top);
    ``glyphs``: (codepoint, raw Shape in font units, scale px per font unit, atlas bounds (l, b, r, t) y up,
    plane left and bottom in pixels).

    ``tie`` (pixels of the atlas): a wrong pixel whose centre lies that close to the outline is a tie that the 8-bit
    rounding of the field decides (a value of exactly 0.5 cannot be stored); such pixels still count as errors, are
    counted in ``ties``, and are resolved to the truth before the topology (components, holes) is compared."""
    out = []
    for codepoint, shape, scale, atlas_bounds, (left, bottom) in glyphs:
        inside = magnified_inside(values, atlas_bounds, magnify)
        h, w = inside.shape[0] // magnify, inside.shape[1] // magnify
        truth = reference_coverage(shape, scale, left, bottom, w, h, magnify, supersample)
        wrong_mask = inside != truth
        wrong = int(np.count_nonzero(wrong_mask))
        comps = holes = (0, 0)
        ties = 0
        if tie > 0 and wrong:
            rows, cols = np.nonzero(wrong_mask)
            centres = np.stack([(cols + 0.5) / magnify, (rows + 0.5) / magnify], axis=1)
            lines = flatten(shape) * scale - np.array([left, bottom])
            is_tie = _distance_to_lines(centres, lines) <= tie
            ties = int(is_tie.sum())
            inside = inside.copy()
            inside[rows[is_tie], cols[is_tie]] = truth[rows[is_tie], cols[is_tie]]
        if topology:
            from scipy import ndimage

            eight = np.ones((3, 3), bool)
            comps = (ndimage.label(truth, eight)[1], ndimage.label(inside, eight)[1])
            holes = (ndimage.label(np.pad(~truth, 1, constant_values=True))[1],
                     ndimage.label(np.pad(~inside, 1, constant_values=True))[1])
        out.append(GlyphError(codepoint, wrong / inside.size, wrong, int(inside.size), int(truth.sum()), comps, holes,
                              ties))
    return out


def atlas_errors(atlas, magnify: int = 8, supersample: int = 5, topology: bool = False) -> list:
    """:func:`glyph_errors` of a :class:`~baker.techniques.glyphs.atlas.GlyphAtlas`, from its 8-bit image; ties are
    pixels within one 8-bit step of distance (range / 255 pixels) of the outline."""
    values = atlas.image.astype(np.float64) / 255.0
    scale = atlas.options.size / atlas.font.metrics.units_per_em
    items = []
    for g, source in zip(atlas.glyphs, atlas.font.glyphs):  # bake_atlas keeps the font's glyph order
        if g.atlas is None:
            continue
        left, bottom = g.plane[0] * atlas.options.size, g.plane[1] * atlas.options.size
        items.append((g.codepoint, source.shape, scale, g.atlas, (left, bottom)))
    return glyph_errors(values, items, magnify, supersample, topology, tie=atlas.options.range / 255.0)
