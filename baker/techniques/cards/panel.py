"""Preview panel of BAKER_hair_cards: the cards alpha-tested at the material's cutoff and shaded Kajiya-Kay along
the flow texture (``runtime-shaders/baker_hair_cards.glsl``). The preview has no TANGENT attribute: the card's
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


PANELS = [
    HairCardsPanel(
        "cards", "hair cards (alpha test, Kajiya-Kay)", ("baker_hair_cards.glsl",),
        "uniform sampler2D u_baseColor;\nuniform sampler2D u_data;\nuniform sampler2D u_flow;\n"
        "uniform float u_cutoff;",
        "vec4 base = texture(u_baseColor, v_uv);\n"
        "    if (baker_hair_cards_cut(base.a, u_cutoff)) discard;\n"
        "    vec3 data = texture(u_data, v_uv).rgb;\n"
        "    vec4 frame = baker_hair_cards_frame(N, dFdx(P), dFdy(P), dFdx(v_uv), dFdy(v_uv));\n"
        "    vec3 T = baker_hair_cards_flow(texture(u_flow, v_uv).rgb, N, frame);\n"
        "    color = 0.25 * base.rgb + baker_hair_cards_shade(base.rgb, T, N, u_light, V, vec3(1.0), data.g, data.b,"
        " 40.0, 0.1, 0.4);",
        inputs="in vec2 v_uv;", order=105),
]
