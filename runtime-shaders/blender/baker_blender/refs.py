"""Where BAKER_* extensions keep references to other glTF objects (from the schemas in schemas/BAKER_*):
accessors (by extension, as key paths), textures (any property whose name contains "texture" holding an index or a
textureInfo) and vertex indices (accessors whose values index the primitive's vertices)."""
from __future__ import annotations

BAKER_PREFIX = "BAKER_"
EDGE_VISIBILITY = "EXT_mesh_primitive_edge_visibility"
# accessor-valued properties; "a.b" = nested object, "a[].b" = each item of an array
ACCESSORS = {
    "BAKER_edges": ("edges", "oppositeVertices", "flags", "dihedralAngles", "wireframeMask"),
    EDGE_VISIBILITY: ("visibility", "silhouetteMates", "lineStrings[].indices"),
    "BAKER_hair": ("widthScale", "ribbonIndices", "guides.ids", "guides.weights", "rootBinding.primitives",
                   "rootBinding.triangles", "rootBinding.barycentrics"),
    "BAKER_glyph_atlas": ("fonts[].glyphs.unicode", "fonts[].glyphs.glyphIndex", "fonts[].glyphs.face",
                          "fonts[].glyphs.advance", "fonts[].glyphs.planeBounds", "fonts[].glyphs.atlasBounds",
                          "fonts[].kerning.pairs", "fonts[].kerning.advance"),
    "BAKER_text": ("glyphs.glyph", "glyphs.position"),
    "BAKER_hair_cards": ("regions", "cardFirstIndex", "coverageMips[].accessor"),
    "BAKER_fur": ("coverageMips[].accessor",),  # the KTX2 bytes of each coverage-preserving mip chain
    # the fibre tables (half-float texels), once per file at the root
    "BAKER_hair_shading": ("tables[].longitudinal.accessor", "tables[].azimuthal.accessor",
                           "tables[].dualScattering.accessor"),
}
# accessors holding vertex indices of their primitive (remapped by position when Blender renumbers vertices)
VERTEX_INDEX_ACCESSORS = {("BAKER_edges", "edges"), ("BAKER_edges", "oppositeVertices"),
                          (EDGE_VISIBILITY, "silhouetteMates")}


def ours(name: str) -> bool:
    return name.startswith(BAKER_PREFIX) or name == EDGE_VISIBILITY


def walk_paths(obj, path: str):
    """(container, key) pairs that ``path`` names inside ``obj`` (only those that exist)."""
    head, _, rest = path.partition(".")
    if head.endswith("[]"):
        items = obj.get(head[:-2]) if isinstance(obj, dict) else None
        for item in items if isinstance(items, list) else []:
            yield from walk_paths(item, rest)
        return
    if not isinstance(obj, dict) or head not in obj:
        return
    if rest:
        yield from walk_paths(obj[head], rest)
    else:
        yield obj, head


def accessor_slots(name: str, ext: dict):
    """(container, key, path) of every accessor index in extension ``name``'s object ``ext``."""
    for path in ACCESSORS.get(name, ()):
        for container, key in walk_paths(ext, path):
            if isinstance(container[key], int):
                yield container, key, path


def texture_slots(obj):
    """(container, key) of every texture index inside ``obj``: ``{...Texture: {"index": i}}``, ``...Textures: [...]``
    and plain integers under a key containing "texture" (BAKER_glyph_atlas ``fonts[].texture``)."""
    if isinstance(obj, dict):
        for key, value in obj.items():
            textured = "texture" in key.lower()
            if textured and isinstance(value, int) and not isinstance(value, bool):
                yield obj, key
            elif textured and isinstance(value, dict) and isinstance(value.get("index"), int):
                yield value, "index"
            elif textured and isinstance(value, list):
                for item in value:
                    if isinstance(item, dict) and isinstance(item.get("index"), int):
                        yield item, "index"
                    else:
                        yield from texture_slots(item)
            else:
                yield from texture_slots(value)
    elif isinstance(obj, list):
        for item in obj:
            yield from texture_slots(item)
