"""Hair cards (`baker cards`, RTR4 14.7.1) against the strands they stand for, as a function of the card count.

    python benchmarks/cards.py [--section cards|coverage|all] [--groom head curly] [--cards 0 32 64 128]
                               [--atlas-size 1024] [--size 160] [--repeat 3]

The grooms are written here by pxr, not by baker's grower: `head` (tests/techniques/cards_groom.py, seed 11: 4000
strands in 120 narrow clumps, some curly) and `curly` (tests/techniques/curly_groom.py, seed 23: 6000 strands in 50
wide clumps, all curly: the held-out groom of issue 39). One section per part of issue 30, each a function; `main`
runs them:

- `cards_section`: per card count (0: baker's default, the count chosen from the groom), the silhouette IoU between
  the strands and the cards from three views (coverage images rendered the same way for both:
  tests/techniques/cards_views.py, orthographic, 4 x 4 supersampled, a pixel covered when any sub-sample is), the
  share of strand points within 5 % of the mean strand length of their card, the quads, and the time of the bake
  (clustering, ribbons, atlas; no file I/O). Peers in the same run: the same card triangles drawn opaque (what the
  alpha-tested atlas buys), and the clustering alone (the k-medoids of `baker guides`, which the cards reuse) for
  time.
- `coverage_per_mip`: for baker's fur shells (the defaults: 16 shells of 128^2; the innermost, a middle and an outer
  shell), the fur fin texture and a synthetic hair-card texture (60 antialiased strands 0.6-1.2 texels wide on 256^2),
  the fraction of texels whose alpha passes the cutoff (0.5) at every level, for the chain baker ships
  (baker.texels.alpha_mips.alpha_mip_chain) and for the plain box chain (the same area filter, alpha not scaled: what
  mipmapping the PNG gives), plus the same levels' coverage under bilinear sampling (4 x 4 samples per texel,
  baker.texels.alpha_mips.bilinear_coverage: what a GPU's LINEAR filter sees). Time: building the chain against
  building the box chain (the same filter without the binary search), best of --repeat.
"""
from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from baker.techniques.cards.kernel import make_cards  # noqa: E402
from baker.techniques.cards.options import CardsOptions  # noqa: E402
from baker.readers import read_groom  # noqa: E402
from baker.readers.groom import clean_groom  # noqa: E402
from baker.techniques.hair.guide_solver import resample_strands, select_guides  # noqa: E402
from techniques.cards_groom import make_groom, write_groom_usd  # noqa: E402
from techniques.curly_groom import make_curly_groom  # noqa: E402
from techniques.cards_views import card_silhouette, coverage_image, strand_silhouette, view_basis  # noqa: E402
from baker.texels.alpha_mips import (alpha_mip_chain, bilinear_coverage, level_sizes,  # noqa: E402
                                   levels_off_coverage)
from baker.techniques.fur.kernel import bake_fur_textures  # noqa: E402
from baker.techniques.fur.options import FurOptions  # noqa: E402
from common import best_of  # noqa: E402


VIEWS = ((0, 0), (90, 10), (200, 35))
SUPERSAMPLE = 4
CUTOFF = 0.5


def read_strands(path: Path, vertices: int):
    groom = clean_groom(read_groom(path), path)
    return resample_strands(groom.points, groom.counts, vertices, groom.widths)


def silhouettes_iou(curves, cards: dict, size: int, cutoff: float) -> float:
    """Mean over VIEWS of the IoU of strand and card coverage images."""
    points = np.concatenate(curves)
    scores = []
    for view in VIEWS:
        basis = view_basis(*view)
        xy = np.stack([points @ basis[0], points @ basis[1]], 1)
        lo = xy.min(0) - 0.01
        box = (lo, float((xy.max(0) + 0.01 - lo).max()))
        strands = coverage_image(strand_silhouette(curves, basis, box, size * SUPERSAMPLE), size)
        drawn = coverage_image(card_silhouette(cards, basis, box, size * SUPERSAMPLE, cutoff), size)
        scores.append((strands & drawn).sum() / (strands | drawn).sum())
    return float(np.mean(scores))


def cards_section(curves, groom_path: Path, counts, atlas_size: int, size: int) -> list[dict]:
    """One row per card count (see the module docstring)."""
    strands, lengths, widths = read_strands(groom_path, CardsOptions().vertices_per_strand)
    rows = []
    for n in counts:
        options = CardsOptions(cards=n, atlas_size=atlas_size)
        start = time.perf_counter()
        result = make_cards(strands, lengths, widths, options)
        seconds = time.perf_counter() - start
        start = time.perf_counter()
        roots = strands[:, 0]
        select_guides(strands - roots[:, None], roots, lengths, result.card_count, locality=options.locality,
                      iterations=8, seed=options.seed)
        clustering = time.perf_counter() - start
        cards = {"positions": result.positions.astype(np.float64), "uv": result.texcoords.astype(np.float64),
                 "triangles": result.indices.astype(np.int64).reshape(-1, 3), "color": result.base_color}
        opaque = dict(cards, color=np.full_like(result.base_color, 255))
        rows.append({"requested": n, "cards": result.card_count, "quads": result.stats["quadCount"],
                     "iou": silhouettes_iou(curves, cards, size, options.alpha_cutoff),
                     "iou_opaque": silhouettes_iou(curves, opaque, size, options.alpha_cutoff),
                     "near": result.stats["cardDistance"]["within5Percent"],
                     "opaque_texels": result.stats["pointsOnOpaqueTexels"], "seconds": seconds,
                     "clustering": clustering})
        print(f"  {n} cards done ({seconds:.2f} s)", file=sys.stderr, flush=True)
    return rows


GROOMS = {"head": ("tests/techniques/cards_groom.py, seed 11: 4000 strands, 120 narrow clumps",
                   lambda: make_groom(strands=4000, clumps=120, seed=11)),
          "curly": ("tests/techniques/curly_groom.py, seed 23: 6000 strands, 50 wide curly clumps",
                    lambda: make_curly_groom())}


def print_cards_table(rows, groom: str, atlas_size: int, size: int) -> None:
    print(f"groom `{groom}` ({GROOMS[groom][0]}); atlas {atlas_size}^2; "
          f"silhouettes {size}^2 ({SUPERSAMPLE}x{SUPERSAMPLE} supersampled), mean IoU over views (az, el) "
          f"{', '.join(map(str, VIEWS))}; 2 shared cores\n")
    print("| --cards | cards | quads | silhouette IoU (alpha-tested) | IoU, same cards opaque | points within 5 % of a card "
          "| points on opaque texels | bake s | clustering alone s | ratio |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['requested'] or 'default'} | {r['cards']} | {r['quads']} | {r['iou']:.3f} | {r['iou_opaque']:.3f} | {100 * r['near']:.1f}% | "
              f"{100 * r['opaque_texels']:.1f}% | {r['seconds']:.2f} | {r['clustering']:.2f} | "
              f"{r['seconds'] / max(r['clustering'], 1e-9):.1f}x |", flush=True)


def hair_card_texture(size: int = 256, strands: int = 60, seed: int = 3) -> np.ndarray:
    """Antialiased strands along gentle random curves, 0.6-1.2 texels wide: a hair card atlas region."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:size, 0:size] + 0.5
    alpha = np.zeros((size, size))
    for _ in range(strands):
        x0, amp, freq, phase = rng.uniform(0, size), rng.uniform(2, 12), rng.uniform(1, 3), rng.uniform(0, 2 * math.pi)
        width = rng.uniform(0.6, 1.2)
        centre = x0 + amp * np.sin(freq * 2 * math.pi * y / size + phase)
        alpha = np.maximum(alpha, np.clip(width / 2 - np.abs(x - centre) + 0.5, 0, 1) * (y < rng.uniform(0.5, 1) * size))
    out = np.zeros((size, size, 4), np.uint8)
    out[..., :3] = (89, 56, 31)
    out[..., 3] = np.rint(alpha * 255)
    return out


def textures() -> list[tuple[str, np.ndarray, str]]:
    fur = bake_fur_textures(FurOptions(), seed=0)
    return [(f"fur shell {i} of 16 (128^2)", fur.shells[i], "gamma2.2") for i in (0, 7, 12)] + \
        [(f"fur fin ({fur.fin.shape[1]} x {fur.fin.shape[0]})", fur.fin, "gamma2.2"),
         ("hair card texture (256^2)", hair_card_texture(), "srgb")]


def coverage_per_mip(repeat: int = 3) -> list[dict]:
    """One row per texture: coverage per level (texel fraction and bilinear) of the preserving and the box chain,
    the levels (down to 8 x 8) more than 10% (or one texel) off level 0's, and the build times."""
    rows = []
    for name, rgba, transfer in textures():
        sizes = level_sizes(*rgba.shape[:2])
        t_chain, chain = best_of(repeat, lambda: alpha_mip_chain(rgba, CUTOFF, transfer=transfer))
        t_box, box = best_of(repeat, lambda: alpha_mip_chain(rgba, CUTOFF, transfer=transfer, preserve_coverage=False))
        rows.append({
            "name": name, "sizes": sizes, "chain": chain.coverage, "box": box.coverage, "scales": chain.scales,
            "chain_bilinear": [bilinear_coverage(lv[..., 3], CUTOFF) for lv in chain.levels],
            "box_bilinear": [bilinear_coverage(lv[..., 3], CUTOFF) for lv in box.levels],
            "chain_off": levels_off_coverage(chain.coverage, sizes), "box_off": levels_off_coverage(box.coverage, sizes),
            "seconds_chain": t_chain, "seconds_box": t_box})
    return rows


def _percent(values, sizes, down_to=2):
    return " / ".join(f"{100 * v:.1f}" for v, (h, w) in zip(values, sizes) if min(h, w) >= down_to)


def print_coverage_table(rows, repeat: int) -> None:
    """The RESULTS.md table of :func:`coverage_per_mip`'s rows."""
    print(f"alpha cutoff {CUTOFF}; coverage in % of texels per level, level 0 first, down to 2 texels on the short "
          f"side; 'off': levels down to 8 x 8 more than 10% (or one texel) from level 0; best of {repeat}, "
          "2 cores\n")
    print("| texture | chain | texel coverage per level (%) | levels off | bilinear coverage per level (%) | "
          "build (ms) |")
    print("|---|---|---|---|---|---:|")
    for r in rows:
        for kind in ("chain", "box"):
            label = "coverage-preserving" if kind == "chain" else "box (plain mips)"
            print(f"| {r['name']} | {label} | {_percent(r[kind], r['sizes'])} | "
                  f"{len(r[kind + '_off'])} {r[kind + '_off'] or ''} | {_percent(r[kind + '_bilinear'], r['sizes'])} | "
                  f"{1000 * r['seconds_' + kind]:.1f} |", flush=True)
    print()
    for r in rows:
        print(f"{r['name']}: chain build {r['seconds_chain'] / r['seconds_box']:.1f}x the box chain's time; "
              f"alpha scales {' '.join(f'{s:.2f}' for s in r['scales'])}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--section", choices=("cards", "coverage", "all"), default="all")
    parser.add_argument("--groom", choices=tuple(GROOMS), nargs="+", default=["head", "curly"])
    parser.add_argument("--cards", type=int, nargs="+", default=[0, 32, 64, 128],
                        help="card counts; 0: the default, chosen from the groom")
    parser.add_argument("--atlas-size", type=int, default=1024)
    parser.add_argument("--size", type=int, default=160, help="silhouette image size (pixels)")
    parser.add_argument("--repeat", type=int, default=3, help="coverage section: best of this many chain builds")
    args = parser.parse_args()
    if args.section in ("cards", "all"):
        for groom in args.groom:
            curves, widths = GROOMS[groom][1]()
            with tempfile.TemporaryDirectory() as folder:
                path = write_groom_usd(Path(folder) / "groom.usda", curves, widths)
                make_cards(*read_strands(path, 8)[:3], CardsOptions(cards=4, atlas_size=64))  # numba compiled
                rows = cards_section(curves, path, args.cards, args.atlas_size, args.size)
            print_cards_table(rows, groom, args.atlas_size, args.size)
            print()
    if args.section in ("coverage", "all"):
        print_coverage_table(coverage_per_mip(args.repeat), args.repeat)


if __name__ == "__main__":
    main()
