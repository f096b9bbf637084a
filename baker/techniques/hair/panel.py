"""Preview panels of BAKER_hair: the strands as view-facing ribbons (their ``ribbonIndices``) with pixel-coverage
opacity over the Lambert scene, shaded by the hair material's ``BAKER_hair_shading`` (Chiang et al. 2016's fibre
tables and Zinke et al. 2008's dual scattering, ``runtime-shaders/baker_hair_shading.glsl``, with the strands'
melanin and fibre counts) in the "hair" panel, and with Kajiya-Kay (``runtime-shaders/baker_hair.glsl``) in
"hair-kajiya-kay" (and in "hair" for strands whose material has no ``BAKER_hair_shading``). Children are drawn when
present, else the guides."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from baker.preview.core import LAMBERT, REFERENCE, Panel, Scene, draw_surfaces, light_direction, module_text, \
    program_source, set_uniforms, transform_points
from baker.techniques.hair.extension import HairStrands, read

DEFAULT_COLOR = (0.3, 0.2, 0.1, 1)


def fibre_table_textures(ctx, tables, dual) -> list:
    """The fibre tables as the runtime modules sample them: RGBA half-float textures (M with a zero fourth channel,
    N, dual scattering), linear, clamped; the hair and the cards panels both bind these."""
    import moderngl

    m_rgba = np.concatenate([tables.longitudinal, np.zeros(tables.longitudinal.shape[:2] + (1,), np.float32)], 2)
    group = []
    for image in (m_rgba, tables.azimuthal, dual.table):
        tex = ctx.texture((image.shape[1], image.shape[0]), 4, np.ascontiguousarray(image, np.float16).tobytes(),
                          dtype="f2")
        tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
        tex.repeat_x = tex.repeat_y = False
        group.append(tex)
    return group


@dataclass
class Strands:
    """A hair primitive in world space."""

    positions: np.ndarray
    tangents: np.ndarray
    params: np.ndarray
    width_scale: np.ndarray  # per vertex
    ribbon: np.ndarray  # ribbon indices
    hair: HairStrands
    material: dict
    sigma: np.ndarray | None = None  # per vertex absorption (RGB per fibre radius), with BAKER_hair_shading
    fibres_positive: np.ndarray | None = None  # per vertex ambient-cube fibre counts toward +x, +y, +z
    fibres_negative: np.ndarray | None = None  # ... and -x, -y, -z
    tables: tuple | None = None  # (HairTables, DualScatteringTable, tilt in radians) of the material
    to_mesh: np.ndarray | None = None  # world -> mesh directions (the fibre counts' ambient cube is in mesh space)


def shading_inputs(doc, attributes: dict, material: dict, count: int):
    """(sigma_a, fibres toward +axes, fibres toward -axes) per vertex from ``_HAIR_MELANIN`` (else the material's
    sigmaA) and ``_HAIR_FIBRES_POS``/``_NEG`` (else none crossed), or Nones when the material has no
    BAKER_hair_shading."""
    from baker.techniques.hair_shading.extension import FIBRES_NEGATIVE, FIBRES_POSITIVE, MELANIN, NAME
    from baker.techniques.hair_shading.kernel import sigma_a_from_melanin

    ext = (material.get("extensions") or {}).get(NAME)
    if ext is None:
        return None, None, None
    def columns(name, width):  # the first `width` components (the compact layout may pad or drop trailing ones)
        values = doc.accessor(attributes[name]).astype(np.float64).reshape(count, -1)[:, :width]
        return np.concatenate([values, np.zeros((count, width - values.shape[1]))], 1)

    if MELANIN in attributes:
        melanin = columns(MELANIN, 2)
        sigma = melanin[:, :1] * sigma_a_from_melanin(1.0) + melanin[:, 1:] * sigma_a_from_melanin(0.0, 1.0)
    else:
        sigma = np.tile(np.asarray(ext["sigmaA"], np.float64), (count, 1))
    counts = [columns(name, 3).astype(np.float32) if name in attributes else np.zeros((count, 3), np.float32)
              for name in (FIBRES_POSITIVE, FIBRES_NEGATIVE)]
    return sigma.astype(np.float32), counts[0], counts[1]


def world_strands(hair: HairStrands, world: np.ndarray, materials: list, doc=None, attributes=None) -> Strands:
    positions = hair.positions.astype(np.float64)
    tangents = hair.tangents.astype(np.float64)
    params = hair.param.astype(np.float32).reshape(-1)
    per = hair.vertices_per_strand
    scale = hair.width_scale.astype(np.float32).reshape(-1) if hair.width_scale is not None \
        else np.ones(len(positions) // per, np.float32)
    tangents = tangents @ world[:3, :3].T
    tangents /= np.maximum(np.linalg.norm(tangents, axis=1, keepdims=True), 1e-20)
    material = materials[hair.material] if hair.material is not None else {}
    sigma, positive, negative = (None, None, None) if doc is None else \
        shading_inputs(doc, attributes or {}, material, len(positions))
    tables = None
    if sigma is not None:
        from baker.techniques.hair_shading.extension import NAME, read_tables

        ext = material["extensions"][NAME]
        tables = (*read_tables(doc, int(ext["tables"])), math.radians(float(ext["alpha"])))
    return Strands(transform_points(positions, world), tangents.astype(np.float32), params,
                   np.repeat(scale, per)[: len(positions)], hair.ribbon_indices.astype(np.uint32).reshape(-1),
                   hair, material, sigma, positive, negative, tables, np.linalg.inv(world[:3, :3]))


class HairPanel(Panel):
    def gather(self, scene, asset, mesh, world, node) -> None:
        prims = asset.meshes()[mesh].get("primitives", [])
        strands = [read(asset.doc, mesh, p) for p in range(len(prims))]
        guides_of_children = {s.guides_primitive for s in strands if s is not None}
        materials = asset.doc.json.get("materials", [])
        for p, hair in enumerate(strands):
            if hair is not None and p not in guides_of_children:
                scene.add("hair", world_strands(hair, world, materials, asset.doc, prims[p].get("attributes", {})))

    def available(self, scene) -> bool:
        return isinstance(scene, Scene) and bool(scene.part("hair"))

    model = "chiang"  # BAKER_hair_shading where the material has it, else Kajiya-Kay

    def draw(self, ctx, scene, camera, size):
        import moderngl

        draw_surfaces(ctx, REFERENCE, scene, camera, size)
        hair_module = module_text(("baker_hair.glsl",))
        kajiya_kay = ctx.program(vertex_shader=program_source("hair_ribbon.vert.glsl", modules=hair_module),
                                 fragment_shader=program_source("hair_kajiya_kay.frag.glsl", modules=hair_module))
        programs, textures = [kajiya_kay], {}
        shading = None
        if self.model == "chiang" and any(s.sigma is not None for s in scene.part("hair")):
            shading = ctx.program(
                vertex_shader=program_source("hair_ribbon_shading.vert.glsl", modules=hair_module),
                fragment_shader=program_source("hair_shading.frag.glsl",
                                               modules=module_text(("baker_hair_shading.glsl",))))
            programs.append(shading)
        vp = (camera.projection @ camera.view).astype(np.float32)
        ctx.enable(ctx.BLEND)
        ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        for s in scene.part("hair"):
            color = (s.material.get("pbrMetallicRoughness") or {}).get("baseColorFactor", DEFAULT_COLOR)[:3]
            uniforms = {"u_viewProjection": vp.T.tobytes(), "u_eye": tuple(camera.eye),
                        "u_light": tuple(light_direction(camera, self.light)),
                        "u_rootWidth": s.hair.root_width, "u_tipWidth": s.hair.tip_width,
                        "u_tanHalfFovY": math.tan(math.radians(camera.fov) / 2),
                        "u_viewportHeight": float(size), "u_baseColor": tuple(float(c) for c in color)}
            n = len(s.positions)
            data = [(np.repeat(s.positions, 2, axis=0), "3f", "POSITION"),
                    (np.repeat(s.tangents, 2, axis=0), "3f", "a_tangent"),
                    (np.repeat(s.params, 2), "1f", "a_param"), (np.repeat(s.width_scale, 2), "1f", "a_widthScale"),
                    (np.tile(np.array([0.0, 1.0], np.float32), n), "1f", "a_side")]
            program = kajiya_kay
            if shading is not None and s.sigma is not None:
                program = shading
                uniforms.update(self.bind_tables(ctx, shading, scene, s, textures))
                to_mesh = s.to_mesh @ light_direction(camera, self.light)
                uniforms["u_lightMesh"] = tuple(float(c) for c in to_mesh / np.linalg.norm(to_mesh))
                data += [(np.repeat(s.sigma, 2, axis=0), "3f", "a_sigma"),
                         (np.repeat(s.fibres_positive, 2, axis=0), "3f", "a_fibresPos"),
                         (np.repeat(s.fibres_negative, 2, axis=0), "3f", "a_fibresNeg")]
            set_uniforms(program, uniforms)
            buffers = [ctx.buffer(np.ascontiguousarray(d, np.float32).tobytes()) for d, _, _ in data]
            ibo = ctx.buffer(s.ribbon.tobytes())
            vao = ctx.vertex_array(program, [(b, f, name) for b, (_, f, name) in zip(buffers, data)],
                                   index_buffer=ibo, index_element_size=4)
            vao.render()
            for obj in [vao, ibo] + buffers:
                obj.release()
        ctx.disable(ctx.BLEND)
        for obj in [*programs, *(t for group in textures.values() for t in group)]:
            obj.release()

    @staticmethod
    def bind_tables(ctx, program, scene, strands, textures: dict) -> dict:
        """The strands' fibre tables as half-float textures (LINEAR, CLAMP_TO_EDGE; uploaded once per table set)
        bound to units 0-2, and the BakerHairShading uniforms."""
        from baker.techniques.hair_shading.kernel import longitudinal_variances

        tables, dual, tilt = strands.tables
        key = id(tables)
        if key not in textures:
            textures[key] = fibre_table_textures(ctx, tables, dual)
        for unit, tex in enumerate(textures[key]):
            tex.use(unit)
        return {"u_m": 0, "u_n": 1, "u_dual": 2,
                "u_variances": tuple(float(v) for v in longitudinal_variances(tables.beta_m)),
                "u_params": (float(tilt), float(tables.slices), float(dual.alpha_f), float(dual.beta_f))}


class KajiyaKayHairPanel(HairPanel):
    """The same strands with Kajiya-Kay, whatever their material (the hosts' shading before BAKER_hair_shading)."""

    model = "kajiya-kay"

    def gather(self, scene, asset, mesh, world, node) -> None:
        pass  # the "hair" panel gathers the strands both draw


PANELS = [HairPanel("hair", "hair ribbons (fibre tables + dual scattering)", (), "", LAMBERT, order=100),
          KajiyaKayHairPanel("hair-kajiya-kay", "hair ribbons (Kajiya-Kay)", (), "", LAMBERT, order=100.5)]
