"""Per-vertex curvature against analytic truth: sphere, torus, plane, jittered and noisy spheres, and the bake's
round trip through the written .glb (seams welded, validators clean)."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

import baker
from baker import validate
from baker.geometry.welding import weld
from baker.techniques.curvature.kernel import principal_curvatures, vertex_adjacency
from baker.gltf.document import GltfDocument
from baker.pipeline import save
from conftest import assert_khronos_clean

REPO = Path(__file__).resolve().parents[2]
SPOT = REPO / "examples" / "spot" / "spot.obj"


def torus(major=2.0, minor=0.5, sections=(160, 64)):
    mesh = trimesh.creation.torus(major_radius=major, minor_radius=minor, major_sections=sections[0],
                                  minor_sections=sections[1])
    return mesh.vertices, mesh.faces


def torus_mean_curvature(vertices, major=2.0, minor=0.5):
    """H(v) = (R + 2 r cos v) / (2 r (R + r cos v)), v the angle around the tube (0 on the outer equator)."""
    rho = np.hypot(vertices[:, 0], vertices[:, 1])
    v = np.arctan2(vertices[:, 2], rho - major)
    return (major + 2 * minor * np.cos(v)) / (2 * minor * (major + minor * np.cos(v)))


# ------------------------------------------------------------------------------------------------------- kernel
@pytest.mark.parametrize("subdivisions", [4, 5])
def test_sphere_radius_half_has_mean_curvature_two(subdivisions):
    sphere = trimesh.creation.icosphere(subdivisions=subdivisions, radius=0.5)
    result = principal_curvatures(sphere.vertices, sphere.faces)
    # sign convention: outward normals, convex positive, H = +1/r
    assert abs(result.mean.mean() - 2.0) / 2.0 < 0.02
    assert np.all(np.abs(result.mean - 2.0) / 2.0 < 0.05)
    assert np.all(np.abs(result.k1 - 2.0) < 0.1) and np.all(np.abs(result.k2 - 2.0) < 0.1)
    assert np.all(result.k1 >= result.k2)


def test_inward_normals_flip_the_sign():
    sphere = trimesh.creation.icosphere(subdivisions=4, radius=0.5)
    result = principal_curvatures(sphere.vertices, sphere.faces[:, ::-1])
    assert abs(result.mean.mean() + 2.0) / 2.0 < 0.02


@pytest.mark.parametrize("smoothing", [0, 2])
def test_torus_matches_analytic_mean_curvature(smoothing):
    vertices, faces = torus()
    result = principal_curvatures(vertices, faces, smoothing=smoothing)
    truth = torus_mean_curvature(vertices)
    rel = np.abs(result.mean - truth) / np.abs(truth)
    assert np.median(rel) < 0.05
    assert np.percentile(rel, 99) < 0.05
    # principal curvatures: 1/r around the tube, cos v / (R + r cos v) along it
    rho = np.hypot(vertices[:, 0], vertices[:, 1])
    v = np.arctan2(vertices[:, 2], rho - 2.0)
    along = np.cos(v) / (2.0 + 0.5 * np.cos(v))
    assert np.median(np.abs(result.k1 - 2.0)) < 0.05
    assert np.median(np.abs(result.k2 - along)) < 0.05
    # the k1 direction runs around the tube: orthogonal to the ring's tangent (-y, x, 0) / rho
    ring_tangent = np.stack([-vertices[:, 1], vertices[:, 0], np.zeros(len(v))], axis=1) / rho[:, None]
    assert np.median(np.abs(np.einsum("ij,ij->i", result.direction1, ring_tangent))) < 0.05


def test_cubic_fit_beats_quadric_fit_on_torus():
    """The adjacent-normal cubic fit (default) against the quadric fit of positions: same rings and smoothing."""
    vertices, faces = torus()
    truth = torus_mean_curvature(vertices)
    errors = {}
    for fit in ("cubic", "quadric"):
        result = principal_curvatures(vertices, faces, fit=fit)
        errors[fit] = np.median(np.abs(result.mean - truth) / truth)
    assert errors["cubic"] < 0.5 * errors["quadric"], errors
    # the plain polynomial equations (no osculating-circle correction) carry the O((k h)^2) bias
    plain = principal_curvatures(vertices, faces, osculating=False)
    assert errors["cubic"] < 0.5 * np.median(np.abs(plain.mean - truth) / truth)
    with pytest.raises(ValueError):
        principal_curvatures(vertices, faces, fit="quartic")


def test_cubic_fit_is_exact_on_a_sphere_with_exact_normals():
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=0.5)
    result = principal_curvatures(sphere.vertices, sphere.faces, normals=sphere.vertices / 0.5, smoothing=0,
                                  jet_normals=False)
    np.testing.assert_allclose(result.k1, 2.0, rtol=1e-8)
    np.testing.assert_allclose(result.k2, 2.0, rtol=1e-8)


def test_radius_neighbourhood_matches_rings():
    vertices, faces = torus()
    result = principal_curvatures(vertices, faces, radius=0.12)
    truth = torus_mean_curvature(vertices)
    assert np.median(np.abs(result.mean - truth) / truth) < 0.05


def test_plane_is_flat():
    rng = np.random.default_rng(3)
    from scipy.spatial import Delaunay

    xy = np.concatenate([rng.random((600, 2)), [[0, 0], [1, 0], [0, 1], [1, 1]]])
    faces = Delaunay(xy).simplices
    # a tilted, offset plane: nothing aligned with the axes
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    vertices = np.concatenate([xy, np.zeros((len(xy), 1))], axis=1) @ q.T + np.array([3.0, -1.0, 2.0])
    result = principal_curvatures(vertices, faces)
    assert np.abs(result.mean).max() < 1e-6
    assert np.abs(result.k1).max() < 1e-6 and np.abs(result.k2).max() < 1e-6


def test_jittered_sphere_irregular_triangles():
    """Vertices slid along the sphere (an irregular, scan-like triangulation that is still exactly spherical)."""
    sphere = trimesh.creation.icosphere(subdivisions=5, radius=0.5)
    edge = sphere.edges_unique_length.mean()
    rng = np.random.default_rng(1)
    jittered = sphere.vertices + rng.normal(scale=0.3 * edge, size=sphere.vertices.shape)
    jittered *= 0.5 / np.linalg.norm(jittered, axis=1, keepdims=True)
    result = principal_curvatures(jittered, sphere.faces)
    assert abs(result.mean.mean() - 2.0) / 2.0 < 0.02
    assert np.all(np.abs(result.mean - 2.0) / 2.0 < 0.05)


def test_noisy_sphere_smoothing_helps():
    """Radial noise of 0.1% of the radius (~3% of an edge): curvature noise, reduced by the smoothing passes."""
    sphere = trimesh.creation.icosphere(subdivisions=5, radius=0.5)
    rng = np.random.default_rng(2)
    noisy = sphere.vertices * (1.0 + rng.uniform(-0.001, 0.001, size=(len(sphere.vertices), 1)))
    raw = np.abs(principal_curvatures(noisy, sphere.faces, smoothing=0).mean - 2.0) / 2.0
    smoothed_result = principal_curvatures(noisy, sphere.faces)
    smoothed = np.abs(smoothed_result.mean - 2.0) / 2.0
    assert abs(smoothed_result.mean.mean() - 2.0) / 2.0 < 0.02
    assert np.median(smoothed) < 0.05
    assert np.median(smoothed) < 0.5 * np.median(raw)


def test_adjacency_is_symmetric_and_deterministic():
    sphere = trimesh.creation.icosphere(subdivisions=2)
    indptr, indices = vertex_adjacency(len(sphere.vertices), sphere.faces)
    pairs = {(a, b) for a in range(len(sphere.vertices)) for b in indices[indptr[a]:indptr[a + 1]]}
    assert pairs == {(b, a) for a, b in pairs}
    assert len(pairs) == 2 * len(sphere.edges_unique)
    a = principal_curvatures(sphere.vertices, sphere.faces)
    b = principal_curvatures(sphere.vertices, sphere.faces)
    assert np.array_equal(a.mean, b.mean) and np.array_equal(a.direction1, b.direction1)


# ------------------------------------------------------------------------------------------------------- bake
@pytest.fixture(scope="module")
def baked_sphere_glb(tmp_path_factory):
    folder = tmp_path_factory.mktemp("curv")
    source = folder / "sphere_split.glb"
    # every triangle with its own three vertices (flat-shaded export): all seams, which the weld must join
    mesh = trimesh.creation.icosphere(subdivisions=4, radius=0.5)
    mesh.unmerge_vertices()
    mesh.export(str(source))
    out = folder / "sphere.glb"
    save(baker.bake(str(source), bakes=["curvature"]), out)
    return out


def test_bake_writes_attributes_that_round_trip(baked_sphere_glb):
    assert_khronos_clean(baked_sphere_glb)
    doc = GltfDocument.load(baked_sphere_glb)
    prim = doc.json["meshes"][0]["primitives"][0]
    positions = doc.accessor(prim["attributes"]["POSITION"])
    mean = doc.accessor(prim["attributes"]["_CURVATURE"])[:, 0]
    principal = doc.accessor(prim["attributes"]["_PRINCIPAL_CURVATURES"])[:, :2]
    direction = doc.accessor(prim["attributes"]["_PRINCIPAL_DIRECTION"])
    assert mean.dtype == np.float32 and principal.shape == (len(positions), 2) and direction.shape == (len(positions), 3)
    assert abs(mean.mean() - 2.0) / 2.0 < 0.02 and np.all(np.abs(mean - 2.0) / 2.0 < 0.05)
    # split copies of one position agree exactly (welded before the fit)
    _, inverse = weld(positions.astype(np.float64))
    assert len(np.unique(inverse)) < len(positions) / 4
    first = np.zeros(inverse.max() + 1, np.int64)
    first[inverse[::-1]] = np.arange(len(inverse))[::-1]
    assert np.array_equal(mean, mean[first[inverse]])
    assert np.array_equal(direction, direction[first[inverse]])
    np.testing.assert_allclose(mean, principal.mean(axis=1), atol=1e-5)
    ext = doc.json["materials"][prim["material"]]["extensions"]["BAKER_curvature"]
    assert ext["attribute"] == "_CURVATURE" and ext["smoothingPasses"] == 2 and ext["rings"] == 2
    assert ext["range"][0] <= mean.min() + 1e-5 and ext["range"][1] >= mean.max() - 1e-5
    report = validate.validate_file(baked_sphere_glb, khronos=False)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]


def test_validator_catches_broken_curvature(baked_sphere_glb, tmp_path):
    doc = GltfDocument.load(baked_sphere_glb)
    prim = doc.json["meshes"][0]["primitives"][0]
    # swap k1 and k2 in the data: k1 < k2 everywhere that is not umbilic, and H stays the mean
    principal = doc.accessor(prim["attributes"]["_PRINCIPAL_CURVATURES"])[:, [1, 0, 2]].copy()
    prim["attributes"]["_PRINCIPAL_CURVATURES"] = doc.add_accessor(principal)
    doc.json["materials"][prim["material"]]["extensions"]["BAKER_curvature"]["range"] = [5.0, 1.0]
    out = tmp_path / "broken.glb"
    doc.save(out)
    codes = {m["code"] for m in validate.validate_file(out, khronos=False)["issues"]["messages"]}
    assert "BAKER_CURVATURE_ORDER" in codes and "BAKER_CURVATURE_RANGE" in codes


def test_curvature_texture(tmp_path):
    source = tmp_path / "sphere.glb"
    trimesh.creation.icosphere(subdivisions=4, radius=0.5).export(str(source))
    asset = baker.bake(str(source), bakes=["curvature"],
                       options={"curvature": {"per_texel": True, "texture_size": 64}})
    out = tmp_path / "tex.glb"
    save(asset, out)
    assert_khronos_clean(out)
    doc = GltfDocument.load(out)
    ext = doc.json["materials"][0]["extensions"]["BAKER_curvature"]
    from baker.gltf.images import decode_image

    image = doc.json["textures"][ext["curvatureTexture"]["index"]]["source"]
    pixels = decode_image(doc.image_bytes(image), ".png")[..., 0].astype(np.float64) / 65535.0
    lo, hi = ext["textureRange"]
    values = lo + pixels * (hi - lo)
    assert np.all(np.abs(values - 2.0) < 0.1)
    assert validate.validate_file(out, khronos=False)["issues"]["numErrors"] == 0


def test_cli_bake_spot_curvature_and_skin_validates(tmp_path):
    """The acceptance command: baker bake spot.obj -o out.glb --bakes curvature,skin, then both validators."""
    out = tmp_path / "out.glb"
    run = subprocess.run([sys.executable, "-m", "baker.cli", "bake", str(SPOT), "-o", str(out),
                          "--bakes", "curvature,skin", "-q"], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert_khronos_clean(out)
    check = subprocess.run([sys.executable, "-m", "baker.cli", "validate", str(out), "--format", "json"],
                           capture_output=True, text=True, timeout=300)
    assert check.returncode == 0, check.stdout + check.stderr
    report = json.loads(check.stdout)
    assert report["issues"]["numErrors"] == 0
    doc = GltfDocument.load(out)
    material = doc.json["materials"][0]["extensions"]
    assert material["BAKER_skin_lut"]["curvatureAttribute"] == "_CURVATURE"
    assert {"BAKER_curvature", "BAKER_skin_lut"} <= set(doc.json["extensionsUsed"])
    assert "extensionsRequired" not in doc.json or not any(e.startswith("BAKER_") for e in doc.json["extensionsRequired"])
    # same input, same options: byte-identical output
    again = tmp_path / "again.glb"
    subprocess.run([sys.executable, "-m", "baker.cli", "bake", str(SPOT), "-o", str(again), "--bakes",
                    "curvature,skin", "-q"], check=True, timeout=300)
    assert again.read_bytes() == out.read_bytes()


def test_compiled_passes_match_numpy_and_any_thread_count():
    """The compiled adjacency, face sums and per-thread visit stamps: the same CSR as a numpy sort, the same normals
    and areas as bincount, and byte-identical curvatures with 1 thread and with all (and on a second call, whose
    stamps must not remember the first)."""
    import numba

    from baker.techniques.curvature.kernel import face_sums

    mesh = trimesh.creation.icosphere(5)
    v = np.asarray(mesh.vertices) * np.array([1.0, 1.3, 0.7])  # an ellipsoid: curvature varies
    f = np.asarray(mesh.faces, np.int64)
    n = len(v)
    indptr, indices = vertex_adjacency(n, f)
    a = np.concatenate([f[:, 0], f[:, 1], f[:, 2], f[:, 1], f[:, 2], f[:, 0]])
    b = np.concatenate([f[:, 1], f[:, 2], f[:, 0], f[:, 0], f[:, 1], f[:, 2]])
    key = np.unique(a * n + b)
    assert np.array_equal(indices, key % n)
    assert np.array_equal(indptr, np.concatenate([[0], np.cumsum(np.bincount(key // n, minlength=n))]))
    normals, areas = face_sums(v, f)
    cross = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    ref = np.stack([np.bincount(f.reshape(-1), weights=np.repeat(cross[:, k], 3), minlength=n) for k in range(3)], 1)
    assert normals.tobytes() == (ref / np.linalg.norm(ref, axis=1, keepdims=True)).tobytes()
    ref_areas = np.bincount(f.reshape(-1), weights=np.repeat(np.linalg.norm(cross, axis=1) / 6.0, 3), minlength=n)
    assert areas.tobytes() == ref_areas.tobytes()

    threads = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        serial = principal_curvatures(v, f)
    finally:
        numba.set_num_threads(threads)
    # convex everywhere, between the ellipsoid's extreme curvatures (0.7 / 1.3^2 and 1.3 / 0.7^2)
    assert (serial.k2 > 0.3).all() and (serial.k1 < 2.8).all()
    for _ in range(2):
        result = principal_curvatures(v, f)
        for name in ("mean", "k1", "k2", "direction1", "normal"):
            assert getattr(result, name).tobytes() == getattr(serial, name).tobytes(), name
