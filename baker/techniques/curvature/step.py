"""Wire the curvature kernel to an Asset: weld, fit, scatter back to the primitives, hand results to the writer."""
from __future__ import annotations

import numpy as np

from baker.geometry.asset import Asset
from baker.techniques.curvature.options import CurvatureOptions
from baker.techniques.curvature.kernel import principal_curvatures
from baker.techniques.curvature import extension as ext
from baker.progress import QUIET, Progress


def run(asset: Asset, options: CurvatureOptions, seed: int = 0, progress: Progress = QUIET) -> None:
    if asset.transfer is not None:
        return run_from_source(asset, options, seed, progress)
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
        textures = write_texel_images(doc, texels, values, options)

    write_materials(doc, stats, textures, options)


def write_texel_images(doc, texels, values: np.ndarray, options: CurvatureOptions) -> dict:
    """Each texture set's mean-curvature PNG: {material: (texture, texcoord, value range)}."""
    textures = {}
    for texel_set, image, _ in texels.images(values):
        png, texture_range = ext.encode_curvature_texture(image, options.texture_bits)
        textures[texel_set.material] = (ext.add_curvature_texture(doc, texel_set.material, png),
                                        texel_set.texcoord, texture_range)
    return textures


def write_materials(doc, stats: dict, textures: dict, options: CurvatureOptions) -> None:
    """BAKER_curvature on every material that got values: range, mean, and its texture when one was baked."""
    for material, (lo, hi, total, count) in stats.items():
        if not count:
            continue
        texture, texcoord, texture_range = textures.get(material, (None, 0, None))
        ext.write_material_parameters(doc, material, options=options, value_range=[lo, hi],
                                      mean_curvature=total / count, per_vertex=options.per_vertex,
                                      directions=options.directions, texture=texture, texcoord=texcoord,
                                      texture_range=texture_range)


def source_curvature(source, options: CurvatureOptions, progress: Progress) -> np.ndarray:
    """The high mesh's own per-vertex (H, k1, k2, direction1 xyz), as ``baker bake HIGH --bakes curvature`` writes
    them; computed once per high mesh and options (:meth:`baker.texels.transfer.SourceMesh.per_vertex`)."""
    def compute(mesh):
        faces = mesh.faces
        faces = faces[(faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])]
        with progress.task("curvature of the source's vertices", 1) as advance:
            result = principal_curvatures(mesh.positions, faces, rings=options.rings, radius=options.radius,
                                          smoothing=options.smoothing, fit=options.fit)
            advance(1)
        return np.column_stack([result.mean, result.k1, result.k2, result.direction1])

    key = repr((options.rings, options.radius, options.smoothing, options.fit))
    return source.per_vertex("curvature", key, compute)


def directions_at(hits, directions: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """The high's first principal direction at each hit, in the low's tangent plane (``normals``): a direction's
    sign is arbitrary, so each triangle's corners are turned to agree with its first before they are interpolated;
    the result is projected on the plane and normalized (a direction along the normal gives any tangent)."""
    from baker.geometry.frames import orthonormal_basis

    corners = directions[hits.source.faces[hits.triangle]]  # (n, 3 corners, 3)
    sign = np.where(np.einsum("kcj,kj->kc", corners, corners[:, 0]) < 0.0, -1.0, 1.0)
    direction = np.einsum("kc,kcj->kj", hits.bary * sign, corners)
    direction -= normals * np.einsum("kj,kj->k", direction, normals)[:, None]
    length = np.linalg.norm(direction, axis=1, keepdims=True)
    fallback = orthonormal_basis(normals)[0]
    return np.where(length > 1e-12, direction / np.maximum(length, 1e-30), fallback)


def run_from_source(asset: Asset, options: CurvatureOptions, seed: int, progress: Progress) -> None:
    """``--from HIGH``: every vertex and texel of the low mesh takes the high's own curvature where its ray through
    the cage meets the high; the principal direction is turned into the low's tangent plane."""
    from baker.geometry.normals import vertex_normals
    from baker.texels.transfer import project_welded, record

    doc, request = asset.doc, asset.transfer
    values = source_curvature(request.source, options, progress)
    groups = asset.material_groups()
    material_of = {mp: mat for mat, members in groups.items() for mp in members}
    stats = {mat: [np.inf, -np.inf, 0.0, 0] for mat in groups}
    found = []
    for m in range(len(asset.meshes())):
        prims = [p for p in asset.triangle_primitives(m) if (m, p) in material_of]
        if not prims or not any(len(asset.primitive(m, p).faces) for p in prims):
            continue
        mesh = asset.welded(m, prims)
        normals = vertex_normals(mesh.positions, mesh.faces)
        hits = project_welded(request, asset, mesh, normals)
        found.append(hits.hit)
        at = hits.interpolate(values[:, :3])
        direction = directions_at(hits, values[:, 3:6], normals) if options.directions else None
        for i, p in enumerate(prims):
            idx = mesh.inverse[mesh.offsets[i]: mesh.offsets[i + 1]]
            mean = at[idx, 0]
            if options.per_vertex:
                ext.write_vertex_curvature(doc, m, p, mean, at[idx, 1:3] if options.directions else None,
                                           direction[idx] if options.directions else None)
            s = stats[material_of[(m, p)]]
            if len(mean):
                s[0], s[1] = min(s[0], float(mean.min())), max(s[1], float(mean.max()))
                s[2] += float(mean.sum())
                s[3] += len(mean)
    if found:
        record(request, "curvature", "vertices", np.concatenate(found))
    textures = {}
    if options.per_texel:
        from baker.texels.sets import gather_texels

        texels = gather_texels(asset, options.texture_size, options.texel_density, seed)
        record(request, "curvature", "texels", texels.source.hit)
        textures = write_texel_images(doc, texels, texels.source.interpolate(values[:, 0]), options)
    write_materials(doc, stats, textures, options)
