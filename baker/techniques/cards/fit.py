"""The default card count: as many cards as the groom needs (issue 30's measure, RTR4 14.7.1's aim of cards that
stand for the strands).

Start from a few clumps (the guides' k-medoids, :func:`.clumps.cluster_strands`), build their ribbons and measure
every strand point's distance to its own card's surface; while fewer than ``target`` of the points lie within
``NEAR`` x the mean strand length, split the clumps holding the most points that are off their card. A clump is
split where a single card cannot cover its cross-section: by its members' offsets along the card normal
(:func:`.clumps.split_by_depth`), so the two halves get cards of their own, each oriented by its members' spread.
The count stops at ``cap`` (from the strand count) whatever the share.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from baker.techniques.cards.atlas import closest_on_cards, points_held
from baker.techniques.cards.clumps import Clumps, cluster_strands, describe_clumps, split_by_depth
from baker.techniques.cards.ribbon import Card, build_card

NEAR = 0.05  # a strand point is held by its card within this fraction of the mean strand length (issue 30)
STRANDS_PER_CARD = 8  # the cap: on average at least this many strands per card
FIRST_STRANDS_PER_CARD = 250  # the first clustering: about one clump per this many strands (at least 4)
GROWTH = 0.25  # at most this share of the clumps is split per round


@dataclass
class Fit:
    clumps: Clumps
    cards: list
    rounds: int  # split rounds after the first clustering
    first_count: int  # clumps of the first clustering
    cap: int
    near: float  # share of strand points within NEAR x mean length of their card


def card_count_cap(strands: int) -> int:
    return max(1, strands // STRANDS_PER_CARD)


def card_triangles(card: Card) -> np.ndarray:
    """(2 (n - 1), 3, 3) corners of the card's triangles (the quads between its kept stations), as written."""
    j = card.kept
    side = card.width_axis[j] * card.half_width[j, None]
    left, right = card.centre[j] - side, card.centre[j] + side
    a, b, c, d = left[:-1], left[1:], right[1:], right[:-1]
    return np.stack([np.stack([a, b, c], 1), np.stack([a, c, d], 1)], 1).reshape(-1, 3, 3)


def card_distances(strands: np.ndarray, labels: np.ndarray, triangles: list) -> np.ndarray:
    """(S, V) distance of every strand point (S, V, 3) to its clump's card (``labels`` (S,) index ``triangles``)."""
    s, v, _ = strands.shape
    count = np.array([len(t) for t in triangles], np.int64)
    start = np.concatenate([[0], np.cumsum(count)[:-1]]).astype(np.int64)
    _, _, distance = closest_on_cards(strands.reshape(-1, 3), np.repeat(labels, v), start, count,
                                      np.concatenate(triangles))
    return distance.reshape(s, v)


def fit_clumps(strands: np.ndarray, lengths: np.ndarray, *, target: float, locality: float, seed: int,
               card_options: dict) -> Fit:
    """Clumps and their cards, split until ``target`` of the strand points lie near their card (see the module
    docstring). ``card_options``: the keywords of :func:`.ribbon.build_card` besides the curve, members and normal."""
    s, v, _ = strands.shape
    cap = card_count_cap(s)
    first = min(cap, max(4, math.ceil(s / FIRST_STRANDS_PER_CARD)))
    clumps = cluster_strands(strands, lengths, first, locality=locality, seed=seed)
    first = clumps.count
    labels = clumps.labels.copy()

    def card_of(k: int) -> Card:
        return build_card(clumps.curves[k], strands[labels == k], clumps.scalp_normals[k], **card_options)

    cards = [card_of(k) for k in range(clumps.count)]
    triangles = [card_triangles(c) for c in cards]
    whole = np.ones(clumps.count, bool)  # False: the clump would not split
    tolerance = NEAR * float(lengths.mean())
    rounds = 0
    distance = card_distances(strands, labels, triangles)
    while True:
        far = distance > tolerance
        near = 1.0 - float(far.mean())
        count = clumps.count
        if near >= target or count >= cap:
            break
        far_points = np.bincount(labels, weights=far.sum(axis=1), minlength=count)
        excess = far.sum() - math.floor((1.0 - target) * far.size)
        budget = min(max(1, int(GROWTH * count)), cap - count)
        chosen, held = [], 0.0
        for k in np.lexsort((np.arange(count), -far_points)).tolist():
            if far_points[k] <= 0 or len(chosen) >= budget or held >= excess:
                break
            if whole[k]:
                chosen.append(k)
                held += far_points[k]
        split = []
        for k in chosen:
            members = np.flatnonzero(labels == k)
            card = cards[k]
            depth = np.einsum("nvi,vi->nv", strands[members] - card.centre[None, :v], card.normal[:v])
            side = split_by_depth(depth)
            if side is None:
                whole[k] = False
                continue
            labels[members[side]] = count + len(split)
            split.append(k)
        if not split:
            break
        rounds += 1
        clumps = describe_clumps(strands, lengths, labels)
        whole = np.concatenate([whole, np.ones(len(split), bool)])
        changed = split + list(range(count, clumps.count))
        for k in changed:
            card = card_of(k)
            if k < count:
                cards[k], triangles[k] = card, card_triangles(card)
            else:
                cards.append(card)
                triangles.append(card_triangles(card))
        # only the strands of split clumps moved to other cards: measure those again
        moved = np.flatnonzero(np.isin(labels, changed))
        distance[moved] = card_distances(strands[moved], labels[moved], triangles)
    return Fit(clumps, cards, rounds, first, cap, near)


# ------------------------------------------------------------------------------------- a fixed number of cards
CANDIDATES = 6  # cards a strand may move to in a refinement round: the nearest clump curves to it
REFINE_ROUNDS = 12
STATION_WINDOW = 4  # a strand point is measured against the card triangles within this many stations of it


def card_station_spans(cards: list) -> tuple[np.ndarray, np.ndarray]:
    """(first, last) station number of every triangle of :func:`card_triangles`, cards after each other."""
    first, last = [], []
    for card in cards:
        j = card.kept
        first.append(np.repeat(j[:-1], 2))
        last.append(np.repeat(j[1:], 2))
    return np.concatenate(first).astype(np.int64), np.concatenate(last).astype(np.int64)


def strand_scores(strands: np.ndarray, candidates: np.ndarray, cards: list, triangles: list,
                  tolerance: float) -> np.ndarray:
    """(S, C) how well each candidate card (``candidates`` (S, C) card numbers) holds each strand: the points within
    ``tolerance`` of the card, less a small share of their mean distance (ties go to the closer card)."""
    count = np.array([len(t) for t in triangles], np.int64)
    start = np.concatenate([[0], np.cumsum(count)[:-1]]).astype(np.int64)
    first, last = card_station_spans(cards)
    held, spread = points_held(np.ascontiguousarray(strands), np.ascontiguousarray(candidates, np.int64), start,
                               count, np.concatenate(triangles), first, last, STATION_WINDOW, tolerance)
    return held - 1e-3 * spread


def refine_clumps(strands: np.ndarray, lengths: np.ndarray, clumps: Clumps, *, card_options: dict,
                  rounds: int = REFINE_ROUNDS) -> tuple[Clumps, list]:
    """Lloyd iterations over card surfaces at a fixed card count (k-means with ribbons for centres, as k-planes
    clustering fits planes: Bradley & Mangasarian 2000): every strand moves to the card among the ``CANDIDATES``
    nearest clump curves that holds most of its points within ``NEAR`` x the mean strand length, then the cards are
    rebuilt from their new members. Each round also moves a few cards from where they are least needed to where
    they are most (a split-merge step, as in ISODATA: Ball & Hall 1965): the cards whose strands lose the fewest
    held points by going to their next-best card are retired and each restarts as the deeper half
    (:func:`.clumps.split_by_depth`) of a clump with the most points off its card. Stops when the held share has
    not risen for two rounds; returns the best (clumps, cards) seen."""
    s, v, _ = strands.shape
    tolerance = NEAR * float(lengths.mean())
    labels = clumps.labels.copy()
    count = clumps.count

    def cards_of(found: Clumps) -> list:
        return [build_card(found.curves[k], strands[labels == k], found.scalp_normals[k], **card_options)
                for k in range(count)]

    cards = cards_of(clumps)
    best = None
    stale = 0
    every = np.arange(s)
    for _ in range(rounds + 1):
        triangles = [card_triangles(c) for c in cards]
        own = card_distances(strands, labels, triangles)
        near = float((own <= tolerance).mean())
        if best is None or near > best[0]:
            best, stale = (near, clumps, cards), 0
        else:
            stale += 1
            if stale >= 2:
                break
        flat = clumps.curves.reshape(count, -1)
        _, candidates = cKDTree(flat).query(strands.reshape(s, -1), k=min(CANDIDATES, count))
        candidates = np.concatenate([labels[:, None], candidates.reshape(s, -1)], axis=1)
        scores = strand_scores(strands, candidates, cards, triangles, tolerance)
        pick = np.argmax(scores, axis=1)  # first best: the own card wins ties
        labels = candidates[every, pick]
        # what each card is worth: the points its strands would lose on their next-best other card
        other = np.where(candidates == labels[:, None], -np.inf, scores).max(axis=1)
        other = np.where(np.isfinite(other), other, 0.0)
        worth = np.bincount(labels, weights=scores[every, pick] - other, minlength=count)
        held = np.floor(scores[every, pick] + 0.01)
        far = np.bincount(labels, weights=v - held, minlength=count)
        moves = max(1, count // 6)
        retired = [k for k in np.lexsort((np.arange(count), worth)).tolist()[:moves]]
        donors = [k for k in np.lexsort((np.arange(count), -far)).tolist() if k not in retired]
        for r in retired:
            if not donors or far[donors[0]] <= 4.0 * worth[r]:  # a split would not win back what retiring loses
                continue
            members = np.flatnonzero(labels == r)
            labels[members] = np.where(np.isfinite(other[members]), candidates[members, np.argmax(
                np.where(candidates[members] == r, -np.inf, scores[members]), axis=1)], r)
            while donors:
                donor = donors.pop(0)
                members = np.flatnonzero(labels == donor)
                card = cards[donor]
                side = split_by_depth(np.einsum("nvi,vi->nv", strands[members] - card.centre[None, :v],
                                                card.normal[:v])) if len(members) > 1 else None
                if side is not None:
                    labels[members[side]] = r
                    break
        used = np.bincount(labels, minlength=count)
        for k in np.flatnonzero(used == 0).tolist():  # a card left empty keeps one strand of the largest clump
            labels[np.flatnonzero(labels == int(np.argmax(np.bincount(labels, minlength=count))))[0]] = k
        clumps = describe_clumps(strands, lengths, labels)
        cards = cards_of(clumps)
    return best[1], best[2]
