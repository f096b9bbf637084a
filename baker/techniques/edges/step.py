"""Wire the edge kernel (:mod:`baker.techniques.edges.kernel`) to an Asset: per glTF mesh, gather its triangle
primitives and their per-corner UVs and normals, run the kernel, write each primitive's data; and the standalone
``baker lines IN -o drawing.svg`` (:func:`run_lines`, the drawing in :mod:`.svg` and :mod:`.line_drawing`)."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from baker.errors import BakerError
from baker.geometry.asset import Asset
from baker.techniques.edges.options import EdgesOptions
from baker.texels.targets import made_by_unwrap
from baker.techniques.edges import extension as ext
from baker.techniques.edges.kernel import mesh_edges
from baker.progress import QUIET, Progress


def is_fin_primitive(prim: dict) -> bool:
    return "finsOf" in ((prim.get("extensions") or {}).get(ext.NAME) or {})


def _corner_attribute(asset: Asset, prim: dict, key: str, faces: np.ndarray, width: int) -> np.ndarray:
    from baker.gltf.accessors import to_float

    acc = (prim.get("attributes") or {}).get(key)
    if acc is None:
        return np.full((len(faces), 3, width), np.nan)
    return to_float(asset.doc, acc)[faces][..., :width]


def run(asset: Asset, options: EdgesOptions, seed: int = 0, progress: Progress = QUIET) -> None:
    doc = asset.doc
    for m, mesh in enumerate(asset.meshes()):
        prims = mesh.get("primitives", [])
        if options.fins:  # a re-bake replaces the fins of an earlier one (they are appended at the end)
            while prims and is_fin_primitive(prims[-1]):
                prims.pop()
        members = []  # (primitive index, positions, all triangles, kept mask)
        for p in asset.triangle_primitives(m):
            prim = prims[p]
            if is_fin_primitive(prim):
                continue
            positions = asset.primitive(m, p).positions
            indices = doc.accessor(prim["indices"]).astype(np.int64) if "indices" in prim else \
                np.arange(len(positions))
            triangles = ext.all_triangles(indices, prim.get("mode", 4))
            keep = ((triangles[:, 0] != triangles[:, 1]) & (triangles[:, 1] != triangles[:, 2])
                    & (triangles[:, 0] != triangles[:, 2]))
            if keep.any():
                members.append((p, positions, triangles, keep))
        if not members:
            continue
        # per-corner attributes only where a primitive has them: no seam work on a mesh without UVs or normals
        # a layout baker made (an unwrap for a texture bake that ran first) is not the mesh's: its seams are not
        # UV seams of the asset, and the edges baked alone would not see them
        has_uv = any("TEXCOORD_0" in (prims[p].get("attributes") or {}) and not made_by_unwrap(asset, m, p, 0)
                     for p, *_ in members)
        has_normals = all("NORMAL" in (prims[p].get("attributes") or {}) for p, *_ in members)
        with progress.task(f"edges mesh {m}", 1) as advance:
            # gathered only if the analysis looks for seams (some position is held by several vertices)
            found = mesh_edges(
                [(positions, triangles, keep) for _, positions, triangles, keep in members],
                (lambda: np.concatenate([_corner_attribute(asset, prims[p], "TEXCOORD_0", t[k], 2)
                                         for p, _, t, k in members])) if has_uv else None,
                (lambda: np.concatenate([_corner_attribute(asset, prims[p], "NORMAL", t[k], 3)
                                         for p, _, t, k in members])) if has_normals else None,
                options, fins=options.fins)
            advance(1)
        for (p, pos, _, _), pe in zip(members, found):
            written = None
            if options.visibility:
                written = ext.write_edge_visibility(doc, m, p, pe.visibility_codes, pe.silhouette_mates, len(pos))
            if options.outline_normals:
                ext.write_outline_normals(doc, m, p, pe.shell_normals)
            fins = ext.write_fin_primitive(doc, m, p, pe) if options.fins and len(pe.edges) else None
            ext.write_primitive_edges(doc, m, p, pe, options=options, vertex_count=len(pos), fins=fins, outline=options.outline_normals,
                                      visibility=written is not None)


def run_lines(args) -> int:
    """``baker lines IN -o drawing.svg``: the hidden-line drawing of the asset from the camera, as SVG."""
    from baker.geometry import edges as E
    from baker.geometry.raycast import RayScene
    from baker.gltf.atomic import write_bytes_atomic
    from baker.techniques.edges import line_drawing as L
    from baker.techniques.edges.svg import DEFAULT_WIDTHS, make_camera, scene_triangles, svg_document

    out = Path(args.output)
    if out.suffix.lower() != ".svg":
        raise BakerError(out, "output must end in .svg")
    widths = dict(DEFAULT_WIDTHS)
    if args.widths:
        for item in args.widths.split(","):
            key, _, value = item.partition("=")
            if key.strip() not in widths:
                raise BakerError(None, f"--widths: unknown line type {key!r} (known: {', '.join(widths)})")
            try:
                widths[key.strip()] = float(value)
            except ValueError:
                raise BakerError(None, f"--widths: {item!r} is not TYPE=NUMBER") from None
    if args.step <= 0:
        raise BakerError(None, "--step must be > 0")
    hatch_settings = None
    if args.hatching:
        from baker.techniques.edges.hatching import HatchSettings
        from baker.techniques.edges.svg import parse_vector

        if not (args.hatch_spacing >= 1.0 and math.isfinite(args.hatch_spacing)):
            raise BakerError(None, "--hatch-spacing must be >= 1 pixel")
        if not (args.hatch_width > 0 and math.isfinite(args.hatch_width)):
            raise BakerError(None, "--hatch-width must be > 0")
        light = parse_vector(args.light, "--light") if args.light else None
        if light is not None and np.linalg.norm(light) == 0:
            raise BakerError(None, "--light must not be zero")
        hatch_settings = HatchSettings(spacing=args.hatch_spacing, light=None if light is None else tuple(light),
                                       seed=args.seed)
    elif args.light:
        raise BakerError(None, "--light needs --hatching")
    from baker import readers
    from baker.memory import check_bake, parse_limit

    # the edge analysis and the ray scene cost what the edges bake does per triangle; hatching adds the curvature
    # fit and the field (about the curvature bake's) and the per-pixel surface image
    limit = parse_limit(args.max_memory)
    asset = readers.read(args.input, max_memory=limit)
    need = check_bake(asset, ("edges", "curvature") if args.hatching else ("edges",), None, limit,
                      "drawing the lines of this asset")
    positions, faces, groups = scene_triangles(asset)
    camera = make_camera(args, asset, positions)
    if args.hatching:
        from baker.memory import human
        from baker.techniques.edges.hatching import BYTES_PER_PIXEL

        need += BYTES_PER_PIXEL * camera.width * camera.height
        if limit is not None and need > limit:
            raise BakerError(asset.source, f"hatching a {camera.width}x{camera.height} drawing needs about "
                                           f"{human(need)}, more than --max-memory {human(limit)}")
    options = E.EdgeSettings(crease_angle=args.crease_angle)
    mesh = E.analyze_mesh(positions, faces, face_group=groups, options=options)
    scene = RayScene(mesh.welded, mesh.faces_welded)
    lines = L.trace_lines(mesh, camera, scene, step=args.step, creases=not args.no_creases)
    hatching = None
    if hatch_settings is not None:
        from baker.techniques.edges.hatching import hatch

        progress = Progress(enabled=False if args.quiet else None)
        hatching = hatch(camera, scene, mesh.welded, mesh.faces_welded, hatch_settings, progress)
    write_bytes_atomic(out, svg_document(lines, camera.width, camera.height, widths, args.hidden, hatching,
                                         args.hatch_width).encode("utf-8"))
    return 0
