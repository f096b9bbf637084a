"""``baker preview``: render a baked asset headlessly with the reference runtime shaders, as a labelled contact sheet.

This module is the core: the scene (every triangle surface of the default scene in world space, plus what panels
gather for themselves), the camera, the :class:`Panel` base class, the shader assembly from the host wrappers in
``runtime-shaders/hosts/`` and the render of the sheet. The panels themselves live with their techniques
(``baker/techniques/<name>/panel.py``, named by ``Technique.panels``) and are found through the registry; each draws
its technique's data with the runtime module an engine would use (``runtime-shaders/baker_*.glsl``, pasted after a
``#version 330 core`` header), bound to the data the technique's ``extension.read`` returns. The sheet starts with a
plain Lambert reference, then the panels by their ``order``. Rendering uses moderngl on an EGL context (Mesa
llvmpipe works), so it runs on CI machines without a display.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from baker import readers
from baker.data import SHADER_ROOT
from baker.errors import BakerError
from baker.geometry.asset import Asset
from baker.geometry.normals import vertex_normals
from baker.gltf.accessors import to_float
from baker.gltf.document import world_nodes
from baker.texels.color import srgb_to_linear

BACKGROUND = (0.16, 0.17, 0.19)
INK = (0.03, 0.03, 0.035)
HOST_ROOT = SHADER_ROOT / "hosts"
HEADER = "#version 330 core\n"


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
    mask: np.ndarray | None = None  # one wireframe edge mask per triangle (expanded draws), set by a panel
    mesh: int | None = None
    primitive_index: int | None = None
    material_index: int | None = None
    # what panels read for this item (``Panel.read_item``), by key; every panel reads every item before any panel
    # draws, so a panel may use what another stored (skin uses "normal_blur")
    data: dict = field(default_factory=dict)
    tangents: np.ndarray | None = None  # (n, 4) float32, world space xyz + handedness w (the TANGENT attribute)
    # the length scale of the node's world matrix (cube root of |det|): lengths in mesh units (fur) times it are world
    # lengths (under KHR_mesh_quantization the node carries the dequantization)
    world_scale: float = 1.0


@dataclass
class Scene:
    """What the panels draw: triangle surfaces, what panels gathered (``parts``: text labels, hair, edge fins, ...,
    by the gathering panel's key) and the document for textures."""

    items: list
    parts: dict = field(default_factory=dict)  # key -> list of objects; those with ``positions`` frame the camera
    doc: object = None
    cache: dict = field(default_factory=dict)  # decoded images and GL textures

    def part(self, key: str) -> list:
        return self.parts.get(key, [])

    def add(self, key: str, value) -> None:
        self.parts.setdefault(key, []).append(value)

    def drawables(self) -> list:
        """Everything with world ``positions``: the items, then the gathered parts that have positions."""
        return list(self.items) + [p for part in self.parts.values() for p in part if hasattr(p, "positions")]

    def points(self) -> np.ndarray:
        return np.concatenate([d.positions for d in self.drawables()]).astype(np.float64)

    def subset(self, items) -> "Scene":
        """The same document and texture cache with only ``items`` (a panel drawing some surfaces differently)."""
        return Scene(list(items), doc=self.doc, cache=self.cache)

    def image(self, texture_index: int) -> np.ndarray:
        """A glTF texture's image as (H, W, C) float32 in [0, 1] (row 0 = the image's top = glTF v 0)."""
        from baker.gltf.images import decode_image

        key = ("image", texture_index)
        if key not in self.cache:
            source = self.doc.json["textures"][texture_index]["source"]
            mime = self.doc.json["images"][source].get("mimeType", "image/png")
            suffix = {"image/jpeg": ".jpg", "image/png": ".png"}.get(mime, ".png")
            pixels = decode_image(self.doc.image_bytes(source), suffix)
            pixels = pixels[..., None] if pixels.ndim == 2 else pixels
            scale = float(np.iinfo(pixels.dtype).max) if pixels.dtype.kind in "ui" else 1.0
            self.cache[key] = np.ascontiguousarray(pixels.astype(np.float32) / np.float32(scale))
        return self.cache[key]

    def texture(self, ctx, texture_index: int, repeat: bool = False, srgb: bool = False):
        """A moderngl texture of a glTF texture (float32, LINEAR; no mipmaps), cached per context."""
        import moderngl

        key = ("gl", id(ctx), texture_index, repeat, srgb)
        if key not in self.cache:
            pixels = self.image(texture_index)
            if srgb:  # colour only: alpha (the 4th channel, or the 2nd of grey + alpha) is linear coverage
                colour = pixels.shape[2] - (pixels.shape[2] in (2, 4))
                pixels = np.concatenate([srgb_to_linear(pixels[..., :colour]), pixels[..., colour:]],
                                        axis=2).astype(np.float32)
            h, w, c = pixels.shape
            tex = ctx.texture((w, h), c, pixels.tobytes(), dtype="f4")
            tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
            tex.repeat_x = tex.repeat_y = repeat
            self.cache[key] = tex
        return self.cache[key]

    def mip_chain(self, ctx, texture_indices: list):
        """One texture whose mip level i is the image of texture_indices[i] (a TAM's custom mip chain)."""
        key = ("chain", id(ctx), tuple(texture_indices))
        if key not in self.cache:
            levels = [self.image(t) for t in texture_indices]
            self.cache[key] = mip_chain_texture(ctx, levels, "f4", repeat=True)
        return self.cache[key]

    def coverage_mips(self, ctx, entry: dict, repeat: bool = True, srgb: bool = False):
        """A texture whose levels are a coverage-preserving mip chain (``coverageMips`` entry,
        :mod:`baker.texels.alpha_mips`), uploaded as given, sampled trilinear; None when the chain cannot be read.
        ``srgb``: colour decoded to linear like :meth:`texture` (float levels; alpha as stored)."""
        from baker.texels.alpha_mips import read_coverage_mips

        key = ("coverage", id(ctx), entry.get("accessor"), repeat, srgb)
        if key not in self.cache:
            try:
                levels = read_coverage_mips(self.doc, entry)
            except Exception:  # `baker validate` says why; the preview draws the PNG instead
                return None
            if srgb:
                levels = [np.concatenate([srgb_to_linear(lv[..., :3].astype(np.float32) / np.float32(255.0)),
                                          lv[..., 3:].astype(np.float32) / np.float32(255.0)], axis=2)
                          for lv in levels]
            self.cache[key] = mip_chain_texture(ctx, levels, "f4" if srgb else "f1", repeat=repeat)
        return self.cache[key]

    def release(self) -> None:
        for key, value in list(self.cache.items()):
            if key[0] != "image":
                value.release()
                del self.cache[key]


def placements(asset: Asset) -> list:
    """(mesh index, world matrix, node index or None) of every mesh drawn by the default scene."""
    gltf = asset.doc.json
    nodes = gltf.get("nodes", [])
    found = [(nodes[i]["mesh"], world, i) for i, world in world_nodes(gltf) if "mesh" in nodes[i]]
    if not found and not gltf.get("scenes"):
        return [(m, np.eye(4), None) for m in range(len(asset.meshes()))]
    return sorted(found, key=lambda p: p[0])


def transform_points(points, world) -> np.ndarray:
    return (points @ world[:3, :3].T + world[:3, 3]).astype(np.float32)


def transform_normals(normals, world) -> np.ndarray:
    n = normals @ np.linalg.inv(world[:3, :3])  # inverse transpose, row-vector form
    return (n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-20)).astype(np.float32)


def transform_directions(directions, world) -> np.ndarray:
    """Tangent directions (n, 3) to world space with their lengths kept (a zero direction stays zero)."""
    d = np.asarray(directions, np.float64)[:, :3]
    moved = d @ world[:3, :3].T
    scale = np.linalg.norm(d, axis=1, keepdims=True) / np.maximum(np.linalg.norm(moved, axis=1, keepdims=True), 1e-20)
    return (moved * scale).astype(np.float32)


def world_tangents(tangents, world, count: int) -> np.ndarray | None:
    """glTF TANGENT (xyz, w handedness) in world space; None when it does not match the vertices."""
    tangents = np.asarray(tangents, np.float64)
    if tangents.shape != (count, 4):
        return None
    xyz = tangents[:, :3] @ world[:3, :3].T
    xyz /= np.maximum(np.linalg.norm(xyz, axis=1, keepdims=True), 1e-20)
    # a mirroring world matrix flips the frame's handedness
    w = tangents[:, 3] * np.sign(np.linalg.det(world[:3, :3]) or 1.0)
    return np.concatenate([xyz, w[:, None]], axis=1).astype(np.float32)


@dataclass
class SurfaceMaterial:
    """What every panel shades with from a glTF material: the base colour (factor, linear; texture, sRGB) and the
    tangent-space normal map. Without a base colour the preview's neutral grey stands in (glTF's default white
    would clip the lit side)."""

    base_color: tuple = (0.8, 0.8, 0.8, 1.0)
    base_texture: int | None = None
    base_texcoord: int = 0
    normal_texture: int | None = None
    normal_texcoord: int = 0
    normal_scale: float = 1.0


def texture_reference(ref, texture_count: int) -> tuple[int | None, int]:
    """(texture index, texcoord set) of a glTF textureInfo; index None when it names no texture of the file."""
    if not isinstance(ref, dict):
        return None, 0
    index, texcoord = ref.get("index"), ref.get("texCoord", 0)
    valid = isinstance(index, int) and not isinstance(index, bool) and 0 <= index < texture_count
    return (index if valid else None), (texcoord if isinstance(texcoord, int) else 0)


def surface_material(material: dict, texture_count: int) -> SurfaceMaterial:
    pbr = material.get("pbrMetallicRoughness") if isinstance(material, dict) else None
    pbr = pbr if isinstance(pbr, dict) else {}
    factor = pbr.get("baseColorFactor")
    base_texture, base_texcoord = texture_reference(pbr.get("baseColorTexture"), texture_count)
    normal = material.get("normalTexture") if isinstance(material, dict) else None
    normal_texture, normal_texcoord = texture_reference(normal, texture_count)
    scale = normal.get("scale", 1.0) if isinstance(normal, dict) else 1.0
    if isinstance(factor, list) and len(factor) == 4 and all(isinstance(c, (int, float)) for c in factor):
        base_color = tuple(float(c) for c in factor)
    elif base_texture is not None:
        base_color = (1.0, 1.0, 1.0, 1.0)  # glTF's default factor, multiplying the texture
    else:
        base_color = SurfaceMaterial.base_color
    return SurfaceMaterial(base_color, base_texture, base_texcoord, normal_texture, normal_texcoord,
                           float(scale) if isinstance(scale, (int, float)) else 1.0)


def material_inputs(scene: "Scene", ctx, item: DrawItem) -> tuple[dict, dict, dict]:
    """(uniforms, textures, per-vertex arrays) of the item's base colour and normal map for the surface shaders."""
    textures_in_file = len(scene.doc.json.get("textures", [])) if scene.doc is not None else 0
    m = surface_material(item.material, textures_in_file)
    n = len(item.positions)
    base = m.base_texture is not None and m.base_texcoord in item.texcoords
    normal = m.normal_texture is not None and m.normal_texcoord in item.texcoords
    uniforms = {"u_baseColorFactor": m.base_color, "u_hasBaseColorTexture": int(base),
                "u_hasNormalTexture": int(normal), "u_normalScale": m.normal_scale,
                "u_hasTangent": int(item.tangents is not None)}
    textures = {}
    if base:
        textures["u_baseColorTexture"] = scene.texture(ctx, m.base_texture, repeat=True, srgb=True)
    if normal:
        textures["u_normalTexture"] = scene.texture(ctx, m.normal_texture, repeat=True)
    zeros = np.zeros((n, 2), np.float32)
    arrays = {"a_baseUV": item.texcoords[m.base_texcoord] if base else zeros,
              "a_normalUV": item.texcoords[m.normal_texcoord] if normal else zeros,
              "a_tangent": item.tangents if item.tangents is not None else np.zeros((n, 4), np.float32)}
    return uniforms, textures, arrays


MODE_LINES, MODE_LINE_LOOP, MODE_LINE_STRIP = 1, 2, 3


@dataclass
class Lines:
    """A plain line primitive (no BAKER_hair: the hair panel draws those) in world space: a groom's strands."""

    positions: np.ndarray  # (n, 3) float32
    tangents: np.ndarray  # (n, 3) float32, unit, along the strand
    segments: np.ndarray  # (m, 2) uint32
    color: tuple  # linear RGB base colour


def line_segments(asset: Asset, mesh: int, primitive: int) -> np.ndarray | None:
    """The (m, 2) vertex pairs of a LINES / LINE_STRIP / LINE_LOOP primitive; None for other modes."""
    prim = asset.meshes()[mesh]["primitives"][primitive]
    mode = prim.get("mode", 4)
    if mode not in (MODE_LINES, MODE_LINE_LOOP, MODE_LINE_STRIP) or "POSITION" not in prim.get("attributes", {}):
        return None
    count = asset.doc.json["accessors"][prim["attributes"]["POSITION"]]["count"]
    order = asset.doc.accessor(prim["indices"]).reshape(-1).astype(np.int64) if "indices" in prim \
        else np.arange(count, dtype=np.int64)
    if len(order) and (order.min() < 0 or order.max() >= count):
        raise BakerError(asset.source, f"/meshes/{mesh}/primitives/{primitive}/indices: index out of range "
                                       f"(POSITION has {count} vertices)")
    if mode == MODE_LINES:
        segments = order[: len(order) // 2 * 2].reshape(-1, 2)
    else:
        chain = np.concatenate([order, order[:1]]) if mode == MODE_LINE_LOOP and len(order) > 2 else order
        segments = np.stack([chain[:-1], chain[1:]], axis=1) if len(chain) > 1 else np.zeros((0, 2), np.int64)
    return segments


def world_lines(asset: Asset, mesh: int, primitive: int, world: np.ndarray) -> Lines | None:
    """A line primitive in world space with per-vertex tangents (the mean direction of its segments)."""
    segments = line_segments(asset, mesh, primitive)
    if segments is None or not len(segments):
        return None
    prim = asset.meshes()[mesh]["primitives"][primitive]
    positions = transform_points(to_float(asset.doc, prim["attributes"]["POSITION"]), world)
    direction = (positions[segments[:, 1]] - positions[segments[:, 0]]).astype(np.float64)
    tangents = np.zeros((len(positions), 3))
    np.add.at(tangents, segments[:, 0], direction)
    np.add.at(tangents, segments[:, 1], direction)
    tangents /= np.maximum(np.linalg.norm(tangents, axis=1, keepdims=True), 1e-20)
    materials = asset.doc.json.get("materials", [])
    index = prim.get("material")
    material = materials[index] if isinstance(index, int) and 0 <= index < len(materials) else {}
    color = surface_material(material, 0).base_color[:3]
    return Lines(positions, tangents.astype(np.float32), segments.astype(np.uint32), color)


def gather_scene(asset: Asset, panels: list | None = None) -> Scene:
    """Everything the default scene draws: the triangle primitives as DrawItems, and what each panel gathers.

    Per placed mesh, a panel that ``owns`` it (text labels) gathers it alone; otherwise every panel ``gather``s
    from it, and its triangle primitives that no panel ``skips`` become items, each ``read_item`` by every panel.
    ``panels`` are every panel (:func:`panels`), whichever are drawn, so the framing never depends on the choice.
    """
    panels = all_panels() if panels is None else panels
    doc = asset.doc
    materials = doc.json.get("materials", [])
    scene = Scene(items=[], doc=doc)
    for mesh, world, node in placements(asset):
        owner = next((p for p in panels if p.owns(scene, asset, mesh, node)), None)
        if owner is not None:
            owner.gather(scene, asset, mesh, world, node)
            continue
        for panel in panels:
            panel.gather(scene, asset, mesh, world, node)
        prims = asset.meshes()[mesh].get("primitives", [])
        for p, prim in enumerate(prims):
            if "BAKER_hair" not in (prim.get("extensions") or {}):
                lines = world_lines(asset, mesh, p, world)
                if lines is not None:
                    scene.add("lines", lines)
        for p in asset.triangle_primitives(mesh):
            if any(panel.skips(asset, mesh, p) for panel in panels):
                continue  # no surface (e.g. degenerate fin quads)
            prim = prims[p]
            g = asset.primitive(mesh, p)
            if not len(g.faces):
                continue
            normals = g.normals if g.normals is not None else vertex_normals(g.positions, g.faces)
            # as numbers: KHR_mesh_quantization's normalized integers (gltf-transform quantize, meshopt) read c / max
            attributes = {k: to_float(doc, a).astype(np.float32) for k, a in prim["attributes"].items()
                          if k.startswith("_")}
            if "_OUTLINE_NORMAL" in attributes:
                attributes["_OUTLINE_NORMAL"] = transform_normals(attributes["_OUTLINE_NORMAL"], world)
            if "_PRINCIPAL_DIRECTION" in attributes:
                attributes["_PRINCIPAL_DIRECTION"] = transform_directions(attributes["_PRINCIPAL_DIRECTION"], world)
            texcoords = {int(k.split("_")[1]): to_float(doc, a).astype(np.float32)
                         for k, a in prim["attributes"].items() if k.startswith("TEXCOORD_")}
            index = g.material if g.material is not None and g.material < len(materials) else None
            tangents = world_tangents(to_float(doc, prim["attributes"]["TANGENT"]), world, len(g.positions)) \
                if "TANGENT" in prim["attributes"] else None
            item = DrawItem(transform_points(g.positions, world), transform_normals(normals, world),
                            g.faces.astype(np.uint32), attributes, materials[index] if index is not None else {},
                            texcoords, prim, mesh=mesh, primitive_index=p, material_index=index, tangents=tangents,
                            world_scale=float(np.cbrt(abs(np.linalg.det(np.asarray(world, np.float64)[:3, :3])))))
            for panel in panels:
                panel.read_item(doc, item)
            scene.items.append(item)
    if not scene.drawables():
        raise BakerError(asset.source, "nothing to preview (no triangle or line primitives, text or hair in the scene)")
    return scene


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
LAMBERT = "color = albedo * (0.15 + 0.85 * max(dot(N, u_light), 0.0));"


def module_text(modules) -> str:
    return "\n".join((SHADER_ROOT / m).read_text() for m in modules)


def host_text(name: str, **parts: str) -> str:
    """A host wrapper of ``runtime-shaders/hosts/`` with its ``// @baker:<part>`` placeholders filled (and the
    comment lines before the first one, which describe the file, left out); missing parts are left empty."""
    lines = (HOST_ROOT / name).read_text().splitlines(keepends=True)
    start = next((i for i, line in enumerate(lines) if not line.startswith("//") or "// @baker:" in line), 0)
    text = "".join(lines[start:])
    while "// @baker:" in text:
        at = text.index("// @baker:") + len("// @baker:")
        end = at
        while end < len(text) and (text[end].isalnum() or text[end] in "_-"):
            end += 1
        key = text[at:end]
        text = text.replace(f"// @baker:{key}", parts.get(key, ""))
    return text


def program_source(name: str, **parts: str) -> str:
    """A host wrapper as a GLSL 3.30 core stage (the preview's includer header)."""
    return HEADER + host_text(name, **parts)


@dataclass
class Panel:
    """A contact-sheet panel: a label, the runtime modules it includes, and a fragment body computing ``color``.

    The body sees ``vec3 N, V, P`` (unit normal, unit direction to the eye, world position), ``float scalar`` (the
    panel's per-vertex attribute, interpolated), ``vec3 u_light`` (unit direction to the light), ``vec3 u_eye``,
    ``vec3 u_ink``, ``float u_width`` (line width in pixels), the inputs listed in ``inputs`` (``v_uv``: the texture
    coordinates of ``texcoord(item)``, ``v_bary`` and ``flat int v_mask``) and the uniforms it declares in
    ``declarations``, set by ``uniforms(item)`` and ``textures(scene, ctx, item)``. Items the panel does not apply
    to (``applies``) are drawn with the Lambert reference. Multi-pass panels override ``draw``.

    Scene hooks (all optional): ``read_item`` stores what the panel reads from the document for one surface in
    ``item.data``; ``gather`` adds what the panel draws besides surfaces to ``scene.parts``; ``owns`` claims a placed
    mesh for the panel alone; ``skips`` keeps a primitive out of the surfaces. ``order`` places the panel in the
    sheet (the Lambert reference first, then ascending ``order``).
    """

    name: str
    label: str
    modules: tuple
    declarations: str
    body: str
    attribute: str | None = None  # the per-vertex attribute bound to ``a_scalar``
    # "side": the key light of the sheet, grazing from the right so the terminator (where skin, normal-blur and toon
    # show) is in view and every panel compares with the reference under the same light; "front" (over the
    # camera's shoulder) or "back" (behind the object)
    light: str = "side"
    needs: tuple = ()  # attributes that must be present for the panel to show
    inputs: str = ""  # extra fragment inputs
    vertex_modules: tuple = ()
    vertex_declarations: str = ""
    vertex_body: str = ""
    expand: bool = False  # non-indexed draw (gl_VertexID % 3 is the triangle corner)
    order: float = 0.0  # position in the contact sheet

    def available(self, scene) -> bool:
        items = scene.items if isinstance(scene, Scene) else scene
        return any(self.applies(i) for i in items)

    def applies(self, item: DrawItem) -> bool:
        return all(n in item.attributes for n in self.needs)

    def describe(self, scene: Scene) -> str:
        """The panel's label on this scene (what it shows at which scale, or why it cannot show)."""
        return self.label

    def decorate(self, image: np.ndarray, scene: Scene) -> np.ndarray:
        """The rendered panel with what the panel draws over it (a legend); (size, size, 3) float32 in [0, 1]."""
        return image

    def attribute_of(self, item: DrawItem) -> str | None:
        return self.attribute

    def texcoord(self, item: DrawItem) -> int:
        return 0

    def uniforms(self, item: DrawItem) -> dict:
        return {}

    def textures(self, scene: Scene, ctx, item: DrawItem) -> dict:
        return {}

    def vertex_arrays(self, item: DrawItem) -> dict:
        """Per-vertex arrays bound to the vertex stage's inputs of the same names (``vertex_declarations``)."""
        return {}

    # scene hooks
    def read_item(self, doc, item: DrawItem) -> None:
        pass

    def gather(self, scene: Scene, asset: Asset, mesh: int, world: np.ndarray, node: int | None) -> None:
        pass

    def owns(self, scene: Scene, asset: Asset, mesh: int, node: int | None) -> bool:
        return False

    def skips(self, asset: Asset, mesh: int, primitive: int) -> bool:
        return False

    # shaders and drawing
    def vertex_shader(self) -> str:
        return program_source("preview_surface.vert.glsl", modules=module_text(self.vertex_modules),
                              declarations=self.vertex_declarations, body=self.vertex_body)

    def fragment_shader(self) -> str:
        line = "uniform vec3 u_ink;\nuniform float u_width;" if "u_ink" in self.body or "u_width" in self.body else ""
        return program_source("preview_surface.frag.glsl", modules=module_text(self.modules), line=line,
                              declarations=self.declarations, inputs=self.inputs, body=self.body)

    def draw(self, ctx, scene: Scene, camera: Camera, size: int) -> None:
        draw_surfaces(ctx, self, scene, camera, size)


class ReferencePanel(Panel):
    """The "before" picture: the surfaces with the material's base colour and normal map under a Lambert light,
    and plain line primitives (a groom) as shaded lines."""

    def available(self, scene) -> bool:
        return super().available(scene) or (isinstance(scene, Scene) and bool(scene.part("lines")))

    def uniforms(self, item):
        return alpha_mode_uniforms(item.material)

    def draw(self, ctx, scene, camera, size):
        draw_surfaces(ctx, self, scene, camera, size)
        draw_lines(ctx, scene, camera, size, light_direction(camera, self.light))


ALPHA_MODES = {"OPAQUE": 0, "MASK": 1, "BLEND": 2}


def alpha_mode_uniforms(material) -> dict:
    """The glTF material's alphaMode and alphaCutoff (defaults OPAQUE, 0.5) as the surface host's uniforms."""
    material = material if isinstance(material, dict) else {}
    cutoff = material.get("alphaCutoff", 0.5)
    return {"u_alphaMode": ALPHA_MODES.get(material.get("alphaMode"), 0),
            "u_alphaCutoff": float(cutoff) if isinstance(cutoff, (int, float)) else 0.5}


REFERENCE = ReferencePanel("lambert", "shaded (reference)", (), "", LAMBERT, order=-math.inf)


def all_panels() -> list:
    """The Lambert reference, then every technique's panels (``Technique.panels``, found by the registry) in sheet
    order (ascending ``order``; ties keep the technique order)."""
    from baker.registry import panels as technique_panels

    return [REFERENCE] + sorted(technique_panels(), key=lambda p: p.order)


def fragment_shader(panel: Panel) -> str:
    return panel.fragment_shader()


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
    """Unit direction to the light: over the camera's right shoulder, from the right at a grazing angle (the
    terminator runs through the middle of the view, so N.L takes every value from -1 to 1 on the visible side), or
    behind the object facing the camera."""
    f = camera.forward
    right = np.cross(f, [0.0, 1.0, 0.0])
    right = right / (np.linalg.norm(right) or 1.0)
    if where == "side":
        d = right + np.array([0.0, 0.3, 0.0]) - 0.15 * f
    elif where == "back":
        # from behind, 8 degrees off the view axis: the lobe (V . -L)^p stays near 1 over the view, so what varies is
        # the light let through
        d = f + 0.1 * right + np.array([0.0, 0.1, 0.0])
    else:
        d = -f + 0.5 * right + np.array([0.0, 0.5, 0.0])
    return d / np.linalg.norm(d)


def set_uniforms(program, uniforms: dict) -> None:
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
            programs[use.name] = ctx.program(vertex_shader=use.vertex_shader(), fragment_shader=use.fragment_shader())
        program = programs[use.name]
        material_uniforms, material_textures, material_arrays = material_inputs(scene, ctx, item)
        set_uniforms(program, dict(common, **material_uniforms, **use.uniforms(item)))
        textures = dict(material_textures, **use.textures(scene, ctx, item))
        for unit, (name, texture) in enumerate(textures.items()):
            texture.use(location=unit)
            set_uniforms(program, {name: unit})
        n = len(item.positions)
        attribute = use.attribute_of(item)
        scalar = item.attributes.get(attribute) if attribute else None
        scalar = np.zeros(n, np.float32) if scalar is None else scalar.reshape(n, -1)[:, 0]
        uv = item.texcoords.get(use.texcoord(item), np.zeros((n, 2), np.float32))
        outline = item.attributes.get("_OUTLINE_NORMAL", item.normals)
        arrays = {"POSITION": item.positions, "NORMAL": item.normals, "a_scalar": scalar, "TEXCOORD_0": uv,
                  "a_outline": outline, **material_arrays, **use.vertex_arrays(item)}
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
        blend = use.uniforms(item).get("u_alphaMode") == ALPHA_MODES["BLEND"]
        if blend:  # a glTF BLEND material: over what is drawn already (in file order, as a simple viewer does)
            ctx.enable(ctx.BLEND)
            ctx.blend_func = ctx.SRC_ALPHA, ctx.ONE_MINUS_SRC_ALPHA
        vao.render()
        if blend:
            ctx.disable(ctx.BLEND)
        for obj in [vao] + buffers + ([ibo] if ibo is not None else []):
            obj.release()
    for program in programs.values():
        program.release()


def draw_lines(ctx, scene: Scene, camera: Camera, size: int, light: np.ndarray) -> None:
    """The scene's plain line primitives, about size / 256 pixels wide (1 where the driver has no wide lines)."""
    lines = scene.part("lines")
    if not lines:
        return
    program = ctx.program(vertex_shader=program_source("preview_lines.vert.glsl"),
                          fragment_shader=program_source("preview_lines.frag.glsl"))
    vp = (camera.projection @ camera.view).astype(np.float32)
    try:
        ctx.line_width = max(1.0, size / 256.0)
    except Exception:  # core profiles may refuse wide lines: thin ones still show the strands
        pass
    for strand_set in lines:
        set_uniforms(program, {"u_viewProjection": vp.T.tobytes(), "u_light": tuple(float(v) for v in light),
                               "u_baseColor": tuple(float(c) for c in strand_set.color)})
        vbo = ctx.buffer(np.ascontiguousarray(strand_set.positions, np.float32).tobytes())
        tbo = ctx.buffer(np.ascontiguousarray(strand_set.tangents, np.float32).tobytes())
        ibo = ctx.buffer(np.ascontiguousarray(strand_set.segments, np.uint32).tobytes())
        vao = ctx.vertex_array(program, [(vbo, "3f", "POSITION"), (tbo, "3f", "a_tangent")],
                               index_buffer=ibo, index_element_size=4, mode=ctx.LINES)
        vao.render()
        for obj in (vao, vbo, tbo, ibo):
            obj.release()
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
    # a groom (lines only) has no triangle faces: the reference panel draws its strands
    asset = path_or_asset if isinstance(path_or_asset, Asset) else readers.read(path_or_asset, require_triangles=False)
    known = all_panels()
    scene = gather_scene(asset, known)
    if panels is not None:
        unknown = sorted(set(panels) - {p.name for p in known})
        if unknown:
            raise BakerError(None, f"unknown preview panel(s) {', '.join(unknown)} "
                                   f"(known: {', '.join(p.name for p in known)})")
    chosen = [p for p in known if p.available(scene) and (panels is None or p.name in panels)]
    if not chosen:
        raise BakerError(asset.source, "no preview panel has its data in this asset")
    camera = frame_camera(scene, azimuth, elevation)
    ctx = create_context()
    try:
        images = [(p, p.decorate(render_panel(ctx, p, scene, camera, size), scene)) for p in chosen]
        labels = [p.describe(scene) for p in chosen]
    finally:
        scene.release()
        ctx.release()
    label_h = max(18, size // 16)
    cols = min(len(images), 3)
    rows = math.ceil(len(images) / cols)
    sheet = np.full((rows * (size + label_h), cols * size, 3), 24, np.uint8)
    placed = []
    for k, ((panel, image), label) in enumerate(zip(images, labels)):
        r, c = divmod(k, cols)
        y, x = r * (size + label_h) + label_h, c * size
        sheet[y: y + size, x: x + size] = np.round(image * 255).astype(np.uint8)
        placed.append((panel.name, label, (y, x, size)))
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
        # drawn in the panel's own strip: a label too long even at the smallest size is cut, not written over the
        # next panel's
        strip = image.crop((x, y, x + width, y + h))
        ImageDraw.Draw(strip).text((6, (h - size) * 0.5), text, fill=(230, 230, 230), font=font)
        image.paste(strip, (x, y))
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


def mip_chain_texture(ctx, levels: list, dtype: str, repeat: bool):
    """A trilinear-sampled texture whose mip levels are ``levels`` (H, W, C arrays, level 0 first) as given, not
    regenerated from level 0."""
    import moderngl

    h, w, c = levels[0].shape
    tex = ctx.texture((w, h), c, np.ascontiguousarray(levels[0]).tobytes(), dtype=dtype)
    tex.build_mipmaps(0, len(levels) - 1)  # allocates the levels; their contents are replaced below
    for i, level in enumerate(levels):
        tex.write(np.ascontiguousarray(level).tobytes(), level=i)
    tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    tex.repeat_x = tex.repeat_y = repeat
    return tex
