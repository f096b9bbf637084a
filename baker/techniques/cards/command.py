"""``baker cards GROOM -o OUT``: the parser; the work is :func:`baker.techniques.cards.step.run_cards`."""
from __future__ import annotations

from baker.options import add_arguments
from baker.technique import lazy
from baker.techniques.cards.options import CardsOptions
from baker.techniques.hair_shading.options import HairMaterialOptions

CARDS_OUTPUT_SUFFIXES = (".glb", ".gltf", ".usda", ".usdc", ".usd")


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("cards", help="dense groom -> alpha-tested hair cards + strand atlas "
                                            "(BAKER_hair_cards)")
    p.add_argument("input", help="groom: .usd .usda .usdc .usdz (BasisCurves), .gltf .glb (LINES, LINE_STRIP, "
                                 "BAKER_hair) or .tfx (TressFX)")
    p.add_argument("-o", "--output", required=True, help=f"output file ({' '.join(CARDS_OUTPUT_SUFFIXES)})")
    p.add_argument("--format", choices=("text", "json"), default="text", help="summary format (stdout for json)")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary")
    add_arguments(p, CardsOptions, "cards", prefixed_flags=False)
    # --hair-*: the cards' hair material (BAKER_hair_shading); the per-strand data is the strands' only
    add_arguments(p, HairMaterialOptions, "hair", skip=("melanin_variation", "occlusion_rays"))
    p.set_defaults(func=lazy("baker.techniques.cards.step:run_cards"))
