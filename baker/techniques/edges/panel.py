"""Preview panels of BAKER_edges (``runtime-shaders/baker_edges.glsl``): the shell outline along ``_OUTLINE_NORMAL``
(a back-face pass, RTR4 15.2.2) plus the fin primitives (McGuire & Hughes 2004), and the single-pass wireframe with
the baked wireframe mask (Baerentzen et al. 2006)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from baker.preview.core import (INK, LAMBERT, REFERENCE, Camera, DrawItem, Panel, Scene, draw_surfaces, module_text,
                                program_source, set_uniforms, transform_points)
from baker.techniques.edges.extension import FIN_ATTRIBUTES, OUTLINE_NORMAL, read

DEFAULT_CREASE = math.radians(60)
WIRE_COVERAGE = 0.4  # the most of a triangle the wireframe panel's lines darken fully


@dataclass
class EdgeFins:
    """A fin primitive in world space."""

    attributes: dict  # _FIN_V0.._FIN_V3 (world), _FIN_CORNER, _FIN_FLAGS
    faces: np.ndarray
    crease_angle: float


class OutlinePanel(Panel):
    """Shell outline (back faces pushed out along _OUTLINE_NORMAL, front faces culled) and the edge fins."""

    def gather(self, scene, asset, mesh, world, node):
        prims = asset.meshes()[mesh].get("primitives", [])
        for p in range(len(prims)):
            edges = read(asset.doc, mesh, p)
            if edges is None or edges.fins_of is None:
                continue
            attrs = {k: a.astype(np.float32) for k, a in edges.fin_attributes.items()}
            for k in FIN_ATTRIBUTES[:4]:
                attrs[k] = transform_points(attrs[k], world)
            source = read(asset.doc, mesh, edges.fins_of)
            crease = source.crease_angle if source is not None and source.crease_angle is not None else DEFAULT_CREASE
            scene.add("edge-fins", EdgeFins(attrs, edges.fin_indices.astype(np.uint32).reshape(-1, 3), float(crease)))

    def applies(self, item):
        return OUTLINE_NORMAL in item.attributes

    def available(self, scene) -> bool:
        return super().available(scene) or bool(isinstance(scene, Scene) and scene.part("edge-fins"))

    def draw(self, ctx, scene, camera, size):
        # an open primitive of a single-sided material as glTF and the hosts draw it: back faces culled, so its
        # openings show what lies behind (a closed one shows no back face either way: left double-sided, so a
        # mirrored node's flipped winding cannot hide it)
        single = [i for i in scene.items if not (i.material or {}).get("doubleSided") and is_open(i)]
        culled = {id(i) for i in single}
        ctx.front_face = "ccw"
        ctx.enable(ctx.CULL_FACE)
        ctx.cull_face = "back"
        draw_surfaces(ctx, REFERENCE, scene.subset(single), camera, size)
        ctx.disable(ctx.CULL_FACE)
        draw_surfaces(ctx, REFERENCE, scene.subset([i for i in scene.items if id(i) not in culled]), camera, size)
        shell = Panel("shell", "", (), "", "color = u_ink;", vertex_modules=("baker_edges.glsl",),
                      vertex_body="float w = (u_viewProjection * vec4(POSITION, 1.0)).w;\n"
                                  "    position = baker_shell_position(POSITION, a_outline, w, u_width, "
                                  "u_viewportHeight, u_projectionScaleY);")
        items = [i for i in scene.items if self.applies(i)]
        if items:
            ctx.enable(ctx.CULL_FACE)
            ctx.cull_face = "front"
            # an open single-sided primitive (zero outline normals on its rims): its back faces into depth only
            # first, so the shell cannot show through its openings (RTR4 15.2.2: the shell needs a closed mesh)
            occluders = [i for i in items if id(i) in culled]
            if occluders:
                ctx.enable(ctx.BLEND)
                ctx.blend_func = ctx.ZERO, ctx.ONE  # depth only (moderngl's color_mask does not hold across draws)
                draw_surfaces(ctx, shell, scene.subset(occluders), camera, size, extra={"u_width": 0.0},
                              fallback=False)
                ctx.blend_func = ctx.DEFAULT_BLENDING
                ctx.disable(ctx.BLEND)
            draw_surfaces(ctx, shell, scene.subset(items), camera, size,
                          extra={"u_width": max(2.0, size / 96.0)}, fallback=False)
            ctx.disable(ctx.CULL_FACE)
        for fins in scene.part("edge-fins"):
            draw_fins(ctx, fins, camera, size)


def is_open(item) -> bool:
    """The bake zeroes _OUTLINE_NORMAL on boundary and non-manifold edges: a primitive with such rows is open."""
    normals = item.attributes.get(OUTLINE_NORMAL)
    return normals is not None and bool((np.einsum("ij,ij->i", normals, normals) < 0.25).any())


def draw_fins(ctx, fins: EdgeFins, camera: Camera, size: int) -> None:
    """McGuire & Hughes fins: contour, ridge, valley and boundary edges extruded to u_width pixels."""
    program = ctx.program(vertex_shader=program_source("edges_fin.vert.glsl", modules=module_text(("baker_edges.glsl",))),
                          fragment_shader=program_source("solid.frag.glsl"))
    vp = (camera.projection @ camera.view).astype(np.float32)
    set_uniforms(program, {"u_viewProjection": vp.T.tobytes(), "u_eye": tuple(camera.eye), "u_creaseCos":
                           math.cos(fins.crease_angle), "u_width": max(1.0, size / 256.0), "u_viewport": (size, size),
                           "u_show": 1 | 2 | 4 | 8, "u_depthOffset": 2e-3, "u_color": INK + (1.0,)})
    content, buffers = [], []
    for name, data in fins.attributes.items():
        if name in program:
            buf = ctx.buffer(np.ascontiguousarray(data, np.float32).tobytes())
            buffers.append(buf)
            content.append((buf, "3f" if data.ndim == 2 and data.shape[1] == 3 else "1f", name))
    ibo = ctx.buffer(fins.faces.astype(np.uint32).tobytes())
    vao = ctx.vertex_array(program, content, index_buffer=ibo, index_element_size=4)
    vao.render()
    for obj in [vao, ibo, program] + buffers:
        obj.release()


class WireframePanel(Panel):
    """The wireframe of the primitives with a baked wireframe mask (one 3-bit mask per triangle), its lines faded
    where the triangles are small on screen (at most about WIRE_COVERAGE of a triangle inked)."""

    def read_item(self, doc, item: DrawItem) -> None:
        edges = read(doc, item.mesh, item.primitive_index) if item.mesh is not None else None
        if edges is not None and edges.wireframe_mask is not None:
            mask = edges.wireframe_mask.reshape(-1).astype(np.float32)
            item.mask = mask if len(mask) == len(item.faces) else None

    def applies(self, item):
        return item.mask is not None


PANELS = [
    OutlinePanel("outline", "shell outline + fins", (), "", LAMBERT, order=60),
    WireframePanel("wireframe", "wireframe (mask)", ("baker_edges.glsl",), "",
                   "vec3 fill = albedo * (0.15 + 0.85 * max(dot(N, u_light), 0.0));\n"
                   "    vec3 slope = fwidth(v_bary);\n"
                   "    vec2 wire = baker_wireframe(v_bary, slope, v_mask, u_width, 0.0);\n"
                   # the share of a triangle its edges' lines cover is about width x the sum of the barycentric
                   # slopes (1 / each height in pixels), all of it from 1 on: where triangles are so small on screen
                   # that it passes WIRE_COVERAGE the lines fade by that ratio, so the ink stays about WIRE_COVERAGE
                   # of the surface and a dense mesh reads as a tone, not a black blob
                   f"    float density = clamp(u_width * (slope.x + slope.y + slope.z), {WIRE_COVERAGE}, 1.0);\n"
                   f"    float fade = {WIRE_COVERAGE} / density;\n"
                   "    color = mix(fill, u_ink, wire.x * fade);",
                   inputs="in vec3 v_bary;\nflat in int v_mask;", vertex_modules=("baker_edges.glsl",),
                   vertex_body="v_bary = baker_barycentric(gl_VertexID);\n    v_mask = int(a_mask + 0.5);",
                   expand=True, order=70),
]
