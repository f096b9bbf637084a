"""Import side: after Blender's glTF importer has built the scene, turn each BAKER_* extension into Blender data.

What appears where (see ../README.md): the stock importer already makes every ``_NAME`` custom attribute a FLOAT_VECTOR
point attribute (baker writes them all as FLOAT VEC3, scalars in x); this module adds
- on each material with BAKER_* extensions: the payload (custom property ``baker_gltf``), the extension textures as
  packed images, and node groups (translucency, skin LUT, toon ramp, tonal art map) mixed in after the Principled BSDF
  with factor 0, so the material looks as before until an artist raises the factor; the caustics (a light map, the
  first frame) are added to the surface, so they show as imported;
- on each mesh with BAKER_* / EXT_mesh_primitive_edge_visibility primitives: the payload (property ``baker_gltf``,
  accessor data included), hard and crease edges of BAKER_edges as Freestyle edge marks, the hard ones also sharp; fin
  primitives (edges, fur) are kept in the payload and hidden in Blender;
- BAKER_hair primitives: a Curves object (one curve per strand, ``_STRAND_TANGENT`` / ``_STRAND_PARAM`` and the
  width as attributes), the original line mesh hidden;
- root and node extensions (BAKER_glyph_atlas, BAKER_text): the payload on the scene / the node's object.
"""
from __future__ import annotations

import json

import bpy
import numpy as np

from . import glb, nodes, refs

PROPERTY = "baker_gltf"
# BAKER_edges flag bits (baker/geometry/edge_codes.py): crease, normal seam ("hard"), boundary
EDGE_CREASE, EDGE_NORMAL_SEAM, EDGE_BOUNDARY = 1 << 2, 1 << 7, 1 << 0


def to_blender(points: np.ndarray) -> np.ndarray:
    """glTF Y up -> Blender Z up, as the importer converts: (x, y, z) -> (x, -z, y)."""
    points = np.asarray(points, np.float64).reshape(-1, 3)
    return np.stack([points[:, 0], -points[:, 2], points[:, 1]], axis=1)


def position_key(point) -> bytes:
    return np.round(np.asarray(point, np.float64), 5).tobytes()


def store_accessors(gltf: dict, binary: bytes, name: str, ext: dict) -> dict:
    """{accessor index: stored array} for every accessor an extension object references."""
    return {str(container[key]): {"array": glb.encode_array(glb.accessor(gltf, binary, container[key])),
                                  "accessor": gltf["accessors"][container[key]]}
            for container, key, _ in refs.accessor_slots(name, ext)}


def store_textures(gltf: dict, binary: bytes, exts: dict) -> dict:
    """{texture index: texture, sampler, image JSON and the packed Blender image holding its bytes} for every texture
    the extension objects reference."""
    out = {}
    for container, key in refs.texture_slots(exts):
        index = container[key]
        if str(index) in out or not 0 <= index < len(gltf.get("textures") or []):
            continue
        texture = gltf["textures"][index]
        source = texture.get("source")
        image_json = dict(gltf["images"][source]) if source is not None else {}
        data = b""
        if "bufferView" in image_json:
            view = gltf["bufferViews"][image_json["bufferView"]]
            data = binary[view.get("byteOffset", 0):view.get("byteOffset", 0) + view["byteLength"]]
        image = bpy.data.images.new(f"baker texture {index} {image_json.get('name', '')}".strip(), 8, 8)
        if data:
            image.pack(data=data, data_len=len(data))
            image.source = "FILE"
            image.filepath_raw = f"//{image.name}.png"
        image.colorspace_settings.name = "Non-Color"
        sampler = gltf["samplers"][texture["sampler"]] if "sampler" in texture else None
        out[str(index)] = {"texture": texture, "sampler": sampler, "image": image_json, "blender_image": image.name}
    return out


def import_materials(gltf_importer, gltf: dict, binary: bytes) -> None:
    for index, material in enumerate(gltf.get("materials") or []):
        exts = {k: v for k, v in (material.get("extensions") or {}).items() if refs.ours(k)}
        if exts and "KHR_materials_volume" in (material.get("extensions") or {}):
            # BAKER_thickness writes KHR_materials_volume.thicknessTexture too; Blender exports it only for
            # transmissive materials, so keep it with the payload (restored only where Blender wrote none)
            exts["KHR_materials_volume"] = material["extensions"]["KHR_materials_volume"]
        if not exts:
            continue
        textures = store_textures(gltf, binary, exts)
        made = getattr(gltf_importer.data.materials[index], "blender_material", None) or {}
        for name in made.values():
            mat = bpy.data.materials.get(name)
            if mat is None:
                continue
            accessors = {}  # the accessors a material extension names (coverage mip chains)
            for name, ext in exts.items():
                accessors.update(store_accessors(gltf, binary, name, ext) if isinstance(ext, dict) else {})
            # the material's own base colour texture, which an extension may name too (BAKER_hair_cards'
            # coverage mip chain): on export it is Blender's exported baseColorTexture, not a copy
            base = ((material.get("pbrMetallicRoughness") or {}).get("baseColorTexture") or {}).get("index")
            mat[PROPERTY] = json.dumps({"index": index, "name": material.get("name"), "extensions": exts,
                                        "textures": textures, "accessors": accessors, "baseColorTexture": base})
            nodes.add_material_groups(mat, exts, textures)


def blender_object(gltf_importer, node_index: int):
    vnode = gltf_importer.vnodes.get(node_index) if hasattr(gltf_importer.vnodes, "get") else None
    name = getattr(vnode, "blender_object", None) or getattr(vnode, "blender_object_name", None)
    if isinstance(name, str):
        return bpy.data.objects.get(name)
    return name


def mark_edges(mesh, positions: np.ndarray, edges: np.ndarray, flags: np.ndarray) -> dict:
    """Freestyle edge marks (``use_freestyle_mark`` in Blender 4.x, the ``freestyle_edge`` attribute from 5.0) on every
    Blender edge whose end positions match a hard (normal seam) or crease BAKER_edges edge, and Sharp on the hard
    ones. Crease edges are not marked sharp: Blender would then split the imported (smooth) custom normals there and
    the untouched mesh would shade differently."""
    points = to_blender(positions)

    def pair_keys(selected):
        keys = set()
        for v0, v1 in edges[selected]:
            a, b = position_key(points[v0]), position_key(points[v1])
            keys.add((a, b) if a <= b else (b, a))
        return keys

    wanted = {"freestyle_edge": pair_keys((flags & (EDGE_CREASE | EDGE_NORMAL_SEAM)) != 0),
              "sharp_edge": pair_keys((flags & EDGE_NORMAL_SEAM) != 0)}
    co = np.zeros(len(mesh.vertices) * 3, np.float32)
    mesh.vertices.foreach_get("co", co)
    keys = [position_key(p) for p in co.reshape(-1, 3)]
    pairs = np.zeros(len(mesh.edges) * 2, np.int32)
    mesh.edges.foreach_get("vertices", pairs)
    edge_keys = [(keys[i], keys[j]) if keys[i] <= keys[j] else (keys[j], keys[i]) for i, j in pairs.reshape(-1, 2)]
    counts = {}
    for name, keep in wanted.items():
        marks = np.fromiter((k in keep for k in edge_keys), bool, len(edge_keys))
        current = np.zeros(len(mesh.edges), bool)
        if name == "freestyle_edge" and not freestyle_marks_are_attributes():
            # Blender < 5 keeps Freestyle marks in their own edge layer (MeshEdge.use_freestyle_mark): Freestyle and
            # Line Art ignore a generic "freestyle_edge" attribute there, and 5.0's versioning would clash with one
            mesh.edges.foreach_get("use_freestyle_mark", current)
            mesh.edges.foreach_set("use_freestyle_mark", current | marks)
        else:
            attribute = mesh.attributes.get(name) or mesh.attributes.new(name, "BOOLEAN", "EDGE")
            attribute.data.foreach_get("value", current)
            attribute.data.foreach_set("value", current | marks)
        counts[name] = int(marks.sum())
    return counts


def freestyle_marks_are_attributes() -> bool:
    """Blender 5.0 moved Freestyle edge marks into the generic boolean edge attribute ``freestyle_edge``; before,
    they were a layer of their own, read and written as ``MeshEdge.use_freestyle_mark``."""
    return bpy.app.version >= (5, 0, 0)


def make_curves(name: str, positions: np.ndarray, tangents: np.ndarray, param: np.ndarray, strands: int,
                per_strand: int, radius: np.ndarray, collection) -> object:
    """A Curves object: one poly curve per strand, guide data as point attributes."""
    curves = bpy.data.hair_curves.new(name) if hasattr(bpy.data, "hair_curves") else bpy.data.curves.new(name, "CURVES")
    curves.add_curves([per_strand] * strands)
    curves.points.foreach_set("position", to_blender(positions).astype(np.float32).reshape(-1))
    curves.points.foreach_set("radius", radius.astype(np.float32))
    for attr_name, values in (("_STRAND_TANGENT", to_blender(tangents)), ("_STRAND_PARAM", param)):
        values = np.asarray(values, np.float32)
        kind = "FLOAT_VECTOR" if values.ndim == 2 else "FLOAT"
        attribute = curves.attributes.new(attr_name, kind, "POINT")
        attribute.data.foreach_set("vector" if kind == "FLOAT_VECTOR" else "value", values.reshape(-1))
    obj = bpy.data.objects.new(name, curves)
    collection.objects.link(obj)
    return obj


def import_meshes(gltf_importer, gltf: dict, binary: bytes) -> None:
    for node_index, node in enumerate(gltf.get("nodes") or []):
        obj = blender_object(gltf_importer, node_index)
        if obj is None:
            continue
        node_exts = {k: v for k, v in (node.get("extensions") or {}).items() if refs.ours(k)}
        if node_exts:
            accessors = {}
            for name, ext in node_exts.items():  # BAKER_text's shaped run: glyph and position accessors
                accessors.update(store_accessors(gltf, binary, name, ext))
            obj[PROPERTY + "_node"] = json.dumps({"index": node_index, "extensions": node_exts,
                                                  "accessors": accessors})
        if "mesh" not in node or obj.type != "MESH":
            continue
        mesh_json = gltf["meshes"][node["mesh"]]
        prims = mesh_json.get("primitives") or []
        stored, derived, any_ours = [], False, False
        for p, prim in enumerate(prims):
            exts = {k: v for k, v in (prim.get("extensions") or {}).items() if refs.ours(k)}
            any_ours |= bool(exts)
            entry = {"extensions": exts, "material": None, "mode": prim.get("mode", 4), "accessors": {}}
            if "material" in prim:
                made = getattr(gltf_importer.data.materials[prim["material"]], "blender_material", None) or {}
                entry["material"] = (gltf["materials"][prim["material"]].get("name"), prim["material"])
                entry["blender_materials"] = sorted(made.values())
            for name, ext in exts.items():
                entry["accessors"].update(store_accessors(gltf, binary, name, ext))
            is_derived = any("finsOf" in (e or {}) for e in exts.values()) or "BAKER_hair" in exts
            entry["derived"] = is_derived
            if is_derived and "material" in prim:
                # Blender exports only materials that faces use: keep the strands' material to put it back
                material_json = json.loads(json.dumps(gltf["materials"][prim["material"]]))
                entry["material_json"] = material_json
                entry["material_textures"] = store_textures(gltf, binary, material_json)
            if exts or is_derived:
                # POSITION (and indices) to match vertices by position on export; derived primitives keep everything
                keep = dict(prim["attributes"]) if is_derived else {"POSITION": prim["attributes"]["POSITION"]}
                entry["attributes"] = {k: {"array": glb.encode_array(glb.accessor(gltf, binary, a)),
                                           "accessor": gltf["accessors"][a]} for k, a in keep.items()}
                if "indices" in prim:
                    entry["indices"] = {"array": glb.encode_array(glb.accessor(gltf, binary, prim["indices"])),
                                        "accessor": gltf["accessors"][prim["indices"]]}
            derived |= is_derived
            stored.append(entry)
            edges_ext = exts.get("BAKER_edges") or {}
            if "edges" in edges_ext and "flags" in edges_ext:
                positions = glb.values(gltf, binary, prim["attributes"]["POSITION"])
                pairs = glb.accessor(gltf, binary, edges_ext["edges"]).astype(np.int64).reshape(-1, 2)
                flags = glb.accessor(gltf, binary, edges_ext["flags"]).astype(np.int64)
                mark_edges(obj.data, positions, pairs, flags)
            if "BAKER_hair" in exts:
                hair = exts["BAKER_hair"]
                attrs = prim["attributes"]
                s, v = int(hair["strandCount"]), int(hair["verticesPerStrand"])
                positions = glb.values(gltf, binary, attrs["POSITION"])
                tangents = glb.values(gltf, binary, attrs[hair.get("tangentAttribute", "_STRAND_TANGENT")])
                param = glb.values(gltf, binary, attrs[hair.get("paramAttribute", "_STRAND_PARAM")])
                param = param[:, 0] if param.ndim == 2 else param
                along = np.tile(np.linspace(0.0, 1.0, v), s)
                width = float(hair.get("rootWidth", 0.0)) * (1 - along) + float(hair.get("tipWidth", 0.0)) * along
                if "widthScale" in hair:
                    width = width * np.repeat(glb.values(gltf, binary, hair["widthScale"]).reshape(-1), v)
                curves = make_curves(f"{obj.name} {hair.get('strandSet', 'strands')}", positions, tangents, param,
                                     s, v, width / 2, obj.users_collection[0])
                curves.parent = obj.parent
                curves.matrix_world = obj.matrix_world
                curves[PROPERTY + "_source"] = json.dumps({"mesh": obj.data.name, "primitive": p})
        if any_ours or derived:
            obj.data[PROPERTY] = json.dumps({"mesh": node["mesh"], "name": mesh_json.get("name"),
                                             "primitives": stored})
        if derived and all(e["derived"] for e in stored):
            obj.hide_render = True  # hair lines: the Curves object stands in for them
            obj.hide_set(True)
        elif derived:
            hide_derived_faces(obj.data)
            surface = {n for prim, e in zip(prims, stored) if not e["derived"] for n in prim["attributes"]}
            for name in {n for prim in prims for n in prim["attributes"]} - surface:
                if name in obj.data.attributes:  # fin-only attributes (zero on the surface): not the surface's data
                    obj.data.attributes.remove(obj.data.attributes[name])


def hide_derived_faces(mesh) -> None:
    """Fin quads are degenerate (v0, v1, v1, v0): drop zero-area faces so Blender shows the surface alone (the fin
    primitives come back from the payload on export)."""
    import bmesh

    bm = bmesh.new()
    bm.from_mesh(mesh)
    dead = [f for f in bm.faces if f.calc_area() <= 1e-14]
    if dead:
        bmesh.ops.delete(bm, geom=dead, context="FACES_ONLY")
        loose = [v for v in bm.verts if not v.link_faces]
        bmesh.ops.delete(bm, geom=loose, context="VERTS")
        bm.to_mesh(mesh)
    bm.free()


def import_root(gltf: dict, binary: bytes) -> None:
    exts = {k: v for k, v in (gltf.get("extensions") or {}).items() if refs.ours(k)}
    if not exts:
        return
    accessors = {}
    for name, ext in exts.items():
        accessors.update(store_accessors(gltf, binary, name, ext))
    bpy.context.scene[PROPERTY] = json.dumps({"extensions": exts, "accessors": accessors,
                                              "textures": store_textures(gltf, binary, exts),
                                              "extensionsUsed": [e for e in gltf.get("extensionsUsed", [])
                                                                 if refs.ours(e)]})


def after_import(gltf_importer) -> None:
    path = gltf_importer.import_settings["filepath"]
    gltf, binary = glb.load(path)
    import_materials(gltf_importer, gltf, binary)
    import_meshes(gltf_importer, gltf, binary)
    import_root(gltf, binary)
