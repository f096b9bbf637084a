"""Preview panel of BAKER_tonal_art_map: Praun's real-time hatching (``runtime-shaders/baker_hatching.glsl``), the
TAM's levels uploaded as the custom mip chains of two textures, six-tone blend, drawn as ink on off-white paper."""
from __future__ import annotations

from baker.preview.core import DrawItem, Panel
from baker.techniques.tam.extension import read


# the hatching's brightness (0 a stroke, 1 the paper) shown as ink on paper, both short of black and white so the
# sheet clips neither (the strokes and the paper are what the panel shows)
PAPER, INK = (0.94, 0.93, 0.9), (0.05, 0.05, 0.06)


class HatchingPanel(Panel):
    """Hatching of the materials with a packed TAM whose texture coordinates the primitive has."""

    def read_item(self, doc, item: DrawItem) -> None:
        if item.material_index is not None:
            item.data["tam"] = read(doc, item.material_index)

    def applies(self, item):
        tam = item.data.get("tam")
        return tam is not None and tam.layout == "packed" and tam.texcoord in item.texcoords

    def texcoord(self, item):
        return item.data["tam"].texcoord

    def uniforms(self, item):
        tam = item.data["tam"]
        return {"u_tonesA": tam.tones[:3], "u_tonesB": tam.tones[3:6], "u_scale": tam.scale,
                "u_finestSize": float(tam.levels[0].size), "u_levelCount": float(len(tam.levels))}

    def textures(self, scene, ctx, item):
        levels = item.data["tam"].levels
        return {f"u_tones{name}": scene.mip_chain(ctx, [level.textures[j] for level in levels])
                for j, name in enumerate(("012", "345"))}


PANELS = [
    HatchingPanel("hatching", "hatching (tonal art map)", ("baker_hatching.glsl",),
                  "uniform sampler2D u_tones012;\nuniform sampler2D u_tones345;\nuniform vec3 u_tonesA;\n"
                  "uniform vec3 u_tonesB;\nuniform float u_scale;\nuniform float u_finestSize;\n"
                  "uniform float u_levelCount;",
                  "vec2 tile = baker_tam_coord(v_uv, u_scale, u_finestSize);\n"
                  "    float lod = baker_tam_lod(dFdx(tile), dFdy(tile), u_finestSize, u_levelCount);\n"
                  "    float darkness = baker_hatching_darkness(N, u_light, 1.0);\n"
                  "    float brightness = baker_hatching(u_tones012, u_tones345, tile, lod, darkness, u_tonesA, u_tonesB);\n"
                  f"    color = mix(vec3{INK}, vec3{PAPER}, brightness);",
                  inputs="in vec2 v_uv;", order=50),
]
