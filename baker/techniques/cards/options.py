"""Options of ``baker cards``: one frozen dataclass feeds the CLI flags, recipe keys and the Python API."""
from __future__ import annotations

from dataclasses import dataclass

from baker.options import opt


@dataclass(frozen=True)
class CardsOptions:
    """Options of the groom -> hair cards bake (``baker cards``)."""

    cards: int = opt(0, "number of cards, one per clump of strands; 0: from the groom, clumps split until --fit of "
                        "the strand points lie within 5 % of the mean strand length of their card (at most one "
                        "card per 8 strands)", min=0, max=65536)
    fit: float = opt(0.9, "the share of strand points the cards must hold (with --cards 0 clumps split until it "
                          "is met; the summary says when it is missed, at any count)", min=0.5, max=1.0)
    refine: int = opt(12, "with --cards N: rounds moving strands to the card that holds most of their points and "
                         "rebuilding the cards (Lloyd over card surfaces; stops early when nothing improves); 0: "
                         "the clustering alone", min=0, max=64)
    atlas_size: int = opt(1024, "atlas width and height in texels (a power of two)", min=64, max=4096)
    vertices_per_strand: int = opt(32, "vertices of every strand after resampling at equal arc-length steps "
                                       "(card segments are chosen among them)", min=4, max=256)
    tolerance: float = opt(0.005, "card segments: the ribbon's centre line may leave the clump's curve by this "
                                  "fraction of the card's length (smaller: more segments where it bends)",
                           min=1e-5, max=0.5)
    max_segments: int = opt(24, "most quads along one card", min=1, max=255)
    coverage: float = opt(1.0, "share of a clump's strand points the card's width covers (per station, across "
                                "the card)", min=0.5, max=1.0)
    locality: float = opt(1.0, "clustering: weight of root distance against shape distance", min=0.0)
    alpha_cutoff: float = opt(0.5, "material alphaCutoff: texels with coverage below it are cut", min=0.01,
                              max=0.99)
    min_strand_texels: float = opt(1.0, "strands narrower than this many texels are drawn this wide (a hair "
                                        "thinner than a texel would vanish under the alpha test)", min=0.25,
                                   max=8.0)
    padding: int = opt(4, "texels around every card's region of the atlas (mips and filtering stay inside)",
                       min=0, max=64)
    coverage_mips: bool = opt(True, "also write the base colour's coverage-preserving mip chain (KTX2 RGBA8, "
                                    "Castano 2010) so the cards do not thin out with distance")
    color: tuple = opt((0.30, 0.19, 0.10), "hair base colour (linear RGB); roots darker, per-strand variation",
                       min=0.0, max=1.0)
    seed: int = opt(0, "random seed; the same seed gives byte-identical output")
    scalp: str | None = opt(None, "scalp (emitter) mesh written beside the cards; default: the groom file's own "
                                  "triangle mesh when it has one (a baker hair output holds its emitter), else none")
    bad_curves: str = opt("skip", "curves with < 2 vertices, NaN/inf points or zero length: skip (counted in the "
                                  "summary) or error", choices=("skip", "error"))
