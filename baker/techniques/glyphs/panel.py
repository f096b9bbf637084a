"""Preview panel of BAKER_text + BAKER_glyph_atlas: each label's quads drawn with the distance-field text shader
(``runtime-shaders/baker_text.glsl``, premultiplied "over") on top of the Lambert scene. A node with a label is
drawn by this panel only (its quads are no surface of the other panels)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from baker.preview.core import LAMBERT, REFERENCE, Panel, Scene, draw_surfaces, module_text, program_source, \
    set_uniforms, transform_points
from baker.techniques.glyphs.extension import TextLabel, read_atlas, read_text

FIELD_TYPES = {"sdf": 0, "psdf": 1, "msdf": 2, "mtsdf": 3}


@dataclass
class Label:
    """The quads of a node with a text label, in world space, and the label (with its font)."""

    positions: np.ndarray
    uv: np.ndarray
    faces: np.ndarray
    text: TextLabel


class TextPanel(Panel):
    def owns(self, scene, asset, mesh, node) -> bool:
        return node is not None and self._label(scene, asset, node) is not None

    def _label(self, scene, asset, node):
        if "text-fonts" not in scene.parts:  # the atlas, read once per scene
            scene.parts["text-fonts"] = read_atlas(asset.doc)
        label = read_text(asset.doc, node, scene.parts["text-fonts"])
        return label if label is not None and label.font is not None else None

    def gather(self, scene, asset, mesh, world, node) -> None:
        if node is None:
            return
        label = self._label(scene, asset, node)
        if label is None:
            return
        prims = asset.meshes()[mesh].get("primitives", [])
        for p in asset.triangle_primitives(mesh):
            g = asset.primitive(mesh, p)
            attrs = prims[p]["attributes"]
            if "TEXCOORD_0" in attrs and len(g.faces):
                scene.add("text", Label(transform_points(g.positions, world),
                                        asset.doc.accessor(attrs["TEXCOORD_0"]).astype(np.float32),
                                        g.faces.astype(np.uint32), label))

    def available(self, scene) -> bool:
        return isinstance(scene, Scene) and bool(scene.part("text"))

    def draw(self, ctx, scene, camera, size):
        import moderngl

        draw_surfaces(ctx, REFERENCE, scene, camera, size)
        program = ctx.program(vertex_shader=program_source("text.vert.glsl"),
                              fragment_shader=program_source("text.frag.glsl", modules=module_text(("baker_text.glsl",))))
        vp = (camera.projection @ camera.view).astype(np.float32)
        ctx.enable(ctx.BLEND)
        ctx.blend_func = moderngl.ONE, moderngl.ONE_MINUS_SRC_ALPHA
        for label in scene.part("text"):
            text, font = label.text, label.text.font
            atlas = scene.texture(ctx, font.texture)
            set_uniforms(program, {
                "u_viewProjection": vp.T.tobytes(), "u_atlasSize": (float(atlas.width), float(atlas.height)),
                "u_distanceRange": font.distance_range, "u_fieldType": FIELD_TYPES.get(font.type, 2),
                "u_style.color": text.color,
                "u_style.softness": 0.0,
                "u_style.outlineColor": text.outline_color,
                "u_style.outlineWidth": text.outline_width * font.size,
                "u_style.glowColor": (0.0, 0.0, 0.0, 0.0), "u_style.glowWidth": 0.0,
                "u_style.shadowColor": (0.0, 0.0, 0.0, 0.0), "u_style.shadowSoftness": 0.0, "u_atlas": 0})
            atlas.use(location=0)
            vbo = ctx.buffer(np.ascontiguousarray(label.positions, np.float32).tobytes())
            tbo = ctx.buffer(np.ascontiguousarray(label.uv, np.float32).tobytes())
            ibo = ctx.buffer(label.faces.tobytes())
            vao = ctx.vertex_array(program, [(vbo, "3f", "POSITION"), (tbo, "2f", "TEXCOORD_0")],
                                   index_buffer=ibo, index_element_size=4)
            vao.render()
            for obj in (vao, vbo, tbo, ibo):
                obj.release()
        ctx.disable(ctx.BLEND)
        program.release()


PANELS = [TextPanel("text", "text (MSDF)", (), "", LAMBERT, order=90)]
