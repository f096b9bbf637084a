"""Wire the surface normal blur to an Asset: per material with a normal map, the texels of that map's layout, their
tangent frames (TANGENT, or generated and written), the blur, and the images and JSON of ``BAKER_normal_blur``."""
from __future__ import annotations

import numpy as np

from baker.errors import BakerError, NothingToBake
from baker.geometry.asset import Asset
from baker.gltf.accessors import to_float
from baker.checks import pointer
from baker.progress import QUIET, Progress
from baker.techniques.normal_blur.options import NormalBlurOptions
from baker.techniques.normal_blur import extension as ext


def profile_in_mesh_units(options: NormalBlurOptions):
    """(profile, variances in mesh units^2, (3, k) weights) of the options' profile (mm) and unit scale."""
    from baker.diffusion_profile import DEON_SKIN, load_profile

    profile = load_profile(options.profile) if options.profile else DEON_SKIN
    variances, weights = profile.arrays()
    mm_per_unit = 1000.0 * options.meters_per_unit
    return profile, variances / mm_per_unit ** 2, weights


def normal_mapped_materials(asset: Asset) -> dict:
    """{material: (normalTexture info, primitives [(mesh, primitive)])} of the materials with a normal map whose
    UV set their primitives have."""
    doc = asset.doc
    found = {}
    for material, members in asset.material_groups().items():
        info = doc.json["materials"][material].get("normalTexture")
        if not isinstance(info, dict):
            continue
        texcoord = f"TEXCOORD_{int(info.get('texCoord', 0))}"
        users = [(m, p) for m, p in members if texcoord in doc.json["meshes"][m]["primitives"][p]["attributes"]]
        if users:
            found[material] = (info, users)
    return found


def _normal_image(asset: Asset, material: int, info: dict) -> tuple[np.ndarray, dict]:
    """The decoded normal map (H, W, 3 unit vectors, scale applied) and its sampler."""
    from baker.gltf.document import sniff_mime
    from baker.gltf.images import decode_image
    from baker.techniques.normal_blur.kernel import decode_normal_pixels

    doc = asset.doc
    where = pointer("materials", material, "normalTexture")
    textures = doc.json.get("textures") or []
    index = info.get("index")
    if not isinstance(index, int) or not 0 <= index < len(textures) or "source" not in textures[index]:
        raise BakerError(asset.source, f"{where}: the normal texture has no image")
    source = textures[index]["source"]
    data = doc.image_bytes(source)
    suffix = {"image/jpeg": ".jpg", "image/png": ".png"}.get(sniff_mime(data) or "", ".png")
    try:
        pixels = decode_image(data, suffix)
        normals = decode_normal_pixels(pixels, float(info.get("scale", 1.0)))
    except (BakerError, ValueError) as exc:
        raise BakerError(asset.source, f"{where}: cannot read the normal map ({exc})") from None
    sampler = {}
    if "sampler" in textures[index]:
        sampler = dict((doc.json.get("samplers") or [])[textures[index]["sampler"]])
    return normals, sampler


def _tangents(asset: Asset, members: list, texcoord: int, generated: list) -> dict:
    """{(mesh, primitive): (vertices, 4) TANGENT}: the primitive's own, else generated (and written as TANGENT when
    the primitive has NORMAL: glTF viewers pair TANGENT with NORMAL)."""
    from baker.texels.tangents import vertex_tangents
    from baker.texels.targets import smooth_normals

    doc = asset.doc
    out = {}
    for m, p in members:
        prim = doc.json["meshes"][m]["primitives"][p]
        g = asset.primitive(m, p)
        if "TANGENT" in prim["attributes"]:
            out[(m, p)] = to_float(doc, prim["attributes"]["TANGENT"])
            continue
        tangents = vertex_tangents(g.positions, g.faces, smooth_normals(g), g.texcoords[texcoord])
        out[(m, p)] = tangents
        if "NORMAL" in prim["attributes"]:
            prim["attributes"]["TANGENT"] = doc.add_accessor(tangents.astype(np.float32))
            generated.append(pointer("meshes", m, "primitives", p))
        else:
            asset.note(f"normal-blur: mesh {m} primitive {p} has no NORMAL: its generated tangents are used for the "
                       "blur but not written (TANGENT needs NORMAL)")
    return out


def _note_layout(asset: Asset, texel_set, shape) -> None:
    """Say so when the normal map's layout cannot pair one surface point with each texel: overlapping (mirrored or
    stacked) charts share texels, which are then blurred at one of their surface points; a non-square map is
    resampled to a square of its larger side."""
    # the triangles' UV area against the texels they cover: equal for a layout without overlaps (up to the texels
    # along chart borders), twice as large where every chart is mirrored onto another
    target = texel_set.target
    uv_area = 0.0
    for pt in target.primitives:
        t = pt.geometry.texcoords[target.texcoord][pt.geometry.faces]
        uv_area += 0.5 * float(np.abs((t[:, 1, 0] - t[:, 0, 0]) * (t[:, 2, 1] - t[:, 0, 1])
                                      - (t[:, 2, 0] - t[:, 0, 0]) * (t[:, 1, 1] - t[:, 0, 1])).sum())
    covered = int(target.mask.sum())
    label = asset.material_label(texel_set.material)
    shared = uv_area * target.size ** 2 / covered - 1.0 if covered else 0.0
    if shared > OVERLAP_TOLERANCE:
        asset.note(f"normal-blur: material {label}: the normal map's UV layout overlaps itself (its triangles cover "
                   f"{100 * shared:.0f}% more UV area than texels; mirrored or stacked charts); each shared texel is "
                   "blurred at one of its surface points")
    if shape[0] != shape[1]:
        asset.note(f"normal-blur: material {label}: the {shape[1]}x{shape[0]} normal map is sampled into "
                   f"{texel_set.size}x{texel_set.size} diffuse maps")


OVERLAP_TOLERANCE = 0.05  # UV area over covered texels beyond 1: chart borders cover partial texels


def run(asset: Asset, options: NormalBlurOptions, seed: int = 0, progress: Progress = QUIET) -> None:
    from baker.texels.tangents import uv_jacobians
    from baker.texels.sets import gather_texels
    from baker.techniques.normal_blur.kernel import (TangentFrames, blur_normals, encode_normal_pixels,
                                                     sample_bilinear, texel_areas)

    doc = asset.doc
    materials = normal_mapped_materials(asset)
    if not materials:
        raise NothingToBake("no material has a normalTexture with texture coordinates")
    profile, variances, weights = profile_in_mesh_units(options)
    inputs, layouts, tangents, generated = {}, {}, {}, {}
    for material, (info, members) in materials.items():
        texcoord = int(info.get("texCoord", 0))
        normals, sampler = _normal_image(asset, material, info)
        size = options.texture_size or int(max(normals.shape[:2]))
        inputs[material] = (normals, sampler)
        layouts[material] = (texcoord, size)
        generated[material] = []
        tangents.update(_tangents(asset, members, texcoord, generated[material]))
    texels = gather_texels(asset, layouts=layouts, seed=seed)
    for texel_set in texels.sets:
        _note_layout(asset, texel_set, inputs[texel_set.material][0].shape)
    frames_all = TangentFrames.from_tangents(texels.normals,
                                             texels.interpolate(lambda g: tangents[(g.mesh, g.primitive)]))
    jacobians = texels.per_face(lambda target, pt: np.concatenate(
        uv_jacobians(pt.geometry.positions, pt.geometry.faces, pt.geometry.texcoords[target.texcoord]), axis=1))
    results = {}
    with progress.task(f"normal-blur texels ({texels.describe()})", len(texels)) as advance:
        for texel_set in texels.sets:
            part = slice(texel_set.start, texel_set.stop)
            size = texel_set.size
            uv = np.stack([(texels.cols[part] + 0.5) / size, (texels.rows[part] + 0.5) / size], axis=1)
            normals, sampler = inputs[texel_set.material]
            local = sample_bilinear(normals, uv, sampler.get("wrapS", 10497), sampler.get("wrapT", 10497))
            local /= np.maximum(np.linalg.norm(local, axis=1, keepdims=True), 1e-12)
            frames = TangentFrames(frames_all.tangent[part], frames_all.bitangent[part], frames_all.normal[part])
            dpdu, dpdv = jacobians[part, :3], jacobians[part, 3:]
            result = blur_normals(texels.positions[part], texel_areas(dpdu, dpdv, size), frames, local, variances,
                                  weights, options.cell_fraction)
            stretch = np.stack([np.linalg.norm(dpdu, axis=1), np.linalg.norm(dpdv, axis=1)], axis=1)
            results[texel_set.material] = (result, stretch)
            advance(texel_set.stop - texel_set.start)

    # one pass over the images: the three diffuse maps (9 values) and the stretch (2) per texel
    values = np.zeros((len(texels), 11))
    for texel_set in texels.sets:
        result, stretch = results[texel_set.material]
        part = slice(texel_set.start, texel_set.stop)
        values[part, :9] = np.concatenate(list(result.diffuse), axis=1)
        values[part, 9:] = stretch
    for texel_set, image, _ in texels.images(values):
        material = texel_set.material
        result = results[material][0]
        textures = [ext.add_texture(doc, ext.encode_png(encode_normal_pixels(image[..., 3 * c: 3 * c + 3])),
                                    f"diffuse_normal_{'rgb'[c]}_m{material}", inputs[material][1])
                    for c in range(3)]
        png, stretch_scale = ext.encode_stretch(image[..., 9:], options.stretch_bits)
        stretch_texture = ext.add_texture(doc, png, f"uv_stretch_m{material}", ext.CLAMP_LINEAR)
        ext.write_material_parameters(doc, material, options=options, profile=profile, variances=variances,
                                      weights=weights, texcoord=texel_set.texcoord, diffuse_textures=textures,
                                      result=result, stretch_texture=stretch_texture, stretch_scale=stretch_scale,
                                      generated_tangents=generated[material], size=texel_set.size)
