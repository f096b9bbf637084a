"""Preview panel of BAKER_fur: what a runtime draws (``runtime-shaders/baker_fur.glsl``, as the three.js and
Babylon.js hosts call it, ``runtime-shaders/hosts/web/fur_shell.*.glsl``): Lengyel's fur shells, the surface as the
Lambert reference draws it (its own base colour: the hosts leave the surface's material as it is) then
``shellCount`` copies pushed out along the normal, each texel darkened towards the root (the hosts' root shade,
0.35) and lit by the ambient and half the key light's diffuse light, as the hosts' shell stage lights it, the key
light from the front as the web viewer's: alpha-tested at ``alphaCutoff`` from each shell texture's coverage-preserving
mip chain (``coverageMips``, Castaño 2010) when the file has them, as the web runtimes do, else alpha-blended from the
PNGs. Fur fin primitives (degenerate quads) are no surface of the preview."""
from __future__ import annotations

import dataclasses

from baker.preview.core import LAMBERT, REFERENCE, DrawItem, Panel, draw_surfaces
from baker.techniques.fur.extension import read, read_fin_source


class FurPanel(Panel):
    """The materials with BAKER_fur: the surface as the reference draws it, then one pass per shell texture."""

    def read_item(self, doc, item: DrawItem) -> None:
        if item.material_index is not None:
            item.data["fur"] = read(doc, item.material_index)

    def skips(self, asset, mesh, primitive) -> bool:
        return read_fin_source(asset.doc, mesh, primitive) is not None

    def applies(self, item):
        return super().applies(item) and item.data.get("fur") is not None

    def draw(self, ctx, scene, camera, size):
        import moderngl

        items = [i for i in scene.items if self.applies(i)]
        # the surface, fur or not, with its base colour under the panel's light, as the hosts leave it
        draw_surfaces(ctx, dataclasses.replace(REFERENCE, light=self.light), scene, camera, size)
        for item in items:
            fur = item.data["fur"]
            shells = list(fur.shell_textures)
            one = scene.subset([item])
            count = len(shells)
            for i, texture in enumerate(shells):
                chain = fur.coverage_mips.get(texture)
                mipped = chain is not None and scene.coverage_mips(ctx, chain) is not None
                if mipped:  # alpha-tested, opaque, depth written: the chain keeps the coverage the test draws
                    ctx.disable(ctx.BLEND)
                    ctx.depth_mask = True
                else:
                    ctx.enable(ctx.BLEND)
                    ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
                    ctx.depth_mask = False
                shell = FurShellPanel(texture, chain if mipped else None, self.light)
                draw_surfaces(ctx, shell, one, camera, size, extra={
                    "u_shell": float(i), "u_shellCount": float(count),
                    "u_shellSpacing": fur.shell_spacing * item.world_scale, "u_tiling": fur.tiling,
                    "u_shellAlphaCutoff": float(chain["alphaCutoff"]) if mipped else 0.01,
                    "u_alphaTest": 1.0 if mipped else 0.0})
            ctx.depth_mask = True
            ctx.disable(ctx.BLEND)


# the hosts' shell stage (runtime-shaders/hosts/web/fur_shell.frag.glsl): the root's shade, and the share of the
# directional diffuse light a shell gets over the ambient; the ambient and key light the Lambert reference's
ROOT_SHADE, SHELL_DIFFUSE = 0.35, 0.5
AMBIENT, KEY = 0.15, 0.85


class FurShellPanel(Panel):
    """One shell: the surface pushed out to its height, shaded with its texture."""

    def __init__(self, texture: int, chain: dict | None = None, light: str = "front"):
        super().__init__(
            "fur-shell", "", ("baker_fur.glsl",),
            "uniform sampler2D u_shellTexture; uniform float u_shell; uniform float u_shellCount; uniform float u_tiling;"
            " uniform float u_shellAlphaCutoff; uniform float u_alphaTest;",
            "vec4 texel = texture(u_shellTexture, baker_fur_shell_uv(v_uv, u_tiling));\n"
            "    if (texel.a < u_shellAlphaCutoff) discard;\n"
            "    float height = baker_fur_shell_height(u_shell, u_shellCount);\n"
            f"    vec4 shaded = baker_fur_shell_shade(texel, height, {ROOT_SHADE});\n"
            f"    color = shaded.rgb * ({AMBIENT} + {KEY} * {SHELL_DIFFUSE} * max(dot(N, u_light), 0.0));\n"
            "    alpha = mix(shaded.a, 1.0, u_alphaTest);",
            inputs="in vec2 v_uv;", vertex_modules=("baker_fur.glsl",),
            vertex_declarations="uniform float u_shell; uniform float u_shellCount; uniform float u_shellSpacing;",
            vertex_body="position = baker_fur_shell_position(POSITION, normalize(NORMAL), u_shell, u_shellSpacing, "
                        "u_shellCount, vec3(0.0));", light=light)
        self.texture_index = texture
        self.chain = chain

    def textures(self, scene, ctx, item):
        if self.chain is not None:
            return {"u_shellTexture": scene.coverage_mips(ctx, self.chain, repeat=True)}
        return {"u_shellTexture": scene.texture(ctx, self.texture_index, repeat=True)}


PANELS = [FurPanel("fur", "fur shells", (), "", LAMBERT, light="front", order=80)]
