"""``baker inspect``: a table of what is in an asset (meshes, counts, materials, extensions, baked data)."""
from __future__ import annotations

import json


def describe(path, allow_outside=None) -> dict:
    import numpy as np

    from baker.geometry.asset import Asset
    from baker.gltf.vertex_attributes import used_columns

    asset = Asset.load(path, allow_outside=allow_outside)
    doc = asset.doc
    meshes = []
    for m, mesh in enumerate(asset.meshes()):
        for p, prim in enumerate(mesh.get("primitives", [])):
            attrs = prim.get("attributes", {})
            row = {
                "mesh": m,
                "name": mesh.get("name", ""),
                "primitive": p,
                "mode": prim.get("mode", 4),
                "vertices": doc.json["accessors"][attrs["POSITION"]]["count"] if "POSITION" in attrs else 0,
                "triangles": len(asset.primitive(m, p).faces) if p in asset.triangle_primitives(m) else 0,
                "material": prim.get("material"),
                "attributes": sorted(attrs),
                "baked": {},
            }
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
    }


def material_textures(doc, material: dict) -> list[dict]:
    """The textures a material references (``slot``: where, e.g. ``KHR_materials_volume.thicknessTexture``) with
    their image's width and height when the image is a PNG or JPEG (read from its header), else None."""
    found = []

    def walk(value, path):
        if isinstance(value, dict):
            for key, item in value.items():
                if key.endswith("Texture") and isinstance(item, dict) and isinstance(item.get("index"), int):
                    found.append({"slot": ".".join(path + [key]), "texture": item["index"],
                                  "size": _texture_size(doc, item["index"])})
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


def add_parser(sub) -> None:
    p = sub.add_parser("inspect", help="print a table of what is in an asset")
    p.add_argument("file")
    p.add_argument("--format", choices=("text", "json"), default="text")
    p.add_argument("--allow-outside", action="append", metavar="PATH", help="also read buffer/image URIs under PATH "
                   "(default: only inside the asset's folder); repeatable")
    p.set_defaults(func=run)


def run(args) -> int:
    return main(args.file, fmt=args.format, allow_outside=args.allow_outside)


def main(path, fmt: str = "text", allow_outside=None) -> int:
    info = describe(path, allow_outside)
    if fmt == "json":
        print(json.dumps(info, indent=2))
        return 0
    print(f"{info['file']}  ({info['generator']})")
    print(f"nodes {info['nodes']}  textures {info['textures']}  images {info['images']}  "
          f"animations {info['animations']}  skins {info['skins']}")
    print(f"extensionsUsed: {', '.join(info['extensionsUsed']) or '-'}")
    print()
    rows = [[r["mesh"], r["name"], r["primitive"], r["vertices"], r["triangles"], r["material"],
             " ".join(a for a in r["attributes"] if not a.startswith("_"))] for r in info["meshes"]]
    print(_table(["mesh", "name", "prim", "vertices", "triangles", "material", "attributes"], rows))
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
    return 0
