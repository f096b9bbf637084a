"""Preview panel of BAKER_hair: the strands as view-facing ribbons (their ``ribbonIndices``) with pixel-coverage
opacity and Kajiya-Kay shading (``runtime-shaders/baker_hair.glsl``), over the Lambert scene. Children are drawn
when present, else the guides."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from baker.preview.core import LAMBERT, REFERENCE, Panel, Scene, draw_surfaces, light_direction, module_text, \
    program_source, set_uniforms, transform_points
from baker.techniques.hair.extension import HairStrands, read

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
    def gather(self, scene, asset, mesh, world, node) -> None:
        prims = asset.meshes()[mesh].get("primitives", [])
        strands = [read(asset.doc, mesh, p) for p in range(len(prims))]
        guides_of_children = {s.guides_primitive for s in strands if s is not None}
        materials = asset.doc.json.get("materials", [])
        for p, hair in enumerate(strands):
            if hair is not None and p not in guides_of_children:
                scene.add("hair", world_strands(hair, world, materials))

    def available(self, scene) -> bool:
        return isinstance(scene, Scene) and bool(scene.part("hair"))

    def draw(self, ctx, scene, camera, size):
        import moderngl

        draw_surfaces(ctx, REFERENCE, scene, camera, size)
        module = module_text(("baker_hair.glsl",))
        program = ctx.program(vertex_shader=program_source("hair_ribbon.vert.glsl", modules=module),
                              fragment_shader=program_source("hair_kajiya_kay.frag.glsl", modules=module))
        vp = (camera.projection @ camera.view).astype(np.float32)
        ctx.enable(ctx.BLEND)
        ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        for s in scene.part("hair"):
            color = (s.material.get("pbrMetallicRoughness") or {}).get("baseColorFactor", DEFAULT_COLOR)[:3]
            set_uniforms(program, {"u_viewProjection": vp.T.tobytes(), "u_eye": tuple(camera.eye),
                                   "u_light": tuple(light_direction(camera, self.light)),
                                   "u_rootWidth": s.hair.root_width, "u_tipWidth": s.hair.tip_width,
                                   "u_tanHalfFovY": math.tan(math.radians(camera.fov) / 2),
                                   "u_viewportHeight": float(size), "u_baseColor": tuple(float(c) for c in color)})
            n = len(s.positions)
            data = [(np.repeat(s.positions, 2, axis=0), "3f", "POSITION"),
                    (np.repeat(s.tangents, 2, axis=0), "3f", "a_tangent"),
                    (np.repeat(s.params, 2), "1f", "a_param"), (np.repeat(s.width_scale, 2), "1f", "a_widthScale"),
                    (np.tile(np.array([0.0, 1.0], np.float32), n), "1f", "a_side")]
            buffers = [ctx.buffer(np.ascontiguousarray(d, np.float32).tobytes()) for d, _, _ in data]
            ibo = ctx.buffer(s.ribbon.tobytes())
            vao = ctx.vertex_array(program, [(b, f, name) for b, (_, f, name) in zip(buffers, data)],
                                   index_buffer=ibo, index_element_size=4)
            vao.render()
            for obj in [vao, ibo] + buffers:
                obj.release()
        ctx.disable(ctx.BLEND)
        program.release()


PANELS = [HairPanel("hair", "hair ribbons (Kajiya-Kay)", (), "", LAMBERT, order=100)]
