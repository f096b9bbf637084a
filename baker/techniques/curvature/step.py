"""Wire the curvature kernel to an Asset: weld, fit, scatter back to the primitives, hand results to the writer."""
from __future__ import annotations

import numpy as np

from baker.geometry.asset import Asset
from baker.techniques.curvature.options import CurvatureOptions
from baker.techniques.curvature.kernel import principal_curvatures
from baker.techniques.curvature import extension as ext
from baker.progress import QUIET, Progress


def run(asset: Asset, options: CurvatureOptions, seed: int = 0, progress: Progress = QUIET) -> None:
    doc = asset.doc
    groups = asset.material_groups()
    material_of = {mp: mat for mat, members in groups.items() for mp in members}
    stats = {mat: [np.inf, -np.inf, 0.0, 0] for mat in groups}  # min, max, sum, count of H
    welded_results = {}  # mesh -> (its WeldedMesh, H per welded vertex)

    for m in range(len(asset.meshes())):
        prims = [p for p in asset.triangle_primitives(m) if (m, p) in material_of]
        geoms = [asset.primitive(m, p) for p in prims]
        geoms_with_faces = [g for g in geoms if len(g.faces)]
        if not geoms_with_faces:
            continue
        # welded across UV/normal seams and primitives: one estimate per position, so split copies agree
        mesh = asset.welded(m, prims)
        welded, inverse, offsets, faces = mesh.positions, mesh.inverse, mesh.offsets, mesh.faces
        keep = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
        if not keep.all():  # a copy only when there are welded-away triangles (F x 24 bytes at scale)
            faces = faces[keep]
        del keep
        with progress.task(f"curvature mesh {m}", 1) as advance:
            result = principal_curvatures(welded, faces, rings=options.rings, radius=options.radius,
                                          smoothing=options.smoothing, fit=options.fit)
            advance(1)
        del faces
        if options.per_texel:
            welded_results[m] = (mesh, result.mean)
        principal = np.stack([result.k1, result.k2], axis=1) if options.directions and options.per_vertex else None
        for i, (p, g) in enumerate(zip(prims, geoms)):
            idx = inverse[offsets[i]: offsets[i + 1]]
            mean = result.mean[idx]
            if options.per_vertex:
                ext.write_vertex_curvature(doc, m, p, mean, principal[idx] if options.directions else None,
                                           result.direction1[idx] if options.directions else None)
            s = stats[material_of[(m, p)]]
            if len(mean):
                s[0], s[1] = min(s[0], float(mean.min())), max(s[1], float(mean.max()))
                s[2] += float(mean.sum())
                s[3] += len(mean)

    textures = {}
    if options.per_texel:
        from baker.texels.sets import gather_texels

        texels = gather_texels(asset, options.texture_size, options.texel_density, seed)
        with progress.task(f"curvature texels ({texels.describe()})", len(texels)) as advance:
            values = texels.interpolate_welded(welded_results)
            advance(len(texels))
        for texel_set, image, _ in texels.images(values):
            png, texture_range = ext.encode_curvature_texture(image, options.texture_bits)
            textures[texel_set.material] = (ext.add_curvature_texture(doc, texel_set.material, png),
                                            texel_set.texcoord, texture_range)

    for material, (lo, hi, total, count) in stats.items():
        if not count:
            continue
        texture, texcoord, texture_range = textures.get(material, (None, 0, None))
        ext.write_material_parameters(doc, material, options=options, value_range=[lo, hi],
                                      mean_curvature=total / count, per_vertex=options.per_vertex,
                                      directions=options.directions, texture=texture, texcoord=texcoord,
                                      texture_range=texture_range)
