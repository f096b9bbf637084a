"""Preview panels of BAKER_thickness: the baked thickness as a false-colour map, and translucency lit from behind
(``runtime-shaders/baker_translucency.glsl``, RTR4 eq. 14.30 / GDC 2011)."""
from __future__ import annotations

import numpy as np

from baker.gltf.vertex_attributes import unpadded
from baker.preview.core import DrawItem, Panel, Scene
from baker.techniques.thickness.extension import ATTRIBUTE, ThicknessMaterial, read


LOW_COLOR, HIGH_COLOR = (0.95, 0.35, 0.1), (0.1, 0.3, 0.9)  # the false colour's ends (linear RGB)


def nice_ceiling(value: float) -> float:
    """The smallest of 1, 2, 5 x 10^k at or above ``value`` (> 0): a scale end a legend can print."""
    if not value > 0:
        return 1.0
    decade = 10.0 ** np.floor(np.log10(value))
    return float(next(m * decade for m in (1.0, 2.0, 5.0, 10.0) if m * decade >= value * (1 - 1e-9)))


class ScalarMapPanel(Panel):
    """False colour of a thickness on a fixed scale, 0 to a round length at or above the asset's largest value (not
    stretched to the asset's range, so ray noise on a uniform thickness stays one colour), with a colour bar along
    the panel's bottom edge; the label gives the scale and the asset's range in metres (glTF's unit)."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.range = (0.0, 1.0)
        self.values = (0.0, 0.0)

    def prepare(self, items) -> None:
        items = items.items if isinstance(items, Scene) else items
        # the scalar only (x): the padding of the blender attribute layout would pull the range down to 0
        values = np.concatenate([unpadded(i.attributes[self.attribute], 1) for i in items
                                 if self.attribute in i.attributes]).astype(np.float64)
        self.values = (float(values.min()), float(values.max()))
        self.range = (0.0, nice_ceiling(self.values[1]))

    def uniforms(self, item: DrawItem) -> dict:
        return {"u_range": self.range}

    def describe(self, scene: Scene) -> str:
        self.prepare(scene)
        return (f"{self.label}: bar 0-{self.range[1]:g} m, asset {self.values[0]:.3g}-{self.values[1]:.3g} m")

    def decorate(self, image: np.ndarray, scene: Scene) -> np.ndarray:
        """The colour bar of the scale, 0 at the left, along the bottom 4% of the panel."""
        size = image.shape[0]
        height, margin = max(3, size // 25), max(2, size // 64)
        t = np.linspace(0.0, 1.0, size - 2 * margin)[:, None]
        bar = (1 - t) * np.array(LOW_COLOR) + t * np.array(HIGH_COLOR)
        out = image.copy()
        out[size - margin - height: size - margin, margin: size - margin] = bar[None].astype(np.float32)
        return out


class TranslucencyPanel(Panel):
    """Translucency with the material's eq. 14.30 parameters (defaults where the material has none)."""

    def read_item(self, doc, item: DrawItem) -> None:
        if item.material_index is not None:
            item.data["thickness"] = read(doc, item.material_index)

    def uniforms(self, item: DrawItem) -> dict:
        p = item.data.get("thickness") or ThicknessMaterial()
        return {
            "u_thickness.attenuationDistance": p.attenuation_distance,
            "u_thickness.distortion": p.distortion,
            "u_thickness.power": p.power,
            "u_thickness.scale": p.scale,
            "u_thickness.ambient": p.ambient,
            "u_thickness.subsurfaceColor": tuple(p.subsurface_color),
        }


PANELS = [
    ScalarMapPanel("thickness", f"thickness ({ATTRIBUTE})", (), "uniform vec2 u_range;",
                   "float t = clamp((scalar - u_range.x) / (u_range.y - u_range.x), 0.0, 1.0);\n"
                   f"    color = mix(vec3{LOW_COLOR}, vec3{HIGH_COLOR}, t);",
                   attribute=ATTRIBUTE, needs=(ATTRIBUTE,), order=10),
    TranslucencyPanel("translucency", "translucency, lit from behind", ("baker_translucency.glsl",),
                      "uniform BakerThickness u_thickness;",
                      "color = 0.05 * albedo * max(dot(N, u_light), 0.0)\n"
                      "          + baker_translucency(u_thickness, N, V, u_light, scalar);",
                      attribute=ATTRIBUTE, light="back", needs=(ATTRIBUTE,), order=20),
]
