"""Wire the local-thickness kernel to an Asset: gather geometry, cast, hand results to the extension writer."""
from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np

from baker.geometry.asset import Asset
from baker.geometry.raycast import RayScene  # ctypes only: the BVH build does not wait for numba
from baker.techniques.thickness.options import ThicknessOptions
from baker.techniques.thickness import extension as ext
from baker.progress import QUIET, Progress


def run(asset: Asset, options: ThicknessOptions, seed: int = 0, progress: Progress = QUIET) -> None:
    # Embree builds the BVHs (GIL released, ~1.6 of 2 cores busy) in a thread while this one welds, computes
    # normals and lays out texels: at 1.1M triangles the build is the largest cost before the first ray
    with ThreadPoolExecutor(1) as builder:
        _run(asset, options, seed, progress, builder)


def _run(asset: Asset, options: ThicknessOptions, seed: int, progress: Progress, builder: ThreadPoolExecutor) -> None:
    doc = asset.doc
    scenes, limits = {}, {}
    for m in range(len(asset.meshes())):
        vertices, faces = asset.mesh_triangles(m)
        if len(faces):
            scenes[m] = builder.submit(RayScene, vertices, faces)
            # the numba-compiled modules are imported once the first build runs: their import waits for numba,
            # which the command started loading on another thread (baker.numba_warmup)
            from baker.techniques.thickness.kernel import default_max_distance

            diag = default_max_distance(vertices)
            limits[m] = (options.max_distance or diag, options.bias if options.bias is not None else 1e-5 * diag)

    from baker.geometry.normals import vertex_normals
    from baker.geometry.texture_space import dilate, interpolate
    from baker.geometry.texture_target import material_groups, material_label, material_targets
    from baker.techniques.thickness.kernel import local_thickness

    def cast(mesh, points, normals, label):
        max_distance, bias = limits[mesh]
        scene = scenes[mesh].result()
        with progress.task(label, len(points)) as advance:
            return local_thickness(scene, points, normals, rays=options.rays,
                                   distribution=options.distribution, spread=options.spread,
                                   max_distance=max_distance, bias=bias, seed=seed, sampler=options.sampler,
                                   progress=advance)

    groups = material_groups(asset)  # also gives material-less primitives a default material
    sums = {mat: [0.0, 0] for mat in groups}
    material_of = {mp: mat for mat, members in groups.items() for mp in members}

    if options.per_vertex:
        for m in scenes:
            prims = [p for p in asset.triangle_primitives(m) if (m, p) in material_of]
            if not prims:
                continue  # every primitive of the mesh is unlit (material_groups leaves them out)
            # welded across UV/normal seams and primitives: one sample per position, so split vertices agree
            mesh = asset.welded(m, prims)
            geoms, welded, inverse, offsets = mesh.geometries, mesh.positions, mesh.inverse, mesh.offsets
            normals = vertex_normals(welded, mesh.faces)
            values = cast(m, welded, normals, f"thickness mesh {m} vertices")[inverse]
            for i, (p, g) in enumerate(zip(prims, geoms)):
                per_vertex = values[offsets[i]: offsets[i + 1]]
                ext.write_vertex_thickness(doc, m, p, per_vertex)
                s = sums[material_of[(m, p)]]
                s[0] += float(per_vertex.sum())
                s[1] += len(per_vertex)

    textured = {}
    if options.per_texel:
        for target in material_targets(asset, options.texture_size, seed):
            image = np.zeros((target.size, target.size), np.float64)
            for pt in target.primitives:
                g, t = pt.geometry, pt.texels
                points = interpolate(g.positions, g.faces, t.triangle, t.bary)
                normals = interpolate(pt.normals, g.faces, t.triangle, t.bary)
                image[t.rows, t.cols] = cast(g.mesh, points, normals, f"thickness material {target.material} texels")
            mask = target.mask
            if not options.per_vertex:
                sums[target.material][0] += float(image[mask].sum())
                sums[target.material][1] += int(mask.sum())
            png, factor = ext.encode_thickness_texture(dilate(image, mask), options.texture_bits)
            textured[target.material] = ext.write_thickness_texture(doc, target.material, png, factor,
                                                                    target.texcoord)
        double_sided = [material_label(doc, m) for m in textured if not ext.volume_allowed(doc, m)]
        if double_sided:
            asset.note("KHR_materials_volume is not valid on double-sided materials: their thickness texture is in "
                       f"BAKER_thickness only: {', '.join(double_sided)}")

    for material, members in groups.items():
        mesh_limits = [limits[m] for m, _ in members if m in limits]
        if not mesh_limits:
            continue
        total, count = sums[material]
        ext.write_material_parameters(doc, material, options=options, max_distance=max(l[0] for l in mesh_limits),
                                      bias=max(l[1] for l in mesh_limits), mean_thickness=total / count if count else 0.0,
                                      per_vertex=options.per_vertex, texture=textured.get(material))
