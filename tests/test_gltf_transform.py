"""A baked asset survives glTF-Transform (dedup, flatten, resample, prune, sparse) with our extension classes."""
from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import baker
from baker import validate
from baker.io.gltf import GltfDocument
from baker.pipeline import save
from conftest import assert_khronos_clean

PACKAGE = Path(__file__).parents[1] / "runtime-shaders" / "gltf-transform"
SPOT = Path(__file__).parents[1] / "examples" / "spot" / "spot.obj"


def _require_package():
    missing = shutil.which("node") is None or not (PACKAGE / "node_modules" / "@gltf-transform" / "core").is_dir()
    if missing:
        if os.environ.get("CI", "").lower() in ("1", "true", "yes"):
            pytest.fail("glTF-Transform is required in CI (scripts/install-node-tools installs it)")
        pytest.skip("node or @gltf-transform not installed (run scripts/install-node-tools)")


def _transform(src, out, control=False):
    env = dict(os.environ, BAKER_GLTF_TRANSFORM_CONTROL="1" if control else "0")
    result = subprocess.run(["node", str(PACKAGE / "test" / "roundtrip.mjs"), str(src), str(out)], env=env,
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr


@pytest.fixture(scope="module")
def baked(tmp_path_factory):
    out = tmp_path_factory.mktemp("gltf_transform") / "spot.glb"
    save(baker.bake(SPOT, options={"thickness": {"rays": 8, "texture_size": 64}}), out)
    return out


def test_baker_extensions_survive_the_pipeline(baked, tmp_path):
    _require_package()
    out = tmp_path / "processed.glb"
    _transform(baked, out)
    before, after = GltfDocument.load(baked), GltfDocument.load(out)
    mat_before, mat_after = before.json["materials"][0], after.json["materials"][0]
    assert mat_after["extensions"]["BAKER_thickness"] == mat_before["extensions"]["BAKER_thickness"]
    assert "BAKER_thickness" in after.json["extensionsUsed"]
    vol_before = mat_before["extensions"]["KHR_materials_volume"]
    vol_after = mat_after["extensions"]["KHR_materials_volume"]
    assert vol_after["thicknessFactor"] == pytest.approx(vol_before["thicknessFactor"])
    image = lambda doc, vol: doc.image_bytes(doc.json["textures"][vol["thicknessTexture"]["index"]]["source"])
    assert image(after, vol_after) == image(before, vol_before)
    prim_before = before.json["meshes"][0]["primitives"][0]["attributes"]
    prim_after = after.json["meshes"][0]["primitives"][0]["attributes"]
    assert np.array_equal(after.accessor(prim_after["_THICKNESS"]), before.accessor(prim_before["_THICKNESS"]))
    report = validate.validate_file(out, khronos=False)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert_khronos_clean(out)


def test_control_without_our_classes_loses_the_extension(baked, tmp_path):
    # proves the test above can fail: glTF-Transform drops extensions it has no class for
    _require_package()
    out = tmp_path / "control.glb"
    _transform(baked, out, control=True)
    after = GltfDocument.load(out)
    assert "BAKER_thickness" not in after.json["materials"][0].get("extensions", {})
