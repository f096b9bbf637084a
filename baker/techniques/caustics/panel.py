"""Preview panel of BAKER_caustics: the material's caustic frames projected in world space and added to a Lambert
shade (``runtime-shaders/baker_caustics.glsl``), at a fixed time of the loop.

The depth fade is left out (fade 1): a preview shows the pattern on any asset, whatever its height below
``waterLevel``. The pattern is shown at the asset's scale: a tile much larger than the asset would light it
uniformly and one much smaller would blur to grey, so the panel projects with the baked tile size clamped to
[extent / 4, extent] (extent: the diagonal of the scene's bounding box) and says so in its label. Faces that are
not horizontal read the frames triplanar (the floor projection along the refracted sun for the up axis, the two
vertical planes for the others, blended by the normal's components to the 4th power) instead of stretching the
floor projection into stripes along the sun."""
from __future__ import annotations

import numpy as np

from baker.preview.core import DrawItem, Panel, Scene
from baker.techniques.caustics.extension import read

LOOP_FRACTION = 0.37  # the still's time, as a fraction of the period: between two frames, so the blend shows too
TILES_PER_EXTENT = (1.0, 4.0)  # the shown tile: between extent / 4 and extent


def shown_tile_size(tile_size: float, extent: float) -> float:
    """The tile size the panel projects with: the baked one when it is within [extent / 4, extent]."""
    if extent <= 0:
        return tile_size
    return float(min(max(tile_size, extent / TILES_PER_EXTENT[1]), extent / TILES_PER_EXTENT[0]))


class CausticsPanel(Panel):
    """Frames of the material's BAKER_caustics at t = 0.37 period, blended and added to the lit colour."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.extent = 0.0

    def read_item(self, doc, item: DrawItem) -> None:
        if item.material_index is not None:
            item.data["caustics"] = caustics = read(doc, item.material_index)
            if caustics is not None:  # PNG colour type (IHDR byte 25): 2 and 6 carry RGB, 0 and 4 gray
                source = doc.json["textures"][caustics.frame_textures[0]]["source"]
                item.data["caustics_rgb"] = float(doc.image_bytes(source)[25:26] in (b"\x02", b"\x06"))

    def applies(self, item):
        return super().applies(item) and item.data.get("caustics") is not None

    def prepare(self, scene: Scene) -> None:
        points = scene.points()
        self.extent = float(np.linalg.norm(points.max(0) - points.min(0))) if len(points) else 0.0

    def describe(self, scene: Scene) -> str:
        self.prepare(scene)
        baked = sorted({i.data["caustics"].tile_size for i in scene.items if self.applies(i)})
        if not baked:
            return self.label
        shown = shown_tile_size(baked[0], self.extent)
        if abs(shown - baked[0]) <= 1e-9 * max(abs(baked[0]), 1e-30):
            return f"{self.label} (tile {baked[0]:.3g}, asset {self.extent:.3g})"
        return f"{self.label} (tile {baked[0]:.3g} shown as {shown:.3g}: asset {self.extent:.3g})"

    def frames(self, caustics):
        count = len(caustics.frame_textures)
        position = LOOP_FRACTION * count
        first = int(position) % count
        return first, (first + 1) % count, position - int(position)

    def uniforms(self, item):
        c = item.data["caustics"]
        _, _, blend = self.frames(c)
        return {"u_projection": c.projection_direction, "u_waterLevel": c.water_level, "u_depth": c.depth,
                "u_tileSize": shown_tile_size(c.tile_size, self.extent), "u_scale": c.intensity_scale,
                "u_strength": c.strength, "u_blend": blend, "u_rgb": item.data["caustics_rgb"]}

    def textures(self, scene, ctx, item):
        c = item.data["caustics"]
        first, following, _ = self.frames(c)
        return {"u_first": scene.texture(ctx, c.frame_textures[first], repeat=True),
                "u_next": scene.texture(ctx, c.frame_textures[following], repeat=True)}


PANELS = [
    CausticsPanel("caustics", "caustics", ("baker_caustics.glsl",),
                  "uniform sampler2D u_first;\nuniform sampler2D u_next;\nuniform vec3 u_projection;\n"
                  "uniform float u_waterLevel;\nuniform float u_depth;\nuniform float u_tileSize;\n"
                  "uniform float u_scale;\nuniform float u_strength;\nuniform float u_blend;\nuniform float u_rgb;",
                  "vec3 w = pow(abs(Ng), vec3(4.0));\n"
                  "    w /= max(w.x + w.y + w.z, 1e-6);\n"
                  "    vec2 floorUV = baker_caustics_uv(P, u_projection, u_waterLevel, u_depth, u_tileSize);\n"
                  "    vec3 irradiance =\n"
                  "        w.y * baker_caustics_irradiance(u_first, u_next, floorUV, u_blend, u_scale, u_rgb)\n"
                  "        + w.x * baker_caustics_irradiance(u_first, u_next, vec2(P.z, P.y) / u_tileSize, u_blend,\n"
                  "                                          u_scale, u_rgb)\n"
                  "        + w.z * baker_caustics_irradiance(u_first, u_next, vec2(P.x, P.y) / u_tileSize, u_blend,\n"
                  "                                          u_scale, u_rgb);\n"
                  "    float lambert = max(dot(N, u_light), 0.0);\n"
                  "    color = baker_caustics_apply(albedo * (0.3 + 0.2 * lambert), albedo * 0.5, irradiance,\n"
                  "                                 u_strength, 1.0);",
                  order=45),
]
