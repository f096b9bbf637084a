"""Groom -> hair cards: clumps (:mod:`.clumps`), ribbons (:mod:`.ribbon`), the strand atlas (:mod:`.atlas`).

Pure numpy/numba: resampled strands in, a :class:`CardsResult` (mesh arrays, atlas images, layout, statistics) out.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from baker.techniques.cards.atlas import closest_on_cards, pack_regions, rasterize_strands
from baker.techniques.cards.clumps import cluster_strands
from baker.techniques.cards.fit import fit_clumps, refine_clumps
from baker.techniques.cards.options import CardsOptions
from baker.techniques.cards.ribbon import build_card, draw_order
from baker.texels.color import linear_to_srgb

# the data texture's channels (RGB) and the flow texture's encoding, as BAKER_hair_cards records them
DATA_CHANNELS = {"r": "depth", "g": "rootToTip", "b": "strandRandom"}
FLOW_ENCODING = "tangentSpace"  # rgb = 0.5 + 0.5 x (flow . tangent, flow . bitangent, flow . normal)


@dataclass
class CardsResult:
    positions: np.ndarray  # (N, 3) float32
    normals: np.ndarray  # (N, 3) float32
    tangents: np.ndarray  # (N, 4) float32, w = -1: bitangent = cross(normal, tangent) x w runs root -> tip (+v)
    texcoords: np.ndarray  # (N, 2) float32, glTF convention (v down)
    indices: np.ndarray  # (3F,) uint32, cards in draw order (inner first)
    card_of_vertex: np.ndarray  # (N,) card number (draw order)
    regions: np.ndarray  # (K, 4) float32 u0, v0, u1, v1 of each card's inside region, draw order
    card_first_index: np.ndarray  # (K,) uint32 first index of each card in ``indices``
    base_color: np.ndarray  # (S, S, 4) uint8 sRGB + coverage alpha
    data: np.ndarray  # (S, S, 3) uint8: depth, root-to-tip, strand random (see DATA_CHANNELS)
    flow: np.ndarray  # (S, S, 3) uint8 tangent-space strand direction
    depth_range: float  # world units: data.r = 0.5 + 0.5 x depth / depth_range
    alpha_cutoff: float
    texel_density: float  # atlas texels per world unit
    strand_labels: np.ndarray  # (S,) card (draw order) of every input strand
    stats: dict = field(default_factory=dict)

    @property
    def card_count(self) -> int:
        return len(self.regions)


def strand_random(count: int, seed: int) -> np.ndarray:
    """A value in [0, 1) per strand, from the seed (the atlas's random/ID channel)."""
    return np.random.default_rng([seed, 0x7CA2D5]).random(count)


def to_u8(x: np.ndarray) -> np.ndarray:
    return np.rint(np.clip(x, 0.0, 1.0) * np.float32(255.0)).astype(np.uint8)


def card_mesh(cards: list, order: np.ndarray, rects: np.ndarray, atlas_size: int, padding: int):
    """Vertices (two per kept station: u = 0 and u = 1 edges), triangles and regions of the cards in draw order."""
    positions, normals, tangents, uvs, tris, owner, regions, first = [], [], [], [], [], [], [], []
    base = 0
    index_count = 0
    for k, c in enumerate(order.tolist()):
        card = cards[c]
        j = card.kept
        x, y, w, h = rects[c]
        u0, u1 = (x + padding) / atlas_size, (x + w - padding) / atlas_size
        v0, v1 = (y + padding) / atlas_size, (y + h - padding) / atlas_size
        side = card.width_axis[j] * card.half_width[j, None]
        ring = np.stack([card.centre[j] - side, card.centre[j] + side], axis=1).reshape(-1, 3)
        positions.append(ring)
        normals.append(np.repeat(card.normal[j], 2, axis=0))
        tangents.append(np.repeat(card.width_axis[j], 2, axis=0))
        v = v0 + (v1 - v0) * card.arc[j] / max(card.length, 1e-300)
        uvs.append(np.stack([np.tile([u0, u1], len(j)), np.repeat(v, 2)], axis=1))
        n = len(j) - 1
        left = base + 2 * np.arange(n)
        # (L_i, L_i+1, R_i+1), (L_i, R_i+1, R_i): counter-clockwise seen from +N
        quads = np.stack([left, left + 2, left + 3, left, left + 3, left + 1], axis=1).reshape(-1)
        tris.append(quads)
        first.append(index_count)
        index_count += len(quads)
        owner.append(np.full(len(ring), k))
        regions.append((u0, v0, u1, v1))
        base += len(ring)
    tangent4 = np.concatenate([np.concatenate(tangents), -np.ones((base, 1))], axis=1)
    return (np.concatenate(positions), np.concatenate(normals), tangent4, np.concatenate(uvs),
            np.concatenate(tris), np.concatenate(owner), np.asarray(regions), np.asarray(first))


def make_cards(strands: np.ndarray, lengths: np.ndarray, widths: np.ndarray | None,
               options: CardsOptions) -> CardsResult:
    """Hair cards of resampled strands (S, V, 3) with input lengths (S,) and per-vertex widths (S, V) or None."""
    s, v, _ = strands.shape
    mean_length = float(lengths.mean())
    if widths is None or not (widths.max(initial=0.0) > 0):
        widths = np.full((s, v), float(np.median(lengths)) / 300.0)
    min_half = max(float(np.median(widths)), 2e-3 * mean_length)
    card_options = dict(coverage=options.coverage, min_half_width=min_half, tolerance=options.tolerance,
                        max_segments=options.max_segments)
    if options.cards:  # an explicit count: one clustering, one card per clump
        clumps = cluster_strands(strands, lengths, options.cards, locality=options.locality, seed=options.seed)
        clumps, cards = refine_clumps(strands, lengths, clumps, card_options=card_options, rounds=options.refine)
        count_from = {"source": "option"}
    else:  # from the groom: split clumps until the cards hold the strands
        fit = fit_clumps(strands, lengths, target=options.fit, locality=options.locality, seed=options.seed,
                         card_options=card_options)
        clumps, cards = fit.clumps, fit.cards
        count_from = {"source": "groom", "target": float(options.fit), "firstCount": int(fit.first_count),
                      "splitRounds": int(fit.rounds), "cap": int(fit.cap)}
    order = draw_order(cards, strands[:, 0])
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    sizes = np.array([[2.0 * c.half_width.max(), c.length] for c in cards])
    size = options.atlas_size
    rects, density = pack_regions(sizes, size, options.padding)
    (positions, normals, tangents, uvs, indices, owner, regions, first) = card_mesh(cards, order, rects, size,
                                                                                    options.padding)
    # every strand point -> the closest point of its card (orthographic along the card normal)
    label = rank[clumps.labels]
    tri_per_card = np.bincount(owner[indices[::3]], minlength=len(cards))
    tri_start = np.concatenate([[0], np.cumsum(tri_per_card)[:-1]])
    corners = positions[indices.reshape(-1, 3)]
    points = strands.reshape(-1, 3)
    tri, bary, distance = closest_on_cards(points, np.repeat(label, v), tri_start, tri_per_card, corners)
    faces = indices.reshape(-1, 3)[tri]
    uv = np.einsum("pk,pkd->pd", bary, uvs[faces])
    n_p = np.einsum("pk,pkd->pd", bary, normals[faces])
    w_p = np.einsum("pk,pkd->pd", bary, tangents[faces, :3])
    t_p = -np.cross(n_p, w_p)  # root -> tip along the card
    foot = np.einsum("pk,pkd->pd", bary, corners[tri])
    depth = np.einsum("pd,pd->p", points - foot, n_p / np.maximum(np.linalg.norm(n_p, axis=1, keepdims=True),
                                                                  1e-300))
    direction = np.gradient(strands, axis=1).reshape(-1, 3)
    flow = np.stack([np.einsum("pd,pd->p", direction, w_p), np.einsum("pd,pd->p", direction, t_p),
                     np.einsum("pd,pd->p", direction, n_p)], axis=1)
    flow /= np.maximum(np.linalg.norm(flow, axis=1, keepdims=True), 1e-300)
    depth_range = float(max(np.abs(depth).max(initial=0.0), 1e-6 * mean_length))
    # rasterise in texel coordinates, each strand clipped to the inside of its card's region
    xy = (uv * size).reshape(s, v, 2)
    grad = np.broadcast_to(np.linspace(0.0, 1.0, v), (s, v))
    attributes = np.concatenate([depth.reshape(s, v, 1), grad[..., None], flow.reshape(s, v, 3)], axis=2)
    radius = 0.5 * np.maximum(widths * density, options.min_strand_texels)
    inside = np.rint(regions[label] * size).astype(np.int64)
    alpha, sums, weight, top = rasterize_strands(np.ascontiguousarray(xy), np.ascontiguousarray(attributes),
                                                 np.ascontiguousarray(radius), inside, size, size)
    covered = weight > 0
    f32 = np.float32
    # float32 from here: a 4096² atlas holds 16.7 M texels, and 8 bits per channel is what is written
    mean = sums / np.maximum(weight, f32(1e-30))[..., None]
    del sums
    random = strand_random(s, options.seed).astype(f32)
    rand_texel = np.where(top >= 0, random[np.maximum(top, 0)], f32(0.5))
    # texels no strand reached: the card's own root-to-tip position, flow along the card, depth 0
    rows = ((np.arange(size) + 0.5) / size).astype(f32)
    grad_texel = np.zeros((size, size), f32)
    for u0, v0, u1, v1 in regions:
        y0, y1, x0, x1 = (int(round(a * size)) for a in (v0, v1, u0, u1))
        grad_texel[y0:y1, x0:x1] = ((rows[y0:y1] - v0) / max(v1 - v0, 1e-30))[:, None]
    grad_texel = np.where(covered, mean[..., 1], grad_texel)
    data = np.stack([to_u8(f32(0.5) + f32(0.5 / depth_range) * np.where(covered, mean[..., 0], f32(0.0))),
                     to_u8(grad_texel), to_u8(rand_texel)], axis=2)
    flow_texel = np.where(covered[..., None], mean[..., 2:5], np.array([0.0, 1.0, 0.0], f32))
    del mean
    flow_texel /= np.maximum(np.linalg.norm(flow_texel, axis=2, keepdims=True), f32(1e-30))
    flow_image = to_u8(f32(0.5) + f32(0.5) * flow_texel)
    del flow_texel
    shade = (f32(0.55) + f32(0.45) * grad_texel) * (f32(0.8) + f32(0.4) * rand_texel)  # darker roots, variation
    rgb = linear_to_srgb(np.asarray(options.color, f32)[None, None, :] * shade[..., None])
    base_color = np.concatenate([to_u8(rgb), to_u8(alpha)[..., None]], axis=2)
    del rgb, shade
    # statistics: how well the cards hold the strands
    near = distance <= 0.05 * mean_length
    texel = np.clip(np.floor(uv * size).astype(np.int64), 0, size - 1)
    passes = base_color[texel[:, 1], texel[:, 0], 3] >= np.rint(options.alpha_cutoff * 255.0)
    stats = {"strandCount": int(s), "verticesPerStrand": int(v), "meanStrandLength": mean_length,
             "cardCount": int(len(cards)), "cardCountFrom": count_from, "quadCount": int(len(indices) // 6),
             "vertexCount": int(len(positions)), "clusteringError": {"rms": clumps.error_rms,
                                                                     "max": clumps.error_max},
             "cardDistance": {"rms": float(np.sqrt(np.mean(distance ** 2)) / mean_length),
                              "max": float(distance.max() / mean_length),
                              "within5Percent": float(near.mean())},
             "pointsOnOpaqueTexels": float(passes.mean()),
             "atlasCoverage": float((base_color[..., 3] >= np.rint(options.alpha_cutoff * 255.0)).mean()),
             "texelDensity": float(density)}
    return CardsResult(positions.astype(np.float32), normals.astype(np.float32), tangents.astype(np.float32),
                       uvs.astype(np.float32), indices.astype(np.uint32), owner.astype(np.int64),
                       regions.astype(np.float32), first.astype(np.uint32), base_color, data, flow_image,
                       depth_range, float(options.alpha_cutoff), float(density), label, stats)
