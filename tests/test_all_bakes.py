"""Every registered bake at once on one asset: the result is valid glTF (both validators) and valid USD."""
from __future__ import annotations

from pathlib import Path

import baker
from baker import validate
from baker.pipeline import save
from baker.registry import bakes

BAKES = bakes()
from conftest import assert_khronos_clean

SPOT = Path(__file__).parents[1] / "examples" / "spot" / "spot.obj"
FAST = {
    "thickness": {"rays": 8, "texture_size": 64},
    "curvature": {"per_texel": True, "texture_size": 64},
    "skin": {"width": 32, "height": 32, "penumbra_size": 16},
    "edges": {"fins": True},
    "tam": {"size": 64, "levels": 2},
    "fur": {"fins": True, "shells": 4, "texture_size": 32, "hairs": 100},
    "caustics": {"size": 32, "frames": 4, "waves": 16},
}


def test_every_bake_together_is_valid(tmp_path):
    asset = baker.bake(SPOT, bakes=list(BAKES), options={k: v for k, v in FAST.items() if k in BAKES})
    out = tmp_path / "all.glb"
    save(asset, out)
    report = validate.validate_file(out, khronos=False)
    assert report["issues"]["numErrors"] == 0, [m for m in report["issues"]["messages"] if m["severity"] == 0]
    assert_khronos_clean(out)
    merged = validate.validate_file(out)
    if merged["khronos"]["ran"]:
        # Khronos cannot see our extensions' references; the merged report drops its "unused" guesses about them
        codes = {m["code"] for m in merged["issues"]["messages"]}
        assert not codes & {"UNUSED_OBJECT", "UNSUPPORTED_EXTENSION"}, codes
    used = set(asset.doc.json["extensionsUsed"])
    assert {"BAKER_thickness", "BAKER_edges", "BAKER_tonal_art_map", "BAKER_fur"} <= used
    assert not set(asset.doc.json.get("extensionsRequired", [])) & used

    from pxr import Usd, UsdGeom

    written = save(asset, tmp_path / "all.usda")
    stage = Usd.Stage.Open(str(written[-1]))
    meshes = [p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)
              and UsdGeom.Imageable(p).ComputePurpose() != UsdGeom.Tokens.guide]
    assert len(meshes) == 1  # fins are guide meshes: runtime geometry no final render draws
    fins = [p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh) and p.HasRelationship("baker:finsOf")]
    assert fins and all(UsdGeom.Imageable(p).ComputePurpose() == UsdGeom.Tokens.guide for p in fins)
    names = {pv.GetPrimvarName() for pv in UsdGeom.PrimvarsAPI(meshes[0]).GetPrimvars()}
    assert {"baker:thickness", "baker:curvature", "baker:outline_normal"} <= names
