"""Export side: after Blender's glTF exporter wrote the file, put every BAKER_* extension back into it.

Blender writes the edited geometry and (with the add-on's pre-export hook turning "Include > Attributes" on) the
``_NAME`` attributes as they are on the mesh now, so per-vertex data follows the artist's edits. The extension
objects stored at import come back unchanged (JSON equal) with their references renumbered: textures from the packed
images, accessors from the stored arrays, vertex indices (BAKER_edges edges / opposite vertices, silhouette mates)
remapped to the exported vertex at the same position, per-triangle data (edge visibility, wireframe mask) remapped
to the exported triangle with the same corner positions, derived primitives (edge and fur fins, hair strands)
appended as they were.
"""
from __future__ import annotations

import copy
import json

import bpy
import numpy as np

from . import glb, refs
from .importing import PROPERTY

ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963
PER_TRIANGLE_BITS = {(refs.EDGE_VISIBILITY, "visibility"): 2, ("BAKER_edges", "wireframeMask"): 1}


class Rewriter:
    def __init__(self, path: str):
        self.path = path
        self.gltf, binary = glb.load(path)
        self.writer = glb.Writer(self.gltf, binary)
        self.textures = {}  # Blender image name -> new texture index
        self.used = set()
        self.removed = False

    # ---------------------------------------------------------------- references
    def texture(self, stored: dict) -> int:
        name = stored["blender_image"]
        if name in self.textures:
            return self.textures[name]
        gltf = self.gltf
        image = bpy.data.images.get(name)
        data = bytes(image.packed_file.data) if image is not None and image.packed_file else b""
        image_json = {k: v for k, v in stored["image"].items() if k not in ("bufferView", "uri")}
        if data:
            image_json["bufferView"] = self.writer.view(data)
            image_json.setdefault("mimeType", "image/png")
        images = gltf.setdefault("images", [])
        images.append(image_json)
        texture = {k: v for k, v in stored["texture"].items() if k not in ("source", "sampler")}
        texture["source"] = len(images) - 1
        if stored.get("sampler") is not None:
            samplers = gltf.setdefault("samplers", [])
            if stored["sampler"] in samplers:
                texture["sampler"] = samplers.index(stored["sampler"])
            else:
                samplers.append(stored["sampler"])
                texture["sampler"] = len(samplers) - 1
        textures = gltf.setdefault("textures", [])
        textures.append(texture)
        self.textures[name] = len(textures) - 1
        return self.textures[name]

    def retexture(self, ext: dict, stored_textures: dict, exported: dict | None = None) -> None:
        """Point every texture reference in ``ext`` at its exported texture: ``exported`` (stored index -> index of a
        texture Blender exported itself, e.g. the material's base colour), else a texture added from the stored
        image."""
        for container, key in refs.texture_slots(ext):
            if exported and container[key] in exported:
                container[key] = exported[container[key]]
                continue
            stored = stored_textures.get(str(container[key]))
            if stored is not None:
                container[key] = self.texture(stored)

    def add_accessor(self, stored: dict, values=None, target=None) -> int:
        values = glb.decode_array(stored["array"]) if values is None else values
        return self.writer.accessor(stored["accessor"], values, target)

    # ---------------------------------------------------------------- meshes
    def material_index(self, name) -> int | None:
        for i, mat in enumerate(self.gltf.get("materials") or []):
            if mat.get("name") == name:
                return i
        return None

    def exported_positions(self, prim: dict) -> np.ndarray:
        return glb.accessor(self.gltf, bytes(self.writer.binary), prim["attributes"]["POSITION"]).astype(np.float32)

    def exported_triangles(self, prim: dict, count: int) -> np.ndarray:
        if "indices" in prim:
            return glb.accessor(self.gltf, bytes(self.writer.binary), prim["indices"]).astype(np.int64).reshape(-1, 3)
        return np.arange(count).reshape(-1, 3)

    def rewrite_mesh(self, mesh_index: int, blender_mesh, payload: dict, moved: dict) -> None:
        exported = self.gltf["meshes"][mesh_index]
        prims = exported["primitives"]
        stored = payload["primitives"]
        # exported primitive for each stored surface primitive: same material name, in order
        taken, target_of = set(), {}
        for s, entry in enumerate(stored):
            if entry["derived"]:
                continue
            wanted = set(entry.get("blender_materials") or []) | ({entry["material"][0]} if entry["material"] else set())
            for p, prim in enumerate(prims):
                name = self.gltf["materials"][prim["material"]].get("name") if "material" in prim else None
                if p not in taken and (name in wanted or (name is None and not wanted)):
                    taken.add(p)
                    target_of[s] = p
                    break
        # derived primitives come back as they were
        for s, entry in enumerate(stored):
            if not entry["derived"]:
                continue
            prim = {"attributes": {k: self.add_accessor(v, target=ARRAY_BUFFER) for k, v in entry["attributes"].items()},
                    "mode": entry["mode"]}
            if "indices" in entry:
                prim["indices"] = self.add_accessor(entry["indices"], target=ELEMENT_ARRAY_BUFFER)
            if entry["material"]:
                index = next((self.material_index(n) for n in entry.get("blender_materials") or []
                              if self.material_index(n) is not None), self.material_index(entry["material"][0]))
                if index is None and "material_json" in entry:
                    material = copy.deepcopy(entry["material_json"])
                    self.retexture(material, entry.get("material_textures") or {})
                    materials = self.gltf.setdefault("materials", [])
                    materials.append(material)
                    index = len(materials) - 1
                if index is not None:
                    prim["material"] = index
            prims.append(prim)
            target_of[s] = len(prims) - 1
        for s, p in target_of.items():
            moved[(payload["mesh"], s)] = (mesh_index, p)
        for s, entry in enumerate(stored):
            if s not in target_of or not entry["extensions"]:
                continue
            prim = prims[target_of[s]]
            exts = copy.deepcopy(entry["extensions"])
            vertex_map = triangle_map = None
            if not entry["derived"]:
                original = glb.decode_array(entry["attributes"]["POSITION"]["array"]).astype(np.float32)
                now = self.exported_positions(prim)
                vertex_map = map_by_position(original, now)
            for name, ext in exts.items():
                visibility = None
                if name == refs.EDGE_VISIBILITY and vertex_map is not None and isinstance(ext.get("visibility"), int):
                    visibility = glb.decode_array(entry["accessors"][str(ext["visibility"])]["array"])
                for container, key, path in list(refs.accessor_slots(name, ext)):
                    stored_acc = entry["accessors"][str(container[key])]
                    values = glb.decode_array(stored_acc["array"])
                    if visibility is not None and path == "silhouetteMates":
                        if triangle_map is None:
                            triangle_map = self.triangle_map(entry, prim, original, now)
                        # one mate per silhouette edge (code 1) in bitfield order: follow the triangles' new order
                        values = reorder_mates(values, visibility, triangle_map)
                    if vertex_map is not None and (name, path) in refs.VERTEX_INDEX_ACCESSORS:
                        values = vertex_map[values.astype(np.int64)].astype(values.dtype)
                    bits = PER_TRIANGLE_BITS.get((name, path))
                    if bits and vertex_map is not None:
                        if triangle_map is None:
                            triangle_map = self.triangle_map(entry, prim, original, now)
                        values = remap_triangle_bits(values, triangle_map, bits)
                    container[key] = self.add_accessor(stored_acc, values)
                for key in ("fins", "finsOf"):
                    if isinstance(ext.get(key), int):
                        ext[key] = target_of.get(ext[key], ext[key])
                guides = ext.get("guides")
                if isinstance(guides, dict) and isinstance(guides.get("primitive"), int):
                    guides["primitive"] = target_of.get(guides["primitive"], guides["primitive"])
                self.used.add(name)
            prim.setdefault("extensions", {}).update(exts)

    def triangle_map(self, entry: dict, prim: dict, original: np.ndarray, now: np.ndarray):
        """For each exported triangle: (original triangle, rotation k so exported corner i = original corner i+k,
        mirrored flag); -1 where no original triangle has the same corner positions."""
        original_tris = glb.decode_array(entry["indices"]["array"]).astype(np.int64).reshape(-1, 3) \
            if "indices" in entry else np.arange(len(original)).reshape(-1, 3)
        return match_triangles(original[original_tris], now[self.exported_triangles(prim, len(now))])

    # ---------------------------------------------------------------- the whole file
    def run(self) -> None:
        gltf = self.gltf
        moved = {}
        by_name = {}
        for mesh in bpy.data.meshes:
            if PROPERTY in mesh:
                by_name.setdefault(mesh.name, (mesh, json.loads(mesh[PROPERTY])))
        handled = set()
        for m, exported in enumerate(gltf.get("meshes") or []):
            found = by_name.get(exported.get("name"))
            if found is not None:
                self.rewrite_mesh(m, *found, moved)
                handled.add(exported.get("name"))
        for name, (mesh, payload) in by_name.items():
            if name in handled or not any(e["derived"] for e in payload["primitives"]):
                continue
            # a mesh of derived primitives only (hair lines): Blender exported nothing for it
            meshes = gltf.setdefault("meshes", [])
            meshes.append({"name": payload.get("name") or name, "primitives": []})
            self.rewrite_mesh(len(meshes) - 1, mesh, payload, moved)
            nodes = gltf.setdefault("nodes", [])
            owners = [o.name for o in bpy.data.objects if o.type == "MESH" and o.data == mesh]
            node = next((n for n in nodes if n.get("name") in owners and "mesh" not in n), None)
            if node is not None:  # Blender wrote the object as an empty node: give it its mesh back
                node["mesh"] = len(meshes) - 1
            else:
                nodes.append({"name": owners[0] if owners else name, "mesh": len(meshes) - 1})
                scenes = gltf.setdefault("scenes", [{"nodes": []}])
                scenes[gltf.get("scene", 0)].setdefault("nodes", []).append(len(nodes) - 1)
        # the Curves objects made for strands are Blender's view of the hair primitive, not scene content
        stand_ins = {o.name for o in bpy.data.objects if PROPERTY + "_source" in o}
        self.removed = remove_empty_nodes(gltf, stand_ins)
        for mat in bpy.data.materials:
            if PROPERTY not in mat:
                continue
            payload = json.loads(mat[PROPERTY])
            index = self.material_index(mat.name)
            if index is None:
                index = self.material_index(payload.get("name"))
            if index is None:
                continue
            exts = copy.deepcopy(payload["extensions"])
            base = ((gltf["materials"][index].get("pbrMetallicRoughness") or {}).get("baseColorTexture") or {}) \
                .get("index")
            own = {payload["baseColorTexture"]: base} if payload.get("baseColorTexture") is not None and \
                base is not None else {}
            self.retexture(exts, payload["textures"], own)
            for name, ext in exts.items():
                for container, key, _ in list(refs.accessor_slots(name, ext)):
                    container[key] = self.add_accessor(payload.get("accessors", {})[str(container[key])])
            for ext in exts.values():
                for ref in ext.get("fins", []) if isinstance(ext.get("fins"), list) else []:
                    if isinstance(ref, dict) and (ref.get("mesh"), ref.get("primitive")) is not None:
                        new = moved.get((ref.get("mesh"), ref.get("primitive")))
                        if new is not None:
                            ref["mesh"], ref["primitive"] = new
            target = gltf["materials"][index].setdefault("extensions", {})
            for name, ext in exts.items():
                if name.startswith("KHR_"):
                    target.setdefault(name, ext)  # Blender's own (an artist's edit) wins over the stored one
                else:
                    target[name] = ext
            self.used.update(exts)
        scene = bpy.context.scene
        if PROPERTY in scene:
            payload = json.loads(scene[PROPERTY])
            exts = copy.deepcopy(payload["extensions"])
            for name, ext in exts.items():
                for container, key, _ in list(refs.accessor_slots(name, ext)):
                    container[key] = self.add_accessor(payload["accessors"][str(container[key])])
            self.retexture(exts, payload["textures"])
            gltf.setdefault("extensions", {}).update(exts)
            self.used.update(exts)
        for obj in bpy.data.objects:
            key = PROPERTY + "_node"
            if key not in obj:
                continue
            payload = json.loads(obj[key])
            for node in gltf.get("nodes") or []:
                if node.get("name") == obj.name:
                    exts = copy.deepcopy(payload["extensions"])
                    for name, ext in exts.items():
                        for container, slot, _ in list(refs.accessor_slots(name, ext)):
                            container[slot] = self.add_accessor(payload["accessors"][str(container[slot])])
                    node.setdefault("extensions", {}).update(exts)
                    self.used.update(payload["extensions"])
        if not self.used and not self.removed:
            return  # nothing of baker's in this scene: leave Blender's file as it wrote it
        used = gltf.setdefault("extensionsUsed", [])
        used.extend(sorted(n for n in self.used if n not in used))
        self.writer.save(self.path)


def map_by_position(original: np.ndarray, now: np.ndarray) -> np.ndarray:
    """For each original vertex, an exported vertex at the same position (the nearest one if it moved)."""
    index = {}
    for i, p in enumerate(np.ascontiguousarray(now, np.float32)):
        index.setdefault(p.tobytes(), i)
    out = np.full(len(original), -1, np.int64)
    for i, p in enumerate(np.ascontiguousarray(original, np.float32)):
        out[i] = index.get(p.tobytes(), -1)
    missing = np.flatnonzero(out < 0)
    for start in range(0, len(missing), 256):
        rows = missing[start:start + 256]
        d = ((original[rows, None, :] - now[None, :, :]) ** 2).sum(axis=2)
        out[rows] = d.argmin(axis=1)
    return out


def match_triangles(original: np.ndarray, now: np.ndarray):
    """original, now: (T, 3, 3) corner positions. Returns (source triangle, rotation) per exported triangle."""
    def key(tri):
        return b"".join(sorted(np.ascontiguousarray(tri, np.float32)[i].tobytes() for i in range(3)))
    table = {key(t): i for i, t in enumerate(original)}
    source = np.full(len(now), -1, np.int64)
    rotation = np.zeros(len(now), np.int64)
    for j, tri in enumerate(now):
        i = table.get(key(tri), -1)
        source[j] = i
        if i >= 0:
            first = np.ascontiguousarray(tri[0], np.float32).tobytes()
            corners = [np.ascontiguousarray(original[i][k], np.float32).tobytes() for k in range(3)]
            rotation[j] = corners.index(first) if first in corners else 0
    return source, rotation


def remap_triangle_bits(values: np.ndarray, triangle_map, bits: int) -> np.ndarray:
    """Per-triangle edge codes (``bits`` per edge, 3 edges per triangle) in the exported triangle order.
    2-bit codes are packed LSB first over the whole accessor (EXT_mesh_primitive_edge_visibility); 1-bit codes are one
    byte per triangle (BAKER_edges.wireframeMask). Edge k of a triangle joins corners k and k+1."""
    source, rotation = triangle_map
    values = np.asarray(values)
    if bits == 1:
        codes = np.stack([(values >> k) & 1 for k in range(3)], axis=1)
    else:
        flat = np.unpackbits(values.astype(np.uint8).reshape(-1), bitorder="little")
        pairs = flat[:(len(flat) // 2) * 2].reshape(-1, 2)
        codes = (pairs[:, 0] | (pairs[:, 1] << 1))[: 3 * (len(pairs) // 3)].reshape(-1, 3)
    out = np.zeros((len(source), 3), np.int64)
    for j, (i, k) in enumerate(zip(source, rotation)):
        if 0 <= i < len(codes):
            # exported corner c is original corner (c + k) % 3, so exported edge e is original edge (e + k) % 3
            # (orientation: Blender keeps the winding of each triangle)
            out[j] = codes[i][[(e + k) % 3 for e in range(3)]]
    if bits == 1:
        return (out[:, 0] | (out[:, 1] << 1) | (out[:, 2] << 2)).astype(values.dtype)
    pairs = np.stack([out.reshape(-1) & 1, (out.reshape(-1) >> 1) & 1], axis=1).reshape(-1).astype(np.uint8)
    packed = np.packbits(pairs, bitorder="little")
    return packed.astype(values.dtype)


def remove_empty_nodes(gltf: dict, names: set) -> bool:
    """Drop leaf nodes named in ``names`` that carry nothing (no mesh, camera, skin, children, extensions),
    renumbering every node reference (children, scenes, skins, animation targets)."""
    nodes = gltf.get("nodes") or []
    referenced = {j.get("skeleton") for j in gltf.get("skins") or []} | \
        {n for s in gltf.get("skins") or [] for n in s.get("joints", [])} | \
        {c["target"].get("node") for a in gltf.get("animations") or [] for c in a.get("channels", [])}
    dead = {i for i, n in enumerate(nodes) if n.get("name") in names and i not in referenced
            and not set(n) - {"name", "translation", "rotation", "scale", "matrix"}}
    if not dead:
        return False
    new_index = {}
    kept = []
    for i, n in enumerate(nodes):
        if i not in dead:
            new_index[i] = len(kept)
            kept.append(n)
    for n in kept:
        if "children" in n:
            n["children"] = [new_index[c] for c in n["children"] if c in new_index]
            if not n["children"]:
                del n["children"]
    for scene in gltf.get("scenes") or []:
        scene["nodes"] = [new_index[c] for c in scene.get("nodes", []) if c in new_index]
    for skin in gltf.get("skins") or []:
        skin["joints"] = [new_index[j] for j in skin.get("joints", [])]
        if "skeleton" in skin:
            skin["skeleton"] = new_index[skin["skeleton"]]
    for animation in gltf.get("animations") or []:
        for channel in animation.get("channels", []):
            if "node" in channel.get("target", {}):
                channel["target"]["node"] = new_index[channel["target"]["node"]]
    gltf["nodes"] = kept
    return True


def edge_codes_of(values: np.ndarray) -> np.ndarray:
    flat = np.unpackbits(np.asarray(values).astype(np.uint8).reshape(-1), bitorder="little")
    pairs = flat[:(len(flat) // 2) * 2].reshape(-1, 2)
    return (pairs[:, 0] | (pairs[:, 1] << 1))[: 3 * (len(pairs) // 3)].reshape(-1, 3)


def reorder_mates(mates: np.ndarray, visibility: np.ndarray, triangle_map) -> np.ndarray:
    """silhouetteMates holds one vertex per silhouette edge (code 1) in bitfield order (triangle by triangle, edge
    by edge); give them in the order of the exported triangles' bitfield."""
    codes = edge_codes_of(visibility)
    order = {}
    n = 0
    for t, row in enumerate(codes):
        for e, code in enumerate(row):
            if code == 1:
                order[(t, e)] = n
                n += 1
    source, rotation = triangle_map
    out = [mates[order[(i, (e + k) % 3)]] for i, k in zip(source, rotation) if i >= 0
           for e in range(3) if (i, (e + k) % 3) in order]
    return np.asarray(out, mates.dtype)


def after_export(path: str) -> None:
    if not str(path).lower().endswith(".glb"):
        print(f"baker_blender: {path}: only .glb exports get the BAKER_* extensions back (choose glTF Binary)")
        return
    Rewriter(path).run()
