"""Preview panel of BAKER_skin_lut: Penner's pre-integrated skin (``runtime-shaders/baker_skin.glsl``), the LUT by
N.L and the baked curvature along the light (Euler's formula from BAKER_curvature's principal curvatures and
direction when baked, else the mean curvature, else the curvature estimated from screen-space derivatives), N.L per
channel from Penner's normal blending of the material's normal map with the interpolated normal; where the
material also has BAKER_normal_blur (``item.data["normal_blur"]``, read by the normal-blur panel), the LUT is read with
its per-channel diffuse normals (``baker_normal_blur.glsl``, tangent frame from screen-space derivatives), as the
three.js and Babylon.js hosts do."""
from __future__ import annotations

import numpy as np

from baker.gltf.vertex_attributes import unpadded
from baker.preview.core import DrawItem, Panel, Scene
from baker.techniques.curvature.extension import DIRECTION, PRINCIPAL
from baker.techniques.skin.extension import read


NEARLY_LAMBERT_ROWS = 3.0  # % of the LUT's curvature axis: below, the profile barely reddens the terminator


class SkinPanel(Panel):
    """Penner's pre-integrated skin: the LUT texture by N.L and the curvature attribute the material names."""

    def read_item(self, doc, item: DrawItem) -> None:
        if item.material_index is not None:
            item.data["skin"] = read(doc, item.material_index)

    def applies(self, item):
        return super().applies(item) and item.data.get("skin") is not None

    def describe(self, scene: Scene) -> str:
        """Which rows of the LUT the asset's curvature reads (5th-95th percentile of the baked curvature, concave
        parts read row 0) and the mesh-unit scale the bake assumed: a subtle panel on a large asset is then told
        apart from a bake that did nothing."""
        items = [i for i in scene.items if self.applies(i)]
        if not items:
            return self.label
        skin = items[0].data["skin"]
        unit = skin.unit
        scale = f"1 unit = {1.0 / skin.curvature_scale:.4g} {unit}" if skin.curvature_scale > 0 else "no scale"
        values = [unpadded(i.attributes[self.attribute_of(i)], 1) for i in items if self.attribute_of(i) in i.attributes]
        if not values:
            return f"skin (curvature from screen derivatives; {scale})"
        lo, hi = skin.curvature_range
        curvature = np.maximum(np.concatenate(values).astype(np.float64), 0.0) * skin.curvature_scale
        k5, k95 = np.percentile(curvature, [5.0, 95.0])
        rows = np.clip((np.array([k5, k95]) - lo) / max(hi - lo, 1e-30), 0.0, 1.0) * 100.0
        why = " - nearly Lambert here" if rows[1] < NEARLY_LAMBERT_ROWS else " - clamped at the LUT's end" \
            if k95 > hi else ""
        return f"skin: LUT rows {rows[0]:.0f}-{rows[1]:.0f}% (1/r {k5:.2g}-{k95:.2g}/{unit}); {scale}{why}"

    def attribute_of(self, item):
        return item.data["skin"].curvature_attribute

    def principal(self, item):
        """True when the primitive has the principal curvatures and direction (the curvature along the light)."""
        return PRINCIPAL in item.attributes and DIRECTION in item.attributes

    def vertex_arrays(self, item):
        n = len(item.positions)
        if not self.principal(item):
            return {"a_principal": np.zeros((n, 2), np.float32), "a_direction": np.zeros((n, 3), np.float32)}
        return {"a_principal": item.attributes[PRINCIPAL].reshape(n, -1)[:, :2],
                "a_direction": item.attributes[DIRECTION].reshape(n, -1)[:, :3]}

    def diffuse_normals(self, item):
        """The material's BAKER_normal_blur when its UV set is on the primitive, else None: what the normal-blur
        panel's ``read_item`` stored (every panel reads every item before any draws), so that skin and normal-blur
        need not import each other."""
        blur = item.data.get("normal_blur")
        return blur if blur is not None and blur.texcoord in item.texcoords else None

    def texcoord(self, item):
        blur = self.diffuse_normals(item)
        return blur.texcoord if blur is not None else 0

    def uniforms(self, item):
        skin = item.data["skin"]
        return {
            "u_skin.curvatureRange": skin.curvature_range,
            "u_skin.curvatureScale": skin.curvature_scale,
            "u_skin.penumbraWidthRange": skin.penumbra_width_range,
            "u_skin.normalBlend": skin.normal_blend,
            "u_skin.wrap": skin.wrap,
            "u_skin.scatterWidth": skin.scatter_width,
            "u_skin.scatterColor": skin.scatter_color,
            "u_hasCurvature": int(self.attribute_of(item) in item.attributes),
            "u_hasPrincipal": int(self.principal(item)),
            "u_hasDiffuseNormals": int(self.diffuse_normals(item) is not None),
        }

    def textures(self, scene, ctx, item):
        skin = item.data["skin"]
        out = {"u_lut": scene.texture(ctx, skin.lut_texture, srgb=skin.encoding == "srgb")}
        blur = self.diffuse_normals(item)
        if blur is not None:
            for name, texture in zip(("u_diffuseRed", "u_diffuseGreen", "u_diffuseBlue"), blur.diffuse_textures):
                out[name] = scene.texture(ctx, texture, repeat=True)
        return out


PANELS = [
    SkinPanel("skin", "pre-integrated skin (LUT x curvature)", ("baker_skin.glsl", "baker_normal_blur.glsl"),
              "uniform BakerSkin u_skin;\nuniform sampler2D u_lut;\nuniform int u_hasCurvature;\n"
              "uniform int u_hasDiffuseNormals;\nuniform sampler2D u_diffuseRed;\nuniform sampler2D u_diffuseGreen;\n"
              "uniform sampler2D u_diffuseBlue;\nuniform int u_hasPrincipal;",
              "float k = u_hasCurvature != 0 ? scalar : baker_skin_curvature_from_derivatives(fwidth(Ng), fwidth(P));\n"
              "    // the curvature of the surface, not of the normal map (Ng: the interpolated normal)\n"
              "    if (u_hasPrincipal != 0) k = baker_skin_curvature_along_light(v_principal, v_direction, Ng, u_light);\n"
              "    // derivatives outside the branch: they are undefined in non-uniform control flow\n"
              "    mat3 tbn = baker_normal_blur_derivative_frame(Ng, dFdx(P), dFdy(P), dFdx(v_uv), dFdy(v_uv));\n"
              "    vec3 ndotl = baker_skin_blended_ndotl(Ng, N, u_light, u_skin.normalBlend);\n"
              "    if (u_hasDiffuseNormals != 0) {\n"
              "        ndotl = baker_normal_blur_ndotl(\n"
              "            normalize(tbn * baker_normal_blur_decode(texture(u_diffuseRed, v_uv).rgb, 1.0)),\n"
              "            normalize(tbn * baker_normal_blur_decode(texture(u_diffuseGreen, v_uv).rgb, 1.0)),\n"
              "            normalize(tbn * baker_normal_blur_decode(texture(u_diffuseBlue, v_uv).rgb, 1.0)), u_light);\n"
              "    }\n"
              "    color = albedo * (0.15 + 0.85 * baker_skin_diffuse_normals(u_skin, u_lut, ndotl, k));",
              attribute="_CURVATURE", inputs="in vec2 v_uv;\nin vec2 v_principal;\nin vec3 v_direction;", order=30,
              vertex_declarations="in vec2 a_principal;\nin vec3 a_direction;\nout vec2 v_principal;\nout vec3 v_direction;",
              vertex_body="v_principal = a_principal;\n    v_direction = a_direction;"),
]
