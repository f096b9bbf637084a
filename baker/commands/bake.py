"""``baker bake IN -o OUT --bakes a,b``: run bakes on an asset and write it (flags made from each technique's options)."""
from __future__ import annotations

import sys

from baker import memory, registry
from baker.errors import BakerError
from baker.options import add_arguments, from_args
from baker.gltf.meshopt_encode import COMPRESSIONS


def add_parser(sub) -> None:
    bakes = registry.bakes()
    p = sub.add_parser("bake", help="bake data into an asset and write it as glTF/GLB or USD")
    p.add_argument("input", help="input asset (.gltf .glb .obj .ply .stl .usd .usda .usdc .usdz)")
    p.add_argument("-o", "--output", required=True, help="output file (.glb .gltf .usda .usdc .usdz)")
    p.add_argument("--bakes", default="thickness", help=f"comma-separated bakes to run (known: {', '.join(bakes)})")
    p.add_argument("--seed", type=int, default=0, help="random seed; the same seed gives byte-identical output")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bars or summary")
    memory.add_argument(p)
    p.add_argument("--allow-outside", action="append", metavar="PATH", help="also read buffer/image URIs under PATH "
                   "(default: only inside the asset's folder); repeatable")
    p.add_argument("--attribute-layout", choices=("blender", "native"), default="blender",
                   help="custom vertex attributes: 'blender' pads them to one width per mesh (FLOAT VEC3, or the "
                   "width of the mesh's own attributes), which Blender 4.5 imports; 'native' writes each at its "
                   "width (SCALAR, VEC2, VEC3) (default: blender)")
    p.add_argument("--compress", choices=COMPRESSIONS, default="none",
                   help="store the geometry as EXT_meshopt_compression, required by the file (three.js with "
                   "MeshoptDecoder and Babylon.js read it; every baked extension and attribute is kept): 'meshopt' "
                   "makes each bufferView as small as it gets, the float vertex attributes through the EXPONENTIAL "
                   "filter (float32 again, 12 to 16 mantissa bits: README, Compressed output), 'meshopt-gzip' as "
                   "small as it gets once gzipped, for servers that gzip (a view stays plain where that is smaller), "
                   "'meshopt-lossless' as 'meshopt' without the filter (every byte kept) (default: none)")
    p.add_argument("--from", dest="source", metavar="HIGH", help="bake from this high-poly mesh onto the input's UVs: "
                   "each texel's ray leaves the cage toward the input's surface and samples the first HIGH surface "
                   "it meets (works with: " + ", ".join(n for n, t in bakes.items() if t.transfers) + ")")
    p.add_argument("--cage", metavar="MESH", help="with --from: the cage, a mesh with the input's topology whose "
                   "vertices the rays leave from (default: the input pushed out along its smoothed normals)")
    p.add_argument("--cage-distance", type=float, metavar="D", help="with --from: push the cage out by D mesh units "
                   "(default: 1.25 x the 99.5th percentile of the high's distance from the input, plus 0.2%% of its "
                   "bounding-box diagonal)")
    for name, technique in bakes.items():
        add_arguments(p, technique.options, name)
    p.set_defaults(func=run)


def run(args) -> int:
    from pathlib import Path

    import warnings

    from baker.api import bake, save
    from baker.errors import BakeNote
    from baker.pipeline import OUTPUT_SUFFIXES
    from baker.progress import Progress

    names = [b.strip() for b in args.bakes.split(",") if b.strip()]
    registry.bake_order(names)  # unknown names fail here, before the input is read
    if Path(args.output).suffix.lower() not in OUTPUT_SUFFIXES:
        raise BakerError(args.output, f"unsupported output type (use one of {', '.join(sorted(OUTPUT_SUFFIXES))})")
    if args.compress != "none" and Path(args.output).suffix.lower() not in (".glb", ".gltf"):
        raise BakerError(args.output, f"--compress {args.compress} writes .glb or .gltf only")
    try:
        options = {name: from_args(registry.bakes()[name].options, name, args) for name in names}
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    from baker.memory import parse_limit

    max_memory = parse_limit(args.max_memory)
    progress = Progress(enabled=False if args.quiet else None)
    from baker import numba_warmup

    # numba's ~1 s first-call set-up runs while the input is read (started after this command's own imports, which
    # would otherwise share the GIL with it on the way to the read)
    numba_warmup.start()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", BakeNote)
        asset = bake(args.input, bakes=names, options=options, seed=args.seed, progress=progress,
                     allow_outside=args.allow_outside, max_memory=max_memory, attribute_layout=args.attribute_layout,
                     source=args.source, cage=args.cage, cage_distance=args.cage_distance)
    for warning in caught:
        if issubclass(warning.category, BakeNote):
            print(f"baker: {warning.category.label}: {warning.message}", file=sys.stderr)
        else:  # not ours (a library's): shown as Python would have
            warnings.showwarning(warning.message, warning.category, warning.filename, warning.lineno)
    transfer = asset.doc.json.get("asset", {}).get("extras", {}).get("baker", {}).get("transfer") \
        if asset.transfer is not None else None
    asset.cache.clear()  # decoded and welded geometry is done with: free it before the file is assembled
    save(asset, args.output, compress=args.compress)
    if not args.quiet:
        print(f"baked {', '.join(names)} -> {args.output}", file=sys.stderr)
        if transfer:
            print(transfer_summary(transfer), file=sys.stderr)
    return 0


def transfer_summary(transfer: dict) -> str:
    """One line on a bake from another mesh: the source, the cage, each bake's samples and misses."""
    cage = f"cage {transfer['cage']}" if "cage" in transfer else f"cage distance {transfer.get('cageDistance', 0):.4g}"
    counts = "; ".join(f"{bake} {kind} {c['samples'] - c['misses']}/{c['samples']} hit"
                       for bake, kinds in transfer.get("bakes", {}).items() for kind, c in kinds.items())
    return f"from {transfer['source']} ({transfer['sourceTriangles']} triangles, {cage}): {counts}"
