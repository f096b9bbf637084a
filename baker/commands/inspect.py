"""``baker inspect``: a table of what is in an asset (meshes, counts, materials, extensions, baked data)."""
from __future__ import annotations

import json

from baker import memory


MODE_NAMES = {0: "POINTS", 1: "LINES", 2: "LINE_LOOP", 3: "LINE_STRIP", 4: "TRIANGLES", 5: "TRIANGLE_STRIP",
              6: "TRIANGLE_FAN"}


def line_strands(indices, mode: int) -> tuple[int, int]:
    """(segments, strands) of a line primitive: a strand is a connected run of segments (a LINE_STRIP or LINE_LOOP
    is one; LINES are chained through shared vertices)."""
    import numpy as np

    n = len(indices)
    if mode == 3:
        return max(n - 1, 0), int(n >= 2)
    if mode == 2:
        return (n if n >= 2 else 0), int(n >= 2)
    pairs = np.asarray(indices, np.int64)[: n - n % 2].reshape(-1, 2)
    if not len(pairs):
        return 0, 0
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    used, local = np.unique(pairs, return_inverse=True)
    local = local.reshape(-1, 2)
    graph = coo_matrix((np.ones(len(local)), (local[:, 0], local[:, 1])), shape=(len(used), len(used)))
    return len(pairs), int(connected_components(graph, directed=False)[0])


def describe(path, allow_outside=None, max_memory: int | None = None) -> dict:
    import numpy as np

    from baker import registry
    from baker.gltf.vertex_attributes import used_columns
    from baker import readers
    from baker.memory import check_bake

    # a groom (lines or points only) is a good glTF too: listed, not refused
    asset = readers.read(path, allow_outside, max_memory, require_triangles=False)
    check_bake(asset, (), None, max_memory, "inspecting this asset")
    doc = asset.doc
    summaries = {name: ext.summary for name, ext in registry.extensions().items() if hasattr(ext, "summary")}
    for ext in registry.extensions().values():  # an extension module's summaries of the others it writes
        summaries.update(getattr(ext, "ALSO_SUMMARIES", {}))
    meshes = []
    for m, mesh in enumerate(asset.meshes()):
        triangle_prims = asset.triangle_primitives(m)
        for p, prim in enumerate(mesh.get("primitives", [])):
            attrs = prim.get("attributes", {})
            mode = prim.get("mode", 4)
            vertices = doc.json["accessors"][attrs["POSITION"]]["count"] if "POSITION" in attrs else 0
            row = {
                "mesh": m,
                "name": mesh.get("name", ""),
                "primitive": p,
                "mode": mode,
                "modeName": MODE_NAMES.get(mode, str(mode)),
                "vertices": vertices,
                "triangles": len(asset.primitive(m, p).faces) if p in triangle_prims else 0,
                "lines": 0,
                "strands": 0,
                "points": vertices if mode == 0 else 0,
                "material": prim.get("material"),
                "attributes": sorted(attrs),
                "baked": {},
                "extensions": {},
            }
            if mode in (1, 2, 3):
                indices = doc.accessor(prim["indices"]).reshape(-1) if "indices" in prim else np.arange(vertices)
                row["lines"], row["strands"] = line_strands(indices, mode)
            for name in sorted(prim.get("extensions") or {}):
                info = summaries[name](doc, m, p) if name in summaries else None
                row["extensions"][name] = info or {}
                if info and "strands" in info:  # the extension knows its strands (BAKER_hair: strandCount)
                    row["strands"] = info["strands"]
            for key in sorted(attrs):
                if key.startswith("_"):
                    values = used_columns(doc.accessor(attrs[key]).astype(np.float64))
                    row["baked"][key] = {"min": float(values.min()), "mean": float(values.mean()),
                                         "max": float(values.max())} if values.size else {}
            meshes.append(row)
    materials = [{"material": i, "name": mat.get("name", ""), "extensions": sorted(mat.get("extensions", {})),
                  "textures": material_textures(doc, mat)} for i, mat in enumerate(doc.json.get("materials", []))]
    return {
        "file": str(path),
        "generator": doc.json.get("asset", {}).get("generator", ""),
        "nodes": len(doc.json.get("nodes", [])),
        "meshes": meshes,
        "materials": materials,
        "textures": len(doc.json.get("textures", [])),
        "images": len(doc.json.get("images", [])),
        "animations": len(doc.json.get("animations", [])),
        "skins": len(doc.json.get("skins", [])),
        "extensionsUsed": doc.json.get("extensionsUsed", []),
        "extensionsRequired": doc.json.get("extensionsRequired", []),
        "coverageMips": coverage_mips(doc),
    }


def coverage_mips(doc) -> list[dict]:
    """Every coverage-preserving mip chain an extension lists (``coverageMips``, :mod:`baker.texels.alpha_mips`):
    where, its texture, size, level count, cutoff and the alpha-test coverage of each level as stored."""
    from baker.texels.alpha_mips import alpha_coverage, read_coverage_mips

    out = []
    places = [("", doc.json)] + [(f"/{kind}/{i}", item) for kind in ("materials", "nodes")
                                 for i, item in enumerate(doc.json.get(kind) or []) if isinstance(item, dict)]
    for where, item in places:
        for name, ext in sorted((item.get("extensions") or {}).items()):
            entries = ext.get("coverageMips") if isinstance(ext, dict) else None
            for entry in entries if isinstance(entries, list) else []:
                row = {"place": f"{where}/extensions/{name}", "texture": entry.get("texture"),
                       "alphaCutoff": entry.get("alphaCutoff"), "levels": None, "size": None, "coverage": None}
                try:
                    levels = read_coverage_mips(doc, entry)
                    row.update(levels=len(levels), size=[int(levels[0].shape[1]), int(levels[0].shape[0])],
                               coverage=[alpha_coverage(lv[..., 3], float(entry["alphaCutoff"])) for lv in levels])
                except Exception:  # unreadable: inspect lists it, `baker validate` says why
                    pass
                out.append(row)
    return out


def material_textures(doc, material: dict) -> list[dict]:
    """The textures a material references (``slot``: where, e.g. ``KHR_materials_volume.thicknessTexture``,
    ``BAKER_tonal_art_map.levels[1].textures[0]``: any ``*Texture``/``texture`` textureInfo and ``*Textures``/``textures``
    list, in lists too) with their image's width and height when the image is a PNG or JPEG (read from its header), else None."""
    found = []

    def walk(value, path):
        if isinstance(value, list):  # e.g. BAKER_tonal_art_map's levels[i].textures
            for i, item in enumerate(value):
                walk(item, path[:-1] + [f"{path[-1]}[{i}]"] if path else [f"[{i}]"])
        elif isinstance(value, dict):
            for key, item in value.items():
                if key.lower().endswith("texture") and isinstance(item, dict) and isinstance(item.get("index"), int):
                    found.append({"slot": ".".join(path + [key]), "texture": item["index"],
                                  "size": _texture_size(doc, item["index"])})
                elif key.lower().endswith("textures") and isinstance(item, list):  # textureInfos (frames, channels)
                    for i, entry in enumerate(item):
                        if isinstance(entry, dict) and isinstance(entry.get("index"), int):
                            found.append({"slot": ".".join(path + [f"{key}[{i}]"]), "texture": entry["index"],
                                          "size": _texture_size(doc, entry["index"])})
                else:
                    walk(item, path + [key] if key not in ("extensions",) else path)

    walk(material, [])
    return found


def _texture_size(doc, texture: int):
    try:
        source = doc.json["textures"][texture]["source"]
        return image_size(doc.image_bytes(source))
    except (IndexError, KeyError, TypeError, OSError, ValueError):
        return None


def image_size(data: bytes) -> list | None:
    """[width, height] from a PNG's IHDR or a JPEG's start-of-frame marker; None for other formats."""
    if data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) >= 24:
        return [int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")]
    if data[:2] == b"\xff\xd8":
        at = 2
        while at + 9 <= len(data) and data[at] == 0xFF:
            marker, length = data[at + 1], int.from_bytes(data[at + 2: at + 4], "big")
            if 0xC0 <= marker <= 0xCF and marker not in (0xC4, 0xC8, 0xCC):
                return [int.from_bytes(data[at + 7: at + 9], "big"), int.from_bytes(data[at + 5: at + 7], "big")]
            at += 2 + length
    return None


def _table(headers: list[str], rows: list[list]) -> str:
    cells = [[str(c) for c in r] for r in rows]
    widths = [max(len(h), *(len(r[i]) for r in cells)) if cells else len(h) for i, h in enumerate(headers)]
    line = lambda r: "  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip()
    return "\n".join([line(headers), line(["-" * w for w in widths])] + [line(r) for r in cells])


def _value(v) -> str:
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, list):
        return ",".join(_value(x) for x in v)
    return str(v)


def add_parser(sub) -> None:
    p = sub.add_parser("inspect", help="print a table of what is in an asset")
    p.add_argument("file")
    p.add_argument("--format", choices=("text", "json"), default="text")
    p.add_argument("--allow-outside", action="append", metavar="PATH", help="also read buffer/image URIs under PATH "
                   "(default: only inside the asset's folder); repeatable")
    memory.add_argument(p)
    p.set_defaults(func=run)


def run(args) -> int:
    return main(args.file, fmt=args.format, allow_outside=args.allow_outside,
                max_memory=memory.parse_limit(args.max_memory))


def main(path, fmt: str = "text", allow_outside=None, max_memory: int | None = None) -> int:
    info = describe(path, allow_outside, max_memory)
    if fmt == "json":
        print(json.dumps(info, indent=2))
        return 0
    print(f"{info['file']}  ({info['generator']})")
    print(f"nodes {info['nodes']}  textures {info['textures']}  images {info['images']}  "
          f"animations {info['animations']}  skins {info['skins']}")
    print(f"extensionsUsed: {', '.join(info['extensionsUsed']) or '-'}")
    print()
    rows = [[r["mesh"], r["name"], r["primitive"], r["modeName"], r["vertices"], r["triangles"], r["lines"],
             r["strands"], r["material"], " ".join(a for a in r["attributes"] if not a.startswith("_"))]
            for r in info["meshes"]]
    print(_table(["mesh", "name", "prim", "mode", "vertices", "triangles", "lines", "strands", "material",
                  "attributes"], rows))
    extensions = [[r["mesh"], r["primitive"], name, "  ".join(f"{k} {_value(v)}" for k, v in data.items()) or "-"]
                  for r in info["meshes"] for name, data in r["extensions"].items()]
    if extensions:
        print()
        print(_table(["mesh", "prim", "primitive extension", "summary"], extensions))
    baked = [[r["mesh"], r["primitive"], k, f"{v.get('min', 0):.6g}", f"{v.get('mean', 0):.6g}", f"{v.get('max', 0):.6g}"]
             for r in info["meshes"] for k, v in r["baked"].items()]
    if baked:
        print()
        print(_table(["mesh", "prim", "baked attribute", "min", "mean", "max"], baked))
    if info["materials"]:
        print()
        print(_table(["material", "name", "extensions"],
                     [[m["material"], m["name"], ", ".join(m["extensions"]) or "-"] for m in info["materials"]]))
    textures = [[m["material"], t["slot"], t["texture"], "x".join(map(str, t["size"])) if t["size"] else "?"]
                for m in info["materials"] for t in m["textures"]]
    if textures:
        print()
        print(_table(["material", "texture slot", "texture", "size"], textures))
    if info["coverageMips"]:
        print()
        print(_table(["coverage mips of", "texture", "size", "levels", "cutoff", "coverage per level"],
                     [[c["place"], c["texture"], "x".join(map(str, c["size"])) if c["size"] else "?",
                       c["levels"] or "?", c["alphaCutoff"],
                       " ".join(f"{v:.3f}" for v in c["coverage"]) if c["coverage"] else "unreadable"]
                      for c in info["coverageMips"]]))
    return 0
