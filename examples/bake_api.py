"""The Python API: bake, inspect the result, write glTF and USD, validate, preview.

    python examples/bake_api.py [MESH] [OUT_DIR]
"""
from __future__ import annotations

import sys
from pathlib import Path

import baker
from baker import validate
from baker.pipeline import save
from baker.preview.core import preview
from baker.gltf.images import write_image

here = Path(__file__).parent
mesh = Path(sys.argv[1]) if len(sys.argv) > 1 else here / "spot" / "spot.obj"
out = Path(sys.argv[2]) if len(sys.argv) > 2 else here / "out" / "api"

# options take the same names as the CLI flags (--thickness-rays -> {"thickness": {"rays": ...}})
asset = baker.bake(mesh, bakes=["thickness", "curvature", "edges"], seed=1,
                   options={"thickness": {"rays": 64, "texture_size": 512}, "edges": {"crease_angle": 45}})

prim = asset.doc.json["meshes"][0]["primitives"][0]
thickness = asset.doc.accessor(prim["attributes"]["_THICKNESS"])[:, 0]  # FLOAT VEC3, the value in x
print(f"{mesh.name}: {len(thickness)} vertices, thickness {thickness.min():.3f} .. {thickness.max():.3f} mesh units")

written = save(asset, out / f"{mesh.stem}.glb") + save(asset, out / f"{mesh.stem}.usdz")
report = validate.validate_file(out / f"{mesh.stem}.glb")
print(f"wrote {', '.join(p.name for p in written)}; validation errors: {report['issues']['numErrors']}")

sheet = preview(asset, size=256, azimuth=150, elevation=15)
write_image(out / f"{mesh.stem}_preview.png", sheet.sheet)
print(f"preview panels: {', '.join(name for name, _, _ in sheet.panels)}")
