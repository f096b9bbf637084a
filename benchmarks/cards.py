"""Hair cards (`baker cards`, RTR4 14.7.1) against the strands they stand for, as a function of the card count.

    python benchmarks/cards.py [--strands 4000] [--cards 16 32 64 128 256] [--atlas-size 1024] [--size 160]

The groom is written here by pxr (tests/techniques/cards_groom.py: a head of clumped, partly curly strands, not
baker's grower). One section per part of issue 30, each a function; `main` runs them:

- `cards_section`: per card count, the silhouette IoU between the strands and the cards from three views (coverage
  images rendered the same way for both: tests/techniques/cards_views.py, orthographic, 4 x 4 supersampled, a pixel
  covered when any sub-sample is), the share of strand points within 5 % of the mean strand length of their card,
  the quads, and the time of the bake (clustering, ribbons, atlas; no file I/O). Peers in the same run: the same
  card triangles drawn opaque (what the alpha-tested atlas buys), and the clustering alone (the k-medoids of
  `baker guides`, which the cards reuse) for time.
"""
from __future__ import annotations

import argparse
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
from baker.techniques.hair.groom import clean_groom, read_groom  # noqa: E402
from baker.techniques.hair.guide_solver import resample_strands, select_guides  # noqa: E402
from techniques.cards_groom import make_groom, write_groom_usd  # noqa: E402
from techniques.cards_views import card_silhouette, coverage_image, strand_silhouette, view_basis  # noqa: E402

VIEWS = ((0, 0), (90, 10), (200, 35))
SUPERSAMPLE = 4


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
        select_guides(strands - roots[:, None], roots, lengths, n, locality=options.locality, iterations=8,
                      seed=options.seed)
        clustering = time.perf_counter() - start
        cards = {"positions": result.positions.astype(np.float64), "uv": result.texcoords.astype(np.float64),
                 "triangles": result.indices.astype(np.int64).reshape(-1, 3), "color": result.base_color}
        opaque = dict(cards, color=np.full_like(result.base_color, 255))
        rows.append({"cards": n, "quads": result.stats["quadCount"],
                     "iou": silhouettes_iou(curves, cards, size, options.alpha_cutoff),
                     "iou_opaque": silhouettes_iou(curves, opaque, size, options.alpha_cutoff),
                     "near": result.stats["cardDistance"]["within5Percent"],
                     "opaque_texels": result.stats["pointsOnOpaqueTexels"], "seconds": seconds,
                     "clustering": clustering})
        print(f"  {n} cards done ({seconds:.2f} s)", file=sys.stderr, flush=True)
    return rows


def print_cards_table(rows, strands: int, atlas_size: int, size: int) -> None:
    print(f"groom: {strands} strands (tests/techniques/cards_groom.py, seed 11, 120 clumps); atlas {atlas_size}^2; "
          f"silhouettes {size}^2 ({SUPERSAMPLE}x{SUPERSAMPLE} supersampled), mean IoU over views (az, el) "
          f"{', '.join(map(str, VIEWS))}; 2 shared cores\n")
    print("| cards | quads | silhouette IoU (alpha-tested) | IoU, same cards opaque | points within 5 % of a card "
          "| points on opaque texels | bake s | clustering alone s | ratio |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['cards']} | {r['quads']} | {r['iou']:.3f} | {r['iou_opaque']:.3f} | {100 * r['near']:.1f}% | "
              f"{100 * r['opaque_texels']:.1f}% | {r['seconds']:.2f} | {r['clustering']:.2f} | "
              f"{r['seconds'] / max(r['clustering'], 1e-9):.1f}x |", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--strands", type=int, default=4000)
    parser.add_argument("--cards", type=int, nargs="+", default=[16, 32, 64, 128, 256])
    parser.add_argument("--atlas-size", type=int, default=1024)
    parser.add_argument("--size", type=int, default=160, help="silhouette image size (pixels)")
    args = parser.parse_args()
    curves, widths = make_groom(strands=args.strands, clumps=120, seed=11)
    with tempfile.TemporaryDirectory() as folder:
        path = write_groom_usd(Path(folder) / "groom.usda", curves, widths)
        make_cards(*read_strands(path, 8)[:3], CardsOptions(cards=4, atlas_size=64))  # numba compiled outside timing
        rows = cards_section(curves, path, args.cards, args.atlas_size, args.size)
    print_cards_table(rows, args.strands, args.atlas_size, args.size)


if __name__ == "__main__":
    main()
