"""Card geometry: per clump a ribbon of quads along its representative curve (RTR4 14.7.1).

For each clump:

1. a frame along the curve: tangent T, then a width direction W perpendicular to it, from the principal axis of
   the members' offsets around the curve (2 x 2 PCA per station in a parallel-transport frame, smoothed along the
   curve) plus a pull towards T x scalp normal, so a clump that spreads evenly lies flat on the scalp, as cards are
   laid; where the members' points over a few stations spread least along an axis that is not the tangent, that
   axis is the card normal (the members' sheet) and W runs across the curve in that plane; N = T x W points out
   of the scalp; the ribbon starts behind the curve's root as far as the farthest member root lies upstream;
2. the width at each station covers the central ``coverage`` share of the members' offsets along W, and the ribbon
   sits at their median offset along N;
3. segments adapted to curvature: starting from the two ends, the station whose edges deviate most from the
   current ribbon is added until every station lies within ``tolerance`` x card length (or ``max_segments``);
4. the cards are drawn inner first: ordered by the mean distance of their vertices to the groom's roots, so the
   cards near the scalp come first in the index buffer (14.7.1's pre-sorted draw order).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

# weight of the scalp-aligned direction against the members' spread when choosing W: a clump whose spread is less
# anisotropic than this lies flat on the scalp. Small: the members' own principal spread decides (0.35 needed 12 %
# more cards to hold 90 % of a curly, wide-clump groom's points, benchmarks/cards.py)
SCALP_PULL = 0.1
# stations either side whose member points fit a card's sheet plane (its normal: their least-spread axis)
SHEET_WINDOW = 2


@dataclass
class Card:
    """One ribbon: stations along its centre line (all V of them), the ones kept as quad edges, and its frame."""

    centre: np.ndarray  # (V, 3) centre line
    width_axis: np.ndarray  # (V, 3) unit W (the +u direction of the texture)
    normal: np.ndarray  # (V, 3) unit N = T x W
    half_width: np.ndarray  # (V,)
    arc: np.ndarray  # (V,) arc length of the centre line from the root
    kept: np.ndarray  # (n,) station numbers that become quad edges (0 and V - 1 included)

    @property
    def length(self) -> float:
        return float(self.arc[-1])


def unit(v: np.ndarray) -> np.ndarray:
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-300)


def curve_tangents(curve: np.ndarray) -> np.ndarray:
    """Unit tangents (V, 3) by central differences; a zero one repeats its neighbour."""
    t = np.gradient(curve, axis=0)
    norm = np.linalg.norm(t, axis=1)
    for j in range(1, len(t)):  # short: V stations
        if norm[j] <= 1e-300:
            t[j], norm[j] = t[j - 1], norm[j - 1]
    for j in range(len(t) - 2, -1, -1):
        if norm[j] <= 1e-300:
            t[j], norm[j] = t[j + 1], norm[j + 1]
    return unit(t)


def transport_frame(tangents: np.ndarray, first: np.ndarray) -> np.ndarray:
    """(V, 3) unit vectors perpendicular to the tangents, ``first`` carried along by parallel transport (Bishop
    1975), so the frame does not spin where the curve twists."""
    out = np.empty_like(tangents)
    b = first
    for j, t in enumerate(tangents):
        b = b - np.dot(b, t) * t
        n = np.linalg.norm(b)
        if n < 1e-9:  # the previous axis became the tangent: any perpendicular will do
            b = np.cross(t, [1.0, 0.0, 0.0] if abs(t[0]) < 0.9 else [0.0, 1.0, 0.0])
            n = np.linalg.norm(b)
        b = b / n
        out[j] = b
    return out


def width_directions(tangents: np.ndarray, offsets: np.ndarray, scalp_normal: np.ndarray, window: int = 2):
    """(W, N) per station (V, 3) each: W the principal axis of the offsets (n, V, 3) perpendicular to T, pulled
    towards T x scalp normal; N = T x W turned out of the scalp."""
    v = len(tangents)
    side = np.cross(tangents, scalp_normal)
    start = side[0] if np.linalg.norm(side[0]) > 1e-6 else np.cross(tangents[0], [0.0, 0.0, 1.0])
    b1 = transport_frame(tangents, unit(start))
    b2 = np.cross(tangents, b1)
    x = np.einsum("nvi,vi->nv", offsets, b1)
    y = np.einsum("nvi,vi->nv", offsets, b2)
    cov = np.stack([(x * x).sum(0), (x * y).sum(0), (y * y).sum(0)], axis=1)  # (V, 3): xx, xy, yy
    kernel = np.ones(2 * window + 1)
    cov = np.stack([np.convolve(np.pad(cov[:, c], window, mode="edge"), kernel, "valid") for c in range(3)], axis=1)
    sx, sy = np.einsum("vi,vi->v", side, b1), np.einsum("vi,vi->v", side, b2)
    sn = np.hypot(sx, sy)
    sx, sy = np.where(sn > 1e-9, sx / np.maximum(sn, 1e-300), 0.0), np.where(sn > 1e-9, sy / np.maximum(sn, 1e-300), 0.0)
    trace = cov[:, 0] + cov[:, 2]
    pull = SCALP_PULL * np.where(trace > 0, trace, 1.0)
    cxx, cxy, cyy = cov[:, 0] + pull * sx * sx, cov[:, 1] + pull * sx * sy, cov[:, 2] + pull * sy * sy
    theta = 0.5 * np.arctan2(2.0 * cxy, cxx - cyy)
    for j in range(1, v):  # an axis is a direction mod pi: keep the one nearest the previous station's
        theta[j] += np.pi * np.round((theta[j - 1] - theta[j]) / np.pi)
    w = unit(np.cos(theta)[:, None] * b1 + np.sin(theta)[:, None] * b2)
    # the members' sheet: where their points at nearby stations (about their mean there) spread least is the card
    # normal, as k-planes clustering fits planes (Bradley & Mangasarian 2000). A clump of hair lying in a sheet
    # spreads along the flow as well as across it (roots scattered on the scalp, tips at different reaches), and
    # the spread perpendicular to T alone can miss the sheet's tilt. W follows the sheet where it is not
    # (nearly) perpendicular to the curve (a baker-hair groom, 120 cards: 66.9 -> 69.6 % of the points held)
    centred = offsets - offsets.mean(axis=0, keepdims=True)
    spread = np.einsum("nvi,nvj->vij", centred, centred)
    spread = np.pad(spread, ((SHEET_WINDOW, SHEET_WINDOW), (0, 0), (0, 0)), mode="edge")
    spread = sum(spread[i:i + v] for i in range(2 * SHEET_WINDOW + 1))
    sheet = np.cross(np.linalg.eigh(spread)[1][:, :, 0], tangents)
    follows = (np.linalg.norm(sheet, axis=1) > 0.3) & (len(offsets) >= 3)
    sheet = np.where(follows[:, None], unit(sheet), w)
    sheet *= np.where(np.einsum("vi,vi->v", sheet, w) < 0, -1.0, 1.0)[:, None]  # the sign of the spread's W
    for j in range(1, v):  # a direction mod pi: keep the one nearest the previous station's
        if np.dot(sheet[j], sheet[j - 1]) < 0:
            sheet[j] = -sheet[j]
    w = sheet
    n = np.cross(tangents, w)
    if np.einsum("vi,i->", n, scalp_normal) < 0:  # the card's front faces away from the scalp
        w, n = -w, -n
    return w, n


def adaptive_stations(left: np.ndarray, right: np.ndarray, tolerance: float, max_segments: int) -> np.ndarray:
    """Station numbers kept as quad edges: both ends, then greedily the station whose edge points lie farthest from
    the ribbon through the kept ones (linear in the station number between kept ones), until all are within
    ``tolerance`` (world units) or ``max_segments`` quads are used."""
    v = len(left)
    kept = [0, v - 1]
    index = np.arange(v)
    while len(kept) - 1 < max_segments:
        ks = np.asarray(sorted(kept))
        hi = np.clip(np.searchsorted(ks, index, side="right"), 1, len(ks) - 1)
        a, b = ks[hi - 1], ks[hi]
        f = ((index - a) / np.maximum(b - a, 1))[:, None]
        gap = np.maximum(np.linalg.norm(left - (left[a] * (1 - f) + left[b] * f), axis=1),
                         np.linalg.norm(right - (right[a] * (1 - f) + right[b] * f), axis=1))
        worst = int(np.argmax(gap))
        if gap[worst] <= tolerance:
            break
        kept.append(worst)
    return np.asarray(sorted(kept), np.int64)


def build_card(curve: np.ndarray, members: np.ndarray, scalp_normal: np.ndarray, *, coverage: float,
               min_half_width: float, tolerance: float, max_segments: int) -> Card:
    """The ribbon of one clump: ``curve`` (V, 3) its representative, ``members`` (n, V, 3) its strands."""
    tangents = curve_tangents(curve)
    # strands longer than the representative run past its tip: one more station carries the card as far along
    # the tip's tangent as the farthest member tip reaches
    reach = float(np.max((members[:, -1] - curve[-1]) @ tangents[-1]))
    if reach > 1e-3 * np.linalg.norm(np.diff(curve, axis=0), axis=1).sum():
        curve = np.concatenate([curve, curve[-1:] + reach * tangents[-1:]])
        members = np.concatenate([members, members[:, -1:]], axis=1)
        tangents = np.concatenate([tangents, tangents[-1:]])
    # and roots behind the representative's root (a clump's roots cover a patch of the scalp, some upstream of
    # their mean): one station before it, back along the root tangent as far as the farthest root lies behind
    behind = float(np.max((curve[0] - members[:, 0]) @ tangents[0]))
    if behind > 1e-3 * np.linalg.norm(np.diff(curve, axis=0), axis=1).sum():
        curve = np.concatenate([curve[:1] - behind * tangents[:1], curve])
        members = np.concatenate([members[:, :1], members], axis=1)
        tangents = np.concatenate([tangents[:1], tangents])
    offsets = members - curve[None]
    w_axis, normal = width_directions(tangents, offsets, scalp_normal)
    across = np.einsum("nvi,vi->nv", offsets, w_axis)
    depth = np.einsum("nvi,vi->nv", offsets, normal)
    q = (1.0 - coverage) / 2.0
    lo, hi = np.quantile(across, q, axis=0), np.quantile(across, 1.0 - q, axis=0)
    # a station's width covers its neighbours' too: strands cross stations between samples
    lo = np.minimum(lo, np.minimum(np.r_[lo[:1], lo[:-1]], np.r_[lo[1:], lo[-1:]]))
    hi = np.maximum(hi, np.maximum(np.r_[hi[:1], hi[:-1]], np.r_[hi[1:], hi[-1:]]))
    mid = 0.5 * (lo + hi)
    half = np.maximum(0.5 * (hi - lo), min_half_width)
    centre = curve + w_axis * mid[:, None] + normal * np.median(depth, axis=0)[:, None]
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(centre, axis=0), axis=1))])
    left, right = centre - w_axis * half[:, None], centre + w_axis * half[:, None]
    kept = adaptive_stations(left, right, tolerance * max(arc[-1], 1e-300), max_segments)
    return Card(centre, w_axis, normal, half, arc, kept)


def draw_order(cards: list, roots: np.ndarray) -> np.ndarray:
    """Card numbers, inner first: ascending mean distance of a card's kept centre stations to the nearest root of
    the groom (how far above the scalp it runs); ties keep card order."""
    tree = cKDTree(roots)
    depth = np.array([tree.query(c.centre[c.kept])[0].mean() for c in cards])
    return np.lexsort((np.arange(len(cards)), depth))
