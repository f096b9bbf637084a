"""``baker preview ASSET -o sheet.png``: a labelled contact sheet of every baked technique, rendered headlessly with
the runtime shaders (:mod:`baker.preview.core`)."""
from __future__ import annotations

from baker import memory


def add_parser(sub) -> None:
    p = sub.add_parser("preview", help="render a baked asset with the runtime shaders as a labelled contact sheet")
    p.add_argument("input", help="a baked asset (.glb, .gltf, or any input baker reads)")
    p.add_argument("-o", "--output", required=True, help="output image (.png)")
    p.add_argument("--size", type=int, default=384, help="panel size in pixels (default 384)")
    p.add_argument("--view", default="30,15", help="camera azimuth,elevation in degrees (default 30,15)")
    p.add_argument("--panels", default=None, help="comma-separated panels (default: every one the asset has data for; "
                                                  "the names are listed in the README)")
    p.add_argument("-q", "--quiet", action="store_true")
    memory.add_argument(p)
    p.add_argument("--allow-outside", action="append", metavar="PATH", help="also read buffer/image URIs under PATH "
                   "(default: only inside the asset's folder); repeatable")
    p.set_defaults(func=run)



def run(args) -> int:
    from baker import readers
    from baker.preview.core import main

    # preview() takes an Asset as well as a path: loaded here under the URI roots and the memory limit
    limit = memory.parse_limit(args.max_memory)
    args.input = readers.read(args.input, args.allow_outside, limit, require_triangles=False)  # a groom: lines
    memory.check_bake(args.input, (), None, limit, "previewing this asset")
    return main(args)
