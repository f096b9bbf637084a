"""``baker hair SCALP_MESH -o OUT`` (run by :func:`baker.techniques.hair.step.run_hair`): grow guide strands and
children on a mesh and write them.

Outputs by suffix: ``.glb``/``.gltf`` (the input asset plus a LINES mesh carrying ``BAKER_hair``), ``.usda``/
``.usdc``/``.usd`` (the asset plus ``UsdGeom.BasisCurves``), ``.tfx`` (AMD TressFX 4 guide strands). Options are
the fields of :class:`baker.techniques.hair.options.HairOptions`, as ``--<name>`` flags.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from baker.geometry.asset import Asset
from baker.geometry.normals import vertex_normals
from baker.geometry.welding import weld
from baker.techniques.hair.kernel import Emitter, HairResult, SurfaceField, generate_hair
from baker.techniques.hair.options import HairOptions
from baker.errors import BakerError
from baker.readers.sniff import check_input

from baker.techniques.hair.command import OUTPUT_SUFFIXES


def _luminance(rgb: np.ndarray) -> np.ndarray:
    rgb = np.asarray(rgb, np.float64)
    if rgb.ndim == 1:
        return rgb
    if rgb.shape[-1] == 1:
        return rgb[..., 0]
    return rgb[..., :3] @ np.array([0.2126, 0.7152, 0.0722]) if rgb.shape[-1] >= 3 else rgb[..., 0]


def _field(asset: Asset, spec: str | None, prims, inverse_parts) -> SurfaceField | None:
    """A density/length field from 'COLOR_0' or an image file, over the emitting corners (in welded order)."""
    if not spec:
        return None
    doc = asset.doc
    if spec.upper() == "COLOR_0":
        values = []
        for m, p, g in prims:
            attrs = asset.meshes()[m]["primitives"][p]["attributes"]
            if "COLOR_0" not in attrs:
                raise BakerError(asset.source, f"--density-map/--length-map COLOR_0: mesh {m} primitive {p} has no "
                                 "vertex colours")
            from baker.gltf.accessors import to_float

            values.append(_luminance(to_float(doc, attrs["COLOR_0"]))[g.faces])
        return SurfaceField(corner_values=np.concatenate(values))
    from baker.gltf.images import read_image

    path = Path(spec)
    # a directory, a named pipe, an empty file: one line saying what it is
    check_input(path, None, "an image", missing="map image not found (use COLOR_0 or an image file)")
    image = read_image(path)
    if image.dtype.kind in "ui":
        image = image.astype(np.float64) / np.iinfo(image.dtype).max
    image = _luminance(np.asarray(image, np.float64).reshape(image.shape[0], image.shape[1], -1))
    uvs = []
    for m, p, g in prims:
        if 0 not in g.texcoords:
            raise BakerError(asset.source, f"an image map needs TEXCOORD_0; mesh {m} primitive {p} has none")
        uvs.append(g.texcoords[0][g.faces])
    return SurfaceField(corner_uv=np.concatenate(uvs), image=image)


def emitter_from_asset(asset: Asset, options: HairOptions) -> Emitter:
    """The emitting triangles of mesh ``options.mesh`` (welded by position, so closedness and normals are
    those of the surface, not of its UV seams); the whole mesh is the collider."""
    meshes = asset.meshes()
    if options.mesh >= len(meshes):
        raise BakerError(asset.source, f"--mesh {options.mesh}: the asset has {len(meshes)} meshes")
    prims = [(options.mesh, p, asset.primitive(options.mesh, p)) for p in asset.triangle_primitives(options.mesh)]
    prims = [(m, p, g) for m, p, g in prims if len(g.faces)]
    if not prims:
        raise BakerError(asset.source, f"mesh {options.mesh} has no triangles")
    positions = np.concatenate([g.positions for _, _, g in prims])
    welded, inverse = weld(positions)
    offsets = np.cumsum([0] + [len(g.positions) for _, _, g in prims])
    all_faces = [inverse[g.faces + offsets[i]] for i, (_, _, g) in enumerate(prims)]
    colliders = np.concatenate(all_faces)
    emitting = [i for i, (_, _, g) in enumerate(prims) if options.material is None or g.material == options.material]
    if not emitting:
        raise BakerError(asset.source, f"no primitive of mesh {options.mesh} uses material {options.material}")
    faces = np.concatenate([all_faces[i] for i in emitting])
    emit_prims = [prims[i] for i in emitting]
    texcoords = None
    if all(0 in g.texcoords for _, _, g in emit_prims):
        texcoords = np.concatenate([g.texcoords[0][g.faces] for _, _, g in emit_prims])
    return Emitter(welded, faces, vertex_normals(welded, colliders),
                   density=_field(asset, options.density_map, emit_prims, inverse),
                   length_scale=_field(asset, options.length_map, emit_prims, inverse),
                   collider_faces=colliders, texcoords=texcoords)


def make_hair(input_path, options: HairOptions, seed: int = 0, max_memory: int | None = None
              ) -> tuple[Asset, HairResult]:
    """Grow hair on the mesh of ``input_path``; ``max_memory``: bytes the loaded emitter may need (None: no limit)."""
    from baker import readers
    from baker.memory import check_bake

    asset = readers.read(input_path, max_memory=max_memory)
    check_bake(asset, (), None, max_memory, "growing hair on this emitter")
    emitter = emitter_from_asset(asset, options)
    try:
        result = generate_hair(emitter, options, seed=seed)
    except ValueError as exc:
        raise BakerError(input_path, str(exc)) from None
    return asset, result


def usd_hair_material(doc, result: HairResult, emitter_mesh: int, shading=None, seed: int = 0):
    """The ``hair_hook`` of :func:`~baker.techniques.hair.usd.write_hair_usd` that binds the hair material and
    writes the strands' precomputes (as :func:`~baker.techniques.hair.extension.write_hair` does for glTF)."""
    from baker.techniques.hair.extension import mesh_triangles
    from baker.techniques.hair_shading.options import HairMaterialOptions
    from baker.techniques.hair_shading.strands import strand_attributes
    from baker.techniques.hair_shading.usd import write_strand_material

    shading = shading or HairMaterialOptions()
    sets = [result.guides] + ([result.children] if result.children.count else [])
    attributes, kwargs = strand_attributes(shading, sets, result.root_width, result.tip_width,
                                           scalp=mesh_triangles(doc, emitter_mesh), seed=seed)
    paths = ["/Root/Hair/guides", "/Root/Hair/children"][:len(sets)]
    return lambda stage: write_strand_material(stage, paths, shading, attributes, kwargs)


def write_output(asset: Asset, result: HairResult, options: HairOptions, output, shading=None, seed: int = 0) -> None:
    """Write the hair as ``output``'s suffix says; ``shading``: the hair material's options
    (:class:`~baker.techniques.hair_shading.options.HairMaterialOptions`, default when None)."""
    output = Path(output)
    suffix = output.suffix.lower()
    if suffix in (".glb", ".gltf"):
        from baker.techniques.hair.extension import write_hair

        write_hair(asset.doc, result, options.mesh, shading, seed=seed)
        asset.doc.save(output)
    elif suffix in (".usda", ".usdc", ".usd"):
        from baker.registry import usd_primitive_hooks
        from baker.techniques.hair.usd import write_hair_usd

        write_hair_usd(asset.doc, result, options.mesh, output, options.curve_type, usd_primitive_hooks(),
                       hair_hook=usd_hair_material(asset.doc, result, options.mesh, shading, seed))
    elif suffix == ".tfx":
        from baker.techniques.hair.tfx import write_tfx

        g = result.guides
        write_tfx(output, g.positions, thickness=g.width_scale, strand_uv=g.root_uv)
    else:
        raise BakerError(output, f"unsupported output type (use one of {', '.join(OUTPUT_SUFFIXES)})")
