"""Wavefront MTL materials read faithfully into glTF materials, and the explicit dielectric of formats without any.

An OBJ's ``mtllib`` files are untrusted input like the OBJ itself: every number is checked (a malformed or
non-finite value is refused naming the file and the line), and every file a statement names (the MTL, each
``map_*`` texture) resolves only inside the asset's folder or an ``allow_outside`` root
(:func:`baker.gltf.structure.local_file`, the rule glTF URIs follow). Those files are optional pieces, though: one
that is absent or unreadable (an OBJ shared without its .mtl) is one :class:`MissingFileWarning` naming the file
and line that name it, and the asset bakes without it (a missing MTL's materials are the dielectric default, a
missing map is left out of its material), as Blender, trimesh and Assimp do.

The mapping (README "Materials"; MTL statements as in the Wavefront spec and the common PBR additions):

- ``newmtl NAME`` -> ``name``;
- ``Kd`` -> ``baseColorFactor`` rgb (clamped to [0, 1]); ``map_Kd`` -> ``baseColorTexture`` (the spec multiplies
  the texture by ``Kd``, as glTF does);
- ``d`` (or ``Tr`` = 1 - d; the later statement wins) -> ``baseColorFactor`` alpha; ``map_d`` -> the alpha channel
  of ``baseColorTexture`` (the map's own alpha when it has one, otherwise its first channel). Alpha mode: a
  ``map_d`` on an otherwise opaque material (d = 1) is a cut-out -> ``MASK`` (cutoff 0.5); any d < 1 -> ``BLEND``;
  otherwise ``OPAQUE``;
- ``Ns`` (Blinn-Phong exponent) -> ``roughnessFactor``: Walter et al. 2007 ("Microfacet Models for Refraction
  through Rough Surfaces", EGSR, sec. 5.2) match the Phong exponent to a Beckmann/GGX width by
  alpha = sqrt(2 / (Ns + 2)); glTF's roughness is perceptual, alpha = roughness^2, so roughness = sqrt(alpha).
  ``Pr`` (PBR extension), when present, is the roughness itself; neither -> 0.5;
- ``Pm`` -> ``metallicFactor``; otherwise 0 (MTL describes dielectrics);
- ``norm``, ``map_Bump``/``bump`` -> ``normalTexture`` with ``-bm`` as its ``scale``. A bump map whose pixels are
  grey (R = G = B everywhere) is a height map, which glTF has no slot for: it is left out;
- ``Ke`` -> ``emissiveFactor``; above 1, the factor is Ke / max(Ke) and ``KHR_materials_emissive_strength`` holds
  max(Ke); ``map_Ke`` -> ``emissiveTexture`` (with factor 1 when there is no ``Ke``).

Other statements (``Ka``, ``Ks``, ``Ni``, ``illum``, ...) and texture options other than ``-bm`` are read past.
Formats without materials (PLY, STL, an OBJ without ``mtllib``, faces before any ``usemtl``) get :data:`DIELECTRIC`.
"""
from __future__ import annotations

import math
import urllib.parse
import warnings
from dataclasses import dataclass, field
from pathlib import Path

from baker.errors import BakeNote, BakerError
from baker.gltf.structure import local_file, uri_roots

DEFAULT_ROUGHNESS = 0.5
# an explicit dielectric: without pbrMetallicRoughness glTF's default is a fully metallic, fully rough surface
DIELECTRIC = {"name": "baker_dielectric",
              "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": DEFAULT_ROUGHNESS}}
EMISSIVE_STRENGTH = "KHR_materials_emissive_strength"

# texture statements -> the role they play; options -> how many numbers/words follow them (min, max)
TEXTURE_STATEMENTS = {"map_kd": "diffuse", "map_d": "dissolve", "map_ke": "emissive", "norm": "normal",
                      "map_norm": "normal", "map_bump": "bump", "bump": "bump"}
TEXTURE_OPTIONS = {"-blendu": (1, 1), "-blendv": (1, 1), "-boost": (1, 1), "-mm": (2, 2), "-o": (1, 3),
                   "-s": (1, 3), "-t": (1, 3), "-texres": (1, 1), "-clamp": (1, 1), "-bm": (1, 1),
                   "-imfchan": (1, 1), "-type": (1, 1), "-cc": (1, 1)}
COLOR_STATEMENTS = {"kd": "diffuse", "ke": "emissive"}
SCALAR_STATEMENTS = {"d": "dissolve", "tr": "transparency", "ns": "shininess", "pr": "roughness", "pm": "metallic"}


class MissingFileWarning(BakeNote):
    """An MTL or texture file an OBJ or MTL names is absent or cannot be read: the asset bakes without it."""

    label = "warning"


@dataclass
class MtlTexture:
    path: Path  # resolved, inside the allowed folders
    source: Path  # the .mtl file naming it
    statement: str  # as written (map_Kd, map_Bump, ...)
    line: int
    bump_multiplier: float = 1.0  # -bm


@dataclass
class MtlMaterial:
    name: str
    source: Path  # the .mtl file
    diffuse: tuple | None = None
    emissive: tuple | None = None
    dissolve: float | None = None  # from d, or 1 - Tr
    shininess: float | None = None
    roughness: float | None = None
    metallic: float | None = None
    textures: dict = field(default_factory=dict)  # role -> MtlTexture


def roughness_from_shininess(ns: float) -> float:
    """glTF roughness for a Blinn-Phong exponent ``ns`` >= 0: alpha = sqrt(2 / (ns + 2)) (Walter et al. 2007,
    eq. 33 inverted), roughness = sqrt(alpha)."""
    return math.sqrt(math.sqrt(2.0 / (ns + 2.0)))


# ---------------------------------------------------------------------------------------------------------- reading
def resolve_file(name: str, base: Path, roots: list, source: Path, where: str, without: str) -> Path | None:
    """The file ``name`` (as written in an OBJ/MTL, not a URI) relative to ``base``, under the URI policy. A refusal
    (a path leaving the allowed folders) is a :class:`BakerError` naming ``source`` and ``where``; a file that is
    absent or unreadable is one :class:`MissingFileWarning` naming them and saying ``without`` (what the asset does
    without it), and None."""
    try:
        target = local_file(urllib.parse.quote(name, safe="/\\:"), base, roots)
    except ValueError as exc:
        raise BakerError(source, f"{where}: {str(exc).replace('URI ', '', 1)}") from None
    problem = unreadable(target)
    if problem is not None:
        warnings.warn(MissingFileWarning(f"{source}: {where}: file {name!r} {problem}; {without}"), stacklevel=2)
        return None
    return target


def unreadable(path: Path) -> str | None:
    """Why ``path`` cannot be read as a file (``"not found"``, ...), or None when it can."""
    if not path.exists():
        return "not found"
    if not path.is_file():
        return "is not a file"
    try:
        with open(path, "rb"):
            pass
    except OSError as exc:
        return f"cannot be read ({exc.strerror or exc})"
    return None


def material_libraries(obj: Path, allow_outside=None) -> list[Path]:
    """The ``mtllib`` files an OBJ names, resolved under the URI policy (a missing one is a warning, left out)."""
    obj = Path(obj)
    found = []
    data = obj.read_bytes()
    # found with bytes.find (a scan's OBJ has millions of lines and a handful of mtllib), kept at a line start
    at = data.find(b"mtllib")
    while at >= 0:
        start, end = at, data.find(b"\n", at)
        at = data.find(b"mtllib", at + 6)
        if start and data[start - 1:start] != b"\n":
            continue
        raw = data[start + 6:end if end >= 0 else len(data)]
        rest = raw.decode("utf-8", errors="replace").strip()
        if not rest or not raw[:1].isspace():
            continue
        line = data.count(b"\n", 0, start) + 1
        where = f"line {line}: mtllib"
        roots = uri_roots(obj.parent, allow_outside)
        # a name with spaces is one file when it exists; otherwise several names separated by spaces (when none of
        # them exists either, the one name as written is the missing file)
        names = rest.split()
        if (obj.parent / rest).is_file() or not any((obj.parent / name).exists() for name in names):
            names = [rest]
        for name in names:
            library = resolve_file(name, obj.parent, roots, obj, where,
                                   "the materials it defines are the dielectric default")
            if library is not None:
                found.append(library)
    return found


def read_obj_materials(obj: Path, allow_outside=None) -> tuple[dict, list]:
    """Every material of an OBJ's ``mtllib`` files by name (a later definition wins), and the MTL files read."""
    libraries = material_libraries(obj, allow_outside)
    roots = uri_roots(Path(obj).parent, allow_outside)
    materials = {}
    for library in libraries:
        materials.update(read_mtl(library, roots))
    return materials, libraries


def _numbers(words: list, source: Path, where: str, count: tuple) -> list:
    low, high = count
    if not low <= len(words) <= high:
        expected = str(low) if low == high else f"{low} to {high}"
        raise BakerError(source, f"{where} expects {expected} numbers, got {len(words)}")
    values = []
    for word in words:
        try:
            value = float(word)
        except ValueError:
            raise BakerError(source, f"{where}: {word!r} is not a number") from None
        if not math.isfinite(value):
            raise BakerError(source, f"{where}: {word!r} is not a finite number")
        values.append(value)
    return values


def _texture(words: list, source: Path, where: str, statement: str, number: int, roots: list,
             material: str) -> MtlTexture | None:
    multiplier = 1.0
    i = 0
    while i < len(words) and words[i].lower() in TEXTURE_OPTIONS:
        option = words[i].lower()
        low, high = TEXTURE_OPTIONS[option]
        args = words[i + 1:i + 1 + low]
        if len(args) < low:
            raise BakerError(source, f"{where}: option {words[i]} expects {low} value(s)")
        i += 1 + low
        while high > low and i < len(words) and _is_number(words[i]):  # -o/-s/-t take 1 to 3 numbers
            high -= 1
            i += 1
        if option == "-bm":
            multiplier = _numbers(args, source, f"{where} -bm", (1, 1))[0]
        elif option in ("-o", "-s", "-t", "-mm", "-boost", "-texres"):
            _numbers(args, source, f"{where} {option}", (low, low))
    name = " ".join(words[i:])
    if not name:
        raise BakerError(source, f"{where} names no file")
    path = resolve_file(name, source.parent, roots, source, where, f"material {material!r} is baked without it")
    return None if path is None else MtlTexture(path, source, statement, number, multiplier)


def _is_number(word: str) -> bool:
    try:
        float(word)
    except ValueError:
        return False
    return True


def read_mtl(path: Path, roots: list) -> dict[str, MtlMaterial]:
    """The materials of one MTL file by name. Numbers are checked; texture files resolve under ``roots``."""
    path = Path(path)
    try:
        text = path.read_bytes().decode("utf-8", errors="replace")
    except OSError as exc:
        raise BakerError(path, f"cannot read: {exc.strerror or exc}") from None
    materials: dict[str, MtlMaterial] = {}
    current = None
    for number, line in enumerate(text.replace("\\\r\n", " ").replace("\\\n", " ").splitlines(), start=1):
        words = line.split("#", 1)[0].split() if not line.lstrip().startswith("#") else []
        if not words:
            continue
        key = words[0].lower()
        where = f"line {number}: {words[0]}"
        if key == "newmtl":
            name = " ".join(words[1:])
            if not name:
                raise BakerError(path, f"{where} has no name")
            current = materials[name] = MtlMaterial(name, path)
            continue
        if key not in COLOR_STATEMENTS and key not in SCALAR_STATEMENTS and key not in TEXTURE_STATEMENTS:
            continue  # Ka, Ks, Ni, illum, map_Ks, ...: not part of the mapping
        if current is None:
            raise BakerError(path, f"{where} before any newmtl")
        if key in COLOR_STATEMENTS:
            values = _numbers(words[1:], path, where, (1, 3))
            if len(values) == 2:
                raise BakerError(path, f"{where} expects 1 or 3 numbers, got 2")
            setattr(current, COLOR_STATEMENTS[key], tuple(values * 3 if len(values) == 1 else values))
        elif key in SCALAR_STATEMENTS:
            args = words[1:]
            if key == "d" and args and args[0].lower() == "-halo":
                args = args[1:]  # the halo variant: the factor is still the dissolve
            value = _numbers(args, path, where, (1, 1))[0]
            if key == "ns" and value < 0:
                raise BakerError(path, f"{where}: a negative exponent ({value:g}) has no meaning")
            if key == "tr":
                current.dissolve = 1.0 - value
            else:
                setattr(current, SCALAR_STATEMENTS[key], value)
        else:
            texture = _texture(words[1:], path, where, words[0], number, roots, current.name)
            if texture is not None:
                current.textures[TEXTURE_STATEMENTS[key]] = texture
            else:  # the later statement wins even when its file is missing: the material has no such map
                current.textures.pop(TEXTURE_STATEMENTS[key], None)
    return materials


# ---------------------------------------------------------------------------------------------------------- to glTF
def _clamp01(value: float) -> float:
    return min(max(float(value), 0.0), 1.0)


class MaterialWriter:
    """Turns MTL materials into glTF materials of one document, each image added once."""

    def __init__(self, doc):
        self.doc = doc
        self.textures: dict = {}  # (role, files) -> texture index

    def material(self, mtl: MtlMaterial | None, textured: bool) -> dict:
        """The glTF material for ``mtl`` (:data:`DIELECTRIC` for None). ``textured``: every primitive using it has
        TEXCOORD_0 (textures need it; without it they are left out)."""
        if mtl is None:
            return {"name": DIELECTRIC["name"], "pbrMetallicRoughness": dict(DIELECTRIC["pbrMetallicRoughness"])}
        out: dict = {"name": mtl.name}
        if mtl.roughness is not None:
            roughness = mtl.roughness
        elif mtl.shininess is not None:
            roughness = roughness_from_shininess(mtl.shininess)
        else:
            roughness = DEFAULT_ROUGHNESS
        alpha = _clamp01(1.0 if mtl.dissolve is None else mtl.dissolve)
        color = [_clamp01(c) for c in (mtl.diffuse or (1.0, 1.0, 1.0))] + [alpha]
        pbr = {"baseColorFactor": color, "metallicFactor": _clamp01(mtl.metallic or 0.0),
               "roughnessFactor": _clamp01(roughness)}
        out["pbrMetallicRoughness"] = pbr
        maps = mtl.textures if textured else {}
        if "diffuse" in maps or "dissolve" in maps:
            pbr["baseColorTexture"] = {"index": self.base_color_texture(maps.get("diffuse"), maps.get("dissolve"))}
        if "dissolve" in maps:
            out["alphaMode"] = "MASK" if alpha >= 1.0 else "BLEND"
        elif alpha < 1.0:
            out["alphaMode"] = "BLEND"
        normal = maps.get("normal") or maps.get("bump")
        if normal is not None:
            index = self.normal_texture(normal)
            if index is not None:
                out["normalTexture"] = {"index": index}
                if normal.bump_multiplier != 1.0:
                    out["normalTexture"]["scale"] = normal.bump_multiplier
        emissive = [max(float(c), 0.0) for c in mtl.emissive] if mtl.emissive else None
        if emissive is None and "emissive" in maps:
            emissive = [1.0, 1.0, 1.0]  # the map alone: glTF's default factor (0) would hide it
        if emissive and max(emissive) > 0:
            strength = max(emissive)
            if strength > 1.0:
                emissive = [c / strength for c in emissive]
                out.setdefault("extensions", {})[EMISSIVE_STRENGTH] = {"emissiveStrength": strength}
                self.doc.use_extension(EMISSIVE_STRENGTH)
            out["emissiveFactor"] = emissive
            if "emissive" in maps:
                out["emissiveTexture"] = {"index": self.file_texture(maps["emissive"])}
        return out

    # ------------------------------------------------------------------ images
    def _add(self, key, data: bytes, mime: str, name: str) -> int:
        if key not in self.textures:
            self.textures[key] = self.doc.add_texture(self.doc.add_image(data, mime, name), name=name)
        return self.textures[key]

    def file_texture(self, texture: MtlTexture) -> int:
        """A texture of the file as it is when it is a PNG or JPEG (glTF's image types), else re-encoded as PNG."""
        from baker.gltf.document import sniff_mime

        data = texture.path.read_bytes()
        mime = sniff_mime(data)
        if mime not in ("image/png", "image/jpeg"):
            from baker.gltf.images import encode_image

            data, mime = encode_image(self.pixels(texture)), "image/png"
        return self._add(("file", texture.path), data, mime, texture.path.stem)

    def pixels(self, texture: MtlTexture):
        from baker.gltf.images import read_image

        try:
            return read_image(texture.path)
        except BakerError:
            raise BakerError(texture.source, f"line {texture.line}: {texture.statement} {texture.path.name!r} is "
                                             "not an image baker can read") from None

    def base_color_texture(self, diffuse: MtlTexture | None, dissolve: MtlTexture | None) -> int:
        """``map_Kd`` as it is, or its colour with the alpha of ``map_d`` (one RGBA image, as glTF keeps alpha)."""
        import numpy as np

        if dissolve is None:
            return self.file_texture(diffuse)
        alpha_image = self.pixels(dissolve)
        if diffuse is not None and diffuse.path == dissolve.path and alpha_image.shape[2] == 4:
            return self.file_texture(diffuse)  # the usual export: one RGBA file named by both statements
        alpha = _unit(alpha_image[:, :, 3 if alpha_image.shape[2] in (2, 4) else 0][:, :, None]) \
            if alpha_image.shape[2] != 2 else _unit(alpha_image[:, :, 1:2])
        if diffuse is None:
            rgb = np.ones(alpha.shape[:2] + (3,), np.float32)
        else:
            colour = _unit(self.pixels(diffuse))
            rgb = colour[:, :, :3] if colour.shape[2] >= 3 else np.repeat(colour[:, :, :1], 3, axis=2)
            if alpha.shape[:2] != rgb.shape[:2]:  # nearest texel of the alpha map at each colour texel
                rows = (np.arange(rgb.shape[0]) * alpha.shape[0]) // rgb.shape[0]
                cols = (np.arange(rgb.shape[1]) * alpha.shape[1]) // rgb.shape[1]
                alpha = alpha[rows][:, cols]
        from baker.gltf.images import encode_image

        rgba = np.rint(np.concatenate([rgb, alpha], axis=2) * 255).astype(np.uint8)
        name = (diffuse or dissolve).path.stem + "_alpha"
        return self._add(("rgba", diffuse and diffuse.path, dissolve.path), encode_image(rgba), "image/png", name)

    def normal_texture(self, texture: MtlTexture) -> int | None:
        """The map as a normal map, or None when it is a height map (grey: R = G = B at every pixel)."""
        import numpy as np

        pixels = self.pixels(texture)
        if pixels.shape[2] < 3 or (np.array_equal(pixels[:, :, 0], pixels[:, :, 1])
                                   and np.array_equal(pixels[:, :, 1], pixels[:, :, 2])):
            return None
        return self.file_texture(texture)


def assign_materials(doc, mtl_by_mesh: dict) -> None:
    """Give every primitive of a converted document its material: ``mtl_by_mesh`` maps a mesh index to its
    :class:`MtlMaterial` (absent or None: the explicit dielectric). A material's textures are
    kept when every primitive using it has TEXCOORD_0."""
    meshes = doc.json.get("meshes", [])
    textured: dict = {}
    for m, mesh in enumerate(meshes):
        mtl = mtl_by_mesh.get(m)
        key = None if mtl is None else mtl.name
        textured[key] = textured.get(key, True) and all("TEXCOORD_0" in prim.get("attributes", {})
                                                          for prim in mesh.get("primitives", []))
    writer = MaterialWriter(doc)
    materials = doc.json["materials"] = []
    index_of: dict = {}
    for m, mesh in enumerate(meshes):
        mtl = mtl_by_mesh.get(m)
        key = None if mtl is None else mtl.name
        if key not in index_of:
            materials.append(writer.material(mtl, textured[key]))
            index_of[key] = len(materials) - 1
        for prim in mesh.get("primitives", []):
            prim["material"] = index_of[key]


def _unit(pixels):
    """Pixels of any stored type as float32 in [0, 1]."""
    import numpy as np

    if pixels.dtype.kind == "f":
        return np.clip(pixels.astype(np.float32), 0.0, 1.0)
    return pixels.astype(np.float32) / float(np.iinfo(pixels.dtype).max)
