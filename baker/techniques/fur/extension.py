"""``BAKER_fur``: shell and fin textures on the material, and fin primitives built on the edge adjacency.

Where the data goes (see ``schemas/BAKER_fur/README.md``):
- ``BAKER_fur`` on the material: shell count, spacing and length (mesh units), tiling (tiles per TEXCOORD_0 unit),
  the shell textures (one RGBA PNG per shell: colour + coverage), the fin texture, the fin primitives;
- one fin primitive per furred triangle primitive (same mesh): per mesh edge a degenerate quad (v0, v1, v1, v0), so
  a plain viewer rasterizes nothing; each vertex carries the edge's corners ``_FIN_V0.._FIN_V3`` (v2, v3: the
  vertices opposite the edge in its two faces, as in BAKER_edges), its corner number ``_FIN_CORNER`` (0, 1 on the
  surface at v0, v1; 2, 3 at the fur tips above v1, v0), the extrusion normal ``_FUR_FIN_NORMAL`` and the fin texture
  coordinate ``_FUR_FIN_UV`` (u, v in x, y), laid out as :mod:`baker.gltf.vertex_attributes` says (``blender``: all
  FLOAT VEC3, scalars in x; ``native``: SCALAR, VEC2, VEC3); ``BAKER_fur`` on it names its source primitive
  (``finsOf``).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from baker.texels.alpha_mips import check_coverage_mips, write_coverage_mips
from baker.gltf.document import TARGET_ELEMENT_ARRAY_BUFFER, GltfDocument
from baker.gltf.derived import copy_skinning, match_morph_targets
from baker.gltf.images import encode_image
from baker.gltf.vertex_attributes import add_vertex_attribute

NAME = "BAKER_fur"
# name -> the data's width (baker.registry)
VERTEX_ATTRIBUTES = {"_FIN_V0": 3, "_FIN_V1": 3, "_FIN_V2": 3, "_FIN_V3": 3, "_FIN_CORNER": 1, "_FUR_FIN_NORMAL": 3,
                     "_FUR_FIN_UV": 2}
SAMPLER_REPEAT = {"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}
SAMPLER_FIN = {"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 33071}


def usd_color_space(params: dict, path: tuple) -> str:
    """USD ``sourceColorSpace`` of a texture this extension names: the shell and fin textures are hair colour
    (sRGB) with linear coverage in alpha (UsdUVTexture decodes only rgb)."""
    return "sRGB" if path and path[0] in ("shellTextures", "finTexture") else "raw"


def encode_rgba_png(pixels: np.ndarray) -> bytes:
    """PNG of straight-alpha RGBA8 pixels, stored as given."""
    return encode_image(np.ascontiguousarray(pixels, np.uint8), ".png")


def write_fur_textures(doc: GltfDocument, shells: np.ndarray, fin: np.ndarray | None,
                       alpha_cutoff: float | None = None) -> tuple[list, int | None, list]:
    """Add the shell textures and the fin texture (None: no fins, so no fin texture), and with ``alpha_cutoff`` each
    one's coverage-preserving mip chain (:mod:`baker.texels.alpha_mips`); returns ([shell texture indices], fin
    texture index or None, coverageMips)."""
    out, mips = [], []
    for i, shell in enumerate(shells):
        image = doc.add_image(encode_rgba_png(shell), "image/png", f"fur_shell{i:02d}")
        out.append(doc.add_texture(image, sampler=SAMPLER_REPEAT, name=f"baker fur shell {i}"))
    fin_texture = None
    if fin is not None:
        image = doc.add_image(encode_rgba_png(fin), "image/png", "fur_fin")
        fin_texture = doc.add_texture(image, sampler=SAMPLER_FIN, name="baker fur fin")
    if alpha_cutoff is not None:
        # the kernel encodes colour with the power 1 / 2.2: the chain filters it in linear light the same way
        textures = out + ([fin_texture] if fin is not None else [])
        mips = [write_coverage_mips(doc, t, pixels, alpha_cutoff, transfer="gamma2.2")
                for t, pixels in zip(textures, [*shells, fin])]
    return out, fin_texture, mips


def write_fin_primitive(doc: GltfDocument, mesh: int, primitive: int, corners: np.ndarray, normals: np.ndarray,
                        fin_u: np.ndarray, edges: np.ndarray | None = None) -> int:
    """Append the fur fin primitive of ``primitive``.

    corners: (E, 4, 3) v0, v1, v2, v3 of every edge; normals: (E, 2, 3) extrusion normals at v0, v1; fin_u: (E, 2)
    fin texture u at v0, v1 (tile units); edges: (E, 2) the primitive's vertices v0, v1 (their joints and weights
    are copied on a skinned mesh)."""
    prims = doc.json["meshes"][mesh]["primitives"]
    n = len(corners)
    corners = corners.astype(np.float32)
    at = np.array([0, 1, 1, 0])  # corner k sits on edge vertex at[k]
    rows = np.repeat(np.arange(n), 4)
    position = corners[rows, np.tile(at, n)]
    attributes = {"POSITION": doc.add_accessor(position, min_max=True)}
    v = np.tile(np.array([0.0, 0.0, 1.0, 1.0], np.float32), n)  # 0 at the root, 1 at the tip
    u = fin_u.astype(np.float32)[rows, np.tile(at, n)]
    columns = {**{f"_FIN_V{j}": np.repeat(corners[:, j], 4, axis=0) for j in range(4)},
               "_FIN_CORNER": np.tile(np.arange(4, dtype=np.float32), n),
               "_FUR_FIN_NORMAL": normals.astype(np.float32)[rows, np.tile(at, n)], "_FUR_FIN_UV": np.stack([u, v], axis=1)}
    for name, values in columns.items():
        add_vertex_attribute(doc, mesh, attributes, name, values, leave_out="--fur-fins false")
    quad = np.array([0, 1, 2, 0, 2, 3], np.int64)
    indices = (np.arange(n)[:, None] * 4 + quad[None, :]).reshape(-1)
    fin = {
        "attributes": attributes,
        "indices": doc.add_accessor(indices.astype(np.uint16 if 4 * n <= 0xFFFF else np.uint32),
                                    target=TARGET_ELEMENT_ARRAY_BUFFER),
        "mode": 4,
        "extensions": {NAME: {"finsOf": int(primitive)}},
    }
    # no material: the fur runtime takes BAKER_fur from the source primitive's material (through finsOf); binding it
    # here would ask for TEXCOORD sets the fin lacks (invalid glTF when the material has textures)
    match_morph_targets(doc, mesh, fin, len(position))
    if edges is not None:
        copy_skinning(doc, mesh, primitive, fin, np.asarray(edges)[rows, np.tile(at, n)])
    prims.append(fin)
    return len(prims) - 1


def write_material(doc: GltfDocument, material: int, *, options, length: float, shell_textures: list,
                   fin_texture: int | None, fins: list, coverage: np.ndarray, tile_size: float,
                   coverage_mips: list = ()) -> dict:
    ext = {
        "shellCount": int(options.shells),
        "length": float(length),
        "shellSpacing": float(length / options.shells),
        "tiling": float(options.tiling),
        "tileSize": float(tile_size),
        "shellTextures": [{"index": int(t)} for t in shell_textures],
        "shellCoverage": [float(c) for c in coverage],
        "fins": [{"mesh": int(m), "primitive": int(p)} for m, p in fins],
        "alphaCutoff": float(options.alpha_cutoff),
    }
    if fin_texture is not None:  # only with fins: nothing else samples it
        ext["finTexture"] = {"index": int(fin_texture)}
    if coverage_mips:
        ext["coverageMips"] = [dict(entry) for entry in coverage_mips]
    return doc.set_material_extension(material, NAME, ext)


def check(doc: GltfDocument, places: list, issues) -> None:
    """Semantic rules of BAKER_fur: one shell texture per shell, textures exist, fin primitives point back at a
    triangle primitive of the same mesh that uses the material, and carry the fin attributes."""
    from baker.checks import is_index, pointer

    gltf = doc.json
    textures = gltf.get("textures") or []
    meshes = gltf.get("meshes") or []
    for parts, ext in places:
        if not isinstance(ext, dict):
            continue
        if len(parts) == 2 and parts[0] == "materials":
            ptr = pointer("materials", parts[1], "extensions", NAME)
            shells = ext.get("shellTextures") or []
            if len(shells) != ext.get("shellCount"):
                issues.error("BAKER_FUR_SHELL_COUNT", f"{len(shells)} shell textures for shellCount "
                             f"{ext.get('shellCount')}", ptr + "/shellTextures")
            for i, info in enumerate(shells + ([ext["finTexture"]] if "finTexture" in ext else [])):
                if not is_index(info.get("index"), textures):
                    issues.error("UNRESOLVED_REFERENCE", f"texture {info.get('index')!r} does not exist", ptr)
            spacing, length, count = ext.get("shellSpacing"), ext.get("length"), ext.get("shellCount")
            if all(isinstance(x, (int, float)) for x in (spacing, length, count)) and count and \
                    abs(spacing * count - length) > 1e-6 * max(length, 1e-30):
                issues.error("BAKER_FUR_SPACING", "shellSpacing x shellCount must equal length", ptr)
            if "coverageMips" in ext:
                check_coverage_mips(doc, ext["coverageMips"], ptr + "/coverageMips", issues)
                mipped = {e.get("texture") for e in ext["coverageMips"] if isinstance(e, dict)} \
                    if isinstance(ext["coverageMips"], list) else set()
                missing = [info.get("index") for info in shells + ([ext["finTexture"]] if "finTexture" in ext else [])
                           if isinstance(info, dict) and info.get("index") not in mipped]
                if missing:
                    issues.warning("BAKER_FUR_COVERAGE_MIPS", f"textures {missing} have no coverage-preserving mip "
                                   "chain", ptr + "/coverageMips")
            for j, ref in enumerate(ext.get("fins") or []):
                m, p = ref.get("mesh"), ref.get("primitive")
                if not is_index(m, meshes) or not is_index(p, meshes[m].get("primitives") or []):
                    issues.error("UNRESOLVED_REFERENCE", f"fin primitive {m}/{p} does not exist", ptr + f"/fins/{j}")
                    continue
                fin = meshes[m]["primitives"][p]
                if ((fin.get("extensions") or {}).get(NAME) or {}).get("finsOf") is None:
                    issues.error("BAKER_FUR_FIN_NOT_MARKED", "the fin primitive has no BAKER_fur.finsOf",
                                 pointer("meshes", m, "primitives", p))
        elif len(parts) == 4 and parts[0] == "meshes" and parts[2] == "primitives":
            m, p = parts[1], parts[3]
            prims = meshes[m].get("primitives") or []
            src = ext.get("finsOf")
            ptr = pointer("meshes", m, "primitives", p, "extensions", NAME)
            if not is_index(src, prims) or src == p:
                issues.error("BAKER_FUR_FINS_OF", f"finsOf {src!r} is not another primitive of this mesh", ptr)
                continue
            attrs = prims[p].get("attributes") or {}
            missing = [a for a in ("_FIN_V0", "_FIN_V1", "_FIN_V2", "_FIN_V3", "_FIN_CORNER", "_FUR_FIN_NORMAL",
                                   "_FUR_FIN_UV") if a not in attrs]
            if missing:
                issues.error("BAKER_FUR_FIN_ATTRIBUTES", f"fin primitive lacks {', '.join(missing)}", ptr)
            if "material" in prims[p] and prims[p]["material"] != prims[src].get("material"):
                issues.warning("BAKER_FUR_FIN_MATERIAL", "the fin primitive's material differs from its source's", ptr)


# ---------------------------------------------------------------------------------------------------- reading back
@dataclass(frozen=True)
class FurMaterial:
    """``BAKER_fur`` of one material as read back (Lengyel et al. 2001): shell textures innermost first, the fin
    texture and the fin primitives."""

    shell_count: int
    shell_spacing: float  # mesh units between shells
    shell_textures: tuple  # texture indices, innermost first
    length: float | None = None
    tiling: float = 1.0  # texture repeats per texture-coordinate unit
    tile_size: float | None = None
    shell_coverage: tuple = ()
    fin_texture: int | None = None
    fins: tuple = ()  # (mesh, primitive) of each fin primitive
    alpha_cutoff: float | None = None  # the alpha-test threshold (None: an older file, shells blended)
    coverage_mips: dict = field(default_factory=dict)  # texture index -> its coverageMips entry


def read(doc: GltfDocument, material: int) -> FurMaterial | None:
    """What :func:`write_material` wrote on ``material``, or None without ``BAKER_fur``."""
    ext = (doc.json.get("materials", [])[material].get("extensions") or {}).get(NAME)
    if ext is None:
        return None
    fin = ext.get("finTexture") or {}
    return FurMaterial(
        shell_count=int(ext["shellCount"]), shell_spacing=float(ext["shellSpacing"]),
        shell_textures=tuple(int(t["index"]) for t in ext["shellTextures"]),
        length=float(ext["length"]) if "length" in ext else None, tiling=float(ext.get("tiling", 1.0)),
        tile_size=float(ext["tileSize"]) if "tileSize" in ext else None,
        shell_coverage=tuple(float(c) for c in ext.get("shellCoverage", ())),
        fin_texture=int(fin["index"]) if "index" in fin else None,
        fins=tuple((int(f["mesh"]), int(f["primitive"])) for f in ext.get("fins", ())),
        alpha_cutoff=float(ext["alphaCutoff"]) if "alphaCutoff" in ext else None,
        coverage_mips={int(e["texture"]): dict(e) for e in ext.get("coverageMips", ())})


def read_fin_source(doc: GltfDocument, mesh: int, primitive: int) -> int | None:
    """The source primitive of a fur fin primitive (its ``BAKER_fur.finsOf``); None for any other primitive."""
    prim = doc.json["meshes"][mesh]["primitives"][primitive]
    ext = (prim.get("extensions") or {}).get(NAME) or {}
    return int(ext["finsOf"]) if "finsOf" in ext else None
