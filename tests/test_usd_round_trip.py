"""baker reads its own USD: ``inspect``, ``preview`` and ``validate`` of a baked ``.usda``/``.usdz`` report the same
baked data as the GLB of the same bake (:mod:`baker.readers.usd_baked`), and a stage whose baked data is broken
(written with pxr: a NaN, a wrong-length primvar) fails validation with one error and is refused by the reader."""
from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

pxr = pytest.importorskip("pxr")

from pxr import Sdf, Usd, UsdGeom, Vt  # noqa: E402

import baker  # noqa: E402
from baker import validate  # noqa: E402
from baker.commands.inspect import describe  # noqa: E402
from baker.errors import BakerError  # noqa: E402
from baker.pipeline import save  # noqa: E402
from baker.preview.core import preview  # noqa: E402

SPOT = Path(__file__).parents[1] / "examples" / "spot" / "spot.obj"
BAKES = ("thickness", "curvature", "skin", "edges", "tam", "toon", "fur", "caustics", "normal-blur")
FAST = {
    "thickness": {"rays": 8, "texture_size": 64},
    "curvature": {"per_texel": True, "texture_size": 64},
    "skin": {"width": 32, "height": 32, "penumbra_size": 16},
    "tam": {"size": 64, "levels": 2},
    "edges": {"fins": True},
    "fur": {"fins": True, "shells": 4, "texture_size": 32, "hairs": 100},  # fins: a fin primitive to read back
    "caustics": {"size": 32, "frames": 2, "waves": 16},
    "normal-blur": {"texture_size": 64},
}


def _spot_with_maps():
    """spot with a base colour and a tangent-space normal map (normal-blur needs one; preview draws both)."""
    from baker import readers
    from baker.gltf.images import encode_image

    asset = readers.read(SPOT)
    doc = asset.doc
    y, x = np.mgrid[0:64, 0:64] / 64.0
    slope = 0.3 * np.sin(2 * np.pi * 4 * x)  # bumps along u
    normal = np.stack([-slope, np.zeros_like(slope), np.ones_like(slope)], -1)
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    color = np.stack([x, y, 0.5 + 0 * x], -1)
    images = {"normal": np.rint((normal + 1) / 2 * 255).astype(np.uint8), "color": np.rint(color * 255).astype(np.uint8)}
    textures = {k: doc.add_texture(doc.add_image(encode_image(v, ".png"), "image/png", k)) for k, v in images.items()}
    material = doc.json["materials"][0]
    material["normalTexture"] = {"index": textures["normal"], "scale": 0.8}
    material["pbrMetallicRoughness"]["baseColorTexture"] = {"index": textures["color"]}
    return asset


@pytest.fixture(scope="module")
def bake(tmp_path_factory):
    folder = tmp_path_factory.mktemp("round_trip")
    asset = baker.bake(_spot_with_maps(), bakes=list(BAKES), options=FAST)
    for name in ("spot.glb", "spot.usda", "spot.usdc", "spot.usdz"):
        save(asset, folder / name)
    return folder




@pytest.mark.parametrize("suffix", [".usda", ".usdz"])
def test_inspect_reports_the_glb_baked_data(bake, suffix):
    glb, usd = describe(bake / "spot.glb"), describe(bake / f"spot{suffix}")
    # the surface, then the fins of edges and of fur (finsOf), each with its baked attributes and extensions
    assert len(glb["meshes"]) == len(usd["meshes"]) == 3
    assert set(glb["meshes"][0]["baked"]) >= {"_THICKNESS", "_CURVATURE", "_OUTLINE_NORMAL"}
    assert set(glb["meshes"][0]["extensions"]) == {"BAKER_edges", "EXT_mesh_primitive_edge_visibility"}
    for a, b in zip(glb["meshes"], usd["meshes"]):
        assert [b[k] for k in ("mesh", "primitive", "vertices", "triangles", "attributes", "extensions")] == \
            [a[k] for k in ("mesh", "primitive", "vertices", "triangles", "attributes", "extensions")]
        assert set(b["baked"]) == set(a["baked"])
        for name, stats in a["baked"].items():
            for key in ("min", "mean", "max"):
                assert b["baked"][name][key] == pytest.approx(stats[key], rel=1e-6, abs=1e-7), (name, key)
    assert [m["extensions"] for m in usd["materials"]] == [m["extensions"] for m in glb["materials"]]
    assert sorted(t["size"] for m in usd["materials"] for t in m["textures"]) == \
        sorted(t["size"] for m in glb["materials"] for t in m["textures"])
    # fur's coverage-preserving mip chains: the KTX2 files come back as the same chains
    chains = [[(c["place"], c["size"], c["levels"], c["coverage"]) for c in info["coverageMips"]] for info in (glb, usd)]
    assert len(chains[0]) == 5 and chains[1] == chains[0]


def _without_indices(value):
    """An extension object without its glTF indices (they number the objects of each document differently)."""
    if isinstance(value, dict):
        return {k: _without_indices(v) for k, v in value.items() if k not in ("index", "texture", "accessor")}
    if isinstance(value, list):
        return [_without_indices(v) for v in value]
    return value


def test_material_extensions_read_back_unchanged(bake):
    from baker import readers

    glb, usd = (readers.read(bake / name).doc.json["materials"][0] for name in ("spot.glb", "spot.usdc"))
    assert sorted(usd["extensions"]) == sorted(glb["extensions"]) and len(glb["extensions"]) >= 9
    for name, params in glb["extensions"].items():
        assert _without_indices(usd["extensions"][name]) == _without_indices(params), name
    assert usd["normalTexture"]["scale"] == pytest.approx(0.8) and "baseColorTexture" in usd["pbrMetallicRoughness"]


def test_preview_draws_the_glb_panels(bake):
    size = 48
    glb, usd = preview(bake / "spot.glb", size=size), preview(bake / "spot.usda", size=size)
    names = [name for name, _, _ in glb.panels]
    assert {"lambert", "thickness", "skin", "normal-blur", "toon", "caustics", "hatching", "outline", "wireframe",
            "fur"} <= set(names), names
    assert [name for name, _, _ in usd.panels] == names
    assert usd.sheet.shape == glb.sheet.shape
    for name, _, (y, x, s) in glb.panels:
        a = glb.sheet[y: y + s, x: x + s].astype(np.float64)
        b = usd.sheet[y: y + s, x: x + s].astype(np.float64)
        assert np.abs(a - b).mean() < 0.5, (name, np.abs(a - b).mean())  # measured: 0 on every panel


def test_validate_passes_a_good_stage_without_khronos(bake, capsys):
    report = validate.validate_file(bake / "spot.usda")  # Khronos asked for: not applicable, not a failure
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert report["khronos"]["ran"] is False and "not applicable" in report["khronos"]["reason"]
    assert report["mimeType"] == "model/vnd.usda"
    assert validate.main([str(bake / "spot.usdz")], khronos=False) == 0
    assert "Khronos glTF-Validator does not apply" in validate.format_text("spot.usda", report)


def _broken_copy(bake, tmp_path, values) -> Path:
    """spot.usda with its thickness primvar replaced by ``values`` (given the original)."""
    shutil.copytree(bake / "spot_textures", tmp_path / "spot_textures")
    out = tmp_path / "spot.usda"
    shutil.copy(bake / "spot.usda", out)
    stage = Usd.Stage.Open(str(out))
    mesh = next(p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh))
    primvar = UsdGeom.PrimvarsAPI(mesh).GetPrimvar("baker:thickness")
    primvar.Set(Vt.FloatArray.FromNumpy(values(np.asarray(primvar.Get(), np.float32))))
    stage.GetRootLayer().Save()
    return out


@pytest.mark.parametrize("broken, problem", [
    (lambda v: np.where(np.arange(len(v)) == 7, np.float32("nan"), v).astype(np.float32), "value 7 is not finite"),
    (lambda v: v[:-1], "values for"),
])
def test_validate_fails_a_stage_with_broken_baked_data(bake, tmp_path, broken, problem):
    out = _broken_copy(bake, tmp_path, broken)
    report = validate.validate_file(out, khronos=False)
    errors = [m for m in report["issues"]["messages"] if m["severity"] == 0]
    assert len(errors) == 1 and errors[0]["code"] == "BAKER_USD_UNREADABLE", errors
    assert "primvars:baker:thickness" in errors[0]["message"] and problem in errors[0]["message"]
    assert validate.main([str(out)], khronos=False) == 1
    with pytest.raises(BakerError, match="primvars:baker:thickness"):
        describe(out)
