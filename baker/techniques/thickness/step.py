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
    from baker.geometry.texels import gather_texels
    from baker.geometry.texture_target import material_groups, material_label
    from baker.techniques.thickness.kernel import local_thickness

    def cast(meshes, points, normals, label, scene_of=None, prior=None, tolerance=0.0, rays=options.rays):
        with progress.task(label, len(points)) as advance:
            return local_thickness([scenes[m].result() for m in meshes], points, normals, rays=rays,
                                   distribution=options.distribution, spread=options.spread,
                                   max_distance=[limits[m][0] for m in meshes], bias=[limits[m][1] for m in meshes],
                                   seed=seed, sampler=options.sampler, progress=advance, scene_of=scene_of,
                                   prior=prior, tolerance=tolerance)

    groups = material_groups(asset)  # also gives material-less primitives a default material
    sums = {mat: [0.0, 0] for mat in groups}
    material_of = {mp: mat for mat, members in groups.items() for mp in members}

    welded = {}  # mesh -> (welded mesh, its vertex normals): welded across UV/normal seams and primitives
    for m in scenes:
        prims = [p for p in asset.triangle_primitives(m) if (m, p) in material_of]
        if not prims:
            continue  # every primitive of the mesh is unlit (material_groups leaves them out)
        mesh = asset.welded(m, prims)
        welded[m] = (prims, mesh, vertex_normals(mesh.positions, mesh.faces))

    if options.per_vertex:
        for m, (prims, mesh, normals) in welded.items():
            # one sample per position, so split vertices agree
            values = cast([m], mesh.positions, normals, f"thickness mesh {m} vertices")[mesh.inverse]
            for i, p in enumerate(prims):
                per_vertex = values[mesh.offsets[i]: mesh.offsets[i + 1]]
                ext.write_vertex_thickness(doc, m, p, per_vertex)
                s = sums[material_of[(m, p)]]
                s[0] += float(per_vertex.sum())
                s[1] += len(per_vertex)

    textured = {}
    if options.per_texel:
        # every material's texels in one ray stream: each texel traces into its own mesh's scene
        texels = gather_texels(asset, options.texture_size, options.texel_density, seed)
        meshes = sorted(scenes)
        scene_of = np.searchsorted(meshes, texels.mesh)
        prior = texel_prior(welded, texels, cast, options.rays * PRIOR_RAYS_FACTOR) if options.tolerance > 0 else None
        values = cast(meshes, texels.positions, texels.normals, f"thickness texels ({texels.describe()})",
                      scene_of=scene_of, prior=prior, tolerance=options.tolerance)
        for texel_set, image, mask in texels.images(values):
            if not options.per_vertex:
                sums[texel_set.material][0] += float(image[mask].sum())
                sums[texel_set.material][1] += int(mask.sum())
            png, factor = ext.encode_thickness_texture(image, options.texture_bits)
            textured[texel_set.material] = ext.write_thickness_texture(doc, texel_set.material, png, factor,
                                                                       texel_set.texcoord)
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


PRIOR_RAYS_FACTOR = 4  # the per-vertex prior traces this many times the texels' rays (its noise then halves)
PRIOR_MIN_TEXELS_PER_VERTEX = 16  # below this the prior's vertices would cost more than a quarter of the texels


def texel_prior(welded: dict, texels, cast, rays: int) -> np.ndarray | None:
    """Each texel's thickness interpolated from a per-vertex solution of ``rays`` rays, or None
    when the mesh has too many vertices for it to pay.

    Most of a texture lies inside triangles where thickness varies almost linearly: there the interpolated vertex
    values are closer to the truth than a texel's own 64 rays (on spot at 1024^2, 1024-ray vertex values
    interpolated are within 0.003 mesh units of the 1024-ray texel reference on 65% of the texels; 64 texel rays
    on 33%). A texel takes the prior only when its first rays agree with it (``--thickness-tolerance``), so
    creases, thin parts and shadowing features the vertices miss still get every ray."""
    vertices = sum(len(mesh.positions) for _, mesh, _ in welded.values())
    if not vertices or len(texels) < PRIOR_MIN_TEXELS_PER_VERTEX * vertices:
        return None
    meshes = sorted(welded)
    positions = np.concatenate([welded[m][1].positions for m in meshes])
    normals = np.concatenate([welded[m][2] for m in meshes])
    scene_of = np.repeat(np.arange(len(meshes)), [len(welded[m][1].positions) for m in meshes])
    values = cast(meshes, positions, normals, "thickness texel prior (vertices)", scene_of=scene_of, rays=rays)
    bounds = np.cumsum([0] + [len(welded[m][1].positions) for m in meshes])
    return texels.interpolate_welded({m: (welded[m][1], values[bounds[i]: bounds[i + 1]])
                                      for i, m in enumerate(meshes)})
