"""Preview panel of BAKER_hair: the strands as view-facing ribbons (their ``ribbonIndices``) with pixel-coverage
opacity, shaded as hair fibres where their material has ``BAKER_hair_shading`` (``runtime-shaders/
baker_hair_shading.glsl``: Chiang et al. 2016 from the file's tables, Zinke et al. 2008's dual scattering with the
baked fibre counts, the rest-pose occlusion on the ambient term), else Kajiya-Kay (``baker_hair.glsl``), over the
Lambert scene. Children are drawn when present, else the guides."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from baker.preview.core import LAMBERT, REFERENCE, Panel, Scene, draw_surfaces, light_direction, module_text, \
    program_source, set_uniforms, transform_points
from baker.techniques.hair.extension import HairStrands, read
from baker.techniques.hair_shading.extension import NAME as HAIR_SHADING, read_table
from baker.techniques.hair_shading.kernel import longitudinal_variances

DEFAULT_COLOR = (0.3, 0.2, 0.1, 1)


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
    fibre: dict | None = None  # BAKER_hair_shading resolved: the tables, parameters and per-vertex arrays


def fibre_shading(doc, prim: dict, material: dict) -> dict | None:
    """The material's BAKER_hair_shading for the fibre shader: its tables (RGBA, half float as stored, widened), the
    BakerHairShading fields, sigma_a, and the strand attributes it names (defaults where absent)."""
    ext = (material.get("extensions") or {}).get(HAIR_SHADING)
    if ext is None:
        return None
    entry = doc.json["extensions"][HAIR_SHADING]["tables"][int(ext["tables"])]
    count = doc.json["accessors"][prim["attributes"]["POSITION"]]["count"]

    def attribute(name, size, fill):
        if name is None or name not in prim["attributes"]:
            return np.full((count, size), fill, np.float32)
        return np.asarray(doc.accessor(prim["attributes"][name]), np.float32).reshape(count, -1)[:, :size]

    return {"m": read_table(doc, entry, "longitudinal"), "n": read_table(doc, entry, "azimuthal"),
            "dual": read_table(doc, entry, "dualScattering"),
            "variances": tuple(float(v) for v in longitudinal_variances(float(ext["betaM"]))),
            "params": (math.radians(float(ext["alpha"])), float(entry["azimuthal"]["slices"]),
                       float(entry["dualScattering"]["alphaF"]), float(entry["dualScattering"]["betaF"])),
            "sigma_a": tuple(float(v) for v in ext["sigmaA"]), "per_vertex": "melaninAttribute" in ext,
            "melanin": attribute(ext.get("melaninAttribute"), 2, 0.0),
            "occlusion": attribute((ext.get("occlusion") or {}).get("attribute"), 1, 1.0),
            "positive": attribute((ext.get("fibreCount") or {}).get("positive"), 3, 0.0),
            "negative": attribute((ext.get("fibreCount") or {}).get("negative"), 3, 0.0)}


def world_strands(hair: HairStrands, world: np.ndarray, materials: list) -> Strands:
    positions = hair.positions.astype(np.float64)
    tangents = hair.tangents.astype(np.float64)
    params = hair.param.astype(np.float32).reshape(-1)
    per = hair.vertices_per_strand
    scale = hair.width_scale.astype(np.float32).reshape(-1) if hair.width_scale is not None \
        else np.ones(len(positions) // per, np.float32)
    tangents = tangents @ world[:3, :3].T
    tangents /= np.maximum(np.linalg.norm(tangents, axis=1, keepdims=True), 1e-20)
    material = materials[hair.material] if hair.material is not None else {}
    return Strands(transform_points(positions, world), tangents.astype(np.float32), params,
                   np.repeat(scale, per)[: len(positions)], hair.ribbon_indices.astype(np.uint32).reshape(-1),
                   hair, material)


class HairPanel(Panel):
    # 'fibre': BAKER_hair_shading where the material has it; 'kajiyaKay': Kajiya & Kay 1989 everywhere (what the
    # preview drew before; set on the instance to compare)
    shading = "fibre"

    def gather(self, scene, asset, mesh, world, node) -> None:
        prims = asset.meshes()[mesh].get("primitives", [])
        strands = [read(asset.doc, mesh, p) for p in range(len(prims))]
        guides_of_children = {s.guides_primitive for s in strands if s is not None}
        materials = asset.doc.json.get("materials", [])
        for p, hair in enumerate(strands):
            if hair is not None and p not in guides_of_children:
                s = world_strands(hair, world, materials)
                s.fibre = fibre_shading(asset.doc, prims[p], s.material)
                if s.fibre is not None:
                    s.fibre["mesh_from_world"] = np.linalg.inv(world[:3, :3])
                scene.add("hair", s)

    def available(self, scene) -> bool:
        return isinstance(scene, Scene) and bool(scene.part("hair"))

    def draw(self, ctx, scene, camera, size):
        import moderngl

        draw_surfaces(ctx, REFERENCE, scene, camera, size)
        programs = {}
        vp = (camera.projection @ camera.view).astype(np.float32)
        light = light_direction(camera, self.light)
        ctx.enable(ctx.BLEND)
        ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        for s in scene.part("hair"):
            fibre = s.fibre if self.shading == "fibre" else None
            if (fibre is not None) not in programs:
                programs[fibre is not None] = strand_program(ctx, fibre is not None)
            program = programs[fibre is not None]
            color = (s.material.get("pbrMetallicRoughness") or {}).get("baseColorFactor", DEFAULT_COLOR)[:3]
            textures = []
            if fibre is not None:
                light_mesh = fibre["mesh_from_world"] @ light
                set_uniforms(program, {"u_lightMesh": tuple(light_mesh / (np.linalg.norm(light_mesh) or 1.0)),
                                       "u_hairVariances": fibre["variances"], "u_hairParams": fibre["params"],
                                       "u_sigmaA": fibre["sigma_a"], "u_melaninPerVertex": float(fibre["per_vertex"])})
                for unit, (name, key) in enumerate((("u_hairLongitudinal", "m"), ("u_hairAzimuthal", "n"),
                                                    ("u_hairDual", "dual"))):
                    table = np.ascontiguousarray(fibre[key], np.float32)
                    tex = ctx.texture((table.shape[1], table.shape[0]), 4, table.tobytes(), dtype="f4")
                    tex.repeat_x = tex.repeat_y = False
                    tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
                    tex.use(unit)
                    set_uniforms(program, {name: unit})
                    textures.append(tex)
            set_uniforms(program, {"u_viewProjection": vp.T.tobytes(), "u_eye": tuple(camera.eye),
                                   "u_light": tuple(light),
                                   "u_rootWidth": s.hair.root_width, "u_tipWidth": s.hair.tip_width,
                                   "u_tanHalfFovY": math.tan(math.radians(camera.fov) / 2),
                                   "u_viewportHeight": float(size), "u_baseColor": tuple(float(c) for c in color)})
            n = len(s.positions)
            data = [(np.repeat(s.positions, 2, axis=0), "3f", "POSITION"),
                    (np.repeat(s.tangents, 2, axis=0), "3f", "a_tangent"),
                    (np.repeat(s.params, 2), "1f", "a_param"), (np.repeat(s.width_scale, 2), "1f", "a_widthScale"),
                    (np.tile(np.array([0.0, 1.0], np.float32), n), "1f", "a_side")]
            if fibre is not None:
                data += [(np.repeat(fibre["melanin"], 2, axis=0), "2f", "a_melanin"),
                         (np.repeat(fibre["occlusion"], 2, axis=0), "1f", "a_occlusion"),
                         (np.repeat(fibre["positive"], 2, axis=0), "3f", "a_fibresPos"),
                         (np.repeat(fibre["negative"], 2, axis=0), "3f", "a_fibresNeg")]
            buffers = [ctx.buffer(np.ascontiguousarray(d, np.float32).tobytes()) for d, _, _ in data]
            ibo = ctx.buffer(s.ribbon.tobytes())
            vao = ctx.vertex_array(program, [(b, f, name) for b, (_, f, name) in zip(buffers, data)],
                                   index_buffer=ibo, index_element_size=4)
            vao.render()
            for obj in [vao, ibo] + buffers + textures:
                obj.release()
        ctx.disable(ctx.BLEND)
        for program in programs.values():
            program.release()


def strand_program(ctx, fibre: bool):
    """The ribbon program: the fibre model (BAKER_hair_shading) or Kajiya-Kay."""
    if fibre:
        module = "#define BAKER_HAIR_SHADING\n" + module_text(("baker_hair.glsl", "baker_hair_shading.glsl"))
        fragment = "hair_fibre.frag.glsl"
    else:
        module, fragment = module_text(("baker_hair.glsl",)), "hair_kajiya_kay.frag.glsl"
    return ctx.program(vertex_shader=program_source("hair_ribbon.vert.glsl", modules=module),
                       fragment_shader=program_source(fragment, modules=module))


PANELS = [HairPanel("hair", "hair ribbons (fibre model; Kajiya-Kay without BAKER_hair_shading)", (), "", LAMBERT,
                   order=100)]
