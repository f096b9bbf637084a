"""``baker hair SCALP -o OUT`` and ``baker guides GROOM -o OUT``: the parsers; the work is
:func:`baker.techniques.hair.step.run_hair` and :func:`~baker.techniques.hair.step.run_guides`, imported when it runs."""
from __future__ import annotations

from baker import memory
from baker.options import add_arguments
from baker.technique import lazy
from baker.techniques.hair.options import GuidesOptions, HairOptions
from baker.techniques.hair_shading.options import HairMaterialOptions

OUTPUT_SUFFIXES = (".glb", ".gltf", ".usda", ".usdc", ".usd", ".tfx")
GUIDES_OUTPUT_SUFFIXES = (".glb", ".gltf", ".usda", ".usdc", ".usd", ".tfx")


def add_parser(subparsers) -> None:
    add_hair_parser(subparsers)
    add_guides_parser(subparsers)


def add_hair_parser(subparsers) -> None:
    p = subparsers.add_parser("hair", help="grow hair guide strands + children on a mesh (glTF, USD or TressFX)")
    p.add_argument("input", help="emitter (scalp) mesh: .gltf .glb .obj .ply .stl .usd .usda .usdc .usdz")
    p.add_argument("-o", "--output", required=True, help=f"output file ({' '.join(OUTPUT_SUFFIXES)})")
    p.add_argument("--seed", type=int, default=0, help="random seed; the same seed gives byte-identical output")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary")
    memory.add_argument(p)
    add_arguments(p, HairOptions, "hair", prefixed_flags=False)
    add_arguments(p, HairMaterialOptions, "hair")  # --hair-*: the hair material (BAKER_hair_shading)
    p.set_defaults(func=lazy("baker.techniques.hair.step:run_hair"))


def add_guides_parser(subparsers) -> None:
    p = subparsers.add_parser("guides", help="dense groom -> simulation guides, 3-guide child weights and LODs")
    p.add_argument("input", help="groom: .usd .usda .usdc .usdz (BasisCurves), .gltf .glb (LINES, LINE_STRIP, "
                                 "BAKER_hair) or .tfx (TressFX)")
    p.add_argument("-o", "--output", required=True, help=f"output file ({' '.join(GUIDES_OUTPUT_SUFFIXES)})")
    p.add_argument("--format", choices=("text", "json"), default="text", help="summary format (stdout for json)")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary, no progress bar")
    memory.add_argument(p, help="refuse a --scalp mesh whose estimated working memory is larger: bytes (512M, 2G), "
                        "a share of RAM (50%%) or 'none' (default: 75%% of RAM)")
    add_arguments(p, GuidesOptions, "guides", prefixed_flags=False)
    add_arguments(p, HairMaterialOptions, "hair")  # --hair-*: the hair material (BAKER_hair_shading)
    p.set_defaults(func=lazy("baker.techniques.hair.step:run_guides"))
