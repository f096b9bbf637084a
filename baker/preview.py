"""``baker preview``: render a baked asset headlessly with the reference runtime shaders, as a labelled contact sheet.

One panel per technique whose data is present in the asset, each drawn by the GLSL module in ``runtime-shaders/``
that an engine would use (the same text, pasted after a ``#version 330 core`` header): a plain Lambert reference,
the baked thickness as a false-colour map, and translucency lit from behind (RTR4 eq. 14.30 / GDC 2011). Rendering
uses moderngl on an EGL context (Mesa llvmpipe works), so it runs on CI machines without a display.

Panels are entries of ``PANELS``: a technique adds its panel with a fragment-shader body and the uniforms it needs.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .asset import Asset, vertex_normals
from .errors import BakerError

SHADER_ROOT = Path(__file__).resolve().parents[1] / "runtime-shaders"
BACKGROUND = (0.16, 0.17, 0.19)


# ---------------------------------------------------------------------------------------------------- scene
@dataclass
class DrawItem:
    """One triangle primitive in world space, with the per-vertex data panels may use."""

    positions: np.ndarray  # (n, 3) float32
    normals: np.ndarray  # (n, 3) float32
    faces: np.ndarray  # (m, 3) uint32
    attributes: dict  # name -> (n,) or (n, k) float32 (baked custom attributes such as _THICKNESS)
    material: dict  # the glTF material JSON (extensions included)


def _node_matrix(node: dict) -> np.ndarray:
    if "matrix" in node:
        return np.array(node["matrix"], np.float64).reshape(4, 4).T  # glTF stores column-major
    t = np.array(node.get("translation", [0, 0, 0]), np.float64)
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    s = np.array(node.get("scale", [1, 1, 1]), np.float64)
    r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    m = np.eye(4)
    m[:3, :3] = r * s[None, :]
    m[:3, 3] = t
    return m


def scene_items(asset: Asset) -> list[DrawItem]:
    """Every triangle primitive drawn by the default scene (or every mesh once when there is no scene)."""
    gltf = asset.doc.json
    nodes = gltf.get("nodes", [])
    placements = []  # (mesh index, world matrix)
    scenes = gltf.get("scenes", [])
    if scenes:
        stack = [(n, np.eye(4)) for n in scenes[gltf.get("scene", 0)].get("nodes", [])]
        while stack:
            index, parent = stack.pop()
            node = nodes[index]
            world = parent @ _node_matrix(node)
            if "mesh" in node:
                placements.append((node["mesh"], world))
            stack.extend((c, world) for c in node.get("children", []))
    else:
        placements = [(m, np.eye(4)) for m in range(len(asset.meshes()))]
    materials = gltf.get("materials", [])
    items = []
    for mesh, world in sorted(placements, key=lambda p: p[0]):
        for p in asset.triangle_primitives(mesh):
            g = asset.primitive(mesh, p)
            if not len(g.faces):
                continue
            normals = g.normals if g.normals is not None else vertex_normals(g.positions, g.faces)
            pos = g.positions @ world[:3, :3].T + world[:3, 3]
            nrm = normals @ np.linalg.inv(world[:3, :3])  # inverse transpose, row-vector form
            nrm /= np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-20)
            prim = asset.meshes()[mesh]["primitives"][p]
            attributes = {k: asset.doc.accessor(a).astype(np.float32) for k, a in prim["attributes"].items()
                          if k.startswith("_")}
            material = materials[g.material] if g.material is not None and g.material < len(materials) else {}
            items.append(DrawItem(pos.astype(np.float32), nrm.astype(np.float32), g.faces.astype(np.uint32),
                                  attributes, material))
    if not items:
        raise BakerError(asset.source, "nothing to preview (no triangle primitives in the scene)")
    return items


@dataclass
class Camera:
    eye: np.ndarray
    target: np.ndarray
    view: np.ndarray  # 4x4
    projection: np.ndarray  # 4x4

    @property
    def forward(self) -> np.ndarray:
        d = self.target - self.eye
        return d / np.linalg.norm(d)


def frame_camera(items: list[DrawItem], azimuth: float = 30.0, elevation: float = 15.0, fov: float = 35.0,
                 aspect: float = 1.0) -> Camera:
    """A perspective camera looking at the bounding sphere's centre from (azimuth, elevation) degrees."""
    points = np.concatenate([i.positions for i in items]).astype(np.float64)
    lo, hi = points.min(0), points.max(0)
    center = (lo + hi) / 2
    radius = max(float(np.linalg.norm(points - center, axis=1).max()), 1e-6)
    az, el = math.radians(azimuth), math.radians(elevation)
    direction = np.array([math.sin(az) * math.cos(el), math.sin(el), math.cos(az) * math.cos(el)])
    distance = radius / math.sin(math.radians(fov) / 2) * 1.05
    eye = center + direction * distance
    f = (center - eye) / np.linalg.norm(center - eye)
    up = np.array([0.0, 1.0, 0.0]) if abs(f[1]) < 0.99 else np.array([0.0, 0.0, 1.0])
    s = np.cross(f, up)
    s /= np.linalg.norm(s)
    u = np.cross(s, f)
    view = np.eye(4)
    view[0, :3], view[1, :3], view[2, :3] = s, u, -f
    view[:3, 3] = -view[:3, :3] @ eye
    near, far = max(distance - radius * 1.5, distance * 1e-3), distance + radius * 1.5
    t = 1.0 / math.tan(math.radians(fov) / 2)
    proj = np.zeros((4, 4))
    proj[0, 0], proj[1, 1] = t / aspect, t
    proj[2, 2], proj[2, 3] = (far + near) / (near - far), 2 * far * near / (near - far)
    proj[3, 2] = -1.0
    return Camera(eye, center, view, proj)


# ---------------------------------------------------------------------------------------------------- panels
VERTEX_SHADER = """#version 330 core
uniform mat4 u_viewProjection;
in vec3 POSITION;
in vec3 NORMAL;
in float a_scalar;
out vec3 v_position;
out vec3 v_normal;
out float v_scalar;
void main() {
    v_position = POSITION;
    v_normal = NORMAL;
    v_scalar = a_scalar;
    gl_Position = u_viewProjection * vec4(POSITION, 1.0);
}
"""


@dataclass
class Panel:
    """A contact-sheet panel: a label, the runtime modules it includes, and a fragment body computing ``color``.

    The body sees ``vec3 N, V, P`` (unit normal, unit direction to the eye, world position), ``float scalar`` (the
    panel's per-vertex attribute, interpolated), ``vec3 u_light`` (unit direction to the light) and the uniforms
    the panel declares in ``declarations``.
    """

    name: str
    label: str
    modules: tuple
    declarations: str
    body: str
    attribute: str | None = None  # the per-vertex attribute bound to ``a_scalar``
    light: str = "front"  # "front" (over the camera's shoulder) or "back" (behind the object)
    needs: tuple = ()  # attributes that must be present for the panel to show

    def available(self, items: list[DrawItem]) -> bool:
        return all(any(n in i.attributes for i in items) for n in self.needs)

    def uniforms(self, item: DrawItem) -> dict:
        return {}


class TranslucencyPanel(Panel):
    def uniforms(self, item: DrawItem) -> dict:
        ext = item.material.get("extensions", {}).get("BAKER_thickness", {})
        color = ext.get("subsurfaceColor", [1.0, 0.45, 0.3])
        return {
            "u_thickness.attenuationDistance": float(ext.get("attenuationDistance", 1.0)),
            "u_thickness.distortion": float(ext.get("distortion", 0.2)),
            "u_thickness.power": float(ext.get("power", 4.0)),
            "u_thickness.scale": float(ext.get("scale", 1.0)),
            "u_thickness.ambient": float(ext.get("ambient", 0.0)),
            "u_thickness.subsurfaceColor": tuple(float(c) for c in color),
        }


class ScalarMapPanel(Panel):
    """False colour of a scalar attribute normalized by its range over the asset."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.range = (0.0, 1.0)

    def prepare(self, items: list[DrawItem]) -> None:
        values = np.concatenate([i.attributes[self.attribute].reshape(-1) for i in items if self.attribute in i.attributes])
        self.range = (float(values.min()), float(max(values.max(), values.min() + 1e-12)))

    def uniforms(self, item: DrawItem) -> dict:
        return {"u_range": self.range}


PANELS = [
    Panel("lambert", "shaded (reference)", (), "",
          "color = vec3(0.8) * (0.15 + 0.85 * max(dot(N, u_light), 0.0));"),
    ScalarMapPanel("thickness", "thickness (_THICKNESS)", (), "uniform vec2 u_range;",
                   "float t = clamp((scalar - u_range.x) / (u_range.y - u_range.x), 0.0, 1.0);\n"
                   "    color = mix(vec3(0.95, 0.35, 0.1), vec3(0.1, 0.3, 0.9), t);",
                   attribute="_THICKNESS", needs=("_THICKNESS",)),
    TranslucencyPanel("translucency", "translucency, lit from behind", ("baker_translucency.glsl",),
                      "uniform BakerThickness u_thickness;",
                      "color = 0.05 * vec3(0.8) * max(dot(N, u_light), 0.0)\n"
                      "          + baker_translucency(u_thickness, N, V, u_light, scalar);",
                      attribute="_THICKNESS", light="back", needs=("_THICKNESS",)),
]


def fragment_shader(panel: Panel) -> str:
    modules = "\n".join((SHADER_ROOT / m).read_text() for m in panel.modules)
    return f"""#version 330 core
{modules}
uniform vec3 u_eye;
uniform vec3 u_light;
{panel.declarations}
in vec3 v_position;
in vec3 v_normal;
in float v_scalar;
out vec4 fragColor;
void main() {{
    vec3 N = normalize(v_normal);
    vec3 V = normalize(u_eye - v_position);
    if (dot(N, V) < 0.0) N = -N;  // double-sided preview
    vec3 P = v_position;
    float scalar = v_scalar;
    vec3 color;
    {panel.body}
    fragColor = vec4(clamp(color, 0.0, 1.0), 1.0);
}}
"""


# ---------------------------------------------------------------------------------------------------- render
def create_context():
    import moderngl

    try:
        return moderngl.create_standalone_context(backend="egl")
    except Exception as exc:  # no EGL: try the platform default (GLX/WGL/CGL)
        try:
            return moderngl.create_standalone_context()
        except Exception:
            raise BakerError(None, f"cannot create an OpenGL context for preview: {exc}") from None


def light_direction(camera: Camera, where: str) -> np.ndarray:
    """Unit direction to the light: over the camera's right shoulder, or behind the object facing the camera."""
    f = camera.forward
    right = np.cross(f, [0.0, 1.0, 0.0])
    right = right / (np.linalg.norm(right) or 1.0)
    if where == "back":
        d = f + 0.25 * right + np.array([0.0, 0.2, 0.0])  # from behind, a little off-axis so the lobe shows
    else:
        d = -f + 0.5 * right + np.array([0.0, 0.5, 0.0])
    return d / np.linalg.norm(d)


def render_panel(ctx, panel: Panel, items: list[DrawItem], camera: Camera, size: int, samples: int = 4) -> np.ndarray:
    """Render one panel; returns (size, size, 3) float32 in [0, 1], row 0 at the top."""
    if hasattr(panel, "prepare"):
        panel.prepare(items)
    program = ctx.program(vertex_shader=VERTEX_SHADER, fragment_shader=fragment_shader(panel))
    fbo = ctx.simple_framebuffer((size, size), components=4, samples=samples)
    fbo.use()
    ctx.enable(ctx.DEPTH_TEST)
    fbo.clear(*BACKGROUND, 1.0)
    vp = (camera.projection @ camera.view).astype(np.float32)
    light = light_direction(camera, panel.light)
    values = {"u_viewProjection": vp.T.tobytes(), "u_eye": tuple(camera.eye), "u_light": tuple(light)}
    for item in items:
        uniforms = dict(values, **panel.uniforms(item))
        for name, value in uniforms.items():
            if name in program:
                if isinstance(value, bytes):
                    program[name].write(value)
                else:
                    program[name].value = value
        scalar = item.attributes.get(panel.attribute) if panel.attribute else None
        scalar = np.zeros(len(item.positions), np.float32) if scalar is None else scalar.reshape(len(item.positions), -1)[:, 0]
        buffers = []
        content = []
        for data, name in ((item.positions, "POSITION"), (item.normals, "NORMAL"), (scalar, "a_scalar")):
            if name in program:
                buf = ctx.buffer(np.ascontiguousarray(data, np.float32).tobytes())
                buffers.append(buf)
                content.append((buf, "3f" if data.ndim == 2 else "1f", name))
        ibo = ctx.buffer(item.faces.astype(np.uint32).tobytes())
        vao = ctx.vertex_array(program, content, index_buffer=ibo, index_element_size=4)
        vao.render()
        vao.release()
        ibo.release()
        for b in buffers:
            b.release()
    resolved = ctx.simple_framebuffer((size, size), components=4)
    ctx.copy_framebuffer(resolved, fbo)
    pixels = np.frombuffer(resolved.read(components=3, dtype="f1"), np.uint8).reshape(size, size, 3)
    program.release()
    fbo.release()
    resolved.release()
    return np.flipud(pixels).astype(np.float32) / 255.0


@dataclass
class Preview:
    sheet: np.ndarray  # (H, W, 3) uint8
    panels: list = field(default_factory=list)  # (name, label, (row, col, size)) of each panel, in sheet pixels


def preview(path_or_asset, size: int = 384, azimuth: float = 30.0, elevation: float = 15.0,
            panels: list[str] | None = None) -> Preview:
    """Render every available panel of an asset into a contact sheet."""
    asset = path_or_asset if isinstance(path_or_asset, Asset) else Asset.load(path_or_asset)
    items = scene_items(asset)
    chosen = [p for p in PANELS if p.available(items) and (panels is None or p.name in panels)]
    camera = frame_camera(items, azimuth, elevation)
    ctx = create_context()
    try:
        images = [(p, render_panel(ctx, p, items, camera, size)) for p in chosen]
    finally:
        ctx.release()
    label_h = max(18, size // 16)
    cols = min(len(images), 3)
    rows = math.ceil(len(images) / cols)
    sheet = np.full((rows * (size + label_h), cols * size, 3), 24, np.uint8)
    placed = []
    for k, (panel, image) in enumerate(images):
        r, c = divmod(k, cols)
        y, x = r * (size + label_h) + label_h, c * size
        sheet[y: y + size, x: x + size] = np.round(image * 255).astype(np.uint8)
        placed.append((panel.name, panel.label, (y, x, size)))
    _draw_labels(sheet, [(label, y - label_h, x, label_h) for _, label, (y, x, _) in placed])
    return Preview(sheet, placed)


def _draw_labels(sheet: np.ndarray, labels) -> None:
    """Write panel labels with DejaVu Sans through Pillow (silently unlabelled when neither is available)."""
    try:
        from PIL import Image, ImageDraw, ImageFont
    except ImportError:
        return
    image = Image.fromarray(sheet)
    draw = ImageDraw.Draw(image)
    for text, y, x, h in labels:
        try:
            font = ImageFont.truetype("DejaVuSans.ttf", int(h * 0.7))
        except OSError:
            font = ImageFont.load_default()
        draw.text((x + 6, y + h * 0.12), text, fill=(230, 230, 230), font=font)
    sheet[...] = np.asarray(image)


def main(args) -> int:
    from .io.atomic import atomic_path
    from .io.images import write_image

    out = Path(args.output)
    if out.suffix.lower() not in (".png", ".exr", ".jpg", ".jpeg", ".tif", ".tiff"):
        raise BakerError(out, "preview output must be an image (.png, .jpg, .exr, .tif)")
    azimuth, elevation = (float(v) for v in args.view.split(","))
    result = preview(args.input, size=args.size, azimuth=azimuth, elevation=elevation,
                     panels=args.panels.split(",") if args.panels else None)
    with atomic_path(out) as tmp:
        write_image(tmp, result.sheet)
    if not args.quiet:
        import sys

        print(f"preview: {', '.join(n for n, _, _ in result.panels)} -> {out}", file=sys.stderr)
    return 0


def add_parser(sub) -> None:
    p = sub.add_parser("preview", help="render a baked asset with the runtime shaders as a labelled contact sheet")
    p.add_argument("input", help="a baked asset (.glb, .gltf, or any input baker reads)")
    p.add_argument("-o", "--output", required=True, help="output image (.png)")
    p.add_argument("--size", type=int, default=384, help="panel size in pixels (default 384)")
    p.add_argument("--view", default="30,15", help="camera azimuth,elevation in degrees (default 30,15)")
    p.add_argument("--panels", default=None, help=f"comma-separated panels (default: every available one of "
                                                   f"{', '.join(p.name for p in PANELS)})")
    p.add_argument("-q", "--quiet", action="store_true")
    p.set_defaults(func=main)
