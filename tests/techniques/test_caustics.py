"""Offline caustics (RTR4 14.5.3): the Done-when of issue 29, checked against closed forms and written files.

- energy: every frame's mean irradiance is 1 within 3 %, flat water is 1 everywhere, the default waves focus light;
- seamless: the steps across the tile's edges and from the last frame to the first are like the steps inside;
- analytic: for h = A cos(k x) under a vertical sun, the crests focus at z_f = 1 / ((1 - 1/n) A k^2) below the
  crest (small slopes), on the lines x = 0 mod wavelength, and the crest's irradiance at depth z is 1 / (1 - z/z_f);
- the command's files (16-bit PNGs, caustics.json, KTX2) read back to the kernel's irradiance, byte-identical per seed;
- an asset baked with ``--bakes caustics`` passes both validators, reads back, and carries the data into USD.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
import trimesh
from jsonschema import Draft202012Validator

import baker
from baker import validate
from baker.cli import main as cli
from baker.data import SCHEMA_ROOT
from baker.gltf.document import GltfDocument
from baker.gltf.images import decode_image, read_image
from baker.gltf.ktx2 import decode_ktx2
from baker.pipeline import save
from baker.techniques.caustics.extension import read
from baker.techniques.caustics.kernel import caustic_frames, irradiance
from baker.techniques.caustics.light import floor_hits
from baker.techniques.caustics.options import CausticsOptions
from baker.techniques.caustics.spectrum import sample_surface, single_wave
from baker.validate import validate_file
from conftest import assert_khronos_clean

SMALL = dict(size=64, frames=8)
VERTICAL = np.array([0.0, 0.0, 1.0])


@pytest.fixture(scope="module")
def default_frames():
    return caustic_frames(CausticsOptions(**SMALL), seed=1).irradiance


# ---------------------------------------------------------------------------------------------------------- energy
@pytest.mark.parametrize("options", [dict(), dict(spectrum="jonswap", wind_speed=2.0, sun_elevation=40.0),
                                     dict(method="jacobian", samples=2), dict(ior_rgb=(1.330, 1.333, 1.340)),
                                     dict(choppiness=1.0, amplitude=0.02, sun_azimuth=120.0)])
def test_every_frame_keeps_the_light(options):
    frames = caustic_frames(CausticsOptions(**SMALL, **options), seed=2).irradiance
    means = frames.mean(axis=(1, 2))
    assert np.all(np.abs(means - 1.0) < 0.03), means
    assert np.isfinite(frames).all() and frames.min() >= 0


@pytest.mark.parametrize("method", ["photons", "jacobian"])
@pytest.mark.parametrize("elevation", [90.0, 35.0])
def test_flat_water_is_uniform(method, elevation):
    frames = caustic_frames(CausticsOptions(**SMALL, amplitude=0.0, method=method, sun_elevation=elevation,
                                            sun_azimuth=30.0)).irradiance
    assert frames.std() < 0.01 and abs(frames.mean() - 1.0) < 0.01


def test_default_waves_focus_light(default_frames):
    peaks = default_frames.max(axis=(1, 2, 3)) / default_frames.mean(axis=(1, 2, 3))
    assert np.all(peaks >= 3.0), peaks


# ---------------------------------------------------------------------------------------------------------- seamless
def steps(a: np.ndarray, axis: int) -> np.ndarray:
    """Mean absolute step between neighbours along ``axis``, per position along it: (n - 1,) interior steps and the
    wrap step last."""
    n = a.shape[axis]
    inside = [np.abs(np.take(a, i + 1, axis) - np.take(a, i, axis)).mean() for i in range(n - 1)]
    return np.array(inside + [np.abs(np.take(a, 0, axis) - np.take(a, n - 1, axis)).mean()])


def assert_wrap_like_inside(a: np.ndarray, axis: int) -> None:
    s = steps(a, axis)
    assert s[:-1].min() <= s[-1] <= s[:-1].max(), (s[-1], s[:-1].min(), s[:-1].max())


@pytest.mark.parametrize("axis", [0, 1, 2])  # time (last frame -> first), rows (top/bottom), columns (left/right)
def test_seamless_in_space_and_time(default_frames, axis):
    assert_wrap_like_inside(default_frames[..., 0], axis)


def test_seam_check_catches_a_seam(default_frames):
    cut = default_frames[..., 0][:, :, : 3 * default_frames.shape[2] // 4]  # a tile cut short: its edges do not meet
    with pytest.raises(AssertionError):
        assert_wrap_like_inside(cut, 2)
    skipped = default_frames[[0, 1, 2, 3, 4, 5], ..., 0]  # a loop missing its last frames: 5 -> 0 jumps 3 frames
    with pytest.raises(AssertionError):
        assert_wrap_like_inside(skipped, 0)


# ---------------------------------------------------------------------------------------------------------- analytic
IOR, AMPLITUDE, TILE, CYCLES = 1.333, 0.002, 1.0, 2
K = 2 * np.pi * CYCLES / TILE
FOCAL = 1.0 / ((1.0 - 1.0 / IOR) * AMPLITUDE * K * K)  # below the crest


def test_crests_focus_at_the_closed_form_depth():
    surface = sample_surface(single_wave(AMPLITUDE, CYCLES, TILE), 0.0, 256)
    # the floor position of the crest's neighbourhood is linear in the floor depth; it stops depending on the
    # surface position (d floor_x / d x = 0) at the focal depth
    slopes = []
    for depth in (1.0, 2.0):
        floor_xy, _ = floor_hits(surface, VERTICAL, IOR, depth)
        x = floor_xy[0, :, 0]
        slopes.append((x[1] - x[-1] + TILE) / (2 * surface.spacing))  # central difference at the crest x = 0
    focus = 1.0 - slopes[0] * (2.0 - 1.0) / (slopes[1] - slopes[0])  # where the slope, linear in depth, is 0
    assert focus + AMPLITUDE == pytest.approx(FOCAL, rel=0.02)


@pytest.mark.parametrize("method", ["photons", "jacobian"])
def test_crest_irradiance_and_caustic_lines(method):
    wave = single_wave(AMPLITUDE, CYCLES, TILE)
    size = 256
    half = irradiance(wave, 0.0, size=size, samples=8, depth=0.5 * FOCAL - AMPLITUDE, ior=IOR, method=method)
    # texel centres at (i + 0.5) / size: the crest x = 0 lies between the first and the last texel
    crest = 0.5 * (half[0, 0] + half[0, -1])
    assert crest == pytest.approx(2.0, rel=0.02)  # 1 / (1 - z / z_f) at z = z_f / 2
    near = irradiance(wave, 0.0, size=size, samples=8, depth=0.9 * FOCAL - AMPLITUDE, ior=IOR, method=method)
    row = near[size // 2]
    wavelength = size / CYCLES  # texels
    for line in range(CYCLES):  # each caustic line: a parabola through the brightest texel and its neighbours
        window = np.arange(int(line * wavelength - wavelength / 4), int(line * wavelength + wavelength / 4))
        i = window[np.argmax(row[window % size])]
        a, b, c = row[(i - 1) % size], row[i % size], row[(i + 1) % size]
        peak = i + 0.5 + 0.5 * (a - c) / (a - 2 * b + c)
        assert abs(peak - line * wavelength) < 0.02 * wavelength
    assert row.max() > 5.0  # focusing: 1 / (1 - 0.9) = 10 at the crest itself, averaged over a texel


# ---------------------------------------------------------------------------------------------------------- files
@pytest.fixture(scope="module")
def written(tmp_path_factory):
    folder = tmp_path_factory.mktemp("caustics")
    flags = ["--caustics-size", "32", "--caustics-frames", "4", "--caustics-waves", "16", "--seed", "4"]
    assert cli(["caustics", "-o", str(folder), "--ktx2", "-q", *flags]) == 0
    return folder, flags


def test_manifest_and_frames_read_back(written):
    folder, _ = written
    manifest = json.loads((folder / "caustics.json").read_text())
    expected = caustic_frames(CausticsOptions(size=32, frames=4, waves=16), seed=4).irradiance
    assert manifest["frameCount"] == 4 and len(manifest["frames"]) == 4
    for f, name in enumerate(manifest["frames"]):
        pixels = read_image(folder / name)
        assert pixels.dtype == np.uint16 and pixels.shape == (32, 32, 1)
        decoded = pixels[..., 0] / 65535.0 * manifest["intensityScale"]
        np.testing.assert_allclose(decoded, expected[f, :, :, 0], atol=manifest["intensityScale"] / 65535)
    assert manifest["tileSize"] == 2.0 and manifest["depth"] == 1.5 and manifest["period"] == 4.0
    assert manifest["ior"] == 1.333 and manifest["sun"]["elevation"] == 70.0 and manifest["seed"] == 4
    assert set(manifest["options"]) >= {"windSpeed", "amplitude", "choppiness", "tileSize", "iorRgb", "frames"}
    ktx = decode_ktx2((folder / "caustics.ktx2").read_bytes())
    assert ktx["layers"] == 4 and len(ktx["levels"]) == 6 == manifest["ktx2"]["levelCount"]
    base = ktx["levels"][0][..., 0] / 255.0 * manifest["intensityScale"]
    np.testing.assert_allclose(base, expected[..., 0], atol=manifest["intensityScale"] / 255)
    np.testing.assert_allclose(ktx["levels"][-1][:, 0, 0, 0] / 255.0 * manifest["intensityScale"],
                               expected[..., 0].mean(axis=(1, 2)), atol=manifest["intensityScale"] / 255)


def test_byte_identical_for_the_same_options(written, tmp_path):
    folder, flags = written
    assert cli(["caustics", "-o", str(tmp_path / "again"), "--ktx2", "-q", *flags]) == 0
    for path in sorted(folder.iterdir()):
        assert (tmp_path / "again" / path.name).read_bytes() == path.read_bytes(), path.name
    assert cli(["caustics", "-o", str(tmp_path / "other"), "-q", *flags[:-1], "5"]) == 0
    assert (tmp_path / "other" / "caustics_000.png").read_bytes() != (folder / "caustics_000.png").read_bytes()


@pytest.mark.parametrize("flags", [["--caustics-size", "100"], ["--caustics-ior-rgb", "0.5,1.3,1.3"],
                                   ["--caustics-waves", "64", "--caustics-size", "16", "--caustics-samples", "2"],
                                   ["--caustics-amplitude", "-1"], ["--caustics-method", "rays"]])
def test_bad_options_exit_2(tmp_path, capsys, flags):
    assert cli(["caustics", "-o", str(tmp_path / "x"), "-q", *flags]) == 2
    err = capsys.readouterr().err
    assert "baker: error:" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "x" / "caustics.json").exists()


# ---------------------------------------------------------------------------------------------------------- glTF
@pytest.fixture(scope="module")
def baked(tmp_path_factory):
    """A floor slab 1.5 m under the water level, and a sphere, baked with caustics and written as GLB."""
    folder = tmp_path_factory.mktemp("baked")
    floor = trimesh.creation.box(extents=(4.0, 0.1, 4.0))
    floor.apply_translation((0.0, -1.55, 0.0))
    source = folder / "pool.glb"
    trimesh.Scene([floor, trimesh.creation.icosphere(subdivisions=2, radius=0.5)]).export(str(source))
    # the tile given as 2 m: the other lengths follow it at scale 1, the defaults of ``baker caustics``
    asset = baker.bake(str(source), bakes=["caustics"], seed=4,
                       options={"caustics": {"size": 32, "frames": 4, "waves": 16, "tile_size": 2.0}})
    out = folder / "pool_caustics.glb"
    save(asset, out)
    return out


def _bake_sphere(folder, radius, **options):
    """An icosphere of ``radius`` metres baked with small caustics; (BAKER_caustics JSON, irradiance frames)."""
    source = folder / f"sphere_{radius:g}.glb"
    trimesh.creation.icosphere(subdivisions=2, radius=radius).export(str(source))
    out = folder / f"sphere_{radius:g}_{len(options)}_caustics.glb"
    save(baker.bake(str(source), bakes=["caustics"], seed=5,
                    options={"caustics": {"size": 64, "frames": 4, "waves": 16, **options}}), out)
    doc = GltfDocument.load(out)
    ext = doc.json["materials"][0]["extensions"]["BAKER_caustics"]
    frames = np.stack([decode_image(doc.image_bytes(doc.json["textures"][t["index"]]["source"])).astype(np.float64)
                       / 65535.0 * ext["intensityScale"] for t in ext["frameTextures"]])
    return ext, frames


def test_lengths_default_at_the_assets_scale(tmp_path):
    """A sphere and the same sphere 10x smaller: the default tile is half the bounding-box diagonal (10x smaller),
    depth, fade and wave height follow it, the wind sqrt(10) slower, all recorded; the water is then geometrically
    similar, so the caustic pattern relative to the tile is the same: frame 0 (t = 0, the same phases) equal, and
    the contrast of every frame alike."""
    large, large_frames = _bake_sphere(tmp_path, 0.5)
    small, small_frames = _bake_sphere(tmp_path, 0.05)
    diagonal = 2 * 0.5 * math.sqrt(3)  # the icosphere's vertices reach the box's faces (within 1e-3)
    assert large["tileSize"] == pytest.approx(0.5 * diagonal, rel=2e-2)
    for key, factor in (("tileSize", 10.0), ("depth", 10.0), ("fadeDistance", 10.0), ("amplitude", 10.0),
                        ("waterScale", 10.0), ("windSpeed", math.sqrt(10.0))):
        assert large[key] == pytest.approx(factor * small[key], rel=1e-6), key  # float32 positions
    assert large["depth"] == pytest.approx(0.75 * large["tileSize"]) and large["windSpeed"] == pytest.approx(
        3.0 * math.sqrt(large["waterScale"]))
    print("tile", large["tileSize"], small["tileSize"], "max |frame 0 difference|",
          np.abs(large_frames[0] - small_frames[0]).max())
    np.testing.assert_allclose(small_frames[0], large_frames[0], atol=2e-3 * large_frames[0].max())

    def contrast(frames):
        return frames.std(axis=(1, 2, 3)) / frames.mean(axis=(1, 2, 3))

    print("contrast large", contrast(large_frames), "small", contrast(small_frames))
    assert contrast(large_frames).min() > 0.2  # a caustic network, not a grey tile
    np.testing.assert_allclose(contrast(small_frames), contrast(large_frames), rtol=0.05)


def test_explicit_lengths_are_kept(tmp_path):
    """Given values are written exactly; the unset ones follow the given tile's scale (tile / 2 m)."""
    ext, _ = _bake_sphere(tmp_path, 0.05, tile_size=0.3, depth=0.7, wind_speed=2.5)
    assert ext["tileSize"] == 0.3 and ext["depth"] == 0.7 and ext["windSpeed"] == 2.5
    assert ext["waterScale"] == pytest.approx(0.15) and ext["fadeDistance"] == pytest.approx(0.15)
    assert ext["amplitude"] == pytest.approx(0.012 * 0.15)


def test_baked_asset_validates_and_reads_back(baked, written):
    report = validate_file(baked, khronos=False)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert_khronos_clean(baked)
    doc = GltfDocument.load(baked)
    assert "BAKER_caustics" in doc.json["extensionsUsed"]
    assert "BAKER_caustics" not in doc.json.get("extensionsRequired", [])
    caustics = read(doc, 0)
    manifest = json.loads((written[0] / "caustics.json").read_text())
    assert len(caustics.frame_textures) == 4 and caustics.intensity_scale == manifest["intensityScale"]
    assert caustics.projection_direction[1] < 0 and caustics.tile_size == 2.0 and caustics.period == 4.0
    for texture, name in zip(caustics.frame_textures, manifest["frames"]):  # the same frames as the command's
        png = doc.image_bytes(doc.json["textures"][texture]["source"])
        np.testing.assert_array_equal(decode_image(png), read_image(written[0] / name))
    # the projection direction is the tile's refracted sun (x, y, z up) in glTF's axes (x, z, -y)
    x, y, z = manifest["projectionDirection"]
    np.testing.assert_allclose(caustics.projection_direction, [x, z, -y], atol=1e-6)


def test_validator_catches_broken_caustics(baked, tmp_path):
    doc = GltfDocument.load(baked)
    ext = doc.json["materials"][0]["extensions"]["BAKER_caustics"]
    ext["projectionDirection"] = [0.0, 1.0, 0.0]
    ext["period"] = -1.0  # the schema's business
    broken = tmp_path / "broken.glb"
    doc.save(broken)
    codes = {m["code"] for m in validate_file(broken, khronos=False)["issues"]["messages"] if m["severity"] == 0}
    assert {"BAKER_CAUSTICS_PROJECTION_UP", "BAKER_SCHEMA"} <= codes


def test_usd_carries_the_frames_and_parameters(baked, tmp_path):
    from pxr import Usd, UsdShade

    out = tmp_path / "pool.usda"
    save(baker.bake(str(baked), bakes=[]), out)
    stage = Usd.Stage.Open(str(out))
    material = next(p for p in stage.Traverse() if p.GetTypeName() == "Material")
    assert material.GetAttribute("baker:caustics:period").Get() == pytest.approx(4.0)
    assert material.GetAttribute("baker:caustics:tileSize").Get() == pytest.approx(2.0)
    frames = [UsdShade.Material(material).GetOutput(f"baker:caustics:frameTextures:_{f}") for f in range(4)]
    assert all(frames)
    shader = UsdShade.Shader(frames[0].GetConnectedSources()[0][0].source.GetPrim())
    assert shader.GetIdAttr().Get() == "UsdUVTexture" and shader.GetInput("wrapS").Get() == "repeat"


def test_readme_example_is_valid():
    name = "BAKER_caustics"
    schema = json.loads(validate.schema_registry()[(name, "material")].read_text())
    readme = (SCHEMA_ROOT / name / "README.md").read_text()
    block = readme.split("```json")[1].split("```")[0].strip()
    ext = json.loads("{" + block + "}")["extensions"][name]
    assert not list(Draft202012Validator(schema).iter_errors(ext))
