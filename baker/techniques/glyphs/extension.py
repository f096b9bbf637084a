"""``BAKER_glyph_atlas`` (root) and ``BAKER_text`` (node): a baked atlas and text drawn with it -> glTF.

Where the data goes (see ``schemas/BAKER_glyph_atlas/README.md`` and ``schemas/BAKER_text/README.md``):
- the distance-field atlas: an image + texture (linear filtering, clamp to edge) referenced by the font entry;
- the glyph table (unicode, advance, planeBounds, atlasBounds) and kerning: FLOAT accessors (code points are exact
  in float32 up to 2^24), named by the font entry; metrics in em as JSON numbers;
- ``BAKER_text`` on a node: the string, font, size, alignment, colors and outline the runtime draws with;
- plain glTF for viewers that know neither: the node's mesh is one quad per glyph (POSITION, NORMAL, TEXCOORD_0)
  with an unlit, alpha-masked material whose base-color texture is the single-channel field in alpha (RGB white).
  Alpha testing a bilinearly filtered distance field at 0.5 is exactly Green's (2007) magnification technique, so
  every viewer shows the text, only with rounder corners than the MSDF shader.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from types import SimpleNamespace

import numpy as np

from baker.gltf.document import TARGET_ELEMENT_ARRAY_BUFFER, GltfDocument
from baker.gltf.images import encode_image

ATLAS_NAME = "BAKER_glyph_atlas"
TEXT_NAME = "BAKER_text"
UNLIT = "KHR_materials_unlit"
# linear filtering without mipmaps (a mip of a distance field blurs neighbouring glyphs into each other), clamp
ATLAS_SAMPLER = {"magFilter": 9729, "minFilter": 9729, "wrapS": 33071, "wrapT": 33071}


def coverage_image(atlas) -> np.ndarray:
    """RGBA8 fallback texture: RGB white, A the single-channel field (median of MSDF, true SDF of MTSDF)."""
    img = atlas.image
    if atlas.options.type == "mtsdf":
        alpha = img[..., 3]
    elif img.shape[2] >= 3:
        alpha = np.median(img[..., :3], axis=2).astype(np.uint8)
    else:
        alpha = img[..., 0]
    out = np.full(img.shape[:2] + (4,), 255, np.uint8)
    out[..., 3] = alpha
    return out


def write_glyph_atlas(doc: GltfDocument, atlas, name: str = "atlas") -> int:
    """Add the atlas image, its glyph table and kerning; append a font to ``BAKER_glyph_atlas.fonts``; return the
    font index."""
    image = doc.add_image(encode_image(atlas.image, ".png"), "image/png", f"{name}_{atlas.options.type}")
    texture = doc.add_texture(image, sampler=dict(ATLAS_SAMPLER), name=f"baker {atlas.options.type} atlas")
    entries = atlas.glyphs
    zero = (0.0, 0.0, 0.0, 0.0)
    table = {
        "count": len(entries),
        "unicode": doc.add_accessor(np.array([g.codepoint for g in entries], np.float32), target=None,
                                    name="glyph unicode"),
        "advance": doc.add_accessor(np.array([g.advance for g in entries], np.float32), target=None,
                                    name="glyph advance"),
        "planeBounds": doc.add_accessor(np.array([g.plane or zero for g in entries], np.float32), target=None,
                                        name="glyph planeBounds"),
        "atlasBounds": doc.add_accessor(np.array([g.atlas or zero for g in entries], np.float32), target=None,
                                        name="glyph atlasBounds"),
        "glyphIndex": doc.add_accessor(np.array([g.index for g in entries], np.float32), target=None,
                                       name="glyph index"),
    }
    if len(atlas.font.faces) > 1:
        table["face"] = doc.add_accessor(np.array([g.face for g in entries], np.float32), target=None,
                                         name="glyph face")
    font = {
        "name": atlas.font.family,
        "texture": texture,
        "type": atlas.options.type,
        "distanceRange": float(atlas.options.range),
        "size": float(atlas.options.size),
        "width": atlas.width,
        "height": atlas.height,
        "yOrigin": "bottom",
        "metrics": {k: float(v) for k, v in atlas.metrics_em().items()},
        "glyphs": table,
    }
    if atlas.font.faces:
        font["faces"] = atlas.faces_json()
    if atlas.kerning:
        font["kerning"] = {
            "count": len(atlas.kerning),
            "pairs": doc.add_accessor(np.array([(a, b) for a, b, _ in atlas.kerning], np.float32), target=None,
                                      name="kerning pairs"),
            "advance": doc.add_accessor(np.array([v for _, _, v in atlas.kerning], np.float32), target=None,
                                        name="kerning advance"),
        }
    ext = doc.json.setdefault("extensions", {}).setdefault(ATLAS_NAME, {"fonts": []})
    ext["fonts"].append(font)
    doc.use_extension(ATLAS_NAME)
    return len(ext["fonts"]) - 1


def write_text_node(doc: GltfDocument, atlas, quads, *, text: str, font: int, em_size: float, align: str,
                    color: tuple, outline_width: float = 0.0, outline_color: tuple = (0.0, 0.0, 0.0, 1.0),
                    line_spacing: float = 1.0, name: str = "text", shaping: dict | None = None) -> int:
    """Add a node with the text's quads (plain glTF) and ``BAKER_text``; returns the node index."""
    n = len(quads.positions)
    positions = np.zeros((n * 4, 3), np.float32)
    positions[:, :2] = quads.positions.reshape(-1, 2) * em_size
    normals = np.tile(np.array([0.0, 0.0, 1.0], np.float32), (n * 4, 1))
    uvs = quads.uvs.reshape(-1, 2).astype(np.float32)
    base = (np.arange(n) * 4)[:, None]
    indices = (base + np.array([0, 1, 2, 0, 2, 3])).reshape(-1)
    indices = indices.astype(np.uint16 if n * 4 < 65536 else np.uint32)

    fallback = doc.add_image(encode_image(coverage_image(atlas), ".png"), "image/png", f"{name}_coverage")
    fallback_tex = doc.add_texture(fallback, sampler=dict(ATLAS_SAMPLER), name="baker text coverage (alpha test)")
    materials = doc.json.setdefault("materials", [])
    materials.append({
        "name": f"{name} (distance field, alpha-tested)",
        "pbrMetallicRoughness": {"baseColorTexture": {"index": fallback_tex},
                                 "baseColorFactor": [float(c) for c in color], "metallicFactor": 0.0,
                                 "roughnessFactor": 1.0},
        "alphaMode": "MASK",
        "alphaCutoff": 0.5,
        "doubleSided": True,
        "extensions": {UNLIT: {}},
    })
    doc.use_extension(UNLIT)
    meshes = doc.json.setdefault("meshes", [])
    mesh = {"name": name, "primitives": [{
        "attributes": {
            "POSITION": doc.add_accessor(positions, min_max=True),
            "NORMAL": doc.add_accessor(normals),
            "TEXCOORD_0": doc.add_accessor(uvs),
        },
        "indices": doc.add_accessor(indices, target=TARGET_ELEMENT_ARRAY_BUFFER),
        "material": len(materials) - 1,
    }]}
    meshes.append(mesh)
    ext = {"text": text, "font": font, "emSize": float(em_size), "align": align,
           "color": [float(c) for c in color], "lineSpacing": float(line_spacing)}
    if outline_width > 0:
        ext["outline"] = {"width": float(outline_width), "color": [float(c) for c in outline_color]}
    if quads.table is not None:  # shaped: the runtime draws these glyphs there, it does not lay out by code point
        ext["glyphs"] = {
            "count": int(len(quads.table)),
            "glyph": doc.add_accessor(quads.table.astype(np.float32), target=None, name="text glyph"),
            "position": doc.add_accessor(quads.origins.astype(np.float32), target=None, name="text glyph position"),
        }
        if shaping:
            ext["shaping"] = dict(shaping)
    nodes = doc.json.setdefault("nodes", [])
    nodes.append({"name": name, "mesh": len(meshes) - 1, "extensions": {TEXT_NAME: ext}})
    doc.use_extension(TEXT_NAME)
    return len(nodes) - 1


# ---------------------------------------------------------------------------------------------------- validation
def check_atlas(doc: GltfDocument, places: list, issues) -> None:
    """Semantic rules of BAKER_glyph_atlas: the texture exists and has the declared size and channels, the glyph
    table's accessors agree in count and type, bounds are ordered and inside the atlas, kerning names known glyphs."""
    from baker.gltf.images import decode_image
    from baker.checks import is_index, pointer

    gltf = doc.json
    accessors = gltf.get("accessors") or []
    for parts, ext in places:
        if parts != () or not isinstance(ext, dict):
            if parts != ():
                issues.error("BAKER_GLYPH_ATLAS_PLACEMENT", "BAKER_glyph_atlas belongs on the glTF root",
                             pointer(*parts, "extensions", ATLAS_NAME))
            continue
        for f, font in enumerate(ext.get("fonts") or []):
            if not isinstance(font, dict):
                continue
            ptr = pointer("extensions", ATLAS_NAME, "fonts", f)
            textures = gltf.get("textures") or []
            tex = font.get("texture")
            width, height = font.get("width"), font.get("height")
            if is_index(tex, textures):
                source = textures[tex].get("source")
                if is_index(source, gltf.get("images") or []):
                    try:
                        pixels = decode_image(doc.image_bytes(source), ".png")
                    except Exception as exc:  # unreadable image: say so, keep checking the rest
                        issues.error("BAKER_GLYPH_ATLAS_IMAGE", f"atlas image {source} cannot be decoded: {exc}",
                                     ptr + "/texture")
                    else:
                        if (pixels.shape[1], pixels.shape[0]) != (width, height):
                            issues.error("BAKER_GLYPH_ATLAS_SIZE", f"atlas image is {pixels.shape[1]} x "
                                         f"{pixels.shape[0]}, the font says {width} x {height}", ptr)
                        need = {"sdf": 1, "psdf": 1, "msdf": 3, "mtsdf": 4}.get(font.get("type"), 1)
                        if pixels.shape[2] < need:
                            issues.error("BAKER_GLYPH_ATLAS_CHANNELS", f"a {font.get('type')} atlas needs {need} "
                                         f"channels, the image has {pixels.shape[2]}", ptr + "/type")
            else:
                issues.error("UNRESOLVED_REFERENCE", f"texture {tex!r} does not exist", ptr + "/texture")
            table = font.get("glyphs") or {}
            count = table.get("count")
            arrays = {}
            for key, kind in (("unicode", "SCALAR"), ("advance", "SCALAR"), ("planeBounds", "VEC4"),
                              ("atlasBounds", "VEC4"), ("glyphIndex", "SCALAR"), ("face", "SCALAR")):
                if key in ("glyphIndex", "face") and key not in table:
                    continue  # optional
                values = _float_accessor(doc, table.get(key), kind, count, f"{ptr}/glyphs/{key}",
                                         "BAKER_GLYPH_ATLAS_ACCESSOR", f"glyphs.{key}", issues)
                if values is not None:
                    arrays[key] = values
            if "unicode" in arrays:
                u = arrays["unicode"]
                if (u != np.round(u)).any() or (u < -1).any() or (u > 0x10FFFF).any():
                    issues.error("BAKER_GLYPH_ATLAS_UNICODE", "glyph code points must be integers in 0..0x10FFFF "
                                 "(-1: none)", f"{ptr}/glyphs/unicode")
                elif len(np.unique(u[u >= 0])) != int((u >= 0).sum()):
                    issues.error("BAKER_GLYPH_ATLAS_UNICODE", "a code point appears twice in the glyph table",
                                 f"{ptr}/glyphs/unicode")
            for key in ("planeBounds", "atlasBounds"):
                if key in arrays:
                    b = arrays[key]
                    if (b[:, 2] < b[:, 0]).any() or (b[:, 3] < b[:, 1]).any():
                        issues.error("BAKER_GLYPH_ATLAS_BOUNDS", f"{key}: right < left or top < bottom",
                                     f"{ptr}/glyphs/{key}")
            if "atlasBounds" in arrays and isinstance(width, int) and isinstance(height, int):
                b = arrays["atlasBounds"]
                if (b < 0).any() or (b[:, 2] > width).any() or (b[:, 3] > height).any():
                    issues.error("BAKER_GLYPH_ATLAS_BOUNDS", "atlasBounds reach outside the atlas",
                                 f"{ptr}/glyphs/atlasBounds")
            faces = font.get("faces")
            for key, limit in (("glyphIndex", 65535), ("face", (len(faces) if isinstance(faces, list) else 1) - 1)):
                if key in arrays:
                    v = arrays[key]
                    if (v != np.round(v)).any() or (v < 0).any() or (v > limit).any():
                        issues.error("BAKER_GLYPH_ATLAS_GLYPH_INDEX", f"glyphs.{key} must hold integers in 0..{limit}",
                                     f"{ptr}/glyphs/{key}")
            if "glyphIndex" in arrays:
                face = arrays.get("face", np.zeros_like(arrays["glyphIndex"]))
                ids = set(zip(face.tolist(), arrays["glyphIndex"].tolist()))
                if len(ids) != len(face):
                    issues.error("BAKER_GLYPH_ATLAS_GLYPH_INDEX", "a (face, glyph id) appears twice in the glyph "
                                 "table", f"{ptr}/glyphs/glyphIndex")
            kerning = font.get("kerning")
            if isinstance(kerning, dict) and "unicode" in arrays:
                pairs = kerning.get("pairs")
                if is_index(pairs, accessors) and accessors[pairs].get("type") == "VEC2":
                    known = set(arrays["unicode"].tolist())
                    p = doc.accessor(pairs)
                    unknown = [c for c in p.reshape(-1).tolist() if c not in known]
                    if unknown:
                        issues.warning("BAKER_GLYPH_ATLAS_KERNING", f"{len(unknown)} kerning code points are not in "
                                       "the glyph table", f"{ptr}/kerning/pairs")


def check_text(doc: GltfDocument, places: list, issues) -> None:
    """Semantic rules of BAKER_text: on a node, its font exists, its characters are in that font's glyph table."""
    from baker.checks import is_index, pointer

    gltf = doc.json
    fonts = ((gltf.get("extensions") or {}).get(ATLAS_NAME) or {}).get("fonts") or []
    for parts, ext in places:
        if len(parts) != 2 or parts[0] != "nodes" or not isinstance(ext, dict):
            continue
        ptr = pointer(*parts, "extensions", TEXT_NAME)
        font = ext.get("font")
        if not is_index(font, fonts):
            issues.error("BAKER_TEXT_FONT_MISSING", f"font {font!r} is not in BAKER_glyph_atlas.fonts", ptr + "/font")
            continue
        if "mesh" not in gltf["nodes"][parts[1]]:
            issues.info("BAKER_TEXT_NO_MESH", "the node has no mesh: viewers without BAKER_text show nothing", ptr)
        table = fonts[font].get("glyphs") or {}
        a = table.get("unicode")
        shaped = ext.get("glyphs")
        if isinstance(shaped, dict):
            _check_shaped(doc, shaped, table, ptr + "/glyphs", issues)
        elif is_index(a, gltf.get("accessors") or []):
            known = set(doc.accessor(a).astype(np.int64).tolist())
            text = ext.get("text") if isinstance(ext.get("text"), str) else ""
            absent = sorted({c for c in text if c != "\n" and ord(c) not in known})
            if absent:
                issues.warning("BAKER_TEXT_GLYPH_MISSING", f"{len(absent)} characters are not in the font's glyph "
                               f"table: {''.join(absent)!r}", ptr + "/text")


def _float_accessor(doc: GltfDocument, index, kind: str, count, ptr: str, code: str, what: str, issues):
    """The float64 values of accessor ``index`` when it exists and is FLOAT ``kind`` x ``count``; else report, None."""
    from baker.checks import is_index, pointer

    accessors = doc.json.get("accessors") or []
    if not is_index(index, accessors):
        issues.error("UNRESOLVED_REFERENCE", f"accessor {index!r} does not exist", ptr)
        return None
    acc = accessors[index]
    if acc.get("componentType") != 5126 or acc.get("type") != kind or acc.get("count") != count:
        issues.error(code, f"{what} must be FLOAT {kind} with count {count}, not {acc.get('componentType')} "
                           f"{acc.get('type')} x {acc.get('count')}", pointer("accessors", index))
        return None
    return doc.accessor(index).astype(np.float64)


def _check_shaped(doc: GltfDocument, shaped: dict, table: dict, ptr: str, issues) -> None:
    """BAKER_text.glyphs: FLOAT accessors of ``count`` elements, glyph indices into the table, finite positions."""
    count = shaped.get("count")
    arrays = {}
    for key, kind in (("glyph", "SCALAR"), ("position", "VEC2")):
        values = _float_accessor(doc, shaped.get(key), kind, count, f"{ptr}/{key}", "BAKER_TEXT_GLYPHS_ACCESSOR",
                                 f"glyphs.{key}", issues)
        if values is None:
            return
        arrays[key] = values
    g = arrays["glyph"]
    size = table.get("count") if isinstance(table.get("count"), int) else 0
    if (g != np.round(g)).any() or (g < 0).any() or (g >= size).any():
        issues.error("BAKER_TEXT_GLYPHS_INDEX", f"glyphs.glyph must index the font's glyph table (0..{size - 1})",
                     ptr + "/glyph")
    if not np.isfinite(arrays["position"]).all():
        issues.error("BAKER_TEXT_GLYPHS_POSITION", "glyph positions must be finite", ptr + "/position")


# ---------------------------------------------------------------------------------------------------- reading back
@dataclass(frozen=True, eq=False)  # holds arrays: compared by identity
class Font:
    """One font of ``BAKER_glyph_atlas`` as read back: the atlas texture, its distance field and glyph table."""

    name: str | None
    texture: int
    type: str  # "sdf", "psdf", "msdf" or "mtsdf"
    distance_range: float  # atlas pixels
    size: float  # atlas pixels per em
    width: int
    height: int
    y_origin: str = "bottom"
    metrics: dict = field(default_factory=dict)  # em units
    glyphs: dict = field(default_factory=dict)  # "unicode", "advance", "planeBounds", "atlasBounds" (and
    # "glyphIndex", "face" when written) -> arrays
    kerning: dict = field(default_factory=dict)  # "pairs", "advance" -> arrays (empty: no kerning)
    faces: tuple = ()  # the fallback list: dicts (name, file, faceIndex, unitsPerEm); glyphs["face"] indexes it


@dataclass(frozen=True)
class TextLabel:
    """``BAKER_text`` of one node as read back, with its font (None when the font index names no atlas font)."""

    text: str
    font_index: int
    font: Font | None
    em_size: float
    align: str = "left"
    color: tuple = (1.0, 1.0, 1.0, 1.0)  # linear RGBA
    line_spacing: float = 1.0
    outline_width: float = 0.0  # em units
    outline_color: tuple = (0.0, 0.0, 0.0, 1.0)
    glyphs: object = None  # shaped text: (n,) glyph-table indices (None: lay out by code point)
    positions: object = None  # (n, 2) em, each glyph's origin
    shaping: dict = field(default_factory=dict)


def read_atlas(doc: GltfDocument) -> list[Font]:
    """The fonts :func:`write_glyph_atlas` appended to ``BAKER_glyph_atlas``, glyph tables read (empty: none)."""
    fonts = ((doc.json.get("extensions") or {}).get(ATLAS_NAME) or {}).get("fonts", [])
    out = []
    for f in fonts:
        table, kerning = f.get("glyphs") or {}, f.get("kerning") or {}
        out.append(Font(
            name=f.get("name"), texture=int(f["texture"]), type=f["type"], distance_range=float(f["distanceRange"]),
            size=float(f["size"]), width=int(f["width"]), height=int(f["height"]), y_origin=f.get("yOrigin", "bottom"),
            metrics=dict(f.get("metrics", {})),
            glyphs={k: doc.accessor(table[k]) for k in ("unicode", "advance", "planeBounds", "atlasBounds", "glyphIndex",
                                                    "face")
                    if k in table},
            kerning={k: doc.accessor(kerning[k]) for k in ("pairs", "advance") if k in kerning},
            faces=tuple(dict(x) for x in f.get("faces") or ())))
    return out


def read_text(doc: GltfDocument, node: int, fonts: list | None = None) -> TextLabel | None:
    """What :func:`write_text_node` wrote on ``node``, or None without ``BAKER_text``; ``fonts``: from
    :func:`read_atlas` (read when not given)."""
    ext = (doc.json.get("nodes", [])[node].get("extensions") or {}).get(TEXT_NAME)
    if ext is None:
        return None
    fonts = read_atlas(doc) if fonts is None else fonts
    index = int(ext.get("font", 0))
    outline = ext.get("outline") or {}
    shaped = ext.get("glyphs") if isinstance(ext.get("glyphs"), dict) else None
    return TextLabel(
        text=ext.get("text", ""), font_index=index, font=fonts[index] if 0 <= index < len(fonts) else None,
        em_size=float(ext.get("emSize", 1.0)), align=ext.get("align", "left"),
        color=tuple(float(c) for c in ext.get("color", (1.0, 1.0, 1.0, 1.0))),
        line_spacing=float(ext.get("lineSpacing", 1.0)), outline_width=float(outline.get("width", 0.0)),
        outline_color=tuple(float(c) for c in outline.get("color", (0.0, 0.0, 0.0, 1.0))),
        glyphs=doc.accessor(shaped["glyph"]).astype(np.int64) if shaped else None,
        positions=doc.accessor(shaped["position"]).astype(np.float64) if shaped else None,
        shaping=dict(ext.get("shaping") or {}))


read = read_text

ATLAS = SimpleNamespace(NAME=ATLAS_NAME, check=check_atlas, read=read_atlas)
TEXT = SimpleNamespace(NAME=TEXT_NAME, check=check_text, read=read_text)
