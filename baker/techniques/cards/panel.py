"""Preview panels of BAKER_hair_cards: the cards alpha-tested at the material's cutoff and shaded along the flow
texture (``runtime-shaders/baker_hair_cards.glsl``): "cards" with the material's ``BAKER_hair_shading`` (Chiang et
al. 2016's fibre tables, ``runtime-shaders/baker_hair_shading.glsl``; no fibre counts on cards: the light arrives
direct, with the neighbours' backscatter), "cards-kajiya-kay" with Kajiya-Kay. The preview has no TANGENT attribute: the card's
tangent frame comes from the screen-space derivatives of position and texture coordinates (the cotangent frame),
which for a card is its TANGENT up to length. The base colour (and the alpha the test cuts) is sampled from the
atlas's coverage-preserving mip chain (``coverageMips``, Castaño 2010) when the file has one, as the web runtimes do,
so the cards keep their coverage at a distance; else from the PNG."""
from __future__ import annotations

from baker.preview.core import LAMBERT, DrawItem, Panel
from baker.techniques.cards.extension import read_material


class HairCardsPanel(Panel):
    """Materials with BAKER_hair_cards: base colour (sRGB) cut at alphaCutoff, flow-map Kajiya-Kay."""

    def read_item(self, doc, item: DrawItem) -> None:
        if item.material_index is not None:
            item.data["hair_cards"] = read_material(doc, item.material_index)

    def applies(self, item):
        return super().applies(item) and item.data.get("hair_cards") is not None and 0 in item.texcoords

    def uniforms(self, item):
        return {"u_cutoff": float(item.material.get("alphaCutoff", 0.5))}

    def textures(self, scene, ctx, item):
        cards = item.data["hair_cards"]
        base = item.material["pbrMetallicRoughness"]["baseColorTexture"]["index"]
        chain = cards.coverage_mips.get(base)
        mipped = scene.coverage_mips(ctx, chain, repeat=False, srgb=True) if chain is not None else None
        return {"u_baseColor": mipped or scene.texture(ctx, base, srgb=True), "u_data": scene.texture(ctx, cards.data_texture),
                "u_flow": scene.texture(ctx, cards.flow_texture)}


class HairCardsShadingPanel(HairCardsPanel):
    """Cards whose material also has BAKER_hair_shading: the fibre tables as half-float textures, sigma_a from the
    material."""

    def read_item(self, doc, item: DrawItem) -> None:
        super().read_item(doc, item)
        from baker.techniques.hair_shading.extension import NAME, read_tables

        ext = (item.material.get("extensions") or {}).get(NAME) if item.material_index is not None else None
        if ext is not None:
            item.data["hair_shading"] = (int(ext["tables"]), *read_tables(doc, int(ext["tables"])), ext)

    def applies(self, item):
        return super().applies(item) and item.data.get("hair_shading") is not None

    def uniforms(self, item):
        import math

        from baker.techniques.hair_shading.kernel import longitudinal_variances

        _, tables, dual, ext = item.data["hair_shading"]
        return {**super().uniforms(item), "u_sigma": tuple(float(x) for x in ext["sigmaA"]),
                "u_variances": tuple(float(v) for v in longitudinal_variances(tables.beta_m)),
                "u_params": (math.radians(float(ext["alpha"])), float(tables.slices), float(dual.alpha_f),
                             float(dual.beta_f))}

    def textures(self, scene, ctx, item):
        from baker.techniques.hair.panel import fibre_table_textures

        index, tables, dual, _ = item.data["hair_shading"]
        key = ("hair_shading", id(ctx), index)
        if key not in scene.cache:
            scene.cache[key] = TextureGroup(fibre_table_textures(ctx, tables, dual))
        m, n, d = scene.cache[key].textures
        return {**super().textures(scene, ctx, item), "u_m": m, "u_n": n, "u_dual": d}


class TextureGroup:
    """The three tables of one set, released together with the scene's cache."""

    def __init__(self, textures):
        self.textures = textures

    def release(self) -> None:
        for t in self.textures:
            t.release()


PANELS = [
    HairCardsShadingPanel(
        "cards", "hair cards (alpha test, fibre tables)", ("baker_hair_cards.glsl", "baker_hair_shading.glsl"),
        "uniform sampler2D u_baseColor;\nuniform sampler2D u_data;\nuniform sampler2D u_flow;\n"
        "uniform float u_cutoff;\nuniform sampler2D u_m;\nuniform sampler2D u_n;\nuniform sampler2D u_dual;\n"
        "uniform vec3 u_sigma;\nuniform vec4 u_variances;\nuniform vec4 u_params;",
        "vec4 base = texture(u_baseColor, v_uv);\n"
        "    if (baker_hair_cards_cut(base.a, u_cutoff)) discard;\n"
        "    vec3 data = texture(u_data, v_uv).rgb;\n"
        "    vec4 frame = baker_hair_cards_frame(N, dFdx(P), dFdy(P), dFdx(v_uv), dFdy(v_uv));\n"
        "    vec3 T = baker_hair_cards_flow(texture(u_flow, v_uv).rgb, N, frame);\n"
        "    BakerHairShading h = BakerHairShading(u_variances, u_params.x, u_params.y, u_params.z, u_params.w, 1.0,"
        " 1.0);\n"
        "    // the cards' root darkening (baker_hair_cards_shade's 0.4) on the fibre model, light of irradiance pi\n"
        "    color = 0.15 * base.rgb + mix(0.4, 1.0, clamp(data.g, 0.0, 1.0)) * 3.14159265"
        " * baker_hair_shading(u_m, u_n, u_dual, h, T, u_light, V, 0.0, u_sigma);",
        inputs="in vec2 v_uv;", order=105),
    HairCardsPanel(
        "cards-kajiya-kay", "hair cards (alpha test, Kajiya-Kay)", ("baker_hair_cards.glsl",),
        "uniform sampler2D u_baseColor;\nuniform sampler2D u_data;\nuniform sampler2D u_flow;\n"
        "uniform float u_cutoff;",
        "vec4 base = texture(u_baseColor, v_uv);\n"
        "    if (baker_hair_cards_cut(base.a, u_cutoff)) discard;\n"
        "    vec3 data = texture(u_data, v_uv).rgb;\n"
        "    vec4 frame = baker_hair_cards_frame(N, dFdx(P), dFdy(P), dFdx(v_uv), dFdy(v_uv));\n"
        "    vec3 T = baker_hair_cards_flow(texture(u_flow, v_uv).rgb, N, frame);\n"
        "    color = 0.25 * base.rgb + baker_hair_cards_shade(base.rgb, T, N, u_light, V, vec3(1.0), data.g, data.b,"
        " 40.0, 0.1, 0.4);",
        inputs="in vec2 v_uv;", order=105.5),
]
