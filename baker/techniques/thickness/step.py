"""Wire the local-thickness kernel to an Asset: gather geometry, cast, hand results to the extension writer."""
from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor
from contextlib import nullcontext

import numpy as np

from baker.geometry.asset import Asset
from baker.geometry.raycast import RayScene  # ctypes only: the BVH build does not wait for numba
from baker.techniques.thickness.options import ThicknessOptions
from baker.techniques.thickness import extension as ext
from baker.progress import QUIET, Progress
from baker import interruptible


def run(asset: Asset, options: ThicknessOptions, seed: int = 0, progress: Progress = QUIET) -> None:
    # Embree builds the BVHs (GIL released, ~1.6 of 2 cores busy) in a thread while this one welds, computes
    # normals and lays out texels: at 1.1M triangles the build is the largest cost before the first ray
    # and, for a texture of a mesh without usable UVs, xatlas in a child process (it holds the GIL): the layout is
    # ready by the time the per-vertex rays are traced
    from baker.texels.targets import unwraps_started

    with interruptible.thread_pool(1) as builder, unwraps_started(asset, options.texture_size) if options.per_texel \
            else nullcontext() as unwrapping:
        _run(asset, options, seed, progress, builder, bool(unwrapping))


def _run(asset: Asset, options: ThicknessOptions, seed: int, progress: Progress, builder: ThreadPoolExecutor,
         unwrapping: bool = False) -> None:
    if asset.transfer is not None:
        return run_from_source(asset, options, seed, progress)
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
    from baker.texels.sets import gather_texels
    from baker.techniques.thickness.kernel import FIRST_RAYS, local_thickness

    def cast(meshes, points, normals, label, scene_of=None, prior=None, tolerance=0.0, rays=options.rays,
             first_means=None, rays_used=None, threads=None):
        with progress.task(label, len(points)) as advance:
            return local_thickness([scenes[m].result() for m in meshes], points, normals, rays=rays,
                                   distribution=options.distribution, spread=options.spread,
                                   max_distance=[limits[m][0] for m in meshes], bias=[limits[m][1] for m in meshes],
                                   seed=seed, sampler=options.sampler, progress=advance, scene_of=scene_of,
                                   prior=prior, tolerance=tolerance, first_means=first_means,
                                   rays_used=rays_used, threads=threads)

    groups = asset.material_groups()  # also gives material-less primitives a default material
    sums = {mat: [0.0, 0] for mat in groups}
    material_of = {mp: mat for mat, members in groups.items() for mp in members}

    welded = {}  # mesh -> (welded mesh, its vertex normals): welded across UV/normal seams and primitives
    for m in scenes:
        prims = [p for p in asset.triangle_primitives(m) if (m, p) in material_of]
        if not prims:
            continue  # every primitive of the mesh is unlit (Asset.material_groups leaves them out)
        mesh = asset.welded(m, prims)
        welded[m] = (prims, mesh, vertex_normals(mesh.positions, mesh.faces))

    vertex_values = {}  # mesh -> per welded vertex thickness
    if options.per_vertex:
        for m, (prims, mesh, normals) in welded.items():
            # one sample per position, so split vertices agree
            # while an unwrap runs in a child, one ray thread leaves it a core: the child is what the texels wait
            # for, the vertices are not (bunny: the layout ready 0.1 s sooner, the vertices 0.3 s later)
            vertex_values[m] = cast([m], mesh.positions, normals, f"thickness mesh {m} vertices",
                                    threads=1 if unwrapping else None)
            values = vertex_values[m][mesh.inverse]
            positions_of = {}  # material -> welded vertices of its primitives in this mesh
            for i, p in enumerate(prims):
                per_vertex = values[mesh.offsets[i]: mesh.offsets[i + 1]]
                ext.write_vertex_thickness(doc, m, p, per_vertex)
                positions_of.setdefault(material_of[(m, p)], []).append(mesh.inverse[mesh.offsets[i]: mesh.offsets[i + 1]])
            for material, ids in positions_of.items():
                # the mean over positions, each once: copies split at seams (an unwrap's, if one ran first) do not
                # weigh twice
                ids = np.unique(np.concatenate(ids))
                sums[material][0] += float(vertex_values[m][ids].sum())
                sums[material][1] += len(ids)

    textured, texel_rule = {}, None
    if options.per_texel:
        # every material's texels in one ray stream: each texel traces into its own mesh's scene
        texels = gather_texels(asset, options.texture_size, options.texel_density, seed,
                               auto_range=AUTO_TEXTURE_SIZE_RANGE)
        meshes = sorted(scenes)
        scene_of = np.searchsorted(meshes, texels.mesh)
        prior = texel_prior(welded, texels, cast, options.rays, vertex_values) if options.tolerance > 0 else None
        # texels beside texels with no prior (whose normal turned from the vertices': a crease) and on the edge of
        # an authored chart trace every ray (a negative prior: none to stop on); see corrected_by_neighbours
        region_edge = np.zeros(len(texels), bool)
        if prior is not None:
            authored = np.zeros(len(texels), bool)
            for texel_set in texels.sets:
                authored[texel_set.start: texel_set.stop] = not texel_set.target.unwrapped
            region_edge = texels.region_edges(prior >= 0, within_charts=True) \
                | (authored & texels.region_edges(prior >= 0))
        first_means, rays_used = np.full(len(texels), np.nan), np.zeros(len(texels), np.int64)
        values = cast(meshes, texels.positions, texels.normals, f"thickness texels ({texels.describe()})",
                      scene_of=scene_of, prior=None if prior is None else np.where(region_edge, -1.0, prior),
                      tolerance=options.tolerance, first_means=first_means, rays_used=rays_used)
        stopped = (rays_used == FIRST_RAYS) & ~np.isnan(first_means)  # tested and stopped
        if stopped.any():
            texel_rule = {"texelTolerance": float(options.tolerance), "texelFirstRays": FIRST_RAYS}
            if options.texel_window > 0:
                texel_rule["texelWindow"] = int(options.texel_window)
                values = corrected_by_neighbours(texels, values, prior, first_means, stopped, region_edge,
                                                 options.texel_window,
                                                 np.array([limits[m][0] for m in meshes])[scene_of])
        textured = write_texel_images(asset, texels, values, options, sums)

    for material, members in groups.items():
        mesh_limits = [limits[m] for m, _ in members if m in limits]
        if not mesh_limits:
            continue
        total, count = sums[material]
        ext.write_material_parameters(doc, material, options=options, max_distance=max(l[0] for l in mesh_limits),
                                      bias=max(l[1] for l in mesh_limits), mean_thickness=total / count if count else 0.0,
                                      per_vertex=options.per_vertex, texture=textured.get(material),
                                      texel_rule=texel_rule if material in textured else None)


# The automatic thickness texture stops at 512^2 (other texture bakes: 2048^2). A mesh dense enough to reach more has
# vertices dense enough for its per-vertex solution, fitted over each one-ring (texel_prior), to carry the shape
# between texels: on the Stanford bunny (69k triangles, benchmarks/unwrap.py) the texture reads 0.0185 relative RMS
# at surface points against 2048 rays at 512^2 and 0.0166 at 1024^2 (the fitted per-vertex values alone: 0.0168),
# while 1024^2 traces 4x the texels (294k) and the texture bake then costs 2.5x the per-vertex one instead of 2.1x.
AUTO_TEXTURE_SIZE_RANGE = (64, 512)
PRIOR_MIN_TEXELS_PER_VERTEX = 16  # below this a prior of its own would cost more than a quarter of the texels
PRIOR_SELF_WEIGHT = 4.0  # a vertex's own value in its ring fit, against 2 per interior neighbour (one per face)
PRIOR_RING_COS = math.cos(math.radians(20.0))  # a neighbour whose normal turns further lies across a crease
PRIOR_NORMAL_COS = math.cos(math.radians(10.0))  # a texel's normal within 10 degrees of the vertices' takes a prior


def texel_prior(welded: dict, texels, cast, rays: int, vertex_values: dict) -> np.ndarray | None:
    """Each texel's thickness interpolated from the per-vertex solution: the one the bake wrote
    (``vertex_values``, mesh -> per welded vertex), else one of ``rays`` rays traced here, or None when the mesh
    has too many vertices for that to pay.

    Most of a texture lies inside triangles where thickness varies almost linearly. A texel takes the prior only
    when its first rays agree with it (``--thickness-tolerance``), so creases, thin parts and shadowing features
    the vertices miss still get every ray; the others add their neighbours' deviation from it
    (:func:`corrected_by_neighbours`), which also evens out the vertices' own noise: on spot a prior of 4x the
    rays gave the same final error (0.0112 vs 0.0117 at 512^2, 0.0103 vs 0.0104 at 1024^2) at 0.2 s more."""
    from baker.techniques.thickness.kernel import ring_fit

    meshes = sorted(welded)
    if not meshes:
        return None
    if all(m in vertex_values for m in meshes):
        values = vertex_values
    else:
        vertices = sum(len(mesh.positions) for _, mesh, _ in welded.values())
        if len(texels) < PRIOR_MIN_TEXELS_PER_VERTEX * vertices:
            return None
        positions = np.concatenate([welded[m][1].positions for m in meshes])
        normals = np.concatenate([welded[m][2] for m in meshes])
        scene_of = np.repeat(np.arange(len(meshes)), [len(welded[m][1].positions) for m in meshes])
        traced = cast(meshes, positions, normals, "thickness texel prior (vertices)", scene_of=scene_of, rays=rays)
        bounds = np.cumsum([0] + [len(welded[m][1].positions) for m in meshes])
        values = {m: traced[bounds[i]: bounds[i + 1]] for i, m in enumerate(meshes)}
    # each vertex's value fitted over its one-ring (ring_fit): the vertices' 64-ray noise averaged down, a field
    # varying linearly across the ring kept, neighbours across a crease (normals 20 degrees apart) left out. Bunny
    # (benchmarks/unwrap.py): per-vertex values interpolated 0.0261 relative RMS at surface points, fitted 0.0168
    # (every neighbour: 0.0175, 10 degrees: 0.0180, 30: 0.0172; own value weighted as two neighbours: with every
    # neighbour 0.0180 as one, 0.0176 as three; a plain one-ring mean 0.0185); the texels' own rays correct the rest
    fitted = {m: ring_fit(welded[m][1].positions, welded[m][1].faces, welded[m][2], values[m], PRIOR_SELF_WEIGHT,
                        PRIOR_RING_COS)
              for m in meshes}
    prior = texels.interpolate_welded({m: (welded[m][1], fitted[m]) for m in meshes})
    # the vertices traced around their welded (smooth) normals; where a texel's own normal turns away from that
    # (a hard edge: flat normals, or normals split at a crease or a UV seam, as an OBJ without normals gets them:
    # spot's seams, up to 40 degrees) the prior is the mean chord of other rays, off by more than the window can
    # correct (a 2 x 1 x 0.5 box with flat faces: 0.066 relative RMS on its texels along the edges): such texels
    # get none (< 0) and trace all their rays. 10 degrees: on spot at 512^2 the same error as 5 (0.0101) at
    # 16.5 rays per texel instead of 19.4; 20 degrees and more, 0.0103
    vertex_normals = texels.interpolate_welded({m: (welded[m][1], welded[m][2]) for m in meshes})
    along = np.einsum("ij,ij->i", vertex_normals, texels.normals)
    turned = along < PRIOR_NORMAL_COS * np.linalg.norm(vertex_normals, axis=1)
    return np.where(turned, -1.0, prior)



def corrected_by_neighbours(texels, values: np.ndarray, prior: np.ndarray, first_means: np.ndarray,
                            stopped: np.ndarray, region_edge: np.ndarray, radius: int,
                            max_distance: np.ndarray) -> np.ndarray:
    """The texels that stopped on their prior, each corrected by the mean deviation of its neighbours' first rays
    from their priors: the prior is a control variate that carries the shape between vertices, and the deviation
    left (the prior's interpolation error, smooth at the scale of a few texels, plus the rays' noise) is averaged
    over the (2 radius + 1)^2 texels around it that lie beside it on the surface and stopped too, then shrunk
    toward 0 by its significance.

    A texel's first 12 rays alone are noisy (relative RMS 0.057 on spot against 1024 rays, where 64 rays give
    0.013) but unbiased, and the prior is noise-free but off by up to a few percent between vertices; averaged over
    a 7 x 7 window (~600 rays) the deviation removes most of the prior's error and the rays' noise both (spot:
    0.0101 at 512^2 in the PNG as written, ``benchmarks/texel.py``). The texels that did not stop (their first rays
    disagree with the prior past the tolerance: a feature the vertices miss) keep their own full estimate and take
    no part in the mean.

    The texels on the edge of the region with a prior (``region_edge``: beside texels whose normal turned away from
    the vertices', :func:`texel_prior`, or on the edge of a chart of the asset's own UVs) traced all their rays (the
    step gives them no prior to stop on) and keep that estimate; their deviation from the prior, of all their rays,
    joins their neighbours' windows. There the window is one-sided, so its mean is the deviation a few texels
    further in, and the prior is at its worst: authored charts are cut along the shape's features, where thickness
    bends most between vertices (spot at 512^2: prior 0.046 relative RMS on chart-edge texels, 0.015 inside); a
    chart's edge matters beyond its share of texels: dilation copies it into the padding, which bilinear filtering
    and every mip level read (spot with its chart edges on the prior: p99 over the whole image 0.048, where 64 rays
    give 0.037). The charts of baker's own unwrap are cut by area, not along features: their edge texels test their
    first rays like the others, which measured better than all their rays (bunny, 27% of the texels on a chart's
    edge: 0.0170 relative RMS at surface points against 0.0192, at 15.6 rays per texel instead of 28.8).

    The correction is shrunk toward 0 by an empirical-Bayes estimate (Efron & Morris, "Stein's Estimation Rule and
    Its Competitors", JASA 1973): over a texture's stopped texels, the spread of the windows' means less their
    mean squared standard error is the spread of the real deviation; a window keeps that share of its mean. On a
    coarse mesh whose vertices miss the curvature the correction stays (torus of 24 x 12 sections); on a dense one
    whose fitted prior is better than the pooled first rays it fades (a texel-by-texel positive-part James-Stein
    factor let noise through there: bunny 0.0192 against 0.0170)."""
    include = stopped | region_edge
    deviation = np.where(stopped, first_means - prior, np.where(region_edge, values - prior, 0.0))
    correction, error = texels.window_mean(deviation, include, radius)
    # shrunk toward 0 by the share of the windows' spread that is not their noise, per texture (see above)
    shrink = np.zeros(len(values))
    usable = stopped & np.isfinite(correction)
    for material in np.unique(texels.material[usable]):
        part = usable & (texels.material == material)
        signal = max(0.0, float(np.mean(correction[part] ** 2) - np.mean(error[part])))
        shrink[part] = signal / np.maximum(signal + error[part], 1e-300)
    corrected = np.clip(prior + np.nan_to_num(shrink * correction), 0.0, max_distance)
    return np.where(stopped, corrected, values)


def write_texel_images(asset: Asset, texels, values: np.ndarray, options: ThicknessOptions, sums: dict) -> dict:
    """Each texture set's thickness PNG into the document ({material: texture info}); without per-vertex data the
    texels' sum and count go to ``sums`` for the material's mean. Shared by the own-mesh and the --from paths."""
    doc = asset.doc
    textured = {}
    for texel_set, image, mask in texels.images(values):
        if not options.per_vertex:
            sums[texel_set.material][0] += float(image[mask].sum())
            sums[texel_set.material][1] += int(mask.sum())
        png, factor = ext.encode_thickness_texture(image, options.texture_bits)
        textured[texel_set.material] = ext.write_thickness_texture(doc, texel_set.material, png, factor,
                                                                   texel_set.texcoord)
    double_sided = [asset.material_label(m) for m in textured if not ext.volume_allowed(doc, m)]
    if double_sided:
        asset.note("KHR_materials_volume is not valid on double-sided materials: their thickness texture is in "
                   f"BAKER_thickness only: {', '.join(double_sided)}")
    return textured


def source_thickness(source, options: ThicknessOptions, seed: int, progress: Progress) -> tuple:
    """The high mesh's own per-vertex thickness (as ``baker bake HIGH --bakes thickness`` writes it), computed once per
    high mesh and options (:meth:`baker.texels.transfer.SourceMesh.per_vertex`)."""
    from baker.techniques.thickness.kernel import default_max_distance, local_thickness

    diag = default_max_distance(source.positions)
    max_distance = options.max_distance or diag
    bias = options.bias if options.bias is not None else 1e-5 * diag

    def compute(mesh):
        with progress.task("thickness of the source's vertices", len(mesh.positions)) as advance:
            return local_thickness(mesh.scene, mesh.positions, mesh.normals, rays=options.rays,
                                   distribution=options.distribution, spread=options.spread,
                                   max_distance=max_distance, bias=bias, seed=seed, sampler=options.sampler,
                                   progress=advance)

    key = repr((options.rays, options.distribution, options.spread, max_distance, bias, seed, options.sampler))
    return source.per_vertex("thickness", key, compute), max_distance, bias


def run_from_source(asset: Asset, options: ThicknessOptions, seed: int, progress: Progress) -> None:
    """``--from HIGH``: every vertex and texel of the low mesh takes the high's own per-vertex thickness where its
    ray through the cage meets the high (the low's own thickness is not the sculpt's: the bunny decimated to 2,000
    triangles is 25% off the 69k-triangle original at the same points)."""
    from baker.geometry.normals import vertex_normals
    from baker.texels.sets import gather_texels
    from baker.texels.transfer import project_welded, record

    doc, request = asset.doc, asset.transfer
    values, max_distance, bias = source_thickness(request.source, options, seed, progress)
    groups = asset.material_groups()
    sums = {mat: [0.0, 0] for mat in groups}
    material_of = {mp: mat for mat, members in groups.items() for mp in members}
    if options.per_vertex:
        found = []
        for m in range(len(asset.meshes())):
            prims = [p for p in asset.triangle_primitives(m) if (m, p) in material_of]
            if not prims:
                continue
            mesh = asset.welded(m, prims)
            hits = project_welded(request, asset, mesh, vertex_normals(mesh.positions, mesh.faces))
            found.append(hits.hit)
            per_welded = hits.interpolate(values)
            for i, p in enumerate(prims):
                ids = mesh.inverse[mesh.offsets[i]: mesh.offsets[i + 1]]
                ext.write_vertex_thickness(doc, m, p, per_welded[ids])
                unique = np.unique(ids)
                sums[material_of[(m, p)]][0] += float(per_welded[unique].sum())
                sums[material_of[(m, p)]][1] += len(unique)
        if found:
            record(request, "thickness", "vertices", np.concatenate(found))
    textured = {}
    if options.per_texel:
        texels = gather_texels(asset, options.texture_size, options.texel_density, seed,
                               auto_range=AUTO_TEXTURE_SIZE_RANGE)
        record(request, "thickness", "texels", texels.source.hit)
        per_texel = texels.source.interpolate(values)
        textured = write_texel_images(asset, texels, per_texel, options, sums)
    for material, members in groups.items():
        total, count = sums[material]
        ext.write_material_parameters(doc, material, options=options, max_distance=max_distance, bias=bias,
                                      mean_thickness=total / count if count else 0.0,
                                      per_vertex=options.per_vertex, texture=textured.get(material))
