"""``baker hair SCALP -o OUT``: the parser; the work is in :mod:`baker.techniques.hair.grow`, imported when it runs."""
from __future__ import annotations

import dataclasses

from baker.technique import lazy
from baker.techniques.hair.options import HairOptions

OUTPUT_SUFFIXES = (".glb", ".gltf", ".usda", ".usdc", ".usd", ".tfx")


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("hair", help="grow hair guide strands + children on a mesh (glTF, USD or TressFX)")
    p.add_argument("input", help="emitter (scalp) mesh: .gltf .glb .obj .ply .stl .usd .usda .usdc .usdz")
    p.add_argument("-o", "--output", required=True, help=f"output file ({' '.join(OUTPUT_SUFFIXES)})")
    p.add_argument("--seed", type=int, default=0, help="random seed; the same seed gives byte-identical output")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary")
    group = p.add_argument_group("hair options", (HairOptions.__doc__ or "").strip())
    for f in dataclasses.fields(HairOptions):
        meta = f.metadata
        shown = ",".join(map(str, f.default)) if isinstance(f.default, tuple) else f.default
        text = meta.get("help", "") + (f" (default: {shown})" if shown is not None else "")
        metavar = "{" + ",".join(map(str, meta["choices"])) + "}" if meta.get("choices") else f.name.upper()
        group.add_argument(f"--{f.name.replace('_', '-')}", dest=f"hair__{f.name}", default=None, metavar=metavar,
                           help=text)
    p.set_defaults(func=lazy("baker.techniques.hair.grow:run"))
