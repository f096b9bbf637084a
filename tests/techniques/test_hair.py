"""Hair strands against independent truth: winding numbers, barycentric reconstruction, file round trips."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import trimesh

import baker.techniques.hair.kernel as hair
from baker import readers
from baker.geometry.normals import vertex_normals
from baker.techniques.hair.kernel import Emitter, generate_hair, segment_lengths
from baker.techniques.hair.options import HairOptions
from baker.cli import main as cli_main
from baker.techniques.hair.extension import read_strands
from baker.readers.tfx import decode_tfx, read_tfx
from baker.techniques.hair.tfx import encode_tfx, resample_strands, tfx_vertex_count
from baker.techniques.hair.grow import emitter_from_asset, make_hair, write_output
from baker.gltf.document import GltfDocument
from baker.validate import validate_file
from conftest import assert_khronos_clean

SPOT = str(Path(__file__).resolve().parents[2] / "examples" / "spot" / "spot.obj")


def winding_number(points: np.ndarray, vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Generalized winding number (Jacobson 2013), plain numpy, vectorized over triangles: the independent truth."""
    tri = vertices[faces]
    out = np.empty(len(points))
    for start in range(0, len(points), 256):
        p = points[start:start + 256]
        a, b, c = (tri[None, :, k, :] - p[:, None, :] for k in range(3))
        la, lb, lc = (np.linalg.norm(x, axis=-1) for x in (a, b, c))
        det = np.einsum("pfi,pfi->pf", a, np.cross(b, c))
        div = la * lb * lc + np.einsum("pfi,pfi->pf", a, b) * lc + np.einsum("pfi,pfi->pf", b, c) * la \
            + np.einsum("pfi,pfi->pf", c, a) * lb
        out[start:start + 256] = (2.0 * np.arctan2(det, div)).sum(axis=1) / (4.0 * math.pi)
    return out


@pytest.fixture(scope="module")
def sphere():
    m = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
    v, f = np.asarray(m.vertices, np.float64), np.asarray(m.faces, np.int64)
    return v, f


def _emitter(v, f):
    return Emitter(v, f, vertex_normals(v, f))


# strong gravity and no stiffness: long strands fall through the emitter unless they are pushed out
DROOPY = dict(guides=120, children=6, segments=16, gravity=2.0, stiffness=0.0, iterations=20)


def _all_strands(result):
    return [result.guides, result.children]


def test_segment_lengths_preserved_and_nothing_inside_sphere(sphere):
    v, f = sphere
    result = generate_hair(_emitter(v, f), HairOptions(length=3.0, clump=0.4, curl_amplitude=0.05, **DROOPY), seed=3)
    for strands in _all_strands(result):
        lengths = segment_lengths(strands.positions)
        assert np.abs(lengths / strands.rest_lengths[:, None] - 1.0).max() < 0.01
        # segments are uniform within a strand and guides have length / segments
        assert np.abs(lengths / lengths.mean(axis=1, keepdims=True) - 1.0).max() < 0.01
        wn = winding_number(strands.positions[:, 1:].reshape(-1, 3), v, f)
        assert wn.max() < 0.5, f"{int((wn >= 0.5).sum())} strand vertices inside the sphere"
    assert np.allclose(segment_lengths(result.guides.positions), 3.0 / 16, rtol=0.01)


def test_push_out_is_what_keeps_strands_outside(sphere, monkeypatch):
    # the control: without the collision pass the same strands do cross the sphere, so the test above can fail
    v, f = sphere
    monkeypatch.setattr(hair, "push_out", lambda *a, **k: 0)
    result = generate_hair(_emitter(v, f), HairOptions(length=3.0, **DROOPY), seed=3)
    wn = winding_number(result.guides.positions[:, 1:].reshape(-1, 3), v, f)
    assert (wn > 0.5).sum() > 50


def test_spot_nothing_inside_by_winding_number():
    asset = readers.read(SPOT)
    opts = HairOptions(guides=60, children=3, length=0.5, gravity=1.0, stiffness=0.1, iterations=12)
    emitter = emitter_from_asset(asset, opts)
    result = generate_hair(emitter, opts, seed=0)
    for strands in _all_strands(result):
        assert np.abs(segment_lengths(strands.positions) / strands.rest_lengths[:, None] - 1.0).max() < 0.01
        pts = strands.positions[:, 1:].reshape(-1, 3)
        wn = winding_number(pts, emitter.vertices, emitter.colliders)
        assert wn.max() < 0.5
        # roots sit on the surface
        mesh = trimesh.Trimesh(emitter.vertices, emitter.colliders, process=False)
        assert trimesh.proximity.closest_point(mesh, strands.positions[:, 0])[1].max() < 1e-9


@pytest.fixture(scope="module")
def dome():
    """An open mesh: the upper half of an icosphere (a bowl upside down, boundary at z = 0), plus a flap sharing one
    of its edges (a non-manifold edge used by three triangles)."""
    m = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
    v, f = np.asarray(m.vertices, np.float64), np.asarray(m.faces, np.int64)
    f = f[v[f].mean(axis=1)[:, 2] > 0.0]
    a, b = f[0, 0], f[0, 1]
    tip = len(v)
    v = np.concatenate([v, [v[a] + v[b] - v[f[0, 2]] + 0.3 * (v[a] + v[b])]])
    f = np.concatenate([f, [[b, a, tip]]])
    return v, f


def test_fast_winding_numbers_match_brute_force(dome):
    v, f = dome
    assert hair.boundary_edge_count(f) > 0
    rng = np.random.default_rng(5)
    box = rng.uniform(-1.5, 1.5, (1500, 3))
    near = v[f[rng.integers(0, len(f), 1500)]].mean(axis=1) + rng.normal(0.0, 0.02, (1500, 3))
    points = np.concatenate([box, near, v[:50]])  # and exactly on vertices
    truth = winding_number(points, v, f)
    fast = hair.WindingTree(v, f)(points)
    assert np.abs(fast - truth).max() < 0.05
    decided = np.abs(truth - 0.5) > 0.05
    assert np.array_equal((fast > 0.5)[decided], (truth > 0.5)[decided])
    assert 200 < (truth > 0.5).sum() < len(points) - 200  # both sides are exercised
    # the compiled brute force agrees with the numpy truth
    assert np.allclose(hair.winding_numbers(points, v, f), truth, atol=1e-9)
    # a single triangle (one leaf: a dipole far from it, exact near it) and an empty mesh
    one, one_truth = hair.WindingTree(v, f[:1])(points), winding_number(points, v, f[:1])
    assert np.abs(one - one_truth).max() < 1e-3
    centre = v[f[0]].mean(axis=0)
    close = np.linalg.norm(points - centre, axis=1) < 0.1
    assert close.sum() > 3 and np.allclose(one[close], one_truth[close], atol=1e-12)
    assert np.array_equal(hair.WindingTree(v, f[:0])(points), np.zeros(len(points)))


DOME_HAIR = dict(guides=150, children=6, segments=16, gravity=2.0, stiffness=0.0, iterations=20,
                 gravity_direction=(0.0, 0.0, -1.0))


def test_open_dome_nothing_inside_by_winding_number(dome):
    v, f = dome
    result = generate_hair(_emitter(v, f), HairOptions(length=2.0, **DOME_HAIR), seed=2)
    assert not result.stats["closed_emitter"]
    for strands in _all_strands(result):
        assert np.abs(segment_lengths(strands.positions) / strands.rest_lengths[:, None] - 1.0).max() < 0.01
        wn = winding_number(strands.positions[:, 1:].reshape(-1, 3), v, f)
        assert wn.max() <= 0.5, f"{int((wn > 0.5).sum())} strand vertices inside the open dome"


def test_open_dome_push_out_is_what_keeps_strands_outside(dome, monkeypatch):
    v, f = dome
    monkeypatch.setattr(hair, "push_out", lambda *a, **k: 0)
    result = generate_hair(_emitter(v, f), HairOptions(length=2.0, **DOME_HAIR), seed=2)
    wn = winding_number(result.guides.positions[:, 1:].reshape(-1, 3), v, f)
    assert (wn > 0.5).sum() > 50


def test_roots_are_blue_noise(sphere):
    v, f = sphere
    rng = np.random.default_rng(0)
    tri, bary, roots, rmax = hair.sample_roots(_emitter(v, f), 400, rng)
    assert len(roots) == 400
    assert np.allclose(np.linalg.norm(roots, axis=1), 1.0, atol=0.02)  # on the surface
    nearest = trimesh.proximity.cKDTree(roots).query(roots, k=2)[0][:, 1]
    white = hair.random_surface_points(v, f, 400, np.random.default_rng(0))
    white_pts = np.einsum("sk,skd->sd", white[1], v[f[white[0]]])
    white_nearest = trimesh.proximity.cKDTree(white_pts).query(white_pts, k=2)[0][:, 1]
    # Poisson-disk: no close pairs (uniform random has many), and spacing close to the ideal hexagonal 2 rmax
    assert nearest.min() > 0.6 * 2 * rmax > 5 * white_nearest.min()
    assert nearest.std() / nearest.mean() < 0.5 * white_nearest.std() / white_nearest.mean()


def test_density_mask_from_vertex_colour(tmp_path):
    m = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
    colors = np.where(m.vertices[:, 1:2] > 0, 255, 0).repeat(3, axis=1)
    m.visual.vertex_colors = np.concatenate([colors, np.full((len(colors), 1), 255)], axis=1).astype(np.uint8)
    path = tmp_path / "masked.glb"
    m.export(str(path))
    opts = HairOptions(guides=100, children=2, density_map="COLOR_0", gravity=0.0)
    asset, result = make_hair(path, opts)
    for strands in _all_strands(result):
        # the mask is 0 below y = -0.3 (interpolation between black and white corners stays above)
        assert strands.positions[:, 0, 1].min() > -0.35
        assert (strands.positions[:, 0, 1] > 0).mean() > 0.6


def test_children_weights_partition_of_unity_and_reconstruct_roots(sphere):
    v, f = sphere
    result = generate_hair(_emitter(v, f), HairOptions(guides=150, children=10, gravity=0.0), seed=1)
    ch, g = result.children, result.guides
    w, ids = ch.guide_weights, ch.guide_ids
    assert ch.count == 1500 and w.min() >= 0.0 and np.allclose(w.sum(axis=1), 1.0, atol=1e-12)
    assert ids.max() < g.count
    # where the child root projects inside its guide triangle (all weights > 0), the weights reproduce it
    inner = (w > 1e-3).all(axis=1)
    assert inner.mean() > 0.3
    a, b, c = (g.positions[ids[inner, k], 0] for k in range(3))
    p = ch.positions[inner, 0]
    n = np.cross(b - a, c - a)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    projected = p - np.einsum("ij,ij->i", p - a, n)[:, None] * n
    rebuilt = np.einsum("ik,ikd->id", w[inner], np.stack([a, b, c], axis=1))
    assert np.abs(projected - rebuilt).max() < 1e-9
    # no spread and no clumping: children lie between their guides (offset shape = weighted guide offsets)
    flat = generate_hair(_emitter(v, f), HairOptions(guides=150, children=2, gravity=0.0, spread=0.0), seed=1)
    c2 = flat.children
    shape = np.einsum("ck,ckvd->cvd", c2.guide_weights,
                      flat.guides.positions[c2.guide_ids] - flat.guides.positions[c2.guide_ids][:, :, :1])
    direction = lambda x: x[:, -1] - x[:, 0]  # noqa: E731
    cos = np.einsum("ij,ij->i", *(d / np.linalg.norm(d, axis=1, keepdims=True)
                                  for d in (direction(c2.positions - c2.positions[:, :1]), shape[:, -1])))
    assert cos.min() > 0.999


def test_gravity_and_stiffness(sphere):
    v, f = sphere
    drop = {}
    for gravity, stiffness in ((0.0, 0.4), (0.5, 0.8), (0.5, 0.0)):
        r = generate_hair(_emitter(v, f), HairOptions(guides=60, children=0, gravity=gravity, stiffness=stiffness,
                                                      length=1.0), seed=2)
        g = r.guides
        if gravity == 0.0:  # no gravity, no curl: straight along the root normal, tip at L n
            assert np.allclose(g.positions[:, -1] - g.positions[:, 0], 1.0 * g.root_normals, atol=1e-9)
        side = np.abs(g.positions[:, 0, 1]) < 0.3  # strands around the equator grow sideways
        drop[(gravity, stiffness)] = (g.positions[side, -1, 1] - g.positions[side, 0, 1]).mean()
    # gravity pulls tips down, and less so when the hair is stiffer
    assert drop[(0.0, 0.4)] > drop[(0.5, 0.8)] + 0.2
    assert drop[(0.5, 0.8)] > drop[(0.5, 0.0)] + 0.08
    assert r.children.count == 0


@pytest.fixture(scope="module")
def spot_hair(tmp_path_factory):
    out = tmp_path_factory.mktemp("hair")
    opts = HairOptions(guides=60, children=4, segments=15, length=0.3, gravity=0.3)
    files = {}
    for suffix in (".glb", ".gltf", ".usda", ".usdc", ".tfx"):
        asset, result = make_hair(SPOT, opts, seed=5)
        write_output(asset, result, opts, out / f"spot{suffix}")
        files[suffix] = out / f"spot{suffix}"
    return opts, result, files


def test_gltf_round_trip_and_validators(spot_hair):
    opts, result, files = spot_hair
    for suffix in (".glb", ".gltf"):
        path = files[suffix]
        report = validate_file(path, khronos=False)
        assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
        assert_khronos_clean(path)
    doc = GltfDocument.load(files[".glb"])
    mesh = next(i for i, m in enumerate(doc.json["meshes"]) if m.get("name") == "hair")
    guides, children = read_strands(doc, mesh, 0), read_strands(doc, mesh, 1)
    assert guides["ext"]["strandSet"] == "guides" and children["ext"]["guides"]["primitive"] == 0
    assert guides["positions"].shape == (60, 16, 3) and children["positions"].shape == (240, 16, 3)
    assert np.allclose(guides["positions"], result.guides.positions, atol=1e-6)
    assert np.allclose(guides["param"][:, 0], 0) and np.allclose(guides["param"][:, -1], 1)
    assert np.allclose(np.linalg.norm(children["tangents"], axis=-1), 1.0, atol=1e-5)
    # tangents point root -> tip
    d = np.diff(children["positions"], axis=1)
    assert (np.einsum("svi,svi->sv", d, children["tangents"][:, :-1]) > 0).all()
    assert np.array_equal(children["guide_ids"], result.children.guide_ids)
    assert np.allclose(children["guide_weights"].sum(axis=1), 1.0, atol=1e-6)
    assert children["guide_weights"].min() >= 0
    ribbon = children["ribbon"]
    assert len(ribbon) == 6 * 240 * 15 and ribbon.max() == 2 * 240 * 16 - 1
    # ribbons never join two strands: every triangle's line vertices belong to one strand
    assert (np.ptp((ribbon.reshape(-1, 3) // 2) // 16, axis=1) == 0).all()
    # nearest-first order: mean distance to the emitter is non-decreasing
    emitter = emitter_from_asset(readers.read(SPOT), opts)
    surface = hair.SurfaceLookup(emitter.vertices, emitter.colliders)
    depth = surface.distance(children["positions"][:, ::5].reshape(-1, 3).astype(np.float64)).reshape(240, -1).mean(1)
    assert np.corrcoef(depth, np.arange(240))[0, 1] > 0.9
    # the node hangs under the emitter's node, and the emitter mesh is untouched
    assert any(doc.json["nodes"][i].get("mesh") == mesh for i in range(len(doc.json["nodes"])))


def test_validator_catches_bad_weights(spot_hair, tmp_path):
    _, _, files = spot_hair
    doc = GltfDocument.load(files[".glb"])
    mesh = next(i for i, m in enumerate(doc.json["meshes"]) if m.get("name") == "hair")
    ext = doc.json["meshes"][mesh]["primitives"][1]["extensions"]["BAKER_hair"]
    weights = doc.accessor(ext["guides"]["weights"])
    ext["guides"]["weights"] = doc.add_accessor((weights * 1.5).astype(np.float32), target=None)
    ext["strandCount"] = ext["strandCount"]
    bad = tmp_path / "bad.glb"
    doc.save(bad)
    codes = {m["code"] for m in validate_file(bad, khronos=False)["issues"]["messages"]}
    assert "BAKER_HAIR_GUIDE_WEIGHTS" in codes


def test_usd_reads_back(spot_hair):
    from pxr import Usd, UsdGeom

    opts, result, files = spot_hair
    for suffix in (".usda", ".usdc"):
        stage = Usd.Stage.Open(str(files[suffix]))
        guides = UsdGeom.BasisCurves(stage.GetPrimAtPath("/Root/Hair/guides"))
        children = UsdGeom.BasisCurves(stage.GetPrimAtPath("/Root/Hair/children"))
        assert guides and children
        assert list(guides.GetCurveVertexCountsAttr().Get()) == [16] * 60
        assert list(children.GetCurveVertexCountsAttr().Get()) == [16] * 240
        assert guides.GetTypeAttr().Get() == "linear"
        points = np.array(children.GetPointsAttr().Get())
        assert np.allclose(points.reshape(240, 16, 3), result.children.positions, atol=1e-6)
        widths = np.array(children.GetWidthsAttr().Get()).reshape(240, 16)
        assert children.GetWidthsInterpolation() == UsdGeom.Tokens.vertex
        scale = result.children.width_scale[:, None]
        assert np.allclose(widths[:, 0], result.root_width * scale[:, 0], rtol=1e-5)
        assert np.allclose(widths[:, -1], result.tip_width * scale[:, 0], rtol=1e-5)
        api = UsdGeom.PrimvarsAPI(children.GetPrim())
        ids = api.GetPrimvar("baker:guideIds")
        weights = api.GetPrimvar("baker:guideWeights")
        assert ids.GetInterpolation() == UsdGeom.Tokens.uniform
        assert np.array_equal(np.array(ids.Get()), result.children.guide_ids)
        assert np.allclose(np.array(weights.Get()).sum(axis=1), 1.0, atol=1e-6)
        param = np.array(api.GetPrimvar("baker:strandParam").Get()).reshape(240, 16)
        assert np.allclose(param[:, 0], 0) and np.allclose(param[:, -1], 1)
        # the emitter is there too
        assert any(p.IsA(UsdGeom.Mesh) for p in stage.Traverse())


def test_usd_cubic_basis(tmp_path):
    from pxr import Usd, UsdGeom

    opts = HairOptions(guides=20, children=0, curve_type="catmullRom")
    asset, result = make_hair(SPOT, opts)
    write_output(asset, result, opts, tmp_path / "c.usda")
    stage = Usd.Stage.Open(str(tmp_path / "c.usda"))  # keep the stage alive while its prims are used
    curves = UsdGeom.BasisCurves(stage.GetPrimAtPath("/Root/Hair/guides"))
    assert curves.GetTypeAttr().Get() == "cubic" and curves.GetBasisAttr().Get() == "catmullRom"
    assert curves.GetWrapAttr().Get() == "pinned"


def test_tfx_header_round_trip(spot_hair):
    opts, result, files = spot_hair
    data = files[".tfx"].read_bytes()
    import struct

    version, strands, verts, pos_off, uv_off, vuv_off, th_off, col_off = struct.unpack_from("<f7I", data)
    assert (version, strands, verts, pos_off) == (4.0, 60, 16, 160)
    assert vuv_off == 0 and col_off == 0 and pos_off % 8 == 0 and th_off % 8 == 0 and th_off >= 160 + 60 * 16 * 16
    tfx = read_tfx(files[".tfx"])
    assert np.allclose(tfx.positions[..., :3], result.guides.positions, atol=1e-6)  # 16 vertices: no resampling
    assert (tfx.positions[:, 0, 3] == 0).all() and (tfx.positions[:, 1:, 3] == 1).all()
    assert np.allclose(tfx.thickness, result.guides.width_scale, atol=1e-7)
    # re-encoding what was read gives the same bytes
    assert encode_tfx(tfx.positions[..., :3].astype(np.float64), tfx.thickness, tfx.strand_uv) == data


def test_tfx_resamples_to_a_power_of_two():
    assert [tfx_vertex_count(n) for n in (2, 5, 17, 24, 33, 100)] == [4, 4, 16, 32, 32, 64]
    t = np.linspace(0, 1, 17)
    strands = np.stack([np.stack([t, t ** 2, 0 * t], axis=1)] * 3)
    out = resample_strands(strands, 16)
    assert np.allclose(out[:, 0], strands[:, 0]) and np.allclose(out[:, -1], strands[:, -1])
    seg = segment_lengths(out)
    assert np.abs(seg / seg.mean() - 1).max() < 0.02
    tfx = decode_tfx(encode_tfx(strands))
    assert tfx.positions.shape == (3, 16, 4) and tfx.thickness is None


def test_same_seed_same_bytes(spot_hair, tmp_path):
    opts, _, files = spot_hair
    for suffix in (".glb", ".usda", ".tfx"):
        asset, result = make_hair(SPOT, opts, seed=5)
        write_output(asset, result, opts, tmp_path / f"again{suffix}")
        assert (tmp_path / f"again{suffix}").read_bytes() == files[suffix].read_bytes(), suffix
    asset, result = make_hair(SPOT, opts, seed=6)
    write_output(asset, result, opts, tmp_path / "other.glb")
    assert (tmp_path / "other.glb").read_bytes() != files[".glb"].read_bytes()


def test_cli(tmp_path, capsys):
    out = tmp_path / "h.glb"
    assert cli_main(["hair", SPOT, "-o", str(out), "--guides", "30", "--children", "2", "-q"]) == 0
    assert validate_file(out, khronos=False)["issues"]["numErrors"] == 0
    assert cli_main(["hair", SPOT, "-o", str(tmp_path / "h.obj")]) == 2
    assert cli_main(["hair", SPOT, "-o", str(tmp_path / "h.glb"), "--stiffness", "3"]) == 2
    assert cli_main(["hair", SPOT, "-o", str(tmp_path / "h2.glb"), "--density-map", "COLOR_0"]) == 2
    assert not (tmp_path / "h2.glb").exists()
