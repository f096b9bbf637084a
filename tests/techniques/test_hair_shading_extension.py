"""``BAKER_hair_shading`` and the strands' rest-pose precomputes against independent truth: the occlusion and fibre
counts against brute-force ray casting (every ray against every other strand's tube and an analytic sphere scalp,
no grid), the embedded tables against a fresh bake through the file's bytes, the validators on good and broken
files."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import trimesh

from baker.cli import main as cli_main
from baker.gltf.document import GltfDocument
from baker.techniques.hair_shading.extension import NAME, read_tables
from baker.techniques.hair_shading.occlusion import ray_directions, strand_occlusion
from baker.techniques.hair_shading.tables import as_half, bake_tables
from baker.validate import validate_file
from conftest import assert_khronos_clean

SPOT = str(Path(__file__).resolve().parents[2] / "examples" / "spot" / "spot.obj")


def small_groom(strands=160, vertices=9, length=0.6, width=0.03, seed=1):
    """Strands on the upper half of a unit sphere: out along the normal, then bent down by a parabola."""
    rng = np.random.default_rng(seed)
    z = rng.uniform(0.1, 1.0, strands)
    phi = rng.uniform(0, 2 * math.pi, strands)
    r = np.sqrt(1 - z * z)
    normal = np.stack([r * np.cos(phi), r * np.sin(phi), z], -1)
    t = np.linspace(0.0, 1.0, vertices)[None, :, None]
    droop = np.array([0.0, 0.0, -1.0])
    positions = normal[:, None] * (1.002 + length * t * 0.8) + droop * (length * 0.6 * t ** 2)
    widths = np.full((strands, vertices), width) * np.linspace(1.0, 0.5, vertices)[None]
    return positions, widths


def brute_force(positions, widths, points, own, directions, distance, radius=1.0):
    """(visibility, fibre count per ray) by testing every ray against every other strand's capsules (the
    closed-form line-segment distance with the ray's parameter clamped to [0, distance]) and the sphere scalp of
    ``radius`` analytically."""
    s, v = positions.shape[:2]
    a = positions[:, :-1].reshape(-1, 3)
    e = (positions[:, 1:] - positions[:, :-1]).reshape(-1, 3)
    rad = (np.maximum(widths[:, :-1], widths[:, 1:]) / 2).reshape(-1)
    seg_strand = np.repeat(np.arange(s), v - 1)
    counts = np.zeros((len(points), directions.shape[1]), int)
    first = np.full((len(points), directions.shape[1]), np.inf)
    sphere_t = np.full((len(points), directions.shape[1]), np.inf)
    for i, (o, dirs) in enumerate(zip(points, directions)):
        # sphere: |o + t d|^2 = R^2, the nearest positive root
        b = dirs @ o
        c = o @ o - radius * radius
        disc = b * b - c
        root = -b - np.sqrt(np.maximum(disc, 0))
        root = np.where(root > 1e-9, root, -b + np.sqrt(np.maximum(disc, 0)))
        sphere_t[i] = np.where((disc > 0) & (root > 1e-9), root, np.inf)
        keep = seg_strand != own[i]
        aa, ee, rr = a[keep], e[keep], rad[keep]
        w = o[None] - aa  # (n, 3)
        for r, d in enumerate(dirs):
            bb = ee @ d
            cc = np.einsum("ij,ij->i", ee, ee)
            dw = w @ d
            ew = np.einsum("ij,ij->i", ee, w)
            denom = cc - bb * bb
            ss = np.clip(np.where(denom > 1e-12 * cc, (ew - bb * dw) / np.where(denom > 0, denom, 1), 0.5), 0, 1)
            tt = ss * bb - dw
            gap = w + tt[:, None] * d[None] - ss[:, None] * ee
            hit = (np.einsum("ij,ij->i", gap, gap) < rr * rr) & (tt > 0)
            limit = min(distance, sphere_t[i, r])
            counts[i, r] = int((hit & (tt <= limit)).sum())
            first[i, r] = tt[hit].min() if hit.any() else np.inf
    visibility = ((first > distance) & (sphere_t > distance)).mean(axis=1)
    return visibility, counts


def test_occlusion_and_fibre_counts_agree_with_brute_force():
    positions, widths = small_groom()
    scalp = trimesh.creation.icosphere(subdivisions=5, radius=1.0)
    visibility, pos, neg, info = strand_occlusion(positions, widths, rays=16,
                                                  scalp=(np.asarray(scalp.vertices), np.asarray(scalp.faces)))
    assert info["scalp"] and info["rays"] == 16
    assert visibility.min() >= 0 and visibility.max() <= 1 and np.isfinite(pos).all() and (neg >= 0).all()
    s, v = positions.shape[:2]
    rng = np.random.default_rng(7)
    pick = rng.choice(s * v, 240, replace=False)
    points = positions.reshape(-1, 3)[pick]
    own = pick // v
    dirs = rng.normal(size=(len(pick), 256, 3))
    dirs /= np.linalg.norm(dirs, axis=-1, keepdims=True)
    truth, counts = brute_force(positions, widths, points, own, dirs, info["distance"])
    r = np.corrcoef(visibility[pick], truth)[0, 1]
    print(f"occlusion: correlation {r:.3f} with brute force (256 rays), mean {visibility[pick].mean():.3f} vs "
          f"{truth.mean():.3f}, spread {truth.std():.3f}")
    assert r >= 0.8
    assert abs(visibility[pick].mean() - truth.mean()) < 0.05
    # fibre counts: the grid walk against brute force along the very directions the bake cast (exact per ray up to
    # rays grazing a tube's surface or the tessellated scalp)
    same = ray_directions(s * v, 16, 0)[pick]
    _, counts = brute_force(positions, widths, points, own, same, info["distance"])
    w_pos = np.where(same > 0, same ** 2, 0.0)
    w_neg = np.where(same < 0, same ** 2, 0.0)
    cube_pos = np.einsum("vra,vr->va", w_pos, counts) / w_pos.sum(1)
    cube_neg = np.einsum("vra,vr->va", w_neg, counts) / w_neg.sum(1)
    baked = np.concatenate([pos[pick], neg[pick]], 1)
    brute = np.concatenate([cube_pos, cube_neg], 1)
    agree = np.isclose(baked, brute, atol=1e-4).all(axis=1).mean()
    print(f"fibre counts: {100 * agree:.1f} % of vertices exact, mean {baked.mean():.3f} vs {brute.mean():.3f}")
    assert agree >= 0.97 and brute.max() >= 2


def test_open_strand_is_open_and_a_wall_is_counted():
    """Two parallel strands far apart: each open everywhere; a sheet of strands between a vertex and +x: counted
    as many times as it holds strands along +x, none along -x."""
    lone = np.array([[[0, 0, 0], [0, 0, 1.0]], [[50, 0, 0], [50, 0, 1.0]]])
    vis, _, _, _ = strand_occlusion(lone, np.full((2, 2), 0.01), rays=32, distance=1.0)
    assert (vis == 1).all()
    # a probe strand at x = 0 and three walls of 40 strands each at x = 0.2, 0.3, 0.4 (strands along z, spaced
    # closer than their width in y: a solid wall)
    ys = np.linspace(-2, 2, 201)
    walls = [np.stack([np.stack([np.full(2, x), np.full(2, y), [-2.0, 2.0]], -1) for y in ys]) for x in (0.2, 0.3, 0.4)]
    probe = np.array([[[0.0, 0.0, -0.01], [0.0, 0.0, 0.01]]])
    positions = np.concatenate([probe] + walls)
    widths = np.full(positions.shape[:2], 0.025)
    vis, pos, neg, _ = strand_occlusion(positions, widths, rays=64, distance=1.0)
    # near +x every ray crosses all three walls; the cos^2 weighting over the hemisphere keeps the mean near 3
    assert pos[0, 0] > 2.0 and neg[0, 0] == 0.0
    assert 0.25 < vis[0] < 0.75  # the half space toward +x is closed


@pytest.fixture(scope="module")
def spot_groom(tmp_path_factory):
    out = tmp_path_factory.mktemp("hairshade")
    files = {}
    for suffix in (".glb", ".usda"):
        files[suffix] = out / f"spot{suffix}"
        assert cli_main(["hair", SPOT, "-o", str(files[suffix]), "--guides", "40", "--children", "3", "--segments",
                         "8", "-q", "--hair-eumelanin", "0.3", "--hair-roughness", "0.25,0.35", "--hair-tilt",
                         "3"]) == 0
    return files


def test_tables_in_the_file_are_the_bake(spot_groom):
    doc = GltfDocument.load(spot_groom[".glb"])
    root = doc.json["extensions"][NAME]
    assert len(root["tables"]) == 1
    material = next(m for m in doc.json["materials"] if NAME in m.get("extensions", {}))
    ext = material["extensions"][NAME]
    assert (ext["betaM"], ext["betaN"], ext["alpha"], ext["eumelanin"]) == (0.25, 0.35, 3.0, 0.3)
    assert ext["occlusion"]["attribute"] == "_HAIR_OCCLUSION" and ext["fibreCount"]["basis"] == "ambientCube"
    tables, dual = read_tables(doc, ext["tables"])
    fresh = as_half(bake_tables(0.25, 0.35, 1.55))
    assert np.array_equal(tables.longitudinal, fresh.longitudinal)
    assert np.array_equal(tables.azimuthal, fresh.azimuthal)
    entry = root["tables"][0]
    for key in ("longitudinal", "azimuthal", "dualScattering"):
        acc = doc.json["accessors"][entry[key]["accessor"]]
        assert (acc["componentType"], acc["type"], acc["count"]) == (5123, "VEC4", entry[key]["width"] * entry[key]["height"])
        view = doc.json["bufferViews"][acc["bufferView"]]
        assert view["byteLength"] == entry[key]["width"] * entry[key]["height"] * 8 and "byteStride" not in view
        assert view["byteOffset"] % 4 == 0  # a Uint16Array / half-float upload can view it in place
    assert dual.table.shape == (entry["azimuthal"]["slices"], entry["dualScattering"]["width"], 4)
    # every strand vertex: occlusion in [0, 1], melanin the same along a strand
    for prim in doc.json["meshes"][-1]["primitives"]:
        occ = doc.accessor(prim["attributes"]["_HAIR_OCCLUSION"])
        mel = doc.accessor(prim["attributes"]["_HAIR_MELANIN"]).reshape(-1, 9, 3)[..., :2]
        assert occ.min() >= 0 and occ.max() <= 1 and occ.std() > 0.05
        assert np.allclose(mel, mel[:, :1]) and mel[..., 0].std() > 0


def test_validators_pass_and_catch_broken_tables(spot_groom, tmp_path):
    good = validate_file(spot_groom[".glb"], khronos=False)
    assert good["issues"]["numErrors"] == 0, good["issues"]["messages"]
    assert_khronos_clean(spot_groom[".glb"])
    doc = GltfDocument.load(spot_groom[".glb"])
    entry = doc.json["extensions"][NAME]["tables"][0]
    view = doc.json["bufferViews"][doc.json["accessors"][entry["longitudinal"]["accessor"]]["bufferView"]]
    doc.bin[view["byteOffset"]: view["byteOffset"] + 2] = np.array([np.nan], "<f2").tobytes()
    entry["azimuthal"]["slices"] += 1
    material = next(m for m in doc.json["materials"] if NAME in m.get("extensions", {}))
    material["extensions"][NAME]["tables"] = 3
    bad = tmp_path / "bad.glb"
    doc.save(bad)
    codes = {m["code"] for m in validate_file(bad, khronos=False)["issues"]["messages"]}
    assert {"BAKER_HAIR_SHADING_TABLE_NOT_FINITE", "BAKER_HAIR_SHADING_TABLE_SIZE",
            "BAKER_HAIR_SHADING_TABLES"} <= codes


def test_usd_reports_what_the_glb_does(spot_groom, capsys):
    """inspect of the USD shows the hair material and the strands' attributes as the GLB's does."""
    reports = {}
    for suffix, path in spot_groom.items():
        assert cli_main(["inspect", str(path), "--format", "json"]) == 0
        reports[suffix] = json.loads(capsys.readouterr().out)
        assert validate_file(path, khronos=False)["issues"]["numErrors"] == 0
    glb, usd = reports[".glb"], reports[".usda"]
    assert NAME in glb["extensionsUsed"] and NAME in usd["extensionsUsed"]
    for report in (glb, usd):
        hair = [row for row in report["meshes"] if "_HAIR_OCCLUSION" in row["baked"]]
        assert len(hair) == 2, [row["name"] for row in report["meshes"]]
    occlusion = [[row["baked"]["_HAIR_OCCLUSION"]["mean"] for row in r["meshes"] if "_HAIR_OCCLUSION" in row["baked"]]
                 for r in (glb, usd)]
    assert np.allclose(occlusion[0], occlusion[1], atol=1e-6)


def test_hair_color_and_bad_flags(tmp_path, capsys):
    out = tmp_path / "c.glb"
    assert cli_main(["hair", SPOT, "-o", str(out), "--guides", "10", "--children", "0", "--segments", "4", "-q",
                     "--hair-color", "0.6,0.4,0.2", "--hair-occlusion-rays", "0"]) == 0
    ext = next(m for m in GltfDocument.load(out).json["materials"] if NAME in m.get("extensions", {}))
    ext = ext["extensions"][NAME]
    assert ext["color"] == [0.6, 0.4, 0.2] and "eumelanin" not in ext and "occlusion" not in ext
    assert "melaninAttribute" not in ext
    # the inversion is a round trip: the base colour is the colour asked for
    base = next(m for m in GltfDocument.load(out).json["materials"] if NAME in m.get("extensions", {}))
    assert np.allclose(base["pbrMetallicRoughness"]["baseColorFactor"][:3], [0.6, 0.4, 0.2], atol=1e-6)
    for flag, value in (("--hair-color", "2,0,0"), ("--hair-roughness", "0.01,0.3"), ("--hair-tilt", "40")):
        with pytest.raises(SystemExit) as exc:
            cli_main(["hair", SPOT, "-o", str(out), flag, value])
        assert exc.value.code == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "Traceback" not in err[0]
