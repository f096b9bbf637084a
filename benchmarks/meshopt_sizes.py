"""File sizes of a full bake: plain GLB vs ``--compress meshopt``, ``meshopt-gzip`` (baker's EXT_meshopt_compression,
float vertex attributes through the EXPONENTIAL filter, so not exact) and ``meshopt-lossless``, each also gzipped (what an HTTP server sends), and optionally gltfpack's output of the plain file (what it keeps).

    python benchmarks/meshopt_sizes.py [--mesh PATH ...] [--gltfpack PATH]

Each mesh is baked once with every surface bake (``--bakes thickness,curvature,skin,edges,tam,toon,fur``, default
options) and written both ways from the same asset. Rows: the input file's bytes, then per output its bytes, the
gzip -9 of those bytes, the share of the plain file's binary data that accessors hold (the rest is images, which
meshopt does not touch), the bufferViews per meshopt mode, and whether every accessor decodes to the plain file's
bytes (baker's reader). ``--gltfpack``: also ``gltfpack -i plain.glb -o out.glb -cc`` and ``-cc -kv -noq``, with the
BAKER_* extensions and custom attributes (``_NAME``) left in each output.
"""
from __future__ import annotations

import argparse
import gzip
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baker.api import bake, save  # noqa: E402
from baker.gltf.compression import decompress  # noqa: E402
from baker.gltf.document import GltfDocument  # noqa: E402
from baker.gltf.meshopt_encode import EXTENSION  # noqa: E402

BAKES = ("thickness", "curvature", "skin", "edges", "tam", "toon", "fur")
MESHES = [ROOT / "examples" / "spot" / "spot.obj", ROOT.parent / "shared" / "assets" / "meshes" / "stanford-bunny.obj"]


def glb_json(path: Path) -> dict:
    data = path.read_bytes()
    return json.loads(data[20: 20 + int.from_bytes(data[12:16], "little")])


def gz(path: Path) -> int:
    return len(gzip.compress(path.read_bytes(), compresslevel=9, mtime=0))


def accessor_share(gltf: dict) -> float:
    """Bytes of bufferViews no image reads, over all bufferView bytes."""
    images = {img["bufferView"] for img in gltf.get("images") or [] if "bufferView" in img}
    views = gltf.get("bufferViews") or []
    total = sum(v["byteLength"] for v in views)
    return sum(v["byteLength"] for i, v in enumerate(views) if i not in images) / max(total, 1)


def kept_bake(gltf: dict) -> tuple[int, int]:
    """(BAKER_* extensions used, custom vertex attributes ``_NAME`` on primitives)."""
    extensions = sum(1 for name in gltf.get("extensionsUsed") or [] if name.startswith("BAKER_"))
    attributes = {name for mesh in gltf.get("meshes") or [] for prim in mesh.get("primitives") or []
                  for name in prim.get("attributes") or {} if name.startswith("_")}
    return extensions, len(attributes)


def same_accessors(plain: Path, packed: Path) -> bool:
    a, b = GltfDocument.load(plain), GltfDocument.load(packed)
    decompress(b)
    count = len(a.json.get("accessors") or [])
    return count == len(b.json.get("accessors") or []) and all(
        np.array_equal(a.accessor(i), b.accessor(i)) and a.accessor(i).dtype == b.accessor(i).dtype
        for i in range(count))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh", action="append", help="input mesh (repeatable; default: spot and the bunny)")
    ap.add_argument("--gltfpack", help="a gltfpack executable (npm package gltfpack)")
    args = ap.parse_args(argv)
    meshes = [Path(m) for m in args.mesh] if args.mesh else MESHES
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for mesh in meshes:
            asset = bake(mesh, bakes=list(BAKES))
            plain, packed = Path(tmp) / f"{mesh.stem}.glb", Path(tmp) / f"{mesh.stem}_meshopt.glb"
            save(asset, plain)
            base = {"mesh": mesh.name, "input": mesh.stat().st_size}
            rows.append({**base, "output": "plain", "bytes": plain.stat().st_size, "gzip": gz(plain),
                         "accessor_share": round(accessor_share(glb_json(plain)), 3), "kept": kept_bake(glb_json(plain))})
            for compress in ("meshopt", "meshopt-gzip", "meshopt-lossless"):
                start = time.perf_counter()
                save(asset, packed, compress=compress)
                seconds = time.perf_counter() - start
                gltf = glb_json(packed)
                modes = {}
                for view in gltf.get("bufferViews") or []:
                    ext = view.get("extensions", {}).get(EXTENSION)
                    if ext:
                        modes[ext["mode"]] = modes.get(ext["mode"], 0) + 1
                rows.append({**base, "output": f"--compress {compress}", "bytes": packed.stat().st_size,
                             "gzip": gz(packed), "modes": modes, "exact": same_accessors(plain, packed),
                             "save_s": round(seconds, 2), "kept": kept_bake(gltf)})
            if args.gltfpack:
                for flags in (["-cc"], ["-cc", "-kv", "-noq"]):
                    out = Path(tmp) / f"{mesh.stem}_gltfpack.glb"
                    run = subprocess.run([args.gltfpack, "-i", str(plain), "-o", str(out), *flags],
                                         capture_output=True, text=True)
                    if run.returncode:
                        rows.append({**base, "output": f"gltfpack {' '.join(flags)}", "error": run.stderr.strip()})
                        continue
                    rows.append({**base, "output": f"gltfpack {' '.join(flags)}", "bytes": out.stat().st_size,
                                 "gzip": gz(out), "kept": kept_bake(glb_json(out))})
    for row in rows:
        print(json.dumps(row))
    return 0


if __name__ == "__main__":
    sys.exit(main())
