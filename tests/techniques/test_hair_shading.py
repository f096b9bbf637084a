"""The hair fibre model (Chiang et al. 2016 as pbrt's HairBxDF) against its defining properties (white-furnace energy
conservation by dense quadrature, reciprocity on the specular cone, d'Eon's M_p against scipy's Bessel function and
its normalisation), and the baked tables (``baker hair-lut``, ``baker.api.hair_bsdf``) against the model with an
independent quadrature over the fibre offset."""
from __future__ import annotations

import contextlib
import io
import json
import math

import numpy as np
import pytest
from scipy import special

import baker.api
from baker.gltf.images import read_image
from baker.techniques.hair_shading import kernel as K
from baker.techniques.hair_shading.extension import read_lut
from baker.techniques.hair_shading.tables import as_half, bake_tables, sphere_directions


def direction(theta_deg, phi_deg=0.0):
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return np.array([math.sin(t), math.cos(t) * math.cos(p), math.cos(t) * math.sin(p)])




@pytest.mark.parametrize("beta", [0.2, 0.4])
def test_white_hair_integrates_to_one(beta):
    """No absorption: the integral of S over every light direction (d omega) is 1 at every incidence (R, TT, TRT
    and the residual carry all the light), by a midpoint rule over (sin theta_i, phi_i, h) that knows nothing of
    how the lobes are normalised."""
    model = K.FibreModel([0.0, 0.0, 0.0], beta, beta, 2.0, 1.55, offsets=24)
    for theta in (0.0, 30.0, 60.0, 80.0):
        albedo = K.albedo_grid(direction(theta), model.sigma_a, model.eta, model.v, model.s, model.sin2k,
                               model.cos2k, model.offsets, model.weights, 120, 180)
        print(f"beta {beta} theta_o {theta}: albedo {albedo[0]:.4f}")
        assert abs(albedo[0] - 1.0) <= 0.02


def test_absorbing_hair_loses_light_in_order():
    """Blond > brown > black, and red > green > blue in each (eumelanin absorbs blue most)."""
    albedos = []
    for eumelanin in (0.3, 1.3, 8.0):
        model = K.FibreModel(K.sigma_a_from_melanin(eumelanin), 0.3, 0.3, 2.0, 1.55, offsets=16)
        a = K.albedo_grid(direction(20.0), model.sigma_a, model.eta, model.v, model.s, model.sin2k, model.cos2k,
                          model.offsets, model.weights, 60, 90)
        assert a[0] > a[1] > a[2] > 0.0
        albedos.append(a)
    assert albedos[0][0] > albedos[1][0] > albedos[2][0]
    assert albedos[2][2] < 0.1  # black: little but the R lobe's few percent of Fresnel


def test_longitudinal_lobe_against_scipy_bessel():
    """d'Eon's M_p = csch(1/v) / (2v) exp(-sin sin / v) I0(cos cos / v), by scipy's scaled I0 in log space, and its
    normalisation: the integral over theta_i of M_p cos theta_i is 1."""
    rng = np.random.default_rng(3)
    for v in (0.005, 0.03, 0.09, 0.11, 0.4, 1.0):
        for theta_i, theta_o in rng.uniform(-1.5, 1.5, (20, 2)):
            a = math.cos(theta_i) * math.cos(theta_o) / v
            b = math.sin(theta_i) * math.sin(theta_o) / v
            log_sinh = 1 / v + math.log((1 - math.exp(-2 / v)) / 2)
            expected = math.exp(math.log(special.i0e(a)) + a - b - math.log(2 * v) - log_sinh)
            got = K.longitudinal(math.cos(theta_i), math.cos(theta_o), math.sin(theta_i), math.sin(theta_o), v)
            assert got == pytest.approx(expected, rel=2e-3, abs=1e-12)
        theta = np.linspace(-math.pi / 2, math.pi / 2, 20001)
        for theta_o in (-1.0, 0.0, 0.7):
            m = np.array([K.longitudinal(math.cos(t), math.cos(theta_o), math.sin(t), math.sin(theta_o), v)
                          for t in theta])
            assert np.trapezoid(m * np.cos(theta), theta) == pytest.approx(1.0, abs=2e-3)


def test_reciprocal_on_the_specular_cone():
    """With no tilt, the h-averaged far field is symmetric under swapping light and view wherever |theta_i| =
    |theta_o| (pbrt's A_p and N_p depend on theta_o alone, so this is where the model is exactly reciprocal)."""
    model = K.FibreModel(K.sigma_a_from_melanin(1.3), 0.3, 0.3, 0.0, 1.55, offsets=32)
    rng = np.random.default_rng(5)
    for theta, phi_o, phi_i, sign in zip(rng.uniform(-80, 80, 12), rng.uniform(-180, 180, 12),
                                         rng.uniform(-180, 180, 12), rng.choice([-1, 1], 12)):
        wo, wi = direction(theta, phi_o), direction(sign * theta, phi_i)
        np.testing.assert_allclose(model(wo, wi), model(wi, wo), rtol=1e-9, atol=1e-12)


def model_with_midpoints(model, wo, wi, count=384):
    """S averaged over h by a fine midpoint rule (the tables use 64 Gauss-Legendre nodes): an independent quadrature
    (384 nodes: narrow azimuthal lobes sweep across phi as h changes, and 48 midpoints alias by 8%)."""
    h = -1 + (np.arange(count) + 0.5) * 2 / count
    w = np.full(count, 1.0 / count)
    wo = np.ascontiguousarray(np.broadcast_to(wo, wi.shape))
    return K.scattering(wo, np.ascontiguousarray(wi), model.sigma_a, model.eta, model.v, model.s, model.sin2k,
                        model.cos2k, h, w)


@pytest.mark.parametrize("beta", [0.2, 0.4])
def test_tables_match_the_model(beta):
    """``baker.api.hair_bsdf`` (half-float tables, bilinear lookups) is within 5% relative L1 over the sphere of light
    directions of the model, per view direction, for blond, brown and black hair."""
    lights = sphere_directions(24, 48)
    worst = 0.0
    for eumelanin in (0.3, 1.3, 8.0):
        model = K.FibreModel(K.sigma_a_from_melanin(eumelanin), beta, beta, 2.0, 1.55)
        for theta in (-50.0, 5.0, 75.0):
            view = direction(theta, 20.0)
            truth = model_with_midpoints(model, view, lights)
            got = baker.api.hair_bsdf([1.0, 0.0, 0.0], lights, view, eumelanin=eumelanin, beta_m=beta,
                                      beta_n=beta, alpha=2.0, eta=1.55)
            error = np.abs(got - truth).sum(0) / truth.sum(0)
            worst = max(worst, error.max())
            assert error.max() <= 0.05, (eumelanin, theta, error)
    print(f"beta {beta}: worst relative L1 {worst:.4f}")


def test_any_tangent_frame():
    """Rotating tangent, light and view together changes nothing (the twin builds its own fibre frame)."""
    rng = np.random.default_rng(8)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    lights = sphere_directions(6, 8)
    view = direction(25.0, 40.0)
    a = baker.api.hair_bsdf([1.0, 0.0, 0.0], lights, view, eumelanin=0.3)
    b = baker.api.hair_bsdf(q @ [1.0, 0.0, 0.0], lights @ q.T, q @ view, eumelanin=0.3)
    np.testing.assert_allclose(a, b, rtol=1e-6, atol=1e-9)


def _cli(*args):
    from baker.cli import main

    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main([str(a) for a in args])
    return code, err.getvalue()


def test_hair_lut_command(tmp_path):
    """The folder holds half-float EXRs of the sizes the sidecar names, whose values are the tables the twin
    samples: the twin reads them back to the same BSDF."""
    out = tmp_path / "lut"
    code, err = _cli("hair-lut", "-o", out, "--hair-beta-m", "0.25", "--hair-beta-n", "0.35", "-q")
    assert code == 0, err
    meta = json.loads((out / "hair_lut.json").read_text())
    m = read_image(out / meta["longitudinal"]["file"])
    n = read_image(out / meta["azimuthal"]["file"])
    assert m.dtype == np.float16 and m.shape == (meta["longitudinal"]["height"], meta["longitudinal"]["width"], 3)
    assert n.dtype == np.float16 and n.shape == (meta["azimuthal"]["height"], meta["azimuthal"]["width"], 4)
    assert meta["parameters"]["betaM"] == 0.25 and meta["azimuthal"]["slices"] * 32 == n.shape[0]
    dual = read_image(out / meta["dualScattering"]["file"])
    assert dual.dtype == np.float16 and dual.shape == (16, 32, 4)
    assert np.isfinite(m.astype(float)).all() and np.isfinite(n.astype(float)).all()
    baked = as_half(bake_tables(0.25, 0.35, 1.55))
    np.testing.assert_array_equal(m.astype(np.float32), baked.longitudinal)
    lights = sphere_directions(8, 16)
    view = direction(10.0)
    from_files = baker.api.hair_bsdf([1, 0, 0], lights, view, eumelanin=1.3, beta_m=0.25, beta_n=0.35,
                                     tables=read_lut(out))
    direct = baker.api.hair_bsdf([1, 0, 0], lights, view, eumelanin=1.3, beta_m=0.25, beta_n=0.35)
    np.testing.assert_allclose(from_files, direct, rtol=1e-6)
    again = tmp_path / "again"
    assert _cli("hair-lut", "-o", again, "--hair-beta-m", "0.25", "--hair-beta-n", "0.35", "-q")[0] == 0
    for name in ("hair_longitudinal.exr", "hair_azimuthal.exr", "hair_dual_scattering.exr", "hair_lut.json"):
        assert (again / name).read_bytes() == (out / name).read_bytes()


def test_hair_lut_command_errors(tmp_path):
    code, err = _cli("hair-lut", "-o", tmp_path / "x", "--hair-beta-m", "2")
    assert code == 2 and "beta_m" in err and len(err.strip().splitlines()) == 1 and not (tmp_path / "x").exists()
    (tmp_path / "file").write_text("")
    code, err = _cli("hair-lut", "-o", tmp_path / "file")
    assert code == 2 and "file" in err and "not a folder" in err


def test_dual_scattering_averages_against_the_model():
    """Zinke's a_f and a_b (from the h-averaged azimuthal integrals) against the model's S integrated by brute force
    over the forward and backward halves of the sphere of light directions; white hair's halves sum to 1."""
    from baker.techniques.hair_shading.tables import dual_scattering_table

    dual = dual_scattering_table(0.3, 0.3, 1.55, 2.0, n_theta=7, slices=5)  # rows at x = 0, .25, .5, .75, 1
    white = dual.table[0, :, 0] + dual.table[0, :, 1]
    np.testing.assert_allclose(white, 1.0, atol=2e-3)
    lights = sphere_directions(90, 180)
    back = np.abs(np.arctan2(lights[:, 2], lights[:, 1])) <= math.pi / 2  # the view sits at phi = 0
    for row in (0, 2):
        sigma = -2.0 * math.log(1.0 - row / 4)
        model = K.FibreModel([sigma] * 3, 0.3, 0.3, 2.0, 1.55, offsets=32)
        for col in (0, 3, 5):  # |theta| = col / 6 * 90 degrees
            view = direction(col * 15.0)
            s = model(np.broadcast_to(view, lights.shape), lights)[:, 0] * 4 * math.pi / len(lights)
            a_f, a_b = s[~back].sum(), s[back].sum()
            assert dual.table[row, col, 0] == pytest.approx(a_f, abs=0.01), (row, col)
            assert dual.table[row, col, 1] == pytest.approx(a_b, abs=0.01), (row, col)
    # opaque fibres pass little forward up to 45 degrees (R's grazing part; at grazing incidence Fresnel -> 1)
    assert (dual.table[-1, :4, 0] < 0.1).all()
    assert dual.alpha_f == pytest.approx(math.radians(2.0)) and 0.0 < dual.table[..., 3].min()


def test_colour_inversion():
    """Chiang's inversion: white is clear, darker channels absorb more, and the hair it makes is, integrated over
    the light sphere, ordered like the colour asked for (a brown colour gives red > green > blue)."""
    assert np.allclose(K.sigma_a_from_color([1.0, 1.0, 1.0], 0.3), 0.0)
    sigma = K.sigma_a_from_color([0.45, 0.25, 0.12], 0.3)
    assert sigma[0] < sigma[1] < sigma[2]
    lights = sphere_directions(24, 48)
    s = baker.api.hair_bsdf([1, 0, 0], lights, direction(10.0), color=[0.45, 0.25, 0.12]).sum(0)
    assert s[0] > s[1] > s[2]


def test_exit_azimuths_against_a_traced_circle():
    """N_p's lobe centres Phi(p) = 2 p gamma_t - 2 gamma_o + p pi (and the internal path length in A_p's
    transmittance) against a ray traced through the fibre's unit-circle cross-section with Snell's law and mirror
    reflections, at perpendicular incidence and at theta_o = 40 degrees (Bravais' index for the projected ray)."""
    for theta in (0.0, 40.0):
        sin_o = math.sin(math.radians(theta))
        etap = math.sqrt(1.55 ** 2 - sin_o ** 2) / math.cos(math.radians(theta))
        for h in (-0.9, -0.4, 0.1, 0.6, 0.95):
            gamma_o, gamma_t, path = K.fibre_geometry(sin_o, 1.55, h)
            # the ray arrives travelling along -y at offset h; where it enters, the outward normal is at -gamma_o
            point = np.array([math.cos(gamma_o), -math.sin(gamma_o)])
            d = np.array([-1.0, 0.0])
            reflected = d - 2 * d.dot(point) * point
            inside = d / etap
            cos_t = math.sqrt(1 - (1 - d.dot(point) ** 2) / etap ** 2)
            inside = inside + (-d.dot(point) / etap - cos_t) * point
            directions = [reflected]
            chord = 0.0
            for p in (1, 2):
                t = -2 * point.dot(inside)  # to the far side of the unit circle
                point = point + t * inside
                chord = t if p == 1 else chord
                n = point
                cos_i = inside.dot(n)
                sin_i2 = 1 - cos_i ** 2
                out = etap * (inside - cos_i * n) + math.sqrt(1 - etap ** 2 * sin_i2) * n  # refract out
                directions.append(out / np.linalg.norm(out))
                inside = inside - 2 * cos_i * n  # reflect inside for the next segment
            for p, out in enumerate(directions):
                phi = math.atan2(out[1], out[0])
                expected = 2 * p * gamma_t - 2 * gamma_o + p * math.pi
                wrapped = (phi - expected + math.pi) % (2 * math.pi) - math.pi
                assert abs(wrapped) < 1e-9, (theta, h, p, phi, expected)
            # a chord of the projected circle is 2 cos gamma_t; the 3D path divides by cos theta_t
            cos_theta_t = math.sqrt(1 - (sin_o / 1.55) ** 2)
            assert chord / cos_theta_t == pytest.approx(path, rel=1e-9)


# ------------------------------------------------------------------ dual scattering against a path-traced slab
SLAB_VIEW = np.array([0.3, 0.1, 1.0]) / np.linalg.norm([0.3, 0.1, 1.0])
SLAB_FRONT = np.array([-0.2, 0.5, 1.0]) / np.linalg.norm([-0.2, 0.5, 1.0])  # from the viewer's side
SLAB_BACK = np.array([-0.2, 0.4, -1.0]) / np.linalg.norm([-0.2, 0.4, -1.0])  # from behind the slab
BLOND = dict(eumelanin=0.3, beta_m=0.3, beta_n=0.3, alpha=2.0, eta=1.55)


def blond_model():
    return K.FibreModel(K.sigma_a_from_melanin(0.3), 0.3, 0.3, 2.0, 1.55)


def test_tracer_samples_the_fibre_model_without_bias():
    """The tracer's direction sampling (pbrt's HairBxDF::Sample_f) has the density its weights divide by: the mean
    of S / pdf is the albedo the midpoint quadrature gives; and one bounce of the tracer is the model itself at the
    fibres the light reaches unblocked (h drawn per event averages to the far field)."""
    from baker.techniques.hair_shading.slab_tracer import Slab, sampled_albedo

    model = K.FibreModel(K.sigma_a_from_melanin(0.3), 0.3, 0.3, 2.0, 1.55, offsets=24)
    for theta in (10.0, 55.0):
        wo = direction(theta, 30.0)
        sampled = sampled_albedo(wo, model.sigma_a, model.eta, model.v, model.s, model.sin2k, model.cos2k, 100000, 3)
        grid = K.albedo_grid(wo, model.sigma_a, model.eta, model.v, model.s, model.sin2k, model.cos2k,
                             model.offsets, model.weights, 120, 180)
        print(f"theta_o {theta}: sampled albedo {np.round(sampled, 4)}, quadrature {np.round(grid, 4)}")
        np.testing.assert_allclose(sampled, grid, rtol=0.01)
    slab = Slab(8, 3.0, 2.0)
    radiance, crossed = slab.trace(model, SLAB_VIEW, SLAB_FRONT, paths=40000, max_bounces=1)
    lit = (crossed == 0).mean()
    expected = model(SLAB_VIEW, SLAB_FRONT)[0] * lit
    error = radiance.std(0) / math.sqrt(len(radiance))
    assert 0.3 < lit < 0.95
    assert np.all(np.abs(radiance.mean(0) - expected) < 4 * error + 1e-4), (radiance.mean(0), expected)


def test_hair_shade_without_fibres_in_front_is_the_bsdf_plus_backscatter():
    """No fibre toward the light: the single scattering of ``hair_bsdf`` exactly, plus the neighbours' backscatter
    (>= 0, zero when d_b = 0); behind fibres the direct term fades continuously and more fibres pass less light."""
    lights = sphere_directions(12, 24)
    view = direction(20.0, 10.0)
    bsdf = baker.api.hair_bsdf([1, 0, 0], lights, view, **BLOND)
    np.testing.assert_allclose(baker.api.hair_shade([1, 0, 0], lights, view, 0, density_back=0.0, **BLOND), bsdf,
                               rtol=1e-12, atol=1e-15)
    shade0 = baker.api.hair_shade([1, 0, 0], lights, view, 0, **BLOND)
    assert np.all(shade0 >= bsdf - 1e-12) and (shade0 - bsdf).sum() > 0.01 * bsdf.sum()
    near_one = baker.api.hair_shade([1, 0, 0], lights, view, 0.999, **BLOND)
    one = baker.api.hair_shade([1, 0, 0], lights, view, 1.0, **BLOND)
    np.testing.assert_allclose(near_one, one, rtol=0.01, atol=1e-4)
    totals = [baker.api.hair_shade([1, 0, 0], lights, view, n, **BLOND).sum(0) for n in (1, 2, 4, 8)]
    assert all(np.all(a > b) for a, b in zip(totals, totals[1:]))
    # never NaN: opaque and clear fibres, grazing light and view, light along the fibre, huge counts
    grazing = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.999999, 0.001, 0.0], [-1.0, 0.0, 0.0]])
    for eumelanin in (0.0, 50.0):
        for n in (0, 0.5, 1, 1000):
            extreme = baker.api.hair_shade([1, 0, 0], grazing, grazing[::-1], n, **{**BLOND, "eumelanin": eumelanin})
            assert np.isfinite(extreme).all() and (extreme >= 0).all(), (eumelanin, n, extreme)
    with pytest.raises(ValueError, match="fibres_crossed"):
        baker.api.hair_shade([1, 0, 0], lights, view, -1, **BLOND)


def slab_figures(light, layers):
    """(path traced, hair_shade at the path tracer's first hits with their fibre counts, at most two bounces,
    single scattering alone (hair_bsdf where the light is not blocked)), each RGB, per unit irradiance."""
    from baker.techniques.hair_shading.slab_tracer import Slab

    model = blond_model()
    slab = Slab(layers, 3.0, 2.0)
    traced, crossed = slab.trace(model, SLAB_VIEW, light, paths=40000)
    two, _ = slab.trace(model, SLAB_VIEW, light, paths=40000, max_bounces=2)
    hit = crossed >= 0
    shade = np.zeros_like(traced)
    shade[hit] = baker.api.hair_shade([1, 0, 0], light, SLAB_VIEW, crossed[hit], **BLOND)
    single = baker.api.hair_bsdf([1, 0, 0], light, SLAB_VIEW, **BLOND)[0] * (crossed == 0).mean()
    return traced.mean(0), traced.std(0) / math.sqrt(len(traced)), shade.mean(0), two.mean(0), single


def test_hair_shade_against_a_path_traced_slab_lit_from_the_front():
    """Blond fibres (eumelanin 0.3, beta 0.3), eight rows, lit from the viewer's side: dual scattering within 20%
    of all bounces (red, green; blue reported), where at most two bounces are about half of it."""
    traced, error, shade, two, single = slab_figures(SLAB_FRONT, 8)
    print(f"front: traced {np.round(traced, 4)} +- {np.round(error, 4)}, hair_shade / traced "
          f"{np.round(shade / traced, 3)}, <= 2 bounces / traced {np.round(two / traced, 3)}, "
          f"single / traced {np.round(single / traced, 3)}")
    assert np.all(np.abs(shade / traced - 1)[:2] <= 0.2)
    assert 0.4 < two[0] / traced[0] < 0.7 and single[0] / traced[0] < 0.6


def test_hair_shade_against_a_path_traced_slab_lit_from_behind():
    """The same fibres, four rows, lit from behind: every visible fibre is behind others, so single scattering
    alone is black and two bounces a third; dual scattering within 30% (red, green; blue reported)."""
    traced, error, shade, two, single = slab_figures(SLAB_BACK, 4)
    print(f"back: traced {np.round(traced, 4)} +- {np.round(error, 4)}, hair_shade / traced "
          f"{np.round(shade / traced, 3)}, <= 2 bounces / traced {np.round(two / traced, 3)}, "
          f"single / traced {np.round(single / traced, 3)}")
    assert np.all(np.abs(shade / traced - 1)[:2] <= 0.3)
    assert two[0] / traced[0] < 0.4 and np.all(single == 0)


def test_embedded_tables_are_what_the_runtime_module_samples(tmp_path):
    """``BAKER_hair_shading``'s tables, written into a GLB and read back by an independent reader (each table's
    UNSIGNED_SHORT VEC4 accessor as the bits of little-endian float16 RGBA), are texel for texel the half-float tables
    ``hair_shade`` and the GLSL/WGSL tests upload (M padded with a zero alpha), so a host uploads them as they are."""
    from baker.gltf.document import GltfDocument
    from baker.techniques.hair_shading.dual import dual_table_for
    from baker.techniques.hair_shading.extension import NAME, add_tables, baked_tables

    doc = GltfDocument()
    tables, dual = baked_tables(0.3, 0.3, 1.55, 2.0)
    index = add_tables(doc, tables, dual, 2.0)
    path = tmp_path / "tables.glb"
    doc.save(path)
    raw = path.read_bytes()
    length = int.from_bytes(raw[12:16], "little")
    gltf = json.loads(raw[20:20 + length])
    binary = raw[20 + length + 8:]
    entry = gltf["extensions"][NAME]["tables"][index]

    def texels(key):
        accessor = gltf["accessors"][entry[key]["accessor"]]
        assert accessor["componentType"] == 5123 and accessor["type"] == "VEC4"  # UNSIGNED_SHORT
        view = gltf["bufferViews"][accessor["bufferView"]]
        start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
        data = binary[start: start + accessor["count"] * 8]
        return np.frombuffer(data, "<f2").astype(np.float32).reshape(entry[key]["height"], entry[key]["width"], 4)

    half = as_half(tables)
    m = texels("longitudinal")
    np.testing.assert_array_equal(m[..., :3], half.longitudinal)
    assert not m[..., 3].any()
    np.testing.assert_array_equal(texels("azimuthal"), half.azimuthal)
    np.testing.assert_array_equal(texels("dualScattering"), dual_table_for(0.3, 0.3, 1.55, 2.0).table)
    assert entry["azimuthal"]["slices"] == half.slices and entry["dualScattering"]["betaF"] == dual.beta_f
