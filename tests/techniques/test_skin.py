"""Pre-integrated skin tables: Penner's LUT against its defining properties and a brute-force integral, the penumbra
LUT against direct integration, the Jimenez and d'Eon kernels, profiles, ``baker skin-lut`` outputs and the glTF
extension's round trip and checks."""
from __future__ import annotations

import json
import math
import subprocess

import numpy as np
import pytest
import trimesh

import baker
from baker import validate
from baker import diffusion_profile as P
from baker.techniques.skin import kernel as S
from baker.errors import BakerError
from baker.gltf.document import GltfDocument
from baker.gltf.images import decode_image, encode_image, read_image
from baker.pipeline import save
from conftest import assert_khronos_clean

Q = 1.0 / 255.0


@pytest.fixture(scope="module")
def lut():
    return S.diffusion_lut()  # defaults: 256 x 256, radii 1 mm .. 100 mm, d'Eon skin, 256 samples


def brute_force(cos_theta, curvature, profile, samples, ring="line"):
    """Independent reference: a plain midpoint sum over the whole ring x in [-pi, pi] with ``samples`` points, all
    columns at once as one matrix product (no per-Gaussian ranges, no trapezoid ends). ``ring``: "line" puts each
    Gaussian's 1D form exp(-d^2 / 2v) / sqrt(2 pi v) on the ring (the 2D profile integrated across it), "radial"
    the 2D form exp(-d^2 / 2v) / (2 pi v)."""
    v, w = profile.arrays()
    x = -math.pi + (np.arange(samples) + 0.5) * (2 * math.pi / samples)
    theta = np.arccos(np.clip(cos_theta, -1, 1))
    lit = np.maximum(np.cos(theta[:, None] + x[None, :]), 0.0)  # (cols, samples)
    d = 2.0 / curvature[None, :] * np.sin(x / 2)[:, None]  # (samples, rows)
    norm = np.sqrt(2 * math.pi * v) if ring == "line" else 2 * math.pi * v
    kernel = (np.exp(-d[..., None] ** 2 / (2 * v)) / norm) @ w.T  # (samples, rows, 3)
    numerator = (lit @ kernel.reshape(samples, -1)).reshape(len(cos_theta), len(curvature), 3)
    return np.swapaxes(numerator / kernel.sum(axis=0)[None], 0, 1)


def test_flattest_row_is_saturated_ndotl(lut):
    values, axes = lut
    assert values.shape == (256, 256, 3)
    assert axes.curvature[0] == pytest.approx(1.0 / 100.0) and axes.curvature[-1] == pytest.approx(1.0)
    saturate = np.clip(axes.ndotl, 0.0, 1.0)[:, None]
    assert np.abs(values[0] - saturate).max() < Q


def test_rows_do_not_decrease_with_ndotl(lut):
    values, _ = lut
    assert np.all(np.diff(values, axis=1) >= 0.0)
    assert np.all(values >= 0.0) and np.all(values <= 1.0)


def test_red_scatters_farthest(lut):
    values, axes = lut
    # exactly at N.L = 0 and the smallest radius (1 mm)
    d = S.penner_integral([0.0], [1.0])[0, 0]
    assert d[0] > d[1] > d[2] > 0.0
    # and in the LUT itself, at the two columns around N.L = 0 of the last row
    for col in (127, 128):
        r, g, b = values[-1, col]
        assert r > g > b
    # more curvature, more light wraps past the terminator
    assert np.all(np.diff(values[:, 127, 0]) >= 0.0)


def test_matches_brute_force_at_8x_samples(lut):
    values, axes = lut
    samples = 8 * len(P.DEON_SKIN.variances) * 256  # 8x the nodes the kernel spends per texel
    reference = brute_force(axes.ndotl, axes.curvature, P.DEON_SKIN, samples)
    assert np.abs(values - reference).max() < 0.5 * Q
    radial = S.penner_integral(axes.ndotl[::8], axes.curvature[::8], ring="radial")
    reference = brute_force(axes.ndotl[::8], axes.curvature[::8], P.DEON_SKIN, samples, ring="radial")
    assert np.abs(radial - reference).max() < 0.5 * Q


def test_line_profile_is_the_cylinder_integral():
    """The line ring profile is what a cylinder lit across its axis receives: the 2D profile summed over the whole
    surface (ring angle x and the axis coordinate z, Euclidean chord distances) at N.L = 0 matches it, and the radial
    profile is far less red (the ratio the README quotes: 0.070 against 0.012 red - green at 1/r = 0.26/mm)."""
    k = 0.26
    r = 1.0 / k
    x = np.linspace(-math.pi, math.pi, 4001)
    z = np.linspace(-25.0, 25.0, 2001)
    d2 = (2 * r * np.sin(x / 2))[:, None] ** 2 + z[None, :] ** 2
    v, w = P.DEON_SKIN.arrays()
    profile = np.einsum("cg,gxz->cxz", w, np.exp(-d2[None] / (2 * v[:, None, None])) / (2 * math.pi * v[:, None, None]))
    lit = np.maximum(np.cos(math.pi / 2 + x), 0.0)[None, :, None]
    surface = (profile * lit).sum(axis=(1, 2)) / profile.sum(axis=(1, 2))
    line = S.penner_integral([0.0], [k])[0, 0]
    radial = S.penner_integral([0.0], [k], ring="radial")[0, 0]
    print("N.L = 0, 1/r = 0.26/mm: surface", surface, "line", line, "radial", radial)
    np.testing.assert_allclose(line, surface, atol=2e-4)
    assert line[0] - line[1] == pytest.approx(0.070, abs=0.002) and radial[0] - radial[1] == pytest.approx(0.012, abs=0.002)
    with pytest.raises(ValueError):
        S.penner_integral([0.0], [k], ring="ring")


def test_flat_and_single_gaussian_limits():
    # zero curvature is exactly saturate(N.L)
    d = S.penner_integral(np.linspace(-1, 1, 9), [0.0])
    np.testing.assert_allclose(d[0], np.clip(np.linspace(-1, 1, 9), 0, 1)[:, None].repeat(3, 1), atol=1e-12)
    # one wide Gaussian on a small ring ~ the ring-averaged light: N.L = 1 gets much less than 1
    wide = P.Profile("wide", (100.0,), ((1.0,), (1.0,), (1.0,)))
    d = S.penner_integral([1.0, -1.0], [10.0], wide)
    assert d[0, 0, 0] == pytest.approx(1.0 / math.pi, abs=0.01)  # uniform kernel: mean of saturate(cos) = 1/pi
    assert d[0, 1, 0] == pytest.approx(1.0 / math.pi, abs=0.01)


def test_penumbra_lut_matches_direct_integration():
    lut, rng = S.penumbra_lut(size=32, sharpening=2.0)
    assert rng == (pytest.approx(0.01), pytest.approx(1.0))
    assert np.all(np.diff(lut, axis=1) >= -1e-12)
    # direct numerical integration at a few texels
    v, w = P.DEON_SKIN.arrays()
    y = np.linspace(-40.0, 40.0, 400001)
    for row, col in ((0, 5), (31, 10), (31, 16), (15, 25)):
        width = 1.0 / np.linspace(rng[0], rng[1], 32)[row]
        x = (col / 31 - 0.5) * width
        shadow = np.clip(2.0 * (x - y) / width + 0.5, 0.0, 1.0)
        profile = (np.exp(-y[:, None] ** 2 / (2 * v)) / np.sqrt(2 * math.pi * v)) @ w.T
        expected = np.trapezoid(shadow[:, None] * profile, y, axis=0) / np.trapezoid(profile, y, axis=0)
        np.testing.assert_allclose(lut[row, col], expected, atol=1e-5)
    # a narrow penumbra lets red bleed furthest into the shadow
    r, g, b = lut[-1, 0]
    assert r > g > b


def test_jimenez_kernel():
    for taps in (11, 17, 25):
        k = S.jimenez_kernel(taps)
        assert k.shape == (taps, 4)
        np.testing.assert_allclose(k[:, :3].sum(axis=0), 1.0, atol=1e-12)  # energy-preserving per channel
        assert k[0, 3] == 0.0  # centre tap first
        extent = 3.0 if taps > 20 else 2.0
        assert k[1:, 3].min() == pytest.approx(-extent) and k[1:, 3].max() == pytest.approx(extent)
        # symmetric weights, red widest: less of red stays in the centre tap
        order = np.argsort(k[1:, 3])
        np.testing.assert_allclose(k[1:, :3][order], k[1:, :3][order][::-1], rtol=1e-12)
        assert k[0, 0] < k[0, 1] < k[0, 2]
    # strength 0: the identity kernel
    k = S.jimenez_kernel(11, strength=(0, 0, 0))
    assert np.all(k[0, :3] == 1.0) and np.all(k[1:, :3] == 0.0)


def test_deon_gaussians():
    g = S.deon_gaussians()
    assert [x["variance"] for x in g] == list(P.DEON_SKIN.variances)
    np.testing.assert_allclose(sum(x["incrementalVariance"] for x in g), 7.41)
    np.testing.assert_allclose(np.sum([x["weights"] for x in g], axis=0), 1.0)
    # GPU Gems 3's 7-tap weights
    np.testing.assert_allclose(g[0]["taps7"]["weights"], [0.006, 0.061, 0.242, 0.383, 0.242, 0.061, 0.006], atol=1.5e-3)


def test_profile_json(tmp_path):
    path = tmp_path / "p.json"
    path.write_text(json.dumps({"name": "cm skin", "unit": "cm", "variances": [0.01, 0.04],
                                "red": [0.5, 0.5], "green": [1, 0], "blue": [1, 0]}))
    p = P.load_profile(path)
    assert p.variances == (pytest.approx(1.0), pytest.approx(4.0))
    for bad in ({"variances": [1], "red": [1], "green": [1]}, {"variances": [-1], "red": [1], "green": [1], "blue": [1]},
                {"variances": [1, 2], "red": [1], "green": [1], "blue": [1]}, [1, 2]):
        path.write_text(json.dumps(bad))
        with pytest.raises(BakerError):
            P.load_profile(path)
    path.write_text("{not json")
    with pytest.raises(BakerError):
        P.load_profile(path)


# ------------------------------------------------------------------------------------------------------- command
def _cli(*args):
    """Run the command in-process (as ``baker`` would): (exit code, stderr)."""
    import contextlib
    import io

    from baker.cli import main

    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main([str(a) for a in args])
    return subprocess.CompletedProcess(args, code, "", err.getvalue())


@pytest.mark.parametrize("name,bits,dtype", [("lut.exr", 16, np.float32), ("lut.png", 16, np.uint16),
                                             ("lut8.png", 8, np.uint8)])
def test_skin_lut_command(tmp_path, lut, name, bits, dtype):
    out = tmp_path / name
    run = _cli("skin-lut", "-o", out, "--skin-bits", bits, "-q")
    assert run.returncode == 0, run.stderr
    pixels = read_image(out)
    assert pixels.dtype == dtype and pixels.shape == (256, 256, 3)
    values = pixels.astype(np.float64) / (np.iinfo(dtype).max if dtype != np.float32 else 1.0)
    step = 1.0 / np.iinfo(dtype).max if dtype != np.float32 else 1e-7
    assert np.abs(values - lut[0]).max() <= 0.5 * step + 1e-7
    meta = json.loads(out.with_suffix(".json").read_text())
    assert meta["lut"]["file"] == name and meta["lut"]["v"]["range"] == [0.01, 1.0]
    assert meta["lut"]["v"]["unit"] == "1/mm" and meta["lut"]["u"]["range"] == [-1.0, 1.0]
    assert meta["profile"]["variances"] == list(P.DEON_SKIN.variances)
    assert len(meta["jimenezKernel"]["kernel"]) == 17 and len(meta["deonGaussians"]["gaussians"]) == 6
    penumbra = read_image(tmp_path / meta["penumbra"]["file"])
    assert penumbra.shape == (128, 128, 3)
    # same options, same bytes
    again = tmp_path / ("again" + out.suffix)
    assert _cli("skin-lut", "-o", again, "--skin-bits", bits, "-q").returncode == 0
    assert again.read_bytes() == out.read_bytes()


def test_skin_lut_command_errors(tmp_path):
    run = _cli("skin-lut", "-o", tmp_path / "x.jpg")
    assert run.returncode == 2 and "unsupported" in run.stderr
    run = _cli("skin-lut", "-o", tmp_path / "x.png", "--skin-min-radius", "50", "--skin-max-radius", "10")
    assert run.returncode == 2 and not (tmp_path / "x.png").exists()
    run = _cli("skin-lut", "-o", tmp_path / "x.png", "--skin-profile", tmp_path / "missing.json")
    assert run.returncode == 2 and "missing.json" in run.stderr


# ------------------------------------------------------------------------------------------------------- glTF
@pytest.fixture(scope="module")
def baked(tmp_path_factory):
    folder = tmp_path_factory.mktemp("skin")
    source = folder / "sphere.glb"
    trimesh.creation.icosphere(subdivisions=3, radius=0.02).export(str(source))  # 2 cm: curvature 0.05 / mm
    out = folder / "skin.glb"
    save(baker.bake(str(source), bakes=["curvature", "skin"], options={"skin": {"width": 64, "height": 32}}), out)
    return out


def test_extension_round_trip(baked):
    assert_khronos_clean(baked)
    report = validate.validate_file(baked, khronos=False)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    doc = GltfDocument.load(baked)
    ext = doc.json["materials"][0]["extensions"]["BAKER_skin_lut"]
    assert ext["curvatureScale"] == pytest.approx(0.001) and ext["curvatureAttribute"] == "_CURVATURE"
    image = doc.json["textures"][ext["lutTexture"]["index"]]["source"]
    pixels = decode_image(doc.image_bytes(image), ".png")
    assert pixels.dtype == np.uint16 and pixels.shape == (32, 64, 3)
    # the curvature axis is fitted to the sphere's one curvature (1/20 mm), widened by 1.5 either side
    lo, hi = ext["curvatureRange"]
    assert ext["curvatureRangePercentiles"] == [1.0, 99.0]
    assert lo < 0.05 < hi and hi / lo < 2.25 * 1.1
    expected, _ = S.diffusion_lut(64, 32, 1.0 / hi, 1.0 / lo)
    assert np.abs(pixels / 65535.0 - expected).max() <= 0.5 / 65535 + 1e-9
    sampler = doc.json["samplers"][doc.json["textures"][ext["lutTexture"]["index"]]["sampler"]]
    assert sampler["wrapS"] == sampler["wrapT"] == 33071
    # the baked curvature lands inside the LUT's axis once scaled: 1 / 20 mm
    curvature = doc.accessor(doc.json["meshes"][0]["primitives"][0]["attributes"]["_CURVATURE"])[:, 0]
    assert np.median(curvature * ext["curvatureScale"]) == pytest.approx(0.05, rel=0.04)  # icosphere(3): 2.7% coarse-mesh bias


def test_lut_axis_spans_the_assets_curvature():
    """The LUT's radii default to the 1st-99th percentile of the asset's |mean curvature| (1/mm); explicit radii are
    kept exactly; no curvature gives 1-100 mm; a flat asset's axis spans at most 1000x."""
    from baker.techniques.skin.options import SkinOptions

    curvature = np.concatenate([np.linspace(0.1, 2.0, 9801), -np.linspace(0.1, 2.0, 199)])  # 1/mm, some concave
    lo, hi = np.percentile(np.abs(curvature), [1, 99])
    assert S.lut_radii(SkinOptions(), curvature) == pytest.approx((1 / hi, 1 / lo, True))
    assert S.lut_radii(SkinOptions(min_radius=0.3), curvature) == pytest.approx((0.3, 1 / lo, True))
    assert S.lut_radii(SkinOptions(min_radius=0.3, max_radius=7.0), curvature) == (0.3, 7.0, False)
    assert S.lut_radii(SkinOptions(), None) == (1.0, 100.0, False)
    assert S.lut_radii(SkinOptions(), np.zeros(10)) == (1.0, 100.0, False)
    flat = np.concatenate([np.zeros(980), np.full(20, 0.5)])  # a plane with a rounded rim
    r_min, r_max, _ = S.lut_radii(SkinOptions(), flat)
    assert r_min == pytest.approx(2.0) and r_max == pytest.approx(2000.0)
    tables = S.skin_tables(SkinOptions(width=16, height=8, samples=16, penumbra=False), curvature)
    assert tables.axes.curvature_range == pytest.approx((lo, hi)) and tables.curvature_percentiles == (1.0, 99.0)
    assert S.skin_tables(SkinOptions(width=16, height=8, samples=16, penumbra=False)).curvature_percentiles is None


def test_validator_catches_broken_lut(baked, tmp_path):
    doc = GltfDocument.load(baked)
    ext = doc.json["materials"][0]["extensions"]["BAKER_skin_lut"]
    image = doc.json["textures"][ext["lutTexture"]["index"]]["source"]
    pixels = decode_image(doc.image_bytes(image), ".png")[:, ::-1].copy()  # N.L reversed: rows decrease
    view = doc.add_buffer_view(encode_image(pixels, ".png"))
    doc.json["images"][image]["bufferView"] = view
    ext["curvatureRange"] = [1.0, 0.01]
    del ext["unit"]
    out = tmp_path / "broken.glb"
    doc.save(out)
    codes = {m["code"] for m in validate.validate_file(out, khronos=False)["issues"]["messages"]}
    assert {"BAKER_SKIN_LUT_NOT_MONOTONIC", "BAKER_SKIN_LUT_RANGE", "BAKER_SCHEMA"} <= codes
