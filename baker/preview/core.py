"""``baker preview``: render a baked asset headlessly with the reference runtime shaders, as a labelled contact sheet.

One panel per technique whose data is present in the asset, each drawn by the GLSL module in ``runtime-shaders/``
that an engine would use (the same text, pasted after a ``#version 330 core`` header), bound to the asset's data
the way the module's README says: a plain Lambert reference; the baked thickness as a false-colour map and
translucency lit from behind (BAKER_thickness); Penner's pre-integrated skin from the LUT texture and ``_CURVATURE``
(BAKER_skin_lut); toon shading from the ramp texture (BAKER_toon_ramp); hatching from the tonal art map uploaded as
custom mip chains with Praun's six-tone blend (BAKER_tonal_art_map); the shell outline along ``_OUTLINE_NORMAL``
(a back-face pass) plus fins, and the single-pass wireframe with the baked wireframe mask (BAKER_edges); fur shells
(BAKER_fur); MSDF text labels (BAKER_text + BAKER_glyph_atlas); hair ribbons (BAKER_hair). Rendering uses moderngl
on an EGL context (Mesa llvmpipe works), so it runs on CI machines without a display.

Panels are entries of ``PANELS`` (the registry): a technique adds its panel there, with a fragment-shader body and
the uniforms and textures it needs (single-pass panels), or a ``draw`` method issuing its passes.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from baker.geometry.asset import Asset
from baker.geometry.normals import vertex_normals
from baker.data import SHADER_ROOT
from baker.errors import BakerError
from baker.gltf.document import world_nodes

BACKGROUND = (0.16, 0.17, 0.19)
INK = (0.03, 0.03, 0.035)


# ---------------------------------------------------------------------------------------------------- scene
@dataclass
class DrawItem:
    """One triangle primitive in world space, with the per-vertex data panels may use."""

    positions: np.ndarray  # (n, 3) float32
    normals: np.ndarray  # (n, 3) float32
    faces: np.ndarray  # (m, 3) uint32
    attributes: dict  # name -> (n,) or (n, k) float32 (baked custom attributes such as _THICKNESS)
    material: dict  # the glTF material JSON (extensions included)
    texcoords: dict = field(default_factory=dict)  # set index -> (n, 2) float32 (glTF convention, v down)
    primitive: dict = field(default_factory=dict)  # the primitive JSON
    mask: np.ndarray | None = None  # BAKER_edges.wireframeMask, one per triangle

    def extension(self, name: str) -> dict | None:
        return (self.material.get("extensions") or {}).get(name)


@dataclass
class Label:
    """The quads of a node with BAKER_text, in world space, and its font."""

    positions: np.ndarray
    uv: np.ndarray
    faces: np.ndarray
    text: dict  # BAKER_text
    font: dict  # BAKER_glyph_atlas.fonts[text.font]


@dataclass
class Strands:
    """A BAKER_hair primitive in world space."""

    positions: np.ndarray
    tangents: np.ndarray
    params: np.ndarray
    width_scale: np.ndarray  # per vertex
    ribbon: np.ndarray  # ribbonIndices
    hair: dict  # BAKER_hair
    material: dict


@dataclass
class EdgeFins:
    """A BAKER_edges fin primitive in world space."""

    attributes: dict  # _FIN_V0.._FIN_V3 (world), _FIN_CORNER, _FIN_FLAGS
    faces: np.ndarray
    crease_angle: float


@dataclass
class Scene:
    """What the panels draw: triangle surfaces, text labels, hair, edge fins, and the document for textures."""

    items: list
    labels: list = field(default_factory=list)
    strands: list = field(default_factory=list)
    fins: list = field(default_factory=list)
    doc: object = None
    _textures: dict = field(default_factory=dict)

    def points(self) -> np.ndarray:
        parts = [i.positions for i in self.items] + [l.positions for l in self.labels] + \
                [s.positions for s in self.strands]
        return np.concatenate(parts).astype(np.float64)

    def image(self, texture_index: int) -> np.ndarray:
        """A glTF texture's image as (H, W, C) float32 in [0, 1] (row 0 = the image's top = glTF v 0)."""
        from baker.gltf.images import decode_image

        key = ("image", texture_index)
        if key not in self._textures:
            source = self.doc.json["textures"][texture_index]["source"]
            mime = self.doc.json["images"][source].get("mimeType", "image/png")
            suffix = {"image/jpeg": ".jpg", "image/png": ".png"}.get(mime, ".png")
            pixels = decode_image(self.doc.image_bytes(source), suffix)
            pixels = pixels[..., None] if pixels.ndim == 2 else pixels
            scale = float(np.iinfo(pixels.dtype).max) if pixels.dtype.kind in "ui" else 1.0
            self._textures[key] = np.ascontiguousarray(pixels.astype(np.float32) / np.float32(scale))
        return self._textures[key]

    def texture(self, ctx, texture_index: int, repeat: bool = False, srgb: bool = False):
        """A moderngl texture of a glTF texture (float32, LINEAR; no mipmaps), cached per context."""
        import moderngl

        key = ("gl", id(ctx), texture_index, repeat, srgb)
        if key not in self._textures:
            pixels = self.image(texture_index)
            if srgb:
                pixels = srgb_to_linear(pixels)
            h, w, c = pixels.shape
            tex = ctx.texture((w, h), c, pixels.tobytes(), dtype="f4")
            tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
            tex.repeat_x = tex.repeat_y = repeat
            self._textures[key] = tex
        return self._textures[key]

    def mip_chain(self, ctx, texture_indices: list):
        """One texture whose mip level i is the image of texture_indices[i] (a TAM's custom mip chain)."""
        import moderngl

        key = ("chain", id(ctx), tuple(texture_indices))
        if key not in self._textures:
            levels = [self.image(t) for t in texture_indices]
            c = levels[0].shape[2]
            h, w = levels[0].shape[:2]
            tex = ctx.texture((w, h), c, levels[0].tobytes(), dtype="f4")
            tex.build_mipmaps(0, len(levels) - 1)  # allocates the levels; their contents are replaced below
            for i, level in enumerate(levels):
                tex.write(np.ascontiguousarray(level).tobytes(), level=i)
            tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
            tex.repeat_x = tex.repeat_y = True
            self._textures[key] = tex
        return self._textures[key]

    def release(self) -> None:
        for key, value in list(self._textures.items()):
            if key[0] != "image":
                value.release()
                del self._textures[key]


def srgb_to_linear(c: np.ndarray) -> np.ndarray:
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4).astype(np.float32)


def _placements(asset: Asset) -> list:
    """(mesh index, world matrix, node JSON or None) of every mesh drawn by the default scene."""
    gltf = asset.doc.json
    nodes = gltf.get("nodes", [])
    placements = [(nodes[i]["mesh"], world, nodes[i]) for i, world in world_nodes(gltf) if "mesh" in nodes[i]]
    if not placements and not gltf.get("scenes"):
        return [(m, np.eye(4), None) for m in range(len(asset.meshes()))]
    return sorted(placements, key=lambda p: p[0])


def _transform(points, world):
    return (points @ world[:3, :3].T + world[:3, 3]).astype(np.float32)


def _transform_normals(normals, world):
    n = normals @ np.linalg.inv(world[:3, :3])  # inverse transpose, row-vector form
    return (n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-20)).astype(np.float32)


def gather_scene(asset: Asset) -> Scene:
    """Everything the default scene draws: triangle primitives, BAKER_text labels, BAKER_hair strands, edge fins."""
    doc = asset.doc
    gltf = doc.json
    materials = gltf.get("materials", [])
    fonts = (gltf.get("extensions", {}).get("BAKER_glyph_atlas") or {}).get("fonts", [])
    scene = Scene(items=[], doc=doc)
    for mesh, world, node in _placements(asset):
        text = ((node or {}).get("extensions") or {}).get("BAKER_text")
        prims = asset.meshes()[mesh].get("primitives", [])
        if text is not None and text.get("font", 0) < len(fonts):  # its quads are the label, drawn as MSDF text
            for p in asset.triangle_primitives(mesh):
                g = asset.primitive(mesh, p)
                attrs = prims[p]["attributes"]
                if "TEXCOORD_0" in attrs and len(g.faces):
                    scene.labels.append(Label(_transform(g.positions, world),
                                              doc.accessor(attrs["TEXCOORD_0"]).astype(np.float32),
                                              g.faces.astype(np.uint32), text, fonts[text.get("font", 0)]))
            continue
        guides_of_children = {(prim.get("extensions", {}).get("BAKER_hair") or {}).get("guides", {}).get("primitive")
                              for prim in prims}
        for p, prim in enumerate(prims):
            ext = prim.get("extensions") or {}
            if "BAKER_hair" in ext and p not in guides_of_children:  # children when present, else the guides
                scene.strands.append(_strands(doc, prim, world, materials))
            edges = ext.get("BAKER_edges") or {}
            if "finsOf" in edges:
                attrs = {k: doc.accessor(a).astype(np.float32) for k, a in prim["attributes"].items()
                         if k.startswith("_FIN_")}
                for k in ("_FIN_V0", "_FIN_V1", "_FIN_V2", "_FIN_V3"):
                    attrs[k] = _transform(attrs[k], world)
                source = prims[edges["finsOf"]].get("extensions", {}).get("BAKER_edges", {})
                scene.fins.append(EdgeFins(attrs, doc.accessor(prim["indices"]).astype(np.uint32).reshape(-1, 3),
                                           float(source.get("creaseAngle", math.radians(60)))))
        for p in asset.triangle_primitives(mesh):
            prim = prims[p]
            if "finsOf" in ((prim.get("extensions") or {}).get("BAKER_fur") or {}):
                continue  # fur fins: degenerate quads
            g = asset.primitive(mesh, p)
            if not len(g.faces):
                continue
            normals = g.normals if g.normals is not None else vertex_normals(g.positions, g.faces)
            attributes = {k: doc.accessor(a).astype(np.float32) for k, a in prim["attributes"].items()
                          if k.startswith("_")}
            if "_OUTLINE_NORMAL" in attributes:
                attributes["_OUTLINE_NORMAL"] = _transform_normals(attributes["_OUTLINE_NORMAL"], world)
            texcoords = {int(k.split("_")[1]): doc.accessor(a).astype(np.float32)
                         for k, a in prim["attributes"].items() if k.startswith("TEXCOORD_")}
            edges = (prim.get("extensions") or {}).get("BAKER_edges") or {}
            mask = None
            if "wireframeMask" in edges:
                mask = doc.accessor(edges["wireframeMask"]).reshape(-1).astype(np.float32)
                mask = mask if len(mask) == len(g.faces) else None
            material = materials[g.material] if g.material is not None and g.material < len(materials) else {}
            scene.items.append(DrawItem(_transform(g.positions, world), _transform_normals(normals, world),
                                        g.faces.astype(np.uint32), attributes, material, texcoords, prim, mask))
    if not (scene.items or scene.labels or scene.strands):
        raise BakerError(asset.source, "nothing to preview (no triangle primitives, text or hair in the scene)")
    return scene


def _strands(doc, prim, world, materials) -> Strands:
    hair = prim["extensions"]["BAKER_hair"]
    attrs = prim["attributes"]
    positions = doc.accessor(attrs["POSITION"]).astype(np.float64)
    tangents = doc.accessor(attrs[hair.get("tangentAttribute", "_STRAND_TANGENT")]).astype(np.float64)
    params = doc.accessor(attrs[hair.get("paramAttribute", "_STRAND_PARAM")]).astype(np.float32).reshape(-1)
    per = int(hair["verticesPerStrand"])
    scale = doc.accessor(hair["widthScale"]).astype(np.float32).reshape(-1) if "widthScale" in hair \
        else np.ones(len(positions) // per, np.float32)
    tangents = tangents @ world[:3, :3].T
    tangents /= np.maximum(np.linalg.norm(tangents, axis=1, keepdims=True), 1e-20)
    material = materials[prim["material"]] if prim.get("material") is not None else {}
    return Strands(_transform(positions, world), tangents.astype(np.float32), params,
                   np.repeat(scale, per)[: len(positions)], doc.accessor(hair["ribbonIndices"]).astype(np.uint32).reshape(-1),
                   hair, material)


def scene_items(asset: Asset) -> list[DrawItem]:
    """Every triangle surface drawn by the default scene (text labels and hair excluded)."""
    return gather_scene(asset).items


@dataclass
class Camera:
    eye: np.ndarray
    target: np.ndarray
    view: np.ndarray  # 4x4
    projection: np.ndarray  # 4x4
    fov: float = 35.0  # vertical, degrees

    @property
    def forward(self) -> np.ndarray:
        d = self.target - self.eye
        return d / np.linalg.norm(d)


def frame_camera(items, azimuth: float = 30.0, elevation: float = 15.0, fov: float = 35.0,
                 aspect: float = 1.0) -> Camera:
    """A perspective camera looking at the bounding sphere's centre from (azimuth, elevation) degrees.

    ``items``: a Scene, or a list of objects with ``positions``."""
    points = items.points() if isinstance(items, Scene) else \
        np.concatenate([i.positions for i in items]).astype(np.float64)
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
    return Camera(eye, center, view, proj, fov)


# ---------------------------------------------------------------------------------------------------- panels
VERTEX_TEMPLATE = """#version 330 core
{modules}
uniform mat4 u_viewProjection;
uniform vec3 u_eye;
uniform float u_viewportHeight;
uniform float u_projectionScaleY;
uniform float u_width;
{declarations}
in vec3 POSITION;
in vec3 NORMAL;
in float a_scalar;
in vec2 TEXCOORD_0;
in vec3 a_outline;
in float a_mask;
out vec3 v_position;
out vec3 v_normal;
out float v_scalar;
out vec2 v_uv;
out vec3 v_bary;
flat out int v_mask;
void main() {{
    vec3 position = POSITION;
    v_normal = NORMAL;
    v_scalar = a_scalar;
    v_uv = TEXCOORD_0;
    v_bary = vec3(0.0);
    v_mask = 0;
    {body}
    v_position = position;
    gl_Position = u_viewProjection * vec4(position, 1.0);
}}
"""
LAMBERT = "color = vec3(0.8) * (0.15 + 0.85 * max(dot(N, u_light), 0.0));"


def module_text(modules) -> str:
    return "\n".join((SHADER_ROOT / m).read_text() for m in modules)


@dataclass
class Panel:
    """A contact-sheet panel: a label, the runtime modules it includes, and a fragment body computing ``color``.

    The body sees ``vec3 N, V, P`` (unit normal, unit direction to the eye, world position), ``float scalar`` (the
    panel's per-vertex attribute, interpolated), ``vec3 u_light`` (unit direction to the light), ``vec3 u_eye``,
    ``vec3 u_ink``, ``float u_width`` (line width in pixels), the inputs listed in ``inputs`` (``v_uv``: the texture
    coordinates of ``texcoord(item)``, ``v_bary`` and ``flat int v_mask``) and the uniforms it declares in
    ``declarations``, set by ``uniforms(item)`` and ``textures(scene, ctx, item)``. Items the panel does not apply
    to (``applies``) are drawn with the Lambert reference. Multi-pass panels override ``draw``.
    """

    name: str
    label: str
    modules: tuple
    declarations: str
    body: str
    attribute: str | None = None  # the per-vertex attribute bound to ``a_scalar``
    light: str = "front"  # "front" (over the camera's shoulder) or "back" (behind the object)
    needs: tuple = ()  # attributes that must be present for the panel to show
    extension: str | None = None  # material extension that must be present (per item: ``applies``)
    inputs: str = ""  # extra fragment inputs
    vertex_modules: tuple = ()
    vertex_declarations: str = ""
    vertex_body: str = ""
    expand: bool = False  # non-indexed draw (gl_VertexID % 3 is the triangle corner)

    def available(self, scene) -> bool:
        items = scene.items if isinstance(scene, Scene) else scene
        return any(self.applies(i) for i in items)

    def applies(self, item: DrawItem) -> bool:
        return all(n in item.attributes for n in self.needs) and \
            (self.extension is None or item.extension(self.extension) is not None)

    def attribute_of(self, item: DrawItem) -> str | None:
        return self.attribute

    def texcoord(self, item: DrawItem) -> int:
        return 0

    def uniforms(self, item: DrawItem) -> dict:
        return {}

    def textures(self, scene: Scene, ctx, item: DrawItem) -> dict:
        return {}

    def vertex_shader(self) -> str:
        return VERTEX_TEMPLATE.format(modules=module_text(self.vertex_modules),
                                      declarations=self.vertex_declarations, body=self.vertex_body)

    def draw(self, ctx, scene: Scene, camera: Camera, size: int) -> None:
        draw_surfaces(ctx, self, scene, camera, size)


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

    def prepare(self, items) -> None:
        items = items.items if isinstance(items, Scene) else items
        values = np.concatenate([i.attributes[self.attribute].reshape(-1) for i in items if self.attribute in i.attributes])
        self.range = (float(values.min()), float(max(values.max(), values.min() + 1e-12)))

    def uniforms(self, item: DrawItem) -> dict:
        return {"u_range": self.range}


class SkinPanel(Panel):
    """Penner's pre-integrated skin: the LUT (BAKER_skin_lut.lutTexture) by N.L and the baked curvature."""

    def attribute_of(self, item):
        return (item.extension("BAKER_skin_lut") or {}).get("curvatureAttribute", "_CURVATURE")

    def uniforms(self, item):
        ext = item.extension("BAKER_skin_lut") or {}
        return {
            "u_skin.curvatureRange": tuple(float(v) for v in ext.get("curvatureRange", (0.01, 1.0))),
            "u_skin.curvatureScale": float(ext.get("curvatureScale", 1.0)),
            "u_skin.penumbraWidthRange": tuple(float(v) for v in ext.get("penumbraWidthRange", (0.01, 1.0))),
            "u_skin.normalBlend": tuple(float(v) for v in ext.get("normalBlend", (1.0, 1.0, 1.0))),
            "u_skin.wrap": float(ext.get("wrap", 0.5)),
            "u_skin.scatterWidth": float(ext.get("scatterWidth", 0.3)),
            "u_skin.scatterColor": tuple(float(v) for v in ext.get("scatterColor", (0.8, 0.25, 0.1))),
            "u_hasCurvature": int(self.attribute_of(item) in item.attributes),
        }

    def textures(self, scene, ctx, item):
        ext = item.extension("BAKER_skin_lut")
        return {"u_lut": scene.texture(ctx, ext["lutTexture"]["index"], srgb=ext.get("encoding") == "srgb")}


class ToonPanel(Panel):
    """The toon ramp (or X-Toon map) of BAKER_toon_ramp indexed by N.L (and the detail function)."""

    def uniforms(self, item):
        ext = item.extension("BAKER_toon_ramp") or {}
        return {"u_xtoon": {"none": 0, "depth": 1, "orientation": 2}.get(ext.get("xtoon", "none"), 0),
                "u_depthRange": tuple(float(v) for v in ext.get("depthRange", (1.0, 50.0))),
                "u_orientationPower": float(ext.get("orientationPower", 1.0))}

    def textures(self, scene, ctx, item):
        return {"u_ramp": scene.texture(ctx, item.extension("BAKER_toon_ramp")["rampTexture"]["index"])}


class HatchingPanel(Panel):
    """Praun's real-time hatching: the TAM's levels as the custom mip chains of two textures, six-tone blend."""

    def applies(self, item):
        ext = item.extension("BAKER_tonal_art_map")
        return ext is not None and ext.get("layout", "packed") == "packed" and \
            int(ext.get("texCoord", 0)) in item.texcoords

    def texcoord(self, item):
        return int(item.extension("BAKER_tonal_art_map").get("texCoord", 0))

    def uniforms(self, item):
        ext = item.extension("BAKER_tonal_art_map")
        tones = [float(t) for t in ext["tones"]]
        return {"u_tonesA": tuple(tones[:3]), "u_tonesB": tuple(tones[3:6]), "u_scale": float(ext["scale"]),
                "u_finestSize": float(ext["levels"][0]["size"]), "u_levelCount": float(len(ext["levels"]))}

    def textures(self, scene, ctx, item):
        levels = item.extension("BAKER_tonal_art_map")["levels"]
        return {f"u_tones{name}": scene.mip_chain(ctx, [lv["textures"][j]["index"] for lv in levels])
                for j, name in enumerate(("012", "345"))}


class WireframePanel(Panel):
    def applies(self, item):
        return item.mask is not None


class OutlinePanel(Panel):
    """Shell outline (back faces pushed out along _OUTLINE_NORMAL, front faces culled) and the BAKER_edges fins."""

    def applies(self, item):
        return "_OUTLINE_NORMAL" in item.attributes

    def available(self, scene) -> bool:
        return super().available(scene) or bool(isinstance(scene, Scene) and scene.fins)

    def draw(self, ctx, scene, camera, size):
        draw_surfaces(ctx, REFERENCE, scene, camera, size)
        shell = Panel("shell", "", (), "", "color = u_ink;", vertex_modules=("baker_edges.glsl",),
                      vertex_body="float w = (u_viewProjection * vec4(POSITION, 1.0)).w;\n"
                                  "    position = baker_shell_position(POSITION, a_outline, w, u_width, "
                                  "u_viewportHeight, u_projectionScaleY);")
        items = [i for i in scene.items if self.applies(i)]
        if items:
            ctx.enable(ctx.CULL_FACE)
            ctx.front_face = "ccw"
            ctx.cull_face = "front"
            draw_surfaces(ctx, shell, Scene(items, doc=scene.doc, _textures=scene._textures), camera, size,
                          extra={"u_width": max(2.0, size / 96.0)}, fallback=False)
            ctx.disable(ctx.CULL_FACE)
        for fins in scene.fins:
            draw_fins(ctx, fins, camera, size)


FIN_VS = """#version 330 core
{module}
in vec3 _FIN_V0;
in vec3 _FIN_V1;
in vec3 _FIN_V2;
in vec3 _FIN_V3;
in float _FIN_CORNER;
in float _FIN_FLAGS;
uniform mat4 u_viewProjection;
uniform vec3 u_eye;
uniform float u_creaseCos;
uniform float u_width;
uniform vec2 u_viewport;
uniform int u_show;
void main() {{
    int kind = baker_fin_classify(_FIN_V0, _FIN_V1, _FIN_V2, _FIN_V3, _FIN_FLAGS, u_eye, u_creaseCos);
    vec4 c0 = u_viewProjection * vec4(_FIN_V0, 1.0);
    vec4 c1 = u_viewProjection * vec4(_FIN_V1, 1.0);
    gl_Position = (kind & u_show) != 0 ? baker_fin_position(c0, c1, _FIN_CORNER, u_width, u_viewport)
                                       : baker_fin_culled();
    gl_Position.z -= 2e-3 * gl_Position.w;  // in front of the surface the edge lies on
}}
"""
SOLID_FS = """#version 330 core
uniform vec3 u_ink;
out vec4 fragColor;
void main() {
    fragColor = vec4(u_ink, 1.0);
}
"""


def draw_fins(ctx, fins: EdgeFins, camera: Camera, size: int) -> None:
    """McGuire & Hughes fins: contour, ridge, valley and boundary edges extruded to u_width pixels."""
    program = ctx.program(vertex_shader=FIN_VS.format(module=module_text(("baker_edges.glsl",))),
                          fragment_shader=SOLID_FS)
    vp = (camera.projection @ camera.view).astype(np.float32)
    _set(program, {"u_viewProjection": vp.T.tobytes(), "u_eye": tuple(camera.eye), "u_creaseCos":
                   math.cos(fins.crease_angle), "u_width": max(1.0, size / 256.0), "u_viewport": (size, size),
                   "u_show": 1 | 2 | 4 | 8, "u_ink": INK})
    content, buffers = [], []
    for name, data in fins.attributes.items():
        if name in program:
            buf = ctx.buffer(np.ascontiguousarray(data, np.float32).tobytes())
            buffers.append(buf)
            content.append((buf, "3f" if data.ndim == 2 and data.shape[1] == 3 else "1f", name))
    ibo = ctx.buffer(fins.faces.astype(np.uint32).tobytes())
    vao = ctx.vertex_array(program, content, index_buffer=ibo, index_element_size=4)
    vao.render()
    for obj in [vao, ibo, program] + buffers:
        obj.release()


class FurPanel(Panel):
    """Lengyel's fur shells: the surface, then shellCount alpha-blended copies pushed out along the normal."""

    def draw(self, ctx, scene, camera, size):
        import moderngl

        items = [i for i in scene.items if self.applies(i)]
        others = Scene([i for i in scene.items if not self.applies(i)], doc=scene.doc, _textures=scene._textures)
        draw_surfaces(ctx, REFERENCE, others, camera, size)
        for item in items:
            ext = item.extension("BAKER_fur")
            shells = [t["index"] for t in ext["shellTextures"]]
            inner = scene.image(shells[0])
            base = (inner[..., :3] * inner[..., 3:]).sum((0, 1)) / max(float(inner[..., 3].sum()), 1e-6)
            one = Scene([item], doc=scene.doc, _textures=scene._textures)
            skin = Panel("fur-skin", "", (), "uniform vec3 u_base;",
                         "color = u_base * 0.4 * (0.3 + 0.7 * max(dot(N, u_light), 0.0));")
            draw_surfaces(ctx, skin, one, camera, size, extra={"u_base": tuple(float(c) for c in base)})
            ctx.enable(ctx.BLEND)
            ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
            ctx.depth_mask = False
            count = len(shells)
            for i, texture in enumerate(shells):
                shell = FurShellPanel(self, texture, i, count)
                draw_surfaces(ctx, shell, one, camera, size, extra={
                    "u_shell": float(i), "u_shellCount": float(count),
                    "u_shellSpacing": float(ext["shellSpacing"]), "u_tiling": float(ext.get("tiling", 1.0))})
            ctx.depth_mask = True
            ctx.disable(ctx.BLEND)


class FurShellPanel(Panel):
    def __init__(self, parent, texture, shell, count):
        super().__init__(
            "fur-shell", "", ("baker_fur.glsl",),
            "uniform sampler2D u_shellTexture; uniform float u_shell; uniform float u_shellCount; uniform float u_tiling;",
            "vec4 texel = texture(u_shellTexture, baker_fur_shell_uv(v_uv, u_tiling));\n"
            "    vec4 shaded = baker_fur_shell_shade(texel, baker_fur_shell_height(u_shell, u_shellCount), 0.4);\n"
            "    color = shaded.rgb * (0.3 + 0.7 * max(dot(N, u_light), 0.0));\n"
            "    alpha = shaded.a;",
            inputs="in vec2 v_uv;", vertex_modules=("baker_fur.glsl",),
            vertex_declarations="uniform float u_shell; uniform float u_shellCount; uniform float u_shellSpacing;",
            vertex_body="position = baker_fur_shell_position(POSITION, normalize(NORMAL), u_shell, u_shellSpacing, "
                        "u_shellCount, vec3(0.0));")
        self.texture_index = texture

    def textures(self, scene, ctx, item):
        return {"u_shellTexture": scene.texture(ctx, self.texture_index, repeat=True)}


TEXT_VS = """#version 330 core
uniform mat4 u_viewProjection;
in vec3 POSITION;
in vec2 TEXCOORD_0;
out vec2 v_uv;
void main() {
    v_uv = TEXCOORD_0;
    gl_Position = u_viewProjection * vec4(POSITION, 1.0);
}
"""
TEXT_FS = """#version 330 core
{module}
in vec2 v_uv;
uniform sampler2D u_atlas;
uniform vec2 u_atlasSize;
uniform float u_distanceRange;
uniform int u_fieldType;
uniform BakerTextStyle u_style;
out vec4 fragColor;
void main() {{
    vec4 texel = texture(u_atlas, v_uv);
    float screenPxRange = baker_text_screen_px_range(u_distanceRange, u_atlasSize, fwidth(v_uv));
    fragColor = baker_text_shade(u_style, texel, texel, u_fieldType, u_distanceRange, screenPxRange);
}}
"""


class TextPanel(Panel):
    """BAKER_text labels: their quads drawn with the MSDF shader (premultiplied "over"), over the Lambert scene."""

    def available(self, scene) -> bool:
        return isinstance(scene, Scene) and bool(scene.labels)

    def draw(self, ctx, scene, camera, size):
        import moderngl

        draw_surfaces(ctx, REFERENCE, scene, camera, size)
        program = ctx.program(vertex_shader=TEXT_VS, fragment_shader=TEXT_FS.format(module=module_text(("baker_text.glsl",))))
        vp = (camera.projection @ camera.view).astype(np.float32)
        ctx.enable(ctx.BLEND)
        ctx.blend_func = moderngl.ONE, moderngl.ONE_MINUS_SRC_ALPHA
        for label in scene.labels:
            font, text = label.font, label.text
            outline = text.get("outline") or {}
            kinds = {"sdf": 0, "psdf": 1, "msdf": 2, "mtsdf": 3}
            atlas = scene.texture(ctx, font["texture"])
            _set(program, {
                "u_viewProjection": vp.T.tobytes(), "u_atlasSize": (float(atlas.width), float(atlas.height)),
                "u_distanceRange": float(font["distanceRange"]), "u_fieldType": kinds.get(font["type"], 2),
                "u_style.color": tuple(float(c) for c in text.get("color", (1, 1, 1, 1))),
                "u_style.softness": 0.0,
                "u_style.outlineColor": tuple(float(c) for c in outline.get("color", (0, 0, 0, 1))),
                "u_style.outlineWidth": float(outline.get("width", 0.0)) * float(font["size"]),
                "u_style.glowColor": (0.0, 0.0, 0.0, 0.0), "u_style.glowWidth": 0.0,
                "u_style.shadowColor": (0.0, 0.0, 0.0, 0.0), "u_style.shadowSoftness": 0.0, "u_atlas": 0})
            atlas.use(location=0)
            vbo = ctx.buffer(np.ascontiguousarray(label.positions, np.float32).tobytes())
            tbo = ctx.buffer(np.ascontiguousarray(label.uv, np.float32).tobytes())
            ibo = ctx.buffer(label.faces.tobytes())
            vao = ctx.vertex_array(program, [(vbo, "3f", "POSITION"), (tbo, "2f", "TEXCOORD_0")],
                                   index_buffer=ibo, index_element_size=4)
            vao.render()
            for obj in (vao, vbo, tbo, ibo):
                obj.release()
        ctx.disable(ctx.BLEND)
        program.release()


HAIR_VS = """#version 330 core
{module}
uniform mat4 u_viewProjection;
uniform vec3 u_eye;
uniform float u_rootWidth;
uniform float u_tipWidth;
uniform float u_tanHalfFovY;
uniform float u_viewportHeight;
in vec3 POSITION;
in vec3 a_tangent;
in float a_param;
in float a_widthScale;
in float a_side;
out vec3 v_position;
out vec3 v_tangent;
out float v_alpha;
void main() {{
    float width = baker_hair_width(u_rootWidth, u_tipWidth, a_param, a_widthScale);
    vec2 coverage = baker_hair_coverage(width, baker_hair_pixel_size(length(u_eye - POSITION), u_tanHalfFovY,
                                                                       u_viewportHeight));
    v_position = baker_hair_ribbon_position(POSITION, a_tangent, u_eye, coverage.x, a_side);
    v_tangent = a_tangent;
    v_alpha = coverage.y;
    gl_Position = u_viewProjection * vec4(v_position, 1.0);
}}
"""
HAIR_FS = """#version 330 core
{module}
uniform vec3 u_eye;
uniform vec3 u_light;
uniform vec3 u_baseColor;
in vec3 v_position;
in vec3 v_tangent;
in float v_alpha;
out vec4 fragColor;
void main() {{
    vec3 T = normalize(v_tangent);
    vec3 V = normalize(u_eye - v_position);
    vec3 c = 0.15 * u_baseColor + baker_hair_kajiya_kay(T, u_light, V, u_baseColor, vec3(0.35), 40.0);
    fragColor = vec4(clamp(c, 0.0, 1.0), v_alpha);
}}
"""


class HairPanel(Panel):
    """BAKER_hair strands as view-facing ribbons (ribbonIndices), pixel-coverage opacity, Kajiya-Kay shading."""

    def available(self, scene) -> bool:
        return isinstance(scene, Scene) and bool(scene.strands)

    def draw(self, ctx, scene, camera, size):
        import moderngl

        draw_surfaces(ctx, REFERENCE, scene, camera, size)
        module = module_text(("baker_hair.glsl",))
        program = ctx.program(vertex_shader=HAIR_VS.format(module=module), fragment_shader=HAIR_FS.format(module=module))
        vp = (camera.projection @ camera.view).astype(np.float32)
        ctx.enable(ctx.BLEND)
        ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        for s in scene.strands:
            color = (s.material.get("pbrMetallicRoughness") or {}).get("baseColorFactor", (0.3, 0.2, 0.1, 1))[:3]
            _set(program, {"u_viewProjection": vp.T.tobytes(), "u_eye": tuple(camera.eye),
                           "u_light": tuple(light_direction(camera, self.light)),
                           "u_rootWidth": float(s.hair["rootWidth"]), "u_tipWidth": float(s.hair["tipWidth"]),
                           "u_tanHalfFovY": math.tan(math.radians(camera.fov) / 2), "u_viewportHeight": float(size),
                           "u_baseColor": tuple(float(c) for c in color)})
            n = len(s.positions)
            data = [(np.repeat(s.positions, 2, axis=0), "3f", "POSITION"),
                    (np.repeat(s.tangents, 2, axis=0), "3f", "a_tangent"),
                    (np.repeat(s.params, 2), "1f", "a_param"), (np.repeat(s.width_scale, 2), "1f", "a_widthScale"),
                    (np.tile(np.array([0.0, 1.0], np.float32), n), "1f", "a_side")]
            buffers = [ctx.buffer(np.ascontiguousarray(d, np.float32).tobytes()) for d, _, _ in data]
            ibo = ctx.buffer(s.ribbon.tobytes())
            vao = ctx.vertex_array(program, [(b, f, name) for b, (_, f, name) in zip(buffers, data)],
                                   index_buffer=ibo, index_element_size=4)
            vao.render()
            for obj in [vao, ibo] + buffers:
                obj.release()
        ctx.disable(ctx.BLEND)
        program.release()


REFERENCE = Panel("lambert", "shaded (reference)", (), "", LAMBERT)

# the registry: one entry per technique, in contact-sheet order; a panel shows when its data is present
PANELS = [
    REFERENCE,
    ScalarMapPanel("thickness", "thickness (_THICKNESS)", (), "uniform vec2 u_range;",
                   "float t = clamp((scalar - u_range.x) / (u_range.y - u_range.x), 0.0, 1.0);\n"
                   "    color = mix(vec3(0.95, 0.35, 0.1), vec3(0.1, 0.3, 0.9), t);",
                   attribute="_THICKNESS", needs=("_THICKNESS",)),
    TranslucencyPanel("translucency", "translucency, lit from behind", ("baker_translucency.glsl",),
                      "uniform BakerThickness u_thickness;",
                      "color = 0.05 * vec3(0.8) * max(dot(N, u_light), 0.0)\n"
                      "          + baker_translucency(u_thickness, N, V, u_light, scalar);",
                      attribute="_THICKNESS", light="back", needs=("_THICKNESS",)),
    SkinPanel("skin", "pre-integrated skin (LUT x curvature)", ("baker_skin.glsl",),
              "uniform BakerSkin u_skin;\nuniform sampler2D u_lut;\nuniform int u_hasCurvature;",
              "float k = u_hasCurvature != 0 ? scalar : baker_skin_curvature_from_derivatives(fwidth(N), fwidth(P));\n"
              "    color = vec3(0.8) * (0.15 + 0.85 * baker_skin_diffuse(u_skin, u_lut, N, N, u_light, k));",
              attribute="_CURVATURE", extension="BAKER_skin_lut"),
    ToonPanel("toon", "toon ramp", ("baker_toon.glsl",),
              "uniform sampler2D u_ramp;\nuniform int u_xtoon;\nuniform vec2 u_depthRange;\n"
              "uniform float u_orientationPower;",
              "float NdotL = dot(N, u_light);\n"
              "    float shade = u_xtoon == 0 ? baker_toon_ramp(u_ramp, NdotL)\n"
              "        : baker_xtoon(u_ramp, NdotL, u_xtoon == 1\n"
              "            ? baker_xtoon_detail_depth(length(u_eye - P), u_depthRange.x, u_depthRange.y)\n"
              "            : baker_xtoon_detail_orientation(N, V, u_orientationPower));\n"
              "    color = vec3(shade);",
              extension="BAKER_toon_ramp"),
    HatchingPanel("hatching", "hatching (tonal art map)", ("baker_hatching.glsl",),
                  "uniform sampler2D u_tones012;\nuniform sampler2D u_tones345;\nuniform vec3 u_tonesA;\n"
                  "uniform vec3 u_tonesB;\nuniform float u_scale;\nuniform float u_finestSize;\n"
                  "uniform float u_levelCount;",
                  "vec2 tile = baker_tam_coord(v_uv, u_scale, u_finestSize);\n"
                  "    float lod = baker_tam_lod(dFdx(tile), dFdy(tile), u_finestSize, u_levelCount);\n"
                  "    float darkness = baker_hatching_darkness(N, u_light, 1.0);\n"
                  "    color = vec3(baker_hatching(u_tones012, u_tones345, tile, lod, darkness, u_tonesA, u_tonesB));",
                  extension="BAKER_tonal_art_map", inputs="in vec2 v_uv;"),
    OutlinePanel("outline", "shell outline + fins", (), "", LAMBERT),
    WireframePanel("wireframe", "wireframe (mask)", ("baker_edges.glsl",), "",
                   "vec3 fill = vec3(0.8) * (0.15 + 0.85 * max(dot(N, u_light), 0.0));\n"
                   "    vec2 wire = baker_wireframe(v_bary, fwidth(v_bary), v_mask, u_width, 0.0);\n"
                   "    color = mix(fill, u_ink, wire.x);",
                   inputs="in vec3 v_bary;\nflat in int v_mask;", vertex_modules=("baker_edges.glsl",),
                   vertex_body="v_bary = baker_barycentric(gl_VertexID);\n    v_mask = int(a_mask + 0.5);",
                   expand=True),
    FurPanel("fur", "fur shells", (), "", LAMBERT, extension="BAKER_fur"),
    TextPanel("text", "text (MSDF)", (), "", LAMBERT),
    HairPanel("hair", "hair ribbons (Kajiya-Kay)", (), "", LAMBERT),
]


def fragment_shader(panel: Panel) -> str:
    return f"""#version 330 core
{module_text(panel.modules)}
uniform vec3 u_eye;
uniform vec3 u_light;
{"uniform vec3 u_ink;" + chr(10) + "uniform float u_width;" if "u_ink" in panel.body or "u_width" in panel.body else ""}
{panel.declarations}
in vec3 v_position;
in vec3 v_normal;
in float v_scalar;
{panel.inputs}
out vec4 fragColor;
void main() {{
    vec3 N = normalize(v_normal);
    vec3 V = normalize(u_eye - v_position);
    if (dot(N, V) < 0.0) N = -N;  // double-sided preview
    vec3 P = v_position;
    float scalar = v_scalar;
    vec3 color;
    float alpha = 1.0;
    {panel.body}
    fragColor = vec4(clamp(color, 0.0, 1.0), alpha);
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


def _set(program, uniforms: dict) -> None:
    for name, value in uniforms.items():
        if name in program:
            if isinstance(value, bytes):
                program[name].write(value)
            else:
                program[name].value = value


def draw_surfaces(ctx, panel: Panel, scene, camera: Camera, size: int, extra: dict | None = None,
                  fallback: bool = True) -> None:
    """One pass over the scene's triangle items with the panel's shaders (the Lambert reference for items the panel
    does not apply to, unless ``fallback`` is False), into the bound framebuffer."""
    scene = scene if isinstance(scene, Scene) else Scene(list(scene))
    if hasattr(panel, "prepare"):
        panel.prepare(scene)
    programs = {}
    vp = (camera.projection @ camera.view).astype(np.float32)
    common = {"u_viewProjection": vp.T.tobytes(), "u_eye": tuple(float(v) for v in camera.eye),
              "u_light": tuple(float(v) for v in light_direction(camera, panel.light)),
              "u_viewportHeight": float(size), "u_projectionScaleY": float(camera.projection[1, 1]),
              "u_ink": INK, "u_width": max(1.0, size / 256.0), **(extra or {})}
    for item in scene.items:
        use = panel if panel.applies(item) else (REFERENCE if fallback else None)
        if use is None:
            continue
        if use.name not in programs:
            programs[use.name] = ctx.program(vertex_shader=use.vertex_shader(), fragment_shader=fragment_shader(use))
        program = programs[use.name]
        _set(program, dict(common, **use.uniforms(item)))
        for unit, (name, texture) in enumerate(use.textures(scene, ctx, item).items()):
            texture.use(location=unit)
            _set(program, {name: unit})
        n = len(item.positions)
        attribute = use.attribute_of(item)
        scalar = item.attributes.get(attribute) if attribute else None
        scalar = np.zeros(n, np.float32) if scalar is None else scalar.reshape(n, -1)[:, 0]
        uv = item.texcoords.get(use.texcoord(item), np.zeros((n, 2), np.float32))
        outline = item.attributes.get("_OUTLINE_NORMAL", item.normals)
        arrays = {"POSITION": item.positions, "NORMAL": item.normals, "a_scalar": scalar, "TEXCOORD_0": uv,
                  "a_outline": outline}
        corners = item.faces.reshape(-1)
        if use.expand:
            arrays = {k: v[corners] for k, v in arrays.items()}
            mask = item.mask if item.mask is not None else np.full(len(item.faces), 7.0, np.float32)
            arrays["a_mask"] = np.repeat(mask.astype(np.float32), 3)
        content, buffers = [], []
        for name, data in arrays.items():
            if name in program:
                data = np.ascontiguousarray(data, np.float32)
                buf = ctx.buffer(data.tobytes())
                buffers.append(buf)
                content.append((buf, f"{1 if data.ndim == 1 else data.shape[1]}f", name))
        if use.expand:
            vao = ctx.vertex_array(program, content)
            ibo = None
        else:
            ibo = ctx.buffer(corners.astype(np.uint32).tobytes())
            vao = ctx.vertex_array(program, content, index_buffer=ibo, index_element_size=4)
        vao.render()
        for obj in [vao] + buffers + ([ibo] if ibo is not None else []):
            obj.release()
    for program in programs.values():
        program.release()


def render_panel(ctx, panel: Panel, items, camera: Camera, size: int, samples: int = 4) -> np.ndarray:
    """Render one panel; returns (size, size, 3) float32 in [0, 1], row 0 at the top. ``items``: a Scene or a list
    of DrawItems."""
    scene = items if isinstance(items, Scene) else Scene(list(items))
    fbo = ctx.simple_framebuffer((size, size), components=4, samples=samples)
    fbo.use()
    ctx.enable(ctx.DEPTH_TEST)
    ctx.disable(ctx.CULL_FACE | ctx.BLEND)
    ctx.depth_mask = True
    fbo.clear(*BACKGROUND, 1.0)
    panel.draw(ctx, scene, camera, size)
    resolved = ctx.simple_framebuffer((size, size), components=4)
    ctx.copy_framebuffer(resolved, fbo)
    pixels = np.frombuffer(resolved.read(components=3, dtype="f1"), np.uint8).reshape(size, size, 3)
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
    scene = gather_scene(asset)
    if panels is not None:
        unknown = sorted(set(panels) - {p.name for p in PANELS})
        if unknown:
            raise BakerError(None, f"unknown preview panel(s) {', '.join(unknown)} "
                                   f"(known: {', '.join(p.name for p in PANELS)})")
    chosen = [p for p in PANELS if p.available(scene) and (panels is None or p.name in panels)]
    if not chosen:
        raise BakerError(asset.source, "no preview panel has its data in this asset")
    camera = frame_camera(scene, azimuth, elevation)
    ctx = create_context()
    try:
        images = [(p, render_panel(ctx, p, scene, camera, size)) for p in chosen]
    finally:
        scene.release()
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
    _draw_labels(sheet, [(label, y - label_h, x, label_h) for _, label, (y, x, _) in placed], size)
    return Preview(sheet, placed)


def _draw_labels(sheet: np.ndarray, labels, width: int) -> None:
    """Write panel labels with DejaVu Sans through Pillow (silently unlabelled when neither is available), each
    shrunk until it fits its panel's ``width``."""
    try:
        from PIL import Image, ImageDraw, ImageFont
    except ImportError:
        return
    image = Image.fromarray(sheet)
    draw = ImageDraw.Draw(image)
    for text, y, x, h in labels:
        size = int(h * 0.7)
        try:
            font = ImageFont.truetype("DejaVuSans.ttf", size)
            while size > 6 and draw.textlength(text, font=font) > width - 12:
                size -= 1
                font = ImageFont.truetype("DejaVuSans.ttf", size)
        except OSError:
            font = ImageFont.load_default()
        draw.text((x + 6, y + (h - size) * 0.5), text, fill=(230, 230, 230), font=font)
    sheet[...] = np.asarray(image)


def main(args) -> int:
    from baker.gltf.atomic import atomic_path
    from baker.gltf.images import write_image

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


