"""Tonal art maps (Praun et al. 2001): the acceptance criteria of issue 6, checked on written files.

- nesting, pixel-exact on the stroke masks of the written PNGs: tone t's ink is inside tone t+1's at every level,
  and the stroke table (each stroke rasterized on its own, by a rasterizer checked against brute force) reproduces
  every (tone, level) mask exactly, so a stroke of level l is in every finer level;
- tone: mean darkness of every (tone, level) within 0.02 of its target, strictly increasing in tone, and a tone's
  levels within 0.03 of each other;
- tiling: the statistics across the wrap seam match those inside (and the check catches a real seam);
- a baked glTF carries the TAM and passes both validators; KTX2 files parse back to the PNG pixels.
"""
from __future__ import annotations

import json
import math
import struct
from pathlib import Path

import numpy as np
import pytest
import trimesh
from jsonschema import Draft202012Validator

import baker
from baker import readers
from baker.techniques.tam.options import TamOptions
from baker.techniques.tam.kernel import generate_tam, rasterize_stroke, tone_targets
from baker.cli import main as cli
from baker.gltf.document import GltfDocument
from baker.gltf.images import decode_image, read_image
from baker.gltf.ktx2 import IDENTIFIER, decode_ktx2, encode_ktx2
from baker.pipeline import save
from baker import validate
from baker.data import SCHEMA_ROOT
from baker.validate import validate_file
from conftest import assert_khronos_clean

STYLES = ("hatching", "cross-hatching", "stippling")
SPOT = Path(__file__).parents[2] / "examples" / "spot" / "spot.obj"


# ---------------------------------------------------------------------------------------------------------- fixtures
@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """`baker tam -o DIR --ktx2` for every style (6 tones x 4 levels, 256 px), read back from the files."""
    out = {}
    for style in STYLES:
        folder = tmp_path_factory.mktemp(style)
        assert cli(["tam", "-o", str(folder), "--ktx2", "--seed", "5", "--tam-style", style, "-q"]) == 0
        manifest = json.loads((folder / "tam.json").read_text())
        levels = []
        for level in manifest["levels"]:
            a, b = (read_image(folder / name) for name in level["files"])
            assert a.dtype == np.uint8 and a.shape == (level["size"], level["size"], 3)
            levels.append(np.concatenate([a, b], axis=2).transpose(2, 0, 1))  # (6 tones, R, R) brightness
        out[style] = {"folder": folder, "manifest": manifest, "levels": levels,
                      "tam": generate_tam(TamOptions(style=style), seed=5)}
    return out


def darkness(brightness_u8: np.ndarray) -> np.ndarray:
    return 1.0 - brightness_u8.astype(np.float64) / 255.0


# ---------------------------------------------------------------------------------------------------------- manifest
def test_manifest_states_tones_levels_and_files(written):
    m = written["hatching"]["manifest"]
    assert m["levelOrder"] == "finestFirst" and m["layout"] == "packed"
    assert m["tones"] == pytest.approx(list(tone_targets(6, 0.85)))
    assert [lv["size"] for lv in m["levels"]] == [256, 128, 64, 32]
    for lv in m["levels"]:
        assert all((written["hatching"]["folder"] / f).is_file() for f in lv["files"])
    assert m["ktx2"]["levelCount"] == 4


# ---------------------------------------------------------------------------------------------------------- nesting
@pytest.mark.parametrize("style", STYLES)
def test_tones_nest_pixel_exactly(written, style):
    """At every level, every inked pixel of tone t is inked in tone t+1, and never lighter."""
    for level in written[style]["levels"]:
        for t in range(5):
            light, dark = level[t], level[t + 1]
            assert np.all(dark <= light), f"tone {t + 1} lighter than tone {t} somewhere"
            mask_light, mask_dark = light < 255, dark < 255
            assert mask_light.any() and np.all(mask_dark[mask_light])
            assert mask_dark.sum() > mask_light.sum()


def _brute_force_coverage(x, y, angle, length, width, size):
    """Independent rasterizer of a straight stroke: distance from every pixel centre to the segment, over the 3 x 3
    neighbouring tiles (toroidal wrap), coverage clamp(w/2 + 1/2 - d, 0, 1)."""
    j, i = np.meshgrid(np.arange(size) + 0.5, np.arange(size) + 0.5)
    c = np.array([x, y]) * size
    u = np.array([math.cos(angle), math.sin(angle)])
    a, b = c - u * length * size / 2, c + u * length * size / 2
    best = np.full((size, size), np.inf)
    for ox in (-size, 0, size):
        for oy in (-size, 0, size):
            p = np.stack([j - ox, i - oy], -1)
            d = b - a
            t = np.clip(((p - a) @ d) / max(d @ d, 1e-300), 0, 1)
            best = np.minimum(best, np.linalg.norm(p - (a + t[..., None] * d), axis=-1))
    return np.clip(width / 2 + 0.5 - best, 0.0, 1.0)


def test_stroke_rasterizer_matches_brute_force():
    rng = np.random.default_rng(3)
    for _ in range(12):
        x, y, angle = rng.random(), rng.random(), rng.uniform(-math.pi, math.pi)
        length, width, size = rng.uniform(0.0, 0.9), rng.uniform(0.7, 4.0), int(rng.choice([16, 32, 64]))
        mine = rasterize_stroke(x, y, angle, length, 0.0, width, size)
        np.testing.assert_allclose(mine, _brute_force_coverage(x, y, angle, length, width, size), atol=1e-9)


def test_stroke_width_is_constant_in_pixels():
    """A stroke drawn at a level twice as fine covers twice the pixels (length scales, width does not)."""
    areas = [rasterize_stroke(0.3, 0.6, 0.4, 0.5, 0.0, 1.5, s).sum() for s in (32, 64, 128, 256)]
    ratios = np.array(areas[1:]) / np.array(areas[:-1])
    assert np.all(np.abs(ratios - 2.0) < 0.15), ratios


@pytest.mark.parametrize("style", STYLES)
def test_strokes_nest_across_levels_pixel_exactly(written, style):
    """Every (tone, level) image is exactly the union of the strokes the table says it has: the strokes of lighter
    tones and of coarser levels, each drawn at this level's resolution (so each stroke of level l is in l+1)."""
    tam, levels = written[style]["tam"], written[style]["levels"]
    s = tam.strokes
    for t in range(6) if style != "stippling" else (0, 3, 5):  # stippling: ~40 000 dots, three tones suffice
        for lv, size in enumerate(tam.sizes):
            present = tam.stroke_set(t, lv)
            if lv + 1 < len(tam.sizes):  # a stroke of a coarser level is also in this finer one
                assert set(tam.stroke_set(t, lv + 1)) <= set(present)
            paper = np.ones((size, size))  # ink over paper: what is left of the paper after every stroke
            for k in present:
                paper *= 1.0 - rasterize_stroke(s["x"][k], s["y"][k], s["angle"][k], s["length"][k],
                                                s["sagitta"][k], s["width"][k], size)
            expected = np.rint(paper * 255.0)
            image = levels[lv][t].astype(np.float64)
            # the same image, to float rounding: equal except where a pixel sits on a rounding boundary
            edge = np.abs(paper * 255.0 - np.floor(paper * 255.0) - 0.5) < 1e-6
            assert np.array_equal(expected[~edge], image[~edge]), \
                f"tone {t} level {lv}: {np.sum(expected[~edge] != image[~edge])} pixels differ"
            assert np.abs(expected - image).max() <= 1.0
            assert np.array_equal((expected < 255)[~edge], (image < 255)[~edge])  # the stroke masks


def test_stroke_table_is_ordered_lightest_tone_coarsest_level_first(written):
    s = written["hatching"]["tam"].strokes
    key = s["tone"] * 100 + (100 - s["level"])
    assert np.all(np.diff(key) >= 0)
    assert set(np.unique(s["level"])) == {0, 1, 2, 3}


# ---------------------------------------------------------------------------------------------------------- tone
@pytest.mark.parametrize("style", STYLES)
def test_tone_accuracy(written, style):
    targets = np.array(written[style]["manifest"]["tones"])
    means = np.array([[darkness(level[t]).mean() for t in range(6)] for level in written[style]["levels"]])
    print(f"\n{style}: max |mean - target| = {np.abs(means - targets).max():.4f}, "
          f"max level spread = {np.ptp(means, axis=0).max():.4f}")
    assert np.abs(means - targets).max() <= 0.02
    assert np.all(np.diff(means, axis=1) > 0)  # strictly darker with the tone, at every level
    assert np.ptp(means, axis=0).max() <= 0.03  # one tone's levels agree
    np.testing.assert_allclose(written[style]["manifest"]["measuredTones"], means, atol=1e-5)


def test_volume_tam_many_tones():
    """Webb's volume TAM: 12 tones, spatial-only levels; same nesting and tone guarantees."""
    tam = generate_tam(TamOptions(tones=12, levels=3, size=128, layout="volume"), seed=2)
    for lv in range(3):
        bright = tam.brightness_u8(lv)
        means = darkness(bright).mean(axis=(1, 2))
        assert np.abs(means - tam.targets).max() <= 0.02 and np.all(np.diff(means) > 0)
        assert np.all(bright[1:] <= bright[:-1])


# ---------------------------------------------------------------------------------------------------------- tiling
def _column_correlations(d: np.ndarray) -> np.ndarray:
    """Correlation of each column j with column j + 1 (wrapped): index R-1 is the seam between the last and first."""
    a, b = d - d.mean(axis=0), np.roll(d, -1, axis=1) - np.roll(d, -1, axis=1).mean(axis=0)
    return (a * b).sum(axis=0) / np.sqrt((a * a).sum(axis=0) * (b * b).sum(axis=0))


def _seam_ok(d: np.ndarray, seam: int) -> bool:
    """The pair of columns across `seam` looks like the interior pairs: correlation above the 2nd percentile of the
    interior, and the border columns' darkness within the interior columns' range."""
    corr = _column_correlations(d)
    interior = np.delete(corr, [(seam - 1) % d.shape[1]])
    means = d.mean(axis=0)
    return (corr[(seam - 1) % d.shape[1]] >= np.percentile(interior, 2)
            and means.min() - 1e-9 <= means[seam] <= means.max() + 1e-9)


@pytest.mark.parametrize("style", ("hatching", "cross-hatching"))
def test_tiles_without_seam(written, style):
    for lv, level in enumerate(written[style]["levels"][:3]):
        for t in (0, 3, 5):
            d = darkness(level[t])
            assert _seam_ok(d, 0), f"vertical seam at tone {t} level {lv}"
            assert _seam_ok(d.T, 0), f"horizontal seam at tone {t} level {lv}"
            # and the ink does not jump across the seam: the 4 columns (rows) left of it against the 4 right of
            # it differ no more than such neighbouring bands do somewhere inside
            for image in (d, d.T):
                columns = image.mean(axis=0)
                left = sum(np.roll(columns, k) for k in range(1, 5)) / 4  # at position j: columns j-4 .. j-1
                right = sum(np.roll(columns, -k) for k in range(0, 4)) / 4  # columns j .. j+3
                jump = np.abs(left - right)
                assert jump[0] <= jump[1:].max()


def test_seam_check_catches_a_seam(written):
    """The same statistic on an image with a real discontinuity (half the columns shifted) flags it."""
    d = darkness(written["hatching"]["levels"][0][2])
    size = d.shape[1]
    broken = np.concatenate([d[:, : size // 2], np.roll(d[:, size // 2:], size // 3, axis=0)], axis=1)
    assert _seam_ok(d, size // 2)
    assert not _seam_ok(broken, size // 2)


# ---------------------------------------------------------------------------------------------------------- files
def test_deterministic_by_seed(tmp_path):
    a, b, c = tmp_path / "a", tmp_path / "b", tmp_path / "c"
    for folder, seed in ((a, 9), (b, 9), (c, 10)):
        assert cli(["tam", "-o", str(folder), "--seed", str(seed), "--ktx2", "-q", "--tam-size", "64",
                    "--tam-levels", "3"]) == 0
    names = sorted(p.name for p in a.iterdir())
    assert names == sorted(p.name for p in b.iterdir())
    for name in names:
        assert (a / name).read_bytes() == (b / name).read_bytes(), name
    assert (a / "tam_level0_tones012.png").read_bytes() != (c / "tam_level0_tones012.png").read_bytes()


def test_ktx2_parses_back_to_the_png_levels(written):
    folder, manifest = written["cross-hatching"]["folder"], written["cross-hatching"]["manifest"]
    for j, name in enumerate(manifest["ktx2"]["files"]):
        blob = (folder / name).read_bytes()
        assert blob[:12] == IDENTIFIER
        vk, type_size, w, h, depth, layers, faces, count, scheme = struct.unpack_from("<9I", blob, 12)
        assert (vk, type_size, w, h, depth, layers, faces, count, scheme) == (37, 1, 256, 256, 0, 0, 1, 4, 0)
        parsed = decode_ktx2(blob)
        assert parsed["kvd"]["KTXwriter"].startswith("baker") and parsed["kvd"]["KTXorientation"] == "rd"
        # DFD: RGBSDA model, linear transfer, 4 samples of 8 bits, channel ids R G B A
        dfd = parsed["dfd"]
        assert dfd[0] == 4 + 24 + 4 * 16 and dfd[2] >> 16 == 24 + 4 * 16 and dfd[3] & 0xFF == 1
        assert (dfd[3] >> 16) & 0xFF == 1 and dfd[5] & 0xFF == 4
        assert [(dfd[7 + 4 * k] >> 24) & 0xF for k in range(4)] == [0, 1, 2, 15]
        # level index: base first; data stored smallest level first, aligned to 4
        offsets = [struct.unpack_from("<3Q", blob, 80 + 24 * i) for i in range(4)]
        assert all(o[0] % 4 == 0 and o[1] == o[2] for o in offsets)
        assert offsets[3][0] < offsets[2][0] < offsets[1][0] < offsets[0][0]
        assert offsets[0][0] + offsets[0][1] == len(blob)
        for i, level in enumerate(written["cross-hatching"]["levels"]):
            rgba = parsed["levels"][i]
            assert rgba.shape == (256 >> i, 256 >> i, 4) and np.all(rgba[..., 3] == 255)
            np.testing.assert_array_equal(rgba[..., :3], level[3 * j: 3 * j + 3].transpose(1, 2, 0))


def test_ktx2_array_round_trip():
    rng = np.random.default_rng(0)
    chain = [rng.integers(0, 256, (5, 16 >> i, 16 >> i, 1), dtype=np.uint8) for i in range(3)]
    parsed = decode_ktx2(encode_ktx2(chain))
    assert parsed["vkFormat"] == 9 and parsed["layers"] == 5
    for a, b in zip(chain, parsed["levels"]):
        np.testing.assert_array_equal(a, b)
    with pytest.raises(ValueError):
        encode_ktx2([np.zeros((8, 8, 4), np.uint8), np.zeros((8, 8, 4), np.uint8)])  # level 1 must be 4 x 4


def test_volume_command_writes_stacked_layers(tmp_path):
    assert cli(["tam", "-o", str(tmp_path), "--ktx2", "-q", "--tam-layout", "volume", "--tam-tones", "8",
                "--tam-size", "64", "--tam-levels", "3", "--tam-style", "stippling"]) == 0
    manifest = json.loads((tmp_path / "tam.json").read_text())
    assert manifest["layout"] == "volume" and len(manifest["tones"]) == 8
    parsed = decode_ktx2((tmp_path / "tam.ktx2").read_bytes())
    assert parsed["layers"] == 8 and len(parsed["levels"]) == 3
    for i, level in enumerate(manifest["levels"]):
        stack = read_image(tmp_path / level["file"])[..., 0]
        assert stack.shape == (8 * level["size"], level["size"])
        np.testing.assert_array_equal(parsed["levels"][i][..., 0], stack.reshape(8, level["size"], level["size"]))


@pytest.mark.parametrize("flags", [["--tam-tones", "4"], ["--tam-size", "100"], ["--tam-levels", "8",
                                   "--tam-size", "64"], ["--tam-stroke-length", "0.5,0.2"]])
def test_bad_options_exit_2(tmp_path, capsys, flags):
    assert cli(["tam", "-o", str(tmp_path / "x"), "-q", *flags]) == 2
    assert "baker: error:" in capsys.readouterr().err
    assert not (tmp_path / "x" / "tam.json").exists()


# ---------------------------------------------------------------------------------------------------------- glTF
@pytest.fixture(scope="module")
def baked(tmp_path_factory):
    """An icosphere without UVs (unwrapped by the bake) baked with tam + toon, written, and read back; the angle of
    the standalone map (a stroke-parameterized bake defaults to 0), so the images compare."""
    folder = tmp_path_factory.mktemp("baked")
    source = folder / "sphere.glb"
    trimesh.creation.icosphere(subdivisions=3, radius=1.0).export(str(source))
    asset = baker.bake(str(source), bakes=["tam", "toon"], seed=5,
                       options={"tam": {"style": "cross-hatching", "angle": 30.0}, "toon": {"bands": 4, "softness": 0.2}})
    out = folder / "sphere_tam.glb"
    save(asset, out)
    return out


def test_baked_gltf_validates(baked, written):
    report = validate_file(baked, khronos=False)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert_khronos_clean(baked)
    doc = GltfDocument.load(baked)
    material = doc.json["materials"][doc.json["meshes"][0]["primitives"][0]["material"]]
    ext = material["extensions"]["BAKER_tonal_art_map"]
    assert "BAKER_tonal_art_map" in doc.json["extensionsUsed"]
    assert "BAKER_tonal_art_map" not in doc.json.get("extensionsRequired", [])
    assert f"TEXCOORD_{ext['texCoord']}" in doc.json["meshes"][0]["primitives"][0]["attributes"]
    assert ext["scale"] > 0 and ext["levelOrder"] == "finestFirst"
    # the images in the glTF are the same TAM the standalone command wrote for the same seed and options
    for i, level in enumerate(ext["levels"]):
        for j, info in enumerate(level["textures"]):
            png = doc.image_bytes(doc.json["textures"][info["index"]]["source"])
            np.testing.assert_array_equal(decode_image(png), written["cross-hatching"]["levels"][i][3 * j: 3 * j + 3]
                                          .transpose(1, 2, 0))
    toon = material["extensions"]["BAKER_toon_ramp"]
    ramp = decode_image(doc.image_bytes(doc.json["textures"][toon["rampTexture"]["index"]]["source"]))
    assert ramp.shape[:2] == (1, 256) and toon["bands"] == 4


def test_spot_baked_with_volume_tam_validates(tmp_path):
    out = tmp_path / "spot.gltf"
    asset = baker.bake(str(SPOT), bakes=["tam"],
                       options={"tam": {"layout": "volume", "tones": 8, "size": 64, "levels": 3, "direction": True}})
    save(asset, out)
    report = validate_file(out, khronos=False)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert_khronos_clean(out)
    ext = GltfDocument.load(out).json["materials"][0]["extensions"]["BAKER_tonal_art_map"]
    # spot's own UVs stay TEXCOORD_0; the stroke parameterization is the next set
    assert ext["texCoord"] == 1 and [lv["size"] for lv in ext["levels"]] == [64, 32, 16]
    assert ext["strokes"]["directionAttribute"] == "_HATCHING_DIRECTION" and ext["scale"] == 64.0


def test_strokes_uv_keeps_the_meshs_own_uvs(tmp_path):
    out = tmp_path / "spot.glb"
    plain = readers.read(SPOT).doc
    save(baker.bake(str(SPOT), bakes=["tam"], options={"tam": {"size": 32, "levels": 1, "strokes": "uv"}}), out)
    doc = GltfDocument.load(out)
    ext = doc.json["materials"][0]["extensions"]["BAKER_tonal_art_map"]
    assert ext["texCoord"] == 0 and "strokes" not in ext and ext["angle"] == pytest.approx(math.radians(30.0))
    prim, before = doc.json["meshes"][0]["primitives"][0], plain.json["meshes"][0]["primitives"][0]
    assert set(prim["attributes"]) == set(before["attributes"])  # no new set, no direction, no split
    assert doc.json["accessors"][prim["attributes"]["POSITION"]]["count"] == \
        plain.json["accessors"][before["attributes"]["POSITION"]]["count"]


def test_validator_catches_broken_tam(baked, tmp_path):
    doc = GltfDocument.load(baked)
    ext = doc.json["materials"][0]["extensions"]["BAKER_tonal_art_map"]
    ext["tones"][2], ext["tones"][3] = ext["tones"][3], ext["tones"][2]
    ext["levels"][1]["size"] = 100
    ext["strokeWidth"] = -1.0  # the schema's business
    prim = doc.json["meshes"][0]["primitives"][0]
    del prim["attributes"][f"TEXCOORD_{ext['texCoord']}"]
    ext["texCoord"] = 7
    ext["strokes"]["directionAttribute"] = "_NO_SUCH_DIRECTION"  # named, not written
    ext["strokes"]["fallbackFaces"] = 10 ** 6
    broken = tmp_path / "broken.gltf"
    doc.save(broken)
    codes = {m["code"] for m in validate_file(broken, khronos=False)["issues"]["messages"] if m["severity"] == 0}
    assert {"BAKER_TAM_TONES_NOT_INCREASING", "BAKER_TAM_LEVEL_SIZE", "BAKER_TAM_TEXCOORD_MISSING",
            "BAKER_TAM_DIRECTION_MISSING", "BAKER_TAM_FALLBACK_COUNT", "BAKER_SCHEMA"} <= codes


def test_usd_carries_the_parameters(baked, tmp_path):
    pytest.importorskip("pxr")
    from pxr import Usd

    out = tmp_path / "sphere.usda"
    save(baker.bake(str(baked), bakes=[]), out)
    stage = Usd.Stage.Open(str(out))
    materials = [p for p in stage.Traverse() if p.GetTypeName() == "Material"]
    tones = materials[0].GetAttribute("baker:tonal_art_map:tones").Get()
    assert tones is not None and len(tones) == 6
    assert materials[0].GetAttribute("baker:toon_ramp:bands").Get() == 4


def test_readme_example_is_valid():
    name = "BAKER_tonal_art_map"
    schema = json.loads(validate.schema_registry()[(name, "material")].read_text())
    readme = (SCHEMA_ROOT / name / "README.md").read_text()
    block = readme.split("```json")[1].split("```")[0].strip()
    example = json.loads(block if block.startswith("{") else "{" + block + "}")  # a whole glTF, or a fragment
    ext = (example["materials"][0]["extensions"] if "materials" in example else example["extensions"])[name]
    assert not list(Draft202012Validator(schema).iter_errors(ext))
