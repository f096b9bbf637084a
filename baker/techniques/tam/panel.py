"""Preview panel of BAKER_tonal_art_map: what a runtime draws (``runtime-shaders/baker_hatching.glsl``, as the
three.js and Babylon.js hosts call it): Praun's real-time hatching, the TAM's levels uploaded as the custom mip chains
of two textures, six-tone blend, the tone from the key light, multiplying the lit colour (the Lambert reference)
with the hosts' own stage (``runtime-shaders/hosts/web/surface_hatching.glsl``). Lit from the front, over the
camera's shoulder, as the web viewer's key light is: the hatching's tone follows the key light, so the panel shows
the strokes the viewer draws."""
from __future__ import annotations

from baker.preview.core import LAMBERT, DrawItem, Panel, host_text
from baker.techniques.tam.extension import read


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
        return {"u_baker_tam_on": 1.0, "u_bakerTamTonesA": tam.tones[:3], "u_bakerTamTonesB": tam.tones[3:6],
                "u_bakerTamScale": tam.scale, "u_bakerTamFinestSize": float(tam.levels[0].size),
                "u_bakerTamLevels": float(len(tam.levels))}

    def textures(self, scene, ctx, item):
        levels = item.data["tam"].levels
        return {f"u_bakerTam{name}": scene.mip_chain(ctx, [level.textures[j] for level in levels])
                for j, name in enumerate(("012", "345"))}


# the web hosts' stage itself: bakerUv the TAM's texture coordinates (the panel binds the set the TAM reads), the
# key light the panel's, bakerColor the lit colour (the Lambert reference) the brightness multiplies
STAGE = host_text("web/surface_hatching.glsl")

PANELS = [
    HatchingPanel("hatching", "hatching (tonal art map)", ("baker_hatching.glsl",),
                  "uniform float u_baker_tam_on;\nuniform sampler2D u_bakerTam012;\nuniform sampler2D u_bakerTam345;\n"
                  "uniform vec3 u_bakerTamTonesA;\nuniform vec3 u_bakerTamTonesB;\nuniform float u_bakerTamScale;\n"
                  "uniform float u_bakerTamFinestSize;\nuniform float u_bakerTamLevels;",
                  f"{LAMBERT}\n"
                  "    vec2 bakerUv = v_uv;\n"
                  "    vec3 bakerNormal = N;\n"
                  "    vec3 bakerKeyLight = u_light;\n"
                  "    vec3 bakerColor = color;\n"
                  f"    {STAGE}\n"
                  "    color = bakerColor;",
                  light="front", inputs="in vec2 v_uv;", order=50),
]
