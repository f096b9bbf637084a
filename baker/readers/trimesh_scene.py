"""The fallback reader: what trimesh reads (an OBJ or PLY the direct readers leave, every STL) or what
:mod:`baker.readers.usd` builds (a trimesh scene) converted to a glTF document through trimesh's GLB exporter, so
every bake and writer deals with one representation."""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from baker.errors import BakerError
from baker.geometry.angle_normals import seamless_vertex_normals, unit_normals
from baker.gltf.document import GltfDocument
from baker.readers.finite import refuse_non_finite
from baker.readers.mtl import assign_materials


class LibraryResolver:
    """What trimesh's OBJ reader may open: the OBJ's MTL files (already checked under the URI policy), served as
    one text so every material is known by name. Texture images are refused: baker reads them itself
    (:mod:`baker.readers.mtl`), under the same policy."""

    def __init__(self, libraries: list):
        self.text = utf8(b"\n".join(p.read_bytes() for p in libraries))

    def __getitem__(self, name: str) -> bytes:  # trimesh asks for the mtllib this way
        return self.text

    def get(self, name: str) -> bytes:  # ... and for texture images this way
        raise OSError(f"{name}: read by baker.readers.mtl")


def utf8(data: bytes) -> bytes:
    """Text bytes as UTF-8: unchanged when they are, else read as Latin-1 (every byte is a character there). trimesh
    decodes text that is not UTF-8 by guessing its encoding with ``charset_normalizer``, which baker does not
    depend on (a PNG renamed .obj failed with "No module named 'charset_normalizer'"); this way it never guesses,
    and the same bytes always give the same names."""
    try:
        data.decode("utf-8")
        return data
    except UnicodeDecodeError:
        return data.decode("latin-1").encode("utf-8")


def utf8_copy(path: Path, folder: Path) -> Path:
    """``path`` itself when trimesh can decode its text as UTF-8, else a copy of the same name in ``folder`` that it
    can: an OBJ or ASCII STL transcoded (:func:`utf8`); a binary STL's 80-byte header (which trimesh decodes as its
    name) with its non-ASCII bytes made ``?``."""
    data = path.read_bytes()
    suffix = path.suffix.lower()
    if suffix == ".stl" and len(data) >= 84 and 84 + 50 * int.from_bytes(data[80:84], "little") == len(data):
        header = data[:80]
        fixed = bytes(b if b < 128 else 63 for b in header)
        if fixed == header:
            return path
        data = fixed + data[80:]
    elif suffix in (".obj", ".stl"):
        fixed = utf8(data)
        if fixed is data:
            return path
        data = fixed
    else:
        return path
    copy = folder / path.name
    copy.write_bytes(data)
    return copy


def load_trimesh(path: Path, **kwargs):
    """The mesh file read by trimesh (``kwargs``: trimesh's, e.g. an OBJ's ``resolver``). Its header, when it has
    one, was checked by the format's reader first; text that is not UTF-8 is handed over as UTF-8
    (:func:`utf8_copy`)."""
    import tempfile

    import trimesh

    with tempfile.TemporaryDirectory(prefix=".baker-utf8-") as folder:
        source = utf8_copy(path, Path(folder))
        try:
            # process=False keeps the file's vertices (no merging); OBJ vertices are split where UVs differ
            return trimesh.load(str(source), process=False, **kwargs)
        except Exception as exc:  # trimesh raises many types for malformed files
            raise BakerError(path, f"cannot read mesh: {exc}") from None


def doc_from_trimesh_scene(path: Path, loaded, materials: dict | None = None, locate=None) -> GltfDocument:
    """Convert what trimesh (or our USD reader) loaded into a glTF document; each mesh gets the MTL material
    ``materials`` holds under its trimesh material's name, or the explicit dielectric. ``locate(path)``: where in
    the file a non-finite number sits (the format reader's), for the refusal."""
    import trimesh

    if isinstance(loaded, trimesh.Trimesh):
        scene = trimesh.Scene(loaded)
    elif isinstance(loaded, trimesh.Scene):
        scene = loaded
    else:
        raise BakerError(path, "no triangle faces (the file holds points or lines only)")
    meshes = [g for g in scene.geometry.values() if isinstance(g, trimesh.Trimesh)]
    if not meshes or sum(len(g.faces) for g in meshes) == 0:
        raise BakerError(path, "no triangle faces")
    # trimesh's own material (an MTL's, or a 2x2 grey image it invents without one) is replaced by baker's: its
    # export would re-encode images and write a metallic default. UVs stay
    material_of = {}
    for key, g in scene.geometry.items():
        if getattr(g.visual, "kind", None) == "texture":
            material_of[key] = (materials or {}).get(getattr(g.visual.material, "name", None))
            g.visual.material = trimesh.visual.material.PBRMaterial()
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        glb = Path(d) / "converted.glb"
        # NaN or float32 overflow in the input would warn here: check_finite refuses such a file first
        check_finite(path, meshes, locate or (lambda _: None))
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            computed = {}
            if path.suffix.lower() in (".obj", ".ply"):  # an STL's facets carry their normals: it stays faceted
                # meshes the file gave no normals: smooth across UV and material seams, as the direct OBJ reader
                without_normals = [i for i, g in enumerate(meshes)
                                   if "vertex_normals" not in getattr(getattr(g, "_cache", None), "cache", {})]
                if without_normals:
                    parts = [(np.asarray(meshes[i].vertices), np.asarray(meshes[i].faces), None)
                             for i in without_normals]
                    computed = dict(zip(without_normals, seamless_vertex_normals(parts)))
            for i, g in enumerate(meshes):
                g.vertex_normals = unit_normals(computed[i] if i in computed else g.vertex_normals)
            glb.write_bytes(trimesh.exchange.gltf.export_glb(scene, include_normals=True))
        try:
            doc = GltfDocument.load(glb)
        except BakerError as exc:  # name the input, not the converted file
            raise BakerError(path, exc.message) from None
    doc.path = path
    # trimesh leaves bufferView.target unset; say which views are vertex data and which are indices
    for mesh in doc.json.get("meshes", []):
        for prim in mesh.get("primitives", []):
            for acc in prim.get("attributes", {}).values():
                set_view_target(doc, acc, 34962)
            if "indices" in prim:
                set_view_target(doc, prim["indices"], 34963)
    doc.json["asset"]["generator"] = "baker (converted from " + path.suffix.lower().lstrip(".") + ")"
    for key in ("materials", "textures", "images", "samplers"):
        doc.json.pop(key, None)  # only the (image-less) PBRMaterial placeholders were written
    assign_materials(doc, {m: material_of.get(mesh.get("name")) for m, mesh in enumerate(doc.json.get("meshes", []))})
    return doc


def check_finite(path: Path, meshes: list, locate) -> None:
    """Refuse NaN, infinite (or beyond float32, which glTF stores) positions, normals or UVs read from a mesh file,
    naming the OBJ line / PLY element / STL triangle where ``locate`` can. Normals are checked only when the file had
    them (trimesh keeps them in its cache; computing them here would cost time)."""
    for m, g in enumerate(meshes):
        named = {"POSITION": g.vertices, "TEXCOORD_0": getattr(g.visual, "uv", None)}
        cache = getattr(getattr(g, "_cache", None), "cache", {})
        named["NORMAL"] = cache.get("vertex_normals")
        for name, values in named.items():
            if values is None:
                continue
            values = np.asarray(values)
            if values.dtype.kind != "f":
                continue
            refuse_non_finite(path, values, f"mesh {m} {name}", locate)


def set_view_target(doc: GltfDocument, accessor: int, target: int) -> None:
    view = doc.json["accessors"][accessor].get("bufferView")
    if view is not None:
        doc.json["bufferViews"][view].setdefault("target", target)
