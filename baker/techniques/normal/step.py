"""Wire the normal-map bake: texels of the low mesh through the cage onto the high (the texel layer's source hits),
the low's tangent frames (its TANGENT, or generated and written), and the map on each material."""
from __future__ import annotations

import numpy as np

from baker.errors import NothingToBake
from baker.geometry.asset import Asset
from baker.progress import QUIET, Progress
from baker.techniques.normal.options import NormalOptions


def frames(asset: Asset, texels, generated: list) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per texel (T, B, N) interpolated from the vertices of the low mesh as a glTF viewer sees them: NORMAL (the
    primitive's, else its welded smooth normals, then written), TANGENT (the primitive's, for the UV set the map
    uses, else generated from that set and written) and ``B = cross(N, T.xyz) * w`` per vertex."""
    from baker.gltf.accessors import to_float
    from baker.texels.tangents import vertex_tangents
    from baker.texels.targets import smooth_normals

    doc = asset.doc
    per_vertex = {}
    for texel_set in texels.sets:
        target = texel_set.target
        existing = doc.json["materials"][target.material].get("normalTexture")
        # a TANGENT belongs to the UV set of the normal map it was made for: kept only for that same layout
        own_frame = not target.unwrapped and (not isinstance(existing, dict)
                                              or existing.get("texCoord", 0) == target.texcoord)
        for pt in target.primitives:
            g = pt.geometry
            prim = doc.json["meshes"][g.mesh]["primitives"][g.primitive]
            attributes = prim["attributes"]
            normals = smooth_normals(g)
            if "NORMAL" not in attributes:
                attributes["NORMAL"] = doc.add_accessor(normals.astype(np.float32))
                generated.append(f"mesh {g.mesh} primitive {g.primitive} NORMAL")
            if "TANGENT" in attributes and own_frame:
                tangents = to_float(doc, attributes["TANGENT"])
            else:
                tangents = vertex_tangents(g.positions, g.faces, normals, g.texcoords[target.texcoord])
                attributes["TANGENT"] = doc.add_accessor(tangents.astype(np.float32))
                generated.append(f"mesh {g.mesh} primitive {g.primitive} TANGENT")
            bitangents = np.cross(normals, tangents[:, :3]) * tangents[:, 3:4]
            per_vertex[(g.mesh, g.primitive)] = np.concatenate([tangents[:, :3], bitangents, normals], axis=1)
    stacked = texels.interpolate(lambda g: per_vertex[(g.mesh, g.primitive)])
    return stacked[:, 0:3], stacked[:, 3:6], stacked[:, 6:9]


def run(asset: Asset, options: NormalOptions, seed: int = 0, progress: Progress = QUIET) -> None:
    from baker.texels.sets import gather_texels
    from baker.texels.transfer import record
    from baker.techniques.normal import extension as ext
    from baker.techniques.normal.kernel import bits_needed, encode_pixels, tangent_space

    if asset.transfer is None:
        raise NothingToBake("a normal map is baked from a high-poly source: give --from HIGH")
    with progress.task("normal: texels through the cage", 1) as advance:
        texels = gather_texels(asset, options.texture_size, options.texel_density, seed)
        advance(1)
    hits = texels.source
    record(asset.transfer, "normal", "texels", hits.hit)
    if options.space == "object":
        values = hits.normals
    else:
        generated = []
        tangents, bitangents, normals = frames(asset, texels, generated)
        values = tangent_space(hits.normals, tangents, bitangents, normals)
        if generated:
            asset.note(f"normal: wrote the frame the map is decoded with: {', '.join(generated)}")
    source = asset.transfer.source_path.name
    for texel_set, image, mask in texels.images(values):
        if texel_set.target.unwrapped:
            asset.note(f"normal: material {asset.material_label(texel_set.material)} has no usable UVs: unwrapped "
                       f"into TEXCOORD_{texel_set.texcoord}, which the normal map uses")
        bits = options.texture_bits or bits_needed(image, mask)
        png = ext.encode_png(encode_pixels(image, bits))
        if ext.write_normal_texture(asset.doc, texel_set.material, png, texel_set.texcoord, options.space, source,
                                    bits):
            asset.note(f"normal: material {asset.material_label(texel_set.material)}: its normalTexture is replaced "
                       f"by the map baked from {source}")
