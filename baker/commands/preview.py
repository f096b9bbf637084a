"""``baker preview ASSET -o sheet.png``: a labelled contact sheet of every baked technique, rendered headlessly with
the runtime shaders (:mod:`baker.preview.core`)."""
from __future__ import annotations


def add_parser(sub) -> None:
    p = sub.add_parser("preview", help="render a baked asset with the runtime shaders as a labelled contact sheet")
    p.add_argument("input", help="a baked asset (.glb, .gltf, or any input baker reads)")
    p.add_argument("-o", "--output", required=True, help="output image (.png)")
    p.add_argument("--size", type=int, default=384, help="panel size in pixels (default 384)")
    p.add_argument("--view", default="30,15", help="camera azimuth,elevation in degrees (default 30,15)")
    p.add_argument("--panels", default=None, help="comma-separated panels (default: every one the asset has data for; "
                                                  "the names are listed in the README)")
    p.add_argument("-q", "--quiet", action="store_true")
    p.add_argument("--allow-outside", action="append", metavar="PATH", help="also read buffer/image URIs under PATH "
                   "(default: only inside the asset's folder); repeatable")
    p.set_defaults(func=run)



def run(args) -> int:
    from baker.preview.core import main

    if args.allow_outside:  # preview() takes an Asset as well as a path
        from baker.geometry.asset import Asset

        args.input = Asset.load(args.input, allow_outside=args.allow_outside)
    return main(args)
