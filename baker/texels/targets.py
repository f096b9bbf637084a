"""Choose, per material, the UV set and texels a texture bake writes into.

A texture bake writes one image per material (a glTF textureInfo belongs to a material). All triangle primitives
using the material share it: their TEXCOORD_0 is used when present, inside [0, 1] and free of overlaps; otherwise
xatlas unwraps all of them into one atlas, each primitive is re-indexed (vertices split along the new seams, every
attribute and morph target copied along) and the new layout becomes a new TEXCOORD set.
"""
from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np

from baker.geometry.asset import Asset, PrimitiveGeometry
from baker.geometry.normals import vertex_normals
from baker.geometry.welding import weld
from baker.gltf.document import TARGET_ELEMENT_ARRAY_BUFFER
from baker.texels.texture_space import (AUTO_SIZE_RANGE, UNWRAP_IN_CHILD_FROM_FACES, SurfaceStatistics, TexelSamples,
                                          UnwrapInChild, rasterize_uv, size_for_density, unwrap,
                                          usable_layout_texels)


@dataclass
class PrimitiveTexels:
    geometry: PrimitiveGeometry
    normals: np.ndarray  # (n, 3) per-vertex normals used for sampling (the primitive's, or welded smooth ones)
    texels: TexelSamples
    # vertex k copies vertex source_vertex[k] of the primitive before the unwrap split it (None: not unwrapped)
    source_vertex: np.ndarray | None = None
    source_positions_shape: tuple | None = None  # the shape of the primitive's positions before the unwrap


@dataclass
class MaterialTarget:
    material: int
    texcoord: int
    size: int
    primitives: list  # of PrimitiveTexels
    unwrapped: bool

    @property
    def mask(self) -> np.ndarray:
        m = np.zeros((self.size, self.size), bool)
        for p in self.primitives:
            m[p.texels.rows, p.texels.cols] = True
        return m


def smooth_normals(geometry: PrimitiveGeometry) -> np.ndarray:
    """The primitive's own normals, or area-weighted normals over position-welded vertices (no seams)."""
    if geometry.normals is not None:
        return geometry.normals
    welded, inverse = weld(geometry.positions)
    return vertex_normals(welded, inverse[geometry.faces])[inverse]


def material_targets(asset: Asset, size: int | None = None, seed: int = 0,
                     density: float | None = None, layouts: dict | None = None,
                     auto_range: tuple[int, int] = AUTO_SIZE_RANGE) -> list[MaterialTarget]:
    """One target per material with triangles. ``size`` forces every texture's width and height; None sizes each
    from its surface (:func:`baker.texels.texture_space.size_for_density`, ``density`` texels per mesh unit or,
    when None, the automatic density within ``auto_range``). The unwrap's layout does not depend on these.

    ``layouts`` ({material: (texcoord, size)}) instead bakes only those materials, each into the UV set and size
    given, as it is (no overlap test, no unwrap): a bake whose output pairs texel for texel with an existing
    texture (a normal map) must use that texture's layout."""
    targets = []
    for material, members in asset.material_groups().items():
        if layouts is not None and material not in layouts:
            continue
        geoms = [asset.primitive(m, p) for m, p in members]
        geoms = [g for g in geoms if len(g.faces)]
        if not geoms:
            continue
        if layouts is not None:
            texcoord, chosen = layouts[material]
            geoms = [g for g in geoms if texcoord in g.texcoords]
            if geoms:
                prims = [PrimitiveTexels(g, smooth_normals(g), rasterize_uv(g.texcoords[texcoord], g.faces, chosen,
                                                                            chosen)) for g in geoms]
                targets.append(MaterialTarget(material, texcoord, chosen, prims, False))
            continue
        made = asset.cache.get(("unwrap", material))
        # the overlap test at 256^2 when the size is not forced: overlapping charts show at any resolution
        tested = None if made is not None else _existing_uv_texels(geoms, size or 256)
        if tested is not None:
            texcoord, unwrapped = 0, False
        else:
            texcoord, vmaps = unwrap_material(asset, material, [(g.mesh, g.primitive) for g in geoms], seed)
            geoms = [asset.primitive(m, p) for m, p in vmaps]
            unwrapped = True
        chosen = size or size_for_density(_statistics(geoms, texcoord), density, auto_range)
        if not unwrapped and tested.width == chosen:
            # the test rasterized every primitive's triangles at this size already: each takes its share
            starts = np.cumsum([0] + [len(g.faces) for g in geoms])
            rasters = [tested.triangles(starts[i], starts[i + 1]) for i in range(len(geoms))]
        else:
            rasters = [rasterize_uv(g.texcoords[texcoord], g.faces, chosen, chosen) for g in geoms]
        prims = [PrimitiveTexels(g, smooth_normals(g), raster, *(vmaps[(g.mesh, g.primitive)] if unwrapped else ()))
                 for g, raster in zip(geoms, rasters)]
        targets.append(MaterialTarget(material, texcoord, chosen, prims, unwrapped))
    return targets


UNWRAP_COVERAGE = 0.6  # share of the UV square xatlas charts cover on ordinary meshes, to size the unwrap's padding


def unwrap_material(asset: Asset, material: int, members: list[tuple[int, int]], seed: int = 0) -> tuple[int, dict]:
    """Unwrap the primitives ``members`` ((mesh, primitive), each with triangles) of ``material`` into one new UV
    set, once per asset: every bake that needs a layout (the texture bakes, tam, fur) gets the same one, whichever
    ran first. Returns (its TEXCOORD index, {(mesh, primitive): (vertex map, positions shape before the unwrap)}).

    The layout depends on the geometry alone, never on a bake's options (its padding is sized for the automatic
    texture size, not a forced ``size``): a bake's output must not depend on which other bakes ran."""
    key = ("unwrap", material)
    if key not in asset.cache:
        geoms, texcoord, resolution = _unwrap_inputs(asset, members)
        started = asset.cache.pop(("unwrap started", material), None)
        if started is not None and started[0] == _unwrap_key(asset, geoms):
            charts = started[1].result()
        else:
            if started is not None:
                started[1].cancel()
            charts = unwrap([(g.positions, g.faces) for g in geoms], resolution=resolution, seed=seed)
        vmaps = {}
        for g, (vmap, faces, uv) in zip(geoms, charts):
            # the slots reindex_primitive fills with the new layout (those the primitive had not)
            asset.cache[("unwrapped texcoords", g.mesh, g.primitive)] = \
                frozenset(k for k in range(texcoord + 1) if k not in g.texcoords)
            reindex_primitive(asset, g.mesh, g.primitive, vmap, faces, uv, texcoord)
            vmaps[(g.mesh, g.primitive)] = (vmap, g.positions.shape)
        asset.cache[key] = (texcoord, vmaps)
    return asset.cache[key]


def _unwrap_inputs(asset: Asset, members: list[tuple[int, int]]) -> tuple[list, int, int]:
    """(primitives, the new TEXCOORD index, xatlas's resolution) of an unwrap of ``members``."""
    geoms = [asset.primitive(m, p) for m, p in members]
    texcoord = max(max(g.texcoords, default=-1) for g in geoms) + 1
    # xatlas pads charts by texels of `resolution`: the size the surface gets at the automatic density and the
    # coverage xatlas typically reaches (a bake's final size follows the coverage it really reached)
    resolution = size_for_density(_statistics(geoms, None, UNWRAP_COVERAGE))
    return geoms, texcoord, resolution


def _unwrap_key(asset: Asset, geoms: list[PrimitiveGeometry]) -> tuple:
    """What an unwrap's input is: the primitives as they are now (their key changes when they are re-indexed)."""
    return tuple(asset.primitive_key(g.mesh, g.primitive) for g in geoms)


@contextmanager
def unwraps_started(asset: Asset, size: int | None = None, materials: list[int] | None = None):
    """Start, in child processes (:class:`~baker.texels.texture_space.UnwrapInChild`), the unwraps a texture bake
    of ``size`` (None: automatic) will ask :func:`unwrap_material` for: the materials whose primitives have no
    usable TEXCOORD_0 (the test :func:`material_targets` makes; or the given ``materials``) and at least
    :data:`~baker.texels.texture_space.UNWRAP_IN_CHILD_FROM_FACES` triangles. The bake meanwhile builds its BVHs
    and traces its per-vertex rays; :func:`unwrap_material` takes the child's layout, the same one it would compute
    itself. Children not asked for by the end of the block (the bake failed, or was interrupted) are killed. The
    block gets the materials whose unwrap runs in a child process meanwhile."""
    started, forked = [], []
    try:
        for material, members in asset.material_groups().items():
            if ("unwrap", material) in asset.cache or ("unwrap started", material) in asset.cache \
                    or (materials is not None and material not in materials):
                continue
            geoms = [g for g in (asset.primitive(m, p) for m, p in members) if len(g.faces)]
            if not geoms or sum(len(g.faces) for g in geoms) < UNWRAP_IN_CHILD_FROM_FACES \
                    or (materials is None and _existing_uv_texels(geoms, size or 256) is not None):
                continue
            geoms, _, resolution = _unwrap_inputs(asset, [(g.mesh, g.primitive) for g in geoms])
            child = UnwrapInChild([(g.positions, g.faces) for g in geoms], resolution)
            asset.cache[("unwrap started", material)] = (_unwrap_key(asset, geoms), child)
            started.append(material)
            if child.pid is not None:
                forked.append(material)
        yield forked
    finally:
        for material in started:
            left = asset.cache.pop(("unwrap started", material), None)
            if left is not None:
                left[1].cancel()


def made_by_unwrap(asset: Asset, mesh: int, primitive: int, texcoord: int) -> bool:
    """Whether TEXCOORD_<texcoord> of the primitive is a layout :func:`unwrap_material` made, not the asset's own."""
    return texcoord in asset.cache.get(("unwrapped texcoords", mesh, primitive), ())


def _statistics(geoms: list[PrimitiveGeometry], texcoord: int | None, coverage: float = 0.0) -> SurfaceStatistics:
    """Surface statistics of the primitives' triangles in UV set ``texcoord`` (None: no layout yet, ``coverage``
    assumed)."""
    if texcoord is None:
        stats = SurfaceStatistics.of([(g.positions, g.faces, np.zeros((len(g.positions), 2))) for g in geoms])
        return SurfaceStatistics(stats.area, coverage, stats.mean_edge)
    return SurfaceStatistics.of([(g.positions, g.faces, g.texcoords[texcoord]) for g in geoms])


def _existing_uv_texels(geoms: list[PrimitiveGeometry], size: int):
    """The texels of TEXCOORD_0 at ``size`` (at most 1024) of the primitives' triangles concatenated, when that
    layout is usable for a bake; else None."""
    if not all(0 in g.texcoords for g in geoms):
        return None
    uvs, faces, base = [], [], 0
    for g in geoms:
        uvs.append(g.texcoords[0])
        faces.append(g.faces + base)
        base += len(g.texcoords[0])
    return usable_layout_texels(np.concatenate(uvs), np.concatenate(faces), size=min(size, 1024))


def renumber_extension_vertices(doc, prim: dict, vmap: np.ndarray) -> list:
    """Primitive extensions' accessors of vertex indices (``doc.vertex_index_members``, which the pipeline fills from
    :func:`baker.registry.vertex_index_members`: BAKER_edges' edge list, the edge-visibility extension's silhouette
    mates) renumbered after a split where new vertex k copies old vertex ``vmap[k]``: each old vertex becomes its
    first copy (same position, so the same edge), the type's maximum ('no vertex') stays that, in the type the new
    vertex count needs. Returns (old accessor, new accessor) pairs."""
    extensions = prim.get("extensions") or {}
    members = doc.vertex_index_members
    replaced = []
    if not any(name in members for name in extensions):
        return replaced
    first_copy = np.full(int(vmap.max()) + 1 if len(vmap) else 0, -1, np.int64)
    first_copy[vmap[::-1]] = np.arange(len(vmap))[::-1]  # reversed: the lowest k wins
    dtype = np.uint16 if len(vmap) < 0xFFFF else np.uint32
    for name, ext in extensions.items():
        for member in members.get(name, ()):
            if not isinstance(ext.get(member), int):
                continue
            old = doc.accessor(ext[member])
            none = old == np.iinfo(old.dtype).max
            found = first_copy[np.where(none | (old >= len(first_copy)), 0, old)]
            new = np.where(none | (found < 0), np.iinfo(dtype).max, found).astype(dtype)
            old_index = ext[member]
            ext[member] = doc.add_accessor(new, target=None, name=doc.json["accessors"][ext[member]].get("name"))
            replaced.append((old_index, ext[member]))
    return replaced


def reindex_primitive(asset: Asset, mesh: int, primitive: int, vmap: np.ndarray, faces: np.ndarray,
                       uv: np.ndarray, texcoord: int) -> None:
    """Split the primitive's vertices (new vertex k copies old vertex ``vmap[k]``: every attribute, morph target and
    primitive extension's vertex indices follow) and add the new UVs as TEXCOORD_<texcoord>."""
    doc = asset.doc
    prim = asset.meshes()[mesh]["primitives"][primitive]
    replaced = []  # (old accessor, the new one in its place)
    first_new = len(doc.json.get("accessors") or [])

    def copy_attributes(attributes: dict) -> dict:
        out = {}
        for key, acc in attributes.items():
            info = doc.json["accessors"][acc]
            data = doc.accessor(acc)[vmap]
            out[key] = doc.add_accessor(data, normalized=bool(info.get("normalized")),
                                        min_max=key == "POSITION" or "min" in info)
            replaced.append((acc, out[key]))
        return out

    prim["attributes"] = copy_attributes(prim["attributes"])
    if "targets" in prim:
        prim["targets"] = [copy_attributes(t) for t in prim["targets"]]
    new_uv = doc.add_accessor(uv.astype(np.float32))
    # TEXCOORD sets must be contiguous: a primitive with fewer sets than its material's others gets the new
    # layout in the missing slots too
    for k in range(texcoord + 1):
        prim["attributes"].setdefault(f"TEXCOORD_{k}", new_uv)
    prim["attributes"][f"TEXCOORD_{texcoord}"] = new_uv
    index_type = np.uint16 if len(vmap) < 65535 else np.uint32
    old_indices = prim.get("indices")
    prim["indices"] = doc.add_accessor(faces.reshape(-1).astype(index_type), target=TARGET_ELEMENT_ARRAY_BUFFER)
    if isinstance(old_indices, int):
        replaced.append((old_indices, prim["indices"]))
    replaced += renumber_extension_vertices(doc, prim, vmap)
    reclaim_accessors(asset, mesh, primitive, replaced, first_new)
    if prim.get("mode", 4) != 4:
        prim["mode"] = 4  # strips and fans came back from xatlas as a triangle list


def reclaim_accessors(asset: Asset, mesh: int, primitive: int, replaced: list, first_new: int) -> None:
    """After a re-index, put each new accessor in the slot of the one it replaced when nothing refers to that one
    any more (``doc.accessor_references``; nothing is reclaimed when it is unset or cannot tell), and drop the
    replaced data's buffer views and bytes: the file holds the split primitive once, not beside its old arrays. The
    accessors this re-index appended are the tail of the list from ``first_new``; those left there close up. The
    primitive's decoded
    geometry is dropped from the asset's cache (its accessor indices may be the old ones again)."""
    doc = asset.doc
    gltf = doc.json
    accessors = gltf["accessors"]
    tail = first_new
    new_ids = list(range(tail, len(accessors)))
    if doc.accessor_references is None or not replaced or any(new < tail for _, new in replaced):
        return
    used = doc.accessor_references(gltf)
    if used is None:
        return
    final, taken = {}, set()
    for old, new in replaced:
        if old < tail and old not in used and old not in taken and new not in final:
            final[new] = old
            taken.add(old)
    if not final:
        return
    views = [accessors[old].get("bufferView") for old in taken]
    for new, old in final.items():
        accessors[old] = accessors[new]
    rest = [n for n in new_ids if n not in final]
    final.update({n: tail + i for i, n in enumerate(rest)})
    accessors[tail:] = [accessors[n] for n in rest]
    prim = asset.meshes()[mesh]["primitives"][primitive]
    for attributes in [prim["attributes"], *prim.get("targets", [])]:
        for key, acc in attributes.items():
            attributes[key] = final.get(acc, acc)
    prim["indices"] = final.get(prim["indices"], prim["indices"])
    for name, ext in (prim.get("extensions") or {}).items():
        for member in doc.vertex_index_members.get(name, ()):
            if isinstance(ext.get(member), int):
                ext[member] = final.get(ext[member], ext[member])
    for view in sorted({v for v in views if isinstance(v, int)}, reverse=True):
        drop_buffer_view(doc, view)
    for key in [k for k in asset.cache if k[0] == "primitive" and k[1][:2] == (mesh, primitive)
                or k[0] == "welded" and any(part[:2] == (mesh, primitive) for part in k[1])]:
        del asset.cache[key]


def drop_buffer_view(doc, view: int) -> None:
    """Remove buffer view ``view`` and its bytes when nothing refers to it (no accessor, sparse accessor or image,
    no extension with a ``bufferView``) and no other view overlaps them; later views move down (by a multiple of
    4 bytes: alignment kept) and the references renumber. Otherwise leave it."""
    gltf = doc.json
    views = gltf.get("bufferViews") or []
    if not 0 <= view < len(views) or views[view].get("buffer", 0) != 0 or '"bufferView"' in _extensions_text(gltf):
        return
    holders = [a for a in gltf.get("accessors") or []] + [i for i in gltf.get("images") or []]
    sparse = [part for a in gltf.get("accessors") or [] for part in
              ((a.get("sparse") or {}).get("indices") or {}, (a.get("sparse") or {}).get("values") or {})]
    if any(h.get("bufferView") == view for h in holders + sparse):
        return
    start = views[view].get("byteOffset", 0)
    end = start + views[view]["byteLength"]
    end += (-(end - start)) % 4
    if any(i != view and v.get("buffer", 0) == 0 and v.get("byteOffset", 0) < end and
           v.get("byteOffset", 0) + v["byteLength"] > start for i, v in enumerate(views)):
        return
    end = min(end, len(doc.bin))
    del doc.bin[start:end]
    for v in views:
        if v.get("buffer", 0) == 0 and v.get("byteOffset", 0) >= end:
            v["byteOffset"] = v["byteOffset"] - (end - start)
    del views[view]
    for h in holders + sparse:
        if isinstance(h.get("bufferView"), int) and h["bufferView"] > view:
            h["bufferView"] -= 1


def _extensions_text(gltf: dict) -> str:
    """Every ``extensions`` object of the document as JSON text (to look for buffer view references in them)."""
    import json

    found = []

    def walk(node):
        if isinstance(node, dict):
            for key, value in node.items():
                if key == "extensions" and isinstance(value, dict):
                    found.append(value)
                else:
                    walk(value)
        elif isinstance(node, list):
            for value in node:
                walk(value)

    walk({k: v for k, v in gltf.items() if k not in ("accessors", "bufferViews")})
    return json.dumps(found, default=str)
