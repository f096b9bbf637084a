"""Preview panels of BAKER_thickness: the baked thickness as a false-colour map, and translucency lit from behind
(``runtime-shaders/baker_translucency.glsl``, RTR4 eq. 14.30 / GDC 2011)."""
from __future__ import annotations

import numpy as np

from baker.gltf.vertex_attributes import unpadded
from baker.preview.core import DrawItem, Panel, Scene
from baker.techniques.thickness.extension import ATTRIBUTE, ThicknessMaterial, read


LOW_COLOR, HIGH_COLOR = (0.95, 0.35, 0.1), (0.1, 0.3, 0.9)  # the false colour's ends (linear RGB)


TICK_STEPS = (1.0, 2.0, 2.5, 5.0)  # x 10^k: the steps a scale's ticks take


def tick_step(value: float) -> float:
    """The largest of 1, 2, 2.5, 5 x 10^k that goes into ``value`` (> 0) at least 4 times: a scale ending at the next
    multiple of it at or above ``value`` ends within 1.25 x ``value`` (at most 5 steps for 4 whole ones) and has 4 to
    10 ticks after 0."""
    if not value > 0:
        return 0.25
    decade = 10.0 ** np.floor(np.log10(value / 4.0))
    candidates = [m * decade * f for f in (1.0, 10.0) for m in TICK_STEPS]
    return float(f"{max(c for c in candidates if value / c >= 4.0 * (1 - 1e-9)):.12g}")


def nice_range(value: float) -> tuple[float, float]:
    """(end, tick step) of a scale from 0 that holds ``value`` (> 0): the first multiple of the tick step at or above
    it, within 1.25 x ``value``. A scale end a legend can print (0.672 -> 0.7 by 0.1; 0.123 -> 0.14 by 0.02)."""
    step = tick_step(value)
    if not value > 0:
        return 1.0, step
    end = np.ceil(value / step * (1 - 1e-9)) * step
    # 12 significant digits: 7 x 0.1 is 0.7, not 0.7000000000000001, and never below `value`
    return max(float(f"{end:.12g}"), value), step


class ScalarMapPanel(Panel):
    """False colour of a thickness on a fixed scale, 0 to a round length at or above the asset's largest value (within
    1.25 x it; not stretched to the asset's range, so ray noise on a uniform thickness stays one colour), with a
    colour bar along the panel's bottom edge, ticked at round steps and labelled at its ends and middle; the panel's
    label gives the scale and the asset's range in metres (glTF's unit)."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.range = (0.0, 1.0)
        self.step = 0.25
        self.values = (0.0, 0.0)

    def prepare(self, items) -> None:
        items = items.items if isinstance(items, Scene) else items
        # the scalar only (x): the padding of the blender attribute layout would pull the range down to 0
        values = np.concatenate([unpadded(i.attributes[self.attribute], 1) for i in items
                                 if self.attribute in i.attributes]).astype(np.float64)
        self.values = (float(values.min()), float(values.max()))
        end, self.step = nice_range(self.values[1])
        self.range = (0.0, end)

    def uniforms(self, item: DrawItem) -> dict:
        return {"u_range": self.range}

    def describe(self, scene: Scene) -> str:
        self.prepare(scene)
        return (f"{self.label}: bar 0-{self.range[1]:g} m, asset {self.values[0]:.3g}-{self.values[1]:.3g} m")

    def ticks(self) -> list[float]:
        """The bar's tick values: 0 to the scale's end by the tick step."""
        count = int(round(self.range[1] / self.step))
        return [round(k * self.step, 12) for k in range(count + 1)]

    def bar_geometry(self, size: int) -> tuple[int, int, int]:
        """(height, margin, bottom row + 1) of the colour bar in a ``size`` panel."""
        height, margin = max(3, size // 25), max(2, size // 64)
        return height, margin, size - margin

    def tick_column(self, value: float, size: int) -> int:
        """The panel column of ``value`` on the bar."""
        _, margin, _ = self.bar_geometry(size)
        return int(round(margin + value / self.range[1] * (size - 2 * margin - 1)))

    def decorate(self, image: np.ndarray, scene: Scene) -> np.ndarray:
        """The colour bar of the scale, 0 at the left, along the bottom 4% of the panel, with a light tick above it at
        every step and the values of the ends and the middle tick written over the ticks."""
        self.prepare(scene)
        size = image.shape[0]
        height, margin, bottom = self.bar_geometry(size)
        t = np.linspace(0.0, 1.0, size - 2 * margin)[:, None]
        bar = (1 - t) * np.array(LOW_COLOR) + t * np.array(HIGH_COLOR)
        out = image.copy()
        top = bottom - height
        out[top: bottom, margin: size - margin] = bar[None].astype(np.float32)
        tick = max(2, height // 2)
        ticks = self.ticks()
        for value in ticks:
            col = self.tick_column(value, size)
            out[top - tick: top, max(col - size // 384, 0): col + 1] = TICK_COLOR
        labelled = [ticks[0], ticks[len(ticks) // 2], ticks[-1]]
        return write_tick_labels(out, [(f"{v:g}", self.tick_column(v, size), top - tick - 1) for v in labelled])


TICK_COLOR = (0.85, 0.85, 0.85)


def write_tick_labels(image: np.ndarray, labels) -> np.ndarray:
    """``labels`` ((text, centre column, bottom row), ...) written in TICK_COLOR with DejaVu Sans through Pillow
    (unlabelled when neither is there), each kept inside the panel."""
    try:
        from PIL import Image, ImageDraw, ImageFont
    except ImportError:
        return image
    size = image.shape[0]
    canvas = Image.fromarray(np.round(np.clip(image, 0, 1) * 255).astype(np.uint8))
    draw = ImageDraw.Draw(canvas)
    points = max(8, size // 32)
    try:
        font = ImageFont.truetype("DejaVuSans.ttf", points)
    except OSError:
        font = ImageFont.load_default()
    colour = tuple(int(round(c * 255)) for c in TICK_COLOR)
    for text, centre, bottom in labels:
        width = draw.textlength(text, font=font)
        x = min(max(centre - width / 2, 1), size - width - 1)
        draw.text((x, bottom - points - 1), text, fill=colour, font=font)
    return np.asarray(canvas).astype(np.float32) / 255.0


# the back light's colour: warm, as light through skin, wax or leaves reads (the runtime multiplies its result by the
# light's colour and intensity, as here)
BACK_LIGHT_TINT = (1.0, 0.78, 0.55)
AMBIENT = 0.03  # x albedo: the floor under the light let through, so a part too thick for it shows dark, not black
BRIGHTEST = 0.9  # what the translucency of the thinnest parts is exposed to (red channel), below white
EXPOSED_PERCENTILE = 99.0  # of the vertices' largest translucency (their transmittance, the lobe at 1)


class TranslucencyPanel(Panel):
    """Translucency with the material's eq. 14.30 parameters (defaults where the material has none), lit from
    nearly straight behind (so the lobe (V . -L)^p is close to 1 over the whole view and the picture is the
    transmittance t_ss = exp(-thickness / attenuationDistance): thin parts glow, thick parts stay dark), by a warm
    light whose intensity exposes the thinnest 1% of the vertices to BRIGHTEST, never darker than a dim floor."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.exposure = 1.0

    def read_item(self, doc, item: DrawItem) -> None:
        if item.material_index is not None:
            item.data["thickness"] = read(doc, item.material_index)

    def prepare(self, items) -> None:
        """The light's intensity: BRIGHTEST over the EXPOSED_PERCENTILE of the largest translucency each vertex can
        show (its thickness' transmittance, the lobe at 1)."""
        items = items.items if isinstance(items, Scene) else items
        most = []
        for item in items:
            if not self.applies(item):
                continue
            p = item.data.get("thickness") or ThicknessMaterial()
            thickness = unpadded(item.attributes[self.attribute], 1).astype(np.float64)
            transmittance = np.exp(-np.maximum(thickness, 0.0) / max(p.attenuation_distance, 1e-12))
            most.append(max(p.subsurface_color) * (p.scale + p.ambient) * transmittance)
        # the light's intensity exposes the EXPOSED_PERCENTILE vertex to BRIGHTEST: the few thinnest tips above it
        # may reach white; a material that lets no light through keeps intensity 1 (the panel shows the ambient)
        bright = float(np.percentile(np.concatenate(most), EXPOSED_PERCENTILE)) if most else 0.0
        self.exposure = float(np.clip(BRIGHTEST / bright, 0.05, 100.0)) if bright > 0 else 1.0

    def uniforms(self, item: DrawItem) -> dict:
        p = item.data.get("thickness") or ThicknessMaterial()
        return {
            "u_thickness.attenuationDistance": p.attenuation_distance,
            "u_thickness.distortion": p.distortion,
            "u_thickness.power": p.power,
            "u_thickness.scale": p.scale,
            "u_thickness.ambient": p.ambient,
            "u_thickness.subsurfaceColor": tuple(p.subsurface_color),
            "u_lightColor": tuple(self.exposure * c for c in BACK_LIGHT_TINT),
        }

    def describe(self, scene: Scene) -> str:
        self.prepare(scene)
        return f"{self.label} (light x{self.exposure:.2g})"


PANELS = [
    ScalarMapPanel("thickness", f"thickness ({ATTRIBUTE})", (), "uniform vec2 u_range;",
                   "float t = clamp((scalar - u_range.x) / (u_range.y - u_range.x), 0.0, 1.0);\n"
                   f"    color = mix(vec3{LOW_COLOR}, vec3{HIGH_COLOR}, t);",
                   attribute=ATTRIBUTE, needs=(ATTRIBUTE,), order=10),
    TranslucencyPanel("translucency", "translucency, lit from behind", ("baker_translucency.glsl",),
                      "uniform BakerThickness u_thickness;\nuniform vec3 u_lightColor;",
                      "color = max(u_lightColor * baker_translucency(u_thickness, N, V, u_light, scalar),\n"
                      f"                {AMBIENT} * albedo);",
                      attribute=ATTRIBUTE, light="back", needs=(ATTRIBUTE,), order=20),
]
