"""Where a GLB's bytes go, per baked quantity: each vertex attribute (all primitives of a name together), each
accessor baker's extensions name (BAKER_edges members, coverage mips, ...), images, indices. Reads the GLB's JSON
chunk only (no baker import), so it measures files written by any version.

    python benchmarks/glb_bytes.py a.glb b.glb ... [--input model.obj ...]

Prints one Markdown table: per quantity its accessor forms (type and component type; "—" where a file lacks it) and
its bytes in each file."""
from __future__ import annotations

import argparse
import json
import struct
from collections import defaultdict
from pathlib import Path

COMPONENT_BYTES = {5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4}
COMPONENT_NAMES = {5120: "i8", 5121: "u8", 5122: "i16", 5123: "u16", 5125: "u32", 5126: "f32"}
COUNTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


def glb_json(path: Path) -> dict:
    data = path.read_bytes()
    length, = struct.unpack_from("<I", data, 12)
    return json.loads(data[20:20 + length])


def quantities(path: Path) -> dict:
    """{quantity: (form, bytes)} of one GLB."""
    gltf = glb_json(path)
    accessors, views = gltf.get("accessors", []), gltf.get("bufferViews", [])
    out: dict = defaultdict(lambda: ["", 0])
    seen = set()

    def add(label: str, index: int) -> None:
        if index in seen:
            return
        seen.add(index)
        acc = accessors[index]
        out[label][0] = f"{acc['type']} {COMPONENT_NAMES[acc['componentType']]}"
        out[label][1] += acc["count"] * COUNTS[acc["type"]] * COMPONENT_BYTES[acc["componentType"]]

    for mesh in gltf.get("meshes", []):
        for prim in mesh["primitives"]:
            where = "fin primitive " if "_FIN_CORNER" in prim["attributes"] else ""
            for name, index in prim["attributes"].items():
                add(where + name, index)
            if "indices" in prim:
                add(where + "indices", prim["indices"])
    for index, acc in enumerate(accessors):
        if index not in seen:
            name = acc.get("name", "other")
            add("coverage mips (KTX2)" if name.startswith("coverage mips") else name, index)
    for image in gltf.get("images", []):
        if "bufferView" in image:
            out["images (PNG)"][0] = "PNG"
            out["images (PNG)"][1] += views[image["bufferView"]]["byteLength"]
    return {k: tuple(v) for k, v in out.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+", type=Path)
    parser.add_argument("--input", type=Path, nargs="*", default=[],
                        help="the model each file baked (one for all, or one per file): the size ratio")
    args = parser.parse_args()
    tables = [quantities(p) for p in args.files]
    names = sorted({k for t in tables for k in t}, key=lambda k: -max(t.get(k, ("", 0))[1] for t in tables))
    print("| quantity | form | " + " | ".join(p.stem for p in args.files) + " |")
    print("|---|---|" + "---:|" * len(args.files))
    for name in names:
        forms = list(dict.fromkeys(t[name][0] for t in tables if name in t))
        if any(name not in t for t in tables):
            forms.append("—")
        cells = [f"{t[name][1]:,}" if name in t else "0" for t in tables]
        print(f"| {name} | {' / '.join(forms)} | " + " | ".join(cells) + " |")
    inputs = args.input * len(args.files) if len(args.input) == 1 else args.input
    cells = [f"**{p.stat().st_size:,}**" + (f" ({p.stat().st_size / i.stat().st_size:.2f}x input)" if i else "")
             for p, i in zip(args.files, inputs or [None] * len(args.files))]
    print("| **GLB total** | | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
