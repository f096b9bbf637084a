"""``baker guides``: dense groom -> guides + 3-guide weights + LODs, checked against independent truth.

Every check reads the written files with its own reader (GLB: JSON + BIN chunk parsed here; USD: pxr; TressFX:
struct), rebuilds the children with the offset formula ``child(t) = root + sum w_i (guide_i(t) - guideRoot_i)``
and compares with the input curves (resampled here by a per-curve ``np.interp``), with a naive baseline and a
k-means peer written here in numpy.
"""
from __future__ import annotations

import json
import math
import struct
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

from baker.cli import main as cli_main
from baker.validate import validate_file
from conftest import assert_khronos_clean

V = 16  # vertices per output strand in these tests
N = 120  # guides


# ------------------------------------------------------------------------------------------------ groom + readers
def make_groom(strands: int = 2400, seed: int = 3):
    """Curves on the upper half of a unit sphere: clumps whose tips pull together, curls per clump, lengths and
    vertex counts (5..40) varying, widths tapering linearly to 0.2 x the root width (a common ratio, so BAKER_hair's
    width model holds them exactly). Returns (list of (v_i, 3) arrays, list of (v_i,) widths)."""
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(strands, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    d[:, 1] = np.abs(d[:, 1]) + 0.05
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    centres = d[rng.choice(strands, strands // 40, replace=False)]
    _, clump = cKDTree(centres).query(d)
    amp = np.where(rng.random(len(centres)) < 0.5, 0.0, rng.uniform(0.03, 0.08, len(centres)))
    freq = rng.uniform(2, 5, len(centres))
    curves, widths = [], []
    down = np.array([0.0, -1.0, 0.0])
    for i in range(strands):
        c = clump[i]
        t = np.linspace(0.0, 1.0, int(rng.integers(5, 41)))[:, None]
        length = 0.6 + 0.4 * rng.random()
        own = d[i] + length * (0.4 * t * d[i] + 0.8 * t * t * down)
        lead = centres[c] + length * (0.4 * t * centres[c] + 0.8 * t * t * down)
        p = own + (lead - own) * 0.6 * t ** 1.5
        e1 = np.cross(d[i], down)
        e1 /= np.linalg.norm(e1) + 1e-12
        e2 = np.cross(e1, down)
        ph = 2 * math.pi * freq[c] * t + c
        p = p + amp[c] * length * np.minimum(t / 0.2, 1) * (np.cos(ph) * e1 + np.sin(ph) * e2)
        curves.append(p)
        widths.append(0.01 * rng.uniform(0.5, 1.0) * (1.0 - 0.8 * t[:, 0]))
    return curves, widths


def write_usd(path: Path, curves, widths, offset=(0.0, 0.0, 0.0)):
    """Two BasisCurves prims written by pxr; the second is translated by ``offset`` (its points stored minus it)."""
    from pxr import Gf, Usd, UsdGeom, Vt

    stage = Usd.Stage.CreateNew(str(path))
    half = len(curves) // 2
    for k, (lo, hi) in enumerate(((0, half), (half, len(curves)))):
        c = UsdGeom.BasisCurves.Define(stage, f"/Groom/part{k}")
        pts = np.concatenate(curves[lo:hi])
        if k == 1:
            c.AddTranslateOp().Set(Gf.Vec3d(*offset))
            pts = pts - np.asarray(offset)
        c.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(pts.astype(np.float32)))
        c.CreateCurveVertexCountsAttr(Vt.IntArray([len(x) for x in curves[lo:hi]]))
        c.CreateWidthsAttr(Vt.FloatArray.FromNumpy(np.concatenate(widths[lo:hi]).astype(np.float32)))
        c.SetWidthsInterpolation(UsdGeom.Tokens.vertex)
    stage.GetRootLayer().Save()


def resample(curve: np.ndarray, count: int) -> np.ndarray:
    """One polyline at ``count`` equal arc-length steps (np.interp per coordinate)."""
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(curve, axis=0), axis=1))])
    t = np.linspace(0.0, arc[-1], count)
    return np.stack([np.interp(t, arc, curve[:, k]) for k in range(3)], axis=1)


def polyline_length(p: np.ndarray) -> np.ndarray:
    return np.linalg.norm(np.diff(p, axis=-2), axis=-1).sum(axis=-1)


def read_glb(path: Path) -> tuple[dict, callable]:
    """(glTF JSON, accessor reader) from the GLB chunks, without baker."""
    data = path.read_bytes()
    magic, version, total = struct.unpack_from("<4sII", data, 0)
    assert magic == b"glTF" and version == 2 and total == len(data)
    json_len, json_type = struct.unpack_from("<I4s", data, 12)
    assert json_type == b"JSON"
    gltf = json.loads(data[20:20 + json_len])
    bin_len, bin_type = struct.unpack_from("<I4s", data, 20 + json_len)
    assert bin_type == b"BIN\x00"
    blob = data[28 + json_len:28 + json_len + bin_len]
    dtypes = {5126: "<f4", 5125: "<u4", 5123: "<u2", 5121: "u1"}
    sizes = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}

    def accessor(i):
        a = gltf["accessors"][i]
        view = gltf["bufferViews"][a["bufferView"]]
        n = sizes[a["type"]]
        arr = np.frombuffer(blob, dtypes[a["componentType"]], a["count"] * n,
                            view.get("byteOffset", 0) + a.get("byteOffset", 0))
        return arr.reshape(a["count"], n) if n > 1 else arr

    return gltf, accessor


def hair_from_glb(path: Path) -> dict:
    gltf, acc = read_glb(path)
    mesh = next(m for m in gltf["meshes"] if m.get("name") == "hair")
    out = {}
    for prim in mesh["primitives"]:
        ext = prim["extensions"]["BAKER_hair"]
        s, v = ext["strandCount"], ext["verticesPerStrand"]
        out[ext["strandSet"]] = {"positions": acc(prim["attributes"]["POSITION"]).reshape(s, v, 3).astype(np.float64),
                                 "widthScale": acc(ext["widthScale"]).astype(np.float64), "ext": ext, "acc": acc}
        if "guides" in ext:
            out[ext["strandSet"]]["ids"] = acc(ext["guides"]["ids"]).astype(np.int64)
            out[ext["strandSet"]]["weights"] = acc(ext["guides"]["weights"]).astype(np.float64)
    return out


def offset_rebuild(guides: np.ndarray, roots: np.ndarray, ids: np.ndarray, weights: np.ndarray) -> np.ndarray:
    shapes = guides - guides[:, :1]
    return roots[:, None, :] + np.einsum("sk,skvd->svd", weights, shapes[ids])


def relative_rms(truth: np.ndarray, rebuilt: np.ndarray) -> tuple[float, float]:
    rel = np.linalg.norm(truth - rebuilt, axis=2) / polyline_length(truth)[:, None]
    return float(np.sqrt(np.mean(rel ** 2))), float(rel.max())


def barycentric(p, a, b, c):
    """Clamped, renormalised barycentric coordinates of p projected on (a, b, c) (the naive baseline's weights)."""
    v0, v1, v2 = b - a, c - a, p - a
    d00, d01, d11 = (v0 * v0).sum(1), (v0 * v1).sum(1), (v1 * v1).sum(1)
    d20, d21 = (v2 * v0).sum(1), (v2 * v1).sum(1)
    den = d00 * d11 - d01 * d01
    den = np.where(np.abs(den) > 1e-18, den, 1.0)
    v = (d11 * d20 - d01 * d21) / den
    w = (d00 * d21 - d01 * d20) / den
    bary = np.clip(np.stack([1 - v - w, v, w], axis=1), 0, None)
    bary[bary.sum(1) <= 0] = (1.0, 0.0, 0.0)
    return bary / bary.sum(1, keepdims=True)


def kmeans_peer(strands: np.ndarray, n: int, rng, iterations: int = 25) -> np.ndarray:
    """Reconstruction by k-means (k-means++ seeding, Lloyd) on flattened strand coordinates: each strand follows
    its cluster's centroid shape from its own root."""
    flat = strands.reshape(len(strands), -1)
    centres = [flat[rng.integers(len(flat))]]
    mind = ((flat - centres[0]) ** 2).sum(1)
    for _ in range(n - 1):
        centres.append(flat[rng.choice(len(flat), p=mind / mind.sum())])
        mind = np.minimum(mind, ((flat - centres[-1]) ** 2).sum(1))
    centres = np.array(centres)
    for _ in range(iterations):
        label = cKDTree(centres).query(flat)[1]
        for k in range(n):
            members = flat[label == k]
            if len(members):
                centres[k] = members.mean(0)
    label = cKDTree(centres).query(flat)[1]
    c = centres.reshape(n, -1, 3)
    return strands[:, :1] + (c - c[:, :1])[label]


# -------------------------------------------------------------------------------------------------------- fixtures
@pytest.fixture(scope="module")
def groom(tmp_path_factory):
    folder = tmp_path_factory.mktemp("groom")
    curves, widths = make_groom()
    offset = (0.0, 0.25, -0.5)
    path = folder / "groom.usda"
    write_usd(path, curves, widths, offset)
    return {"path": path, "folder": folder, "curves": curves, "widths": widths}


@pytest.fixture(scope="module")
def baked(groom):
    """The groom through `baker guides` once per output type (same options and seed), with the JSON summaries."""
    import contextlib
    import io

    out = {}
    for suffix in (".glb", ".usda", ".tfx"):
        path = groom["folder"] / f"out{suffix}"
        with contextlib.redirect_stdout(io.StringIO()) as buffer:
            assert cli_main(["guides", str(groom["path"]), "-o", str(path), "--guides", str(N),
                             "--vertices-per-strand", str(V), "--format", "json"]) == 0
        out[suffix] = path
        out["summary" + suffix] = json.loads(buffer.getvalue())
    return out


def truth(groom) -> np.ndarray:
    """The input curves at V vertices: resampled, except those that have V already (kept, as baker documents)."""
    return np.stack([c if len(c) == V else resample(c, V) for c in groom["curves"]])


def match_children(groom, children: np.ndarray) -> np.ndarray:
    """Index of the input curve whose (world-space) root each written child starts at."""
    roots = np.stack([c[0] for c in groom["curves"]])
    dist, idx = cKDTree(roots).query(children[:, 0])
    assert dist.max() < 1e-5, "a child's root is not an input root"
    assert len(np.unique(idx)) == len(roots), "children and input curves do not match one to one"
    return idx


# ----------------------------------------------------------------------------------------------------------- tests
def test_children_are_the_input_strands_resampled(groom, baked):
    hair = hair_from_glb(baked[".glb"])
    children = hair["children"]["positions"]
    assert children.shape == (len(groom["curves"]), V, 3)
    idx = match_children(groom, children)  # also proves the second prim's translation was applied
    want = truth(groom)[idx]
    lengths = np.array([polyline_length(c) for c in groom["curves"]])[idx]
    # every vertex on the input curve, at equal arc-length steps: an independent resampling gives the same points
    assert (np.linalg.norm(children - want, axis=2).max(axis=1) / lengths).max() < 1e-5
    # so lengths are kept up to the corners cut by the new vertices: little for the straight half of the clumps,
    # more for the curls (5 turns in 16 vertices)
    loss = 1.0 - polyline_length(children) / lengths
    assert loss.min() > -1e-6 and np.percentile(loss, 25) < 0.005 and loss.max() < 0.4
    assert np.allclose(children[:, -1], np.stack([groom["curves"][i][-1] for i in idx]), atol=0.02)


def test_reconstruction_from_the_file_beats_naive_and_kmeans(groom, baked):
    """Done-when of the issue on a small groom: RMS <= 0.7 x naive and <= k-means, from the written file alone."""
    hair = hair_from_glb(baked[".glb"])
    guides, ch = hair["guides"]["positions"], hair["children"]
    children, ids, weights = ch["positions"], ch["ids"], ch["weights"]
    assert guides.shape == (N, V, 3) and ids.shape == weights.shape == (len(children), 3)
    assert ids.max() < N and weights.min() >= 0 and np.allclose(weights.sum(1), 1, atol=1e-6)
    assert ch["ext"]["guides"]["interpolation"] == "offset"
    # guides are input strands: every guide is one of the children exactly
    dist, _ = cKDTree(children.reshape(len(children), -1)).query(guides.reshape(N, -1))
    assert dist.max() < 1e-6
    rms, worst = relative_rms(children, offset_rebuild(guides, children[:, 0], ids, weights))
    summary = baked["summary.glb"]
    assert summary["rmsError"] == pytest.approx(rms, rel=1e-3) and summary["maxError"] == pytest.approx(worst, rel=1e-2)
    strands = truth(groom)
    rng = np.random.default_rng(0)
    naive = []
    for _ in range(3):
        g = rng.choice(len(strands), N, replace=False)
        roots = strands[:, 0]
        _, nn = cKDTree(roots[g]).query(roots, k=3)
        w = barycentric(roots, roots[g][nn[:, 0]], roots[g][nn[:, 1]], roots[g][nn[:, 2]])
        naive.append(relative_rms(strands, offset_rebuild(strands[g], roots, nn, w))[0])
    kmeans = relative_rms(strands, kmeans_peer(strands, N, rng))[0]
    assert rms <= 0.7 * min(naive), (rms, naive)
    assert rms <= kmeans, (rms, kmeans)


def test_weights_are_optimal_for_their_guides(groom, baked):
    """No vertex of the weight simplex (a single guide) of a child's 3 guides does better than its solved weights,
    and a brute-force grid over the simplex finds nothing better (to the grid's step)."""
    hair = hair_from_glb(baked[".glb"])
    guides, ch = hair["guides"]["positions"], hair["children"]
    children, ids, weights = ch["positions"][:300], ch["ids"][:300], ch["weights"][:300]
    shapes = guides - guides[:, :1]
    target = children - children[:, :1]
    err = lambda w: ((target - np.einsum("sk,skvd->svd", w, shapes[ids])) ** 2).sum(axis=(1, 2))  # noqa: E731
    solved = err(weights)
    steps = np.linspace(0, 1, 21)
    best = np.full(len(children), np.inf)
    for a in steps:
        for b in steps[steps <= 1 - a + 1e-12]:
            w = np.tile([a, b, max(1 - a - b, 0.0)], (len(children), 1))
            best = np.minimum(best, err(w))
    assert (solved <= best * (1 + 1e-3) + 1e-9).all()


def test_lods_are_blue_noise_prefixes(groom, baked):
    hair = hair_from_glb(baked[".glb"])
    ext = hair["children"]["ext"]
    s = ext["strandCount"]
    lods = ext["lods"]
    assert ext["order"] == "lodPrefix" and lods[0]["strandCount"] == s and len(lods) == 4
    assert [x["strandCount"] for x in lods] == sorted([x["strandCount"] for x in lods], reverse=True)
    for lod in lods:
        assert lod["widthScale"] == pytest.approx(s / lod["strandCount"])
    roots = hair["children"]["positions"][:, 0]
    rng = np.random.default_rng(1)
    for lod in lods[1:]:
        n = lod["strandCount"]
        prefix = roots[:n]
        random = roots[rng.choice(s, n, replace=False)]
        # blue noise: no two roots of the prefix crowd together, and every root has a prefix root nearby
        nn = lambda p: cKDTree(p).query(p, k=2)[0][:, 1]  # noqa: E731
        assert np.percentile(nn(prefix), 5) > 2.0 * np.percentile(nn(random), 5)
        assert cKDTree(prefix).query(roots)[0].max() < cKDTree(random).query(roots)[0].max()


def test_glb_validates(baked):
    report = validate_file(baked[".glb"], khronos=False)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert_khronos_clean(baked[".glb"])


def test_usd_output_read_by_pxr(groom, baked):
    from pxr import Usd, UsdGeom

    hair = hair_from_glb(baked[".glb"])
    stage = Usd.Stage.Open(str(baked[".usda"]))
    sets = {}
    for name in ("guides", "children"):
        curves = UsdGeom.BasisCurves(stage.GetPrimAtPath(f"/Root/Hair/{name}"))
        counts = np.asarray(curves.GetCurveVertexCountsAttr().Get())
        points = np.asarray(curves.GetPointsAttr().Get()).reshape(-1, V, 3)
        assert (counts == V).all() and len(points) == len(counts)
        sets[name] = (curves, points)
    assert np.allclose(sets["guides"][1], hair["guides"]["positions"], atol=1e-6)
    assert np.allclose(sets["children"][1], hair["children"]["positions"], atol=1e-6)
    api = UsdGeom.PrimvarsAPI(sets["children"][0].GetPrim())
    ids = np.asarray(api.GetPrimvar("baker:guideIds").Get())
    weights = np.asarray(api.GetPrimvar("baker:guideWeights").Get())
    assert np.array_equal(ids, hair["children"]["ids"]) and np.allclose(weights, hair["children"]["weights"])
    assert api.GetPrimvar("baker:guideIds").GetInterpolation() == UsdGeom.Tokens.uniform
    # widths: the input's per-vertex widths (linear taper, common ratio) come back per vertex
    idx = match_children(groom, sets["children"][1])
    widths = np.asarray(sets["children"][0].GetWidthsAttr().Get()).reshape(-1, V)
    want = np.stack([np.interp(np.linspace(0, 1, V), np.linspace(0, 1, len(groom["widths"][i])), groom["widths"][i])
                     for i in idx])
    assert np.allclose(widths, want, rtol=2e-3, atol=1e-7)
    hair_prim = stage.GetPrimAtPath("/Root/Hair")
    assert hair_prim.GetAttribute("baker:hair:interpolation").Get() == "offset"
    counts = list(hair_prim.GetAttribute("baker:hair:lod:strandCounts").Get())
    assert counts == [x["strandCount"] for x in hair["children"]["ext"]["lods"]]


def test_tfx_output_parsed_raw(groom, baked):
    hair = hair_from_glb(baked[".glb"])
    path = baked[".tfx"]

    def parse(p):
        data = p.read_bytes()
        version, s, v, pos, uv, vuv, th, col = struct.unpack_from("<f7I", data, 0)
        assert version == 4.0 and pos >= 160 and pos + 16 * s * v <= len(data)
        xyzw = np.frombuffer(data, "<f4", 4 * s * v, pos).reshape(s, v, 4)
        thickness = np.frombuffer(data, "<f4", s, th) if th else None
        return xyzw, thickness

    guides, g_thick = parse(path)
    children, c_thick = parse(path.with_name("out.children.tfx"))
    assert guides.shape == (N, V, 4) and children.shape == (len(groom["curves"]), V, 4)
    assert (guides[:, 0, 3] == 0).all() and (guides[:, 1:, 3] == 1).all()  # pinned roots
    assert np.allclose(guides[..., :3], hair["guides"]["positions"], atol=1e-6)
    assert np.allclose(c_thick, hair["children"]["widthScale"]) and np.allclose(g_thick, hair["guides"]["widthScale"])
    data = path.with_name("out.weights").read_bytes()
    magic, version, s, n = struct.unpack_from("<4s3I", data, 0)
    assert magic == b"BKHW" and version == 1 and s == len(children) and n == N and len(data) == 16 + 24 * s
    ids = np.frombuffer(data, "<u4", 3 * s, 16).reshape(s, 3)
    weights = np.frombuffer(data, "<f4", 3 * s, 16 + 12 * s).reshape(s, 3)
    assert np.array_equal(ids, hair["children"]["ids"]) and np.allclose(weights, hair["children"]["weights"])


def test_glb_and_tfx_inputs_round_trip(groom, baked, tmp_path):
    """The written .glb (BAKER_hair children) and .children.tfx read back as grooms: same strands, same widths."""
    hair = hair_from_glb(baked[".glb"])
    children = hair["children"]["positions"]
    out = tmp_path / "again.glb"
    assert cli_main(["guides", str(baked[".glb"]), "-o", str(out), "--guides", str(N), "--vertices-per-strand",
                     str(V), "-q"]) == 0
    again = hair_from_glb(out)
    assert again["children"]["positions"].shape == children.shape
    order = cKDTree(children[:, 0]).query(again["children"]["positions"][:, 0])[1]
    assert np.allclose(again["children"]["positions"], children[order], atol=1e-5)
    assert np.allclose(again["children"]["widthScale"], hair["children"]["widthScale"][order], rtol=1e-5)
    for key in ("rootWidth", "tipWidth"):
        assert again["children"]["ext"][key] == pytest.approx(hair["children"]["ext"][key], rel=1e-5)
    out = tmp_path / "from_tfx.glb"
    assert cli_main(["guides", str(baked[".tfx"].with_name("out.children.tfx")), "-o", str(out), "--guides", "40",
                     "--vertices-per-strand", str(V), "-q"]) == 0
    from_tfx = hair_from_glb(out)
    assert from_tfx["children"]["ext"]["strandCount"] == len(children)
    order = cKDTree(children[:, 0]).query(from_tfx["children"]["positions"][:, 0])[1]
    assert np.allclose(from_tfx["children"]["positions"], children[order], atol=1e-5)
    # TressFX thickness is a per-strand scale: it comes back as widthScale
    assert np.allclose(from_tfx["children"]["widthScale"], hair["children"]["widthScale"][order], rtol=1e-5)


def test_plain_gltf_lines_with_node_transform(tmp_path):
    """A hand-written glTF: LINES (3 strands of 4, 3 and 5 vertices) under a translated, scaled node, and a
    LINE_STRIP; roots, counts and world positions come back."""
    import base64

    strands = [np.array([[0, 0, 0], [0, 1, 0], [0, 2, 0], [0, 3, 0]], float),
               np.array([[1, 0, 0], [1, 1, 0.5], [1, 2, 1]], float),
               np.array([[2, 0, 0], [2, 1, 0], [2, 2, 0], [2, 3, 0], [2, 4, 0]], float)]
    strip = np.array([[5, 0, 0], [5, 0, 1], [5, 0, 2]], float)
    pos = np.concatenate(strands + [strip]).astype(np.float32)
    segs, start = [], 0
    for s in strands:
        segs += [(start + k, start + k + 1) for k in range(len(s) - 1)]
        start += len(s)
    rng = np.random.default_rng(0)
    segs = np.array(segs, np.uint32)[rng.permutation(len(segs))]  # segment order must not matter
    n_lines = start
    blob = pos[:n_lines].tobytes() + segs.tobytes() + pos[n_lines:].tobytes()
    gltf = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "translation": [0, 10, 0], "scale": [2, 2, 2]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 1},
                                   {"attributes": {"POSITION": 2}, "mode": 3}]}],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 12 * n_lines},
                        {"buffer": 0, "byteOffset": 12 * n_lines, "byteLength": segs.nbytes},
                        {"buffer": 0, "byteOffset": 12 * n_lines + segs.nbytes, "byteLength": 36}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n_lines, "type": "VEC3",
             "min": pos[:n_lines].min(0).tolist(), "max": pos[:n_lines].max(0).tolist()},
            {"bufferView": 1, "componentType": 5125, "count": segs.size, "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": strip.min(0).tolist(), "max": strip.max(0).tolist()}],
    }
    src = tmp_path / "lines.gltf"
    src.write_text(json.dumps(gltf))
    out = tmp_path / "lines.glb"
    assert cli_main(["guides", str(src), "-o", str(out), "--guides", "2", "--vertices-per-strand", "5", "-q"]) == 0
    hair = hair_from_glb(out)
    children = hair["children"]["positions"]
    world = [s * 2 + np.array([0, 10, 0]) for s in strands + [strip]]
    roots = np.stack([w[0] for w in world])
    idx = cKDTree(roots).query(children[:, 0])[1]
    assert sorted(idx.tolist()) == [0, 1, 2, 3]
    for child, i in zip(children, idx):
        assert np.allclose(child, resample(world[i], 5), atol=1e-4)
        assert np.allclose(child[-1], world[i][-1], atol=1e-4)


def test_bad_curves_skipped_or_refused(tmp_path, capsys):
    from pxr import Usd, UsdGeom, Vt

    curves, widths = make_groom(60, seed=5)
    bad = [np.array([[0.0, 0.0, 0.0]]), np.array([[0.0, 1.0, 0.0], [np.nan, 1.0, 0.0], [0.0, 2.0, 0.0]]),
           np.array([[0.5, 0.5, 0.5]] * 4)]
    stage = Usd.Stage.CreateNew(str(tmp_path / "bad.usda"))
    c = UsdGeom.BasisCurves.Define(stage, "/Groom")
    c.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(np.concatenate(curves + bad).astype(np.float32)))
    c.CreateCurveVertexCountsAttr(Vt.IntArray([len(x) for x in curves + bad]))
    stage.GetRootLayer().Save()
    out = tmp_path / "out.glb"
    assert cli_main(["guides", str(tmp_path / "bad.usda"), "-o", str(out), "--guides", "10", "--format",
                     "json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["strands"] == 60
    assert info["skipped"] == {"fewer than 2 vertices": 1, "non-finite points": 1, "zero length": 1}
    data = out.read_bytes()
    assert b"NaN" not in data and np.isfinite(hair_from_glb(out)["children"]["positions"]).all()
    assert cli_main(["guides", str(tmp_path / "bad.usda"), "-o", str(out), "--guides", "10", "--bad-curves",
                     "error"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "bad.usda" in err and "curve 60" in err and "fewer than 2" in err


@pytest.mark.parametrize("case", ["counts_past_end", "offset_past_end", "truncated", "no_lines", "broken_usd",
                                  "usd_counts", "usd_outside"])
def test_bad_files_one_line_exit_2(tmp_path, capsys, case):
    if case == "no_lines":
        path = tmp_path / "tri.gltf"
        path.write_text(json.dumps({"asset": {"version": "2.0"}}))
    elif case == "broken_usd":
        path = tmp_path / "broken.usda"
        path.write_text("#usda 1.0\n( garbage\n")
    elif case == "usd_outside":  # a sublayer outside the groom's folder is refused
        (tmp_path / "outside.usda").write_text('#usda 1.0\ndef BasisCurves "c" {\n    int[] curveVertexCounts = [2]\n'
                                                '    point3f[] points = [(0, 0, 0), (0, 1, 0)]\n}\n')
        (tmp_path / "inner").mkdir()
        path = tmp_path / "inner" / "groom.usda"
        path.write_text('#usda 1.0\n(\n    subLayers = [@../outside.usda@]\n)\n')
    elif case == "usd_counts":  # curveVertexCounts that need more points than there are
        path = tmp_path / "counts.usda"
        path.write_text('#usda 1.0\ndef BasisCurves "c" {\n    int[] curveVertexCounts = [3, 5]\n'
                        '    point3f[] points = [(0, 0, 0), (0, 1, 0), (0, 2, 0)]\n}\n')
    else:
        head = bytearray(struct.pack("<f7I32I", 4.0, 2, 4, 160, 0, 0, 0, 0, *([0] * 32)))
        body = np.zeros((2, 4, 4), "<f4").tobytes()
        if case == "counts_past_end":
            struct.pack_into("<I", head, 4, 1_000_000)  # header says a million strands
        if case == "offset_past_end":
            struct.pack_into("<I", head, 24, 10_000)  # thickness block offset beyond the file
        data = bytes(head) + (body if case != "truncated" else body[:40])
        path = tmp_path / "bad.tfx"
        path.write_bytes(data)
    assert cli_main(["guides", str(path), "-o", str(tmp_path / "o.glb")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and path.name in err and "Traceback" not in err
    assert not (tmp_path / "o.glb").exists()


def test_same_seed_same_bytes(groom, tmp_path):
    curves, widths = make_groom(300, seed=9)
    src = tmp_path / "g.usda"
    write_usd(src, curves, widths)
    outs = []
    for k in range(2):
        out = tmp_path / f"o{k}.glb"
        assert cli_main(["guides", str(src), "-o", str(out), "--guides", "20", "--seed", "4", "-q"]) == 0
        outs.append(out.read_bytes())
    assert outs[0] == outs[1]


@pytest.mark.parametrize("offset", [(0.0, 0.0, 0.0), (0.0, 2.0, -1.0)])
def test_scalp_binding(tmp_path, offset):
    """Roots bound to a sphere scalp (an OBJ, or a GLB whose node translates the sphere by ``offset``, the groom
    translated alike): rootBinding rebuilds every root from the scalp's own triangles, the roots lie on the sphere
    and no strand vertex is inside it; the hair node hangs under the scalp's node."""
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
    offset = np.asarray(offset)
    if offset.any():
        scalp = tmp_path / "scalp.glb"
        scene = trimesh.Scene()
        scene.add_geometry(sphere, node_name="head", transform=trimesh.transformations.translation_matrix(offset))
        scene.export(scalp)
    else:
        scalp = tmp_path / "scalp.obj"
        sphere.export(scalp)
    curves, widths = make_groom(200, seed=11)
    curves = [c * 1.02 + offset for c in curves]  # roots slightly off the surface: binding snaps them
    src = tmp_path / "g.usda"
    write_usd(src, curves, widths)
    out = tmp_path / "bound.glb"
    assert cli_main(["guides", str(src), "-o", str(out), "--guides", "20", "--scalp", str(scalp), "-q"]) == 0
    report = validate_file(out, khronos=False)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    gltf, acc = read_glb(out)
    hair_mesh = next(i for i, m in enumerate(gltf["meshes"]) if m.get("name") == "hair")
    mesh = gltf["meshes"][hair_mesh]
    ext = mesh["primitives"][1]["extensions"]["BAKER_hair"]
    binding = ext["rootBinding"]
    s = ext["strandCount"]
    children = acc(mesh["primitives"][1]["attributes"]["POSITION"]).reshape(s, -1, 3).astype(np.float64)
    emitter = gltf["meshes"][binding["mesh"]]["primitives"]
    prim_ids, tris, bary = acc(binding["primitives"]), acc(binding["triangles"]), acc(binding["barycentrics"])
    assert (prim_ids == 0).all()
    prim = emitter[0]
    positions = acc(prim["attributes"]["POSITION"]).astype(np.float64)
    faces = acc(prim["indices"]).reshape(-1, 3).astype(np.int64)
    roots = np.einsum("sk,skd->sd", bary.astype(np.float64), positions[faces[tris]])
    assert np.abs(roots - children[:, 0]).max() < 1e-5
    # the hair node is a child of the node drawing the scalp mesh: strands are in the scalp mesh's space
    parent = next(n for n in gltf["nodes"] if n.get("mesh") == binding["mesh"])
    assert any(gltf["nodes"][c].get("mesh") == hair_mesh for c in parent.get("children", []))
    translation = parent["matrix"][12:15] if "matrix" in parent else parent.get("translation", [0, 0, 0])
    assert np.allclose(translation, offset)
    # roots on the surface (a mesh of the unit sphere: within its chord error), strands outside it
    assert np.abs(np.linalg.norm(children[:, 0], axis=1) - 1.0).max() < 0.01
    inside = sphere.contains(children[:, 1:].reshape(-1, 3))
    assert not inside.any()


def test_inspect_lists_a_groom(baked, capsys):
    """`baker inspect` on a `baker guides` output (lines only): exit 0, its LINES primitives with the strand counts
    and BAKER_hair data this test reads from the GLB's own JSON and BIN chunk."""
    path = baked[".glb"]
    gltf, accessor = read_glb(path)
    assert cli_main(["inspect", str(path), "--format", "json"]) == 0
    info = json.loads(capsys.readouterr().out)
    rows = {(r["mesh"], r["primitive"]): r for r in info["meshes"]}
    hair_prims = [(m, p, prim) for m, mesh in enumerate(gltf["meshes"]) for p, prim in enumerate(mesh["primitives"])
                  if "BAKER_hair" in prim.get("extensions", {})]
    assert {prim["extensions"]["BAKER_hair"]["strandSet"] for _, _, prim in hair_prims} == {"guides", "children"}
    for m, p, prim in hair_prims:
        ext, row = prim["extensions"]["BAKER_hair"], rows[(m, p)]
        s, v = ext["strandCount"], ext["verticesPerStrand"]
        assert row["mode"] == 1 and row["modeName"] == "LINES" and row["triangles"] == 0
        assert row["vertices"] == gltf["accessors"][prim["attributes"]["POSITION"]]["count"] == s * v
        assert row["strands"] == s and row["lines"] == len(accessor(prim["indices"])) // 2 == s * (v - 1)
        summary = row["extensions"]["BAKER_hair"]
        assert summary["strandSet"] == ext["strandSet"] and summary["strands"] == s
        assert summary["verticesPerStrand"] == v
        assert summary["rootWidth"] == pytest.approx(ext["rootWidth"]) and summary["tipWidth"] == pytest.approx(
            ext["tipWidth"])
        assert summary.get("lodStrands", []) == [lod["strandCount"] for lod in ext.get("lods", [])]
        assert summary.get("guidesPrimitive") == ext.get("guides", {}).get("primitive")
        strands = accessor(prim["attributes"]["POSITION"]).astype(np.float64).reshape(s, v, 3)
        assert summary["meanLength"] == pytest.approx(polyline_length(strands).mean(), rel=1e-6)
    assert cli_main(["inspect", str(path)]) == 0
    text = capsys.readouterr().out
    assert "LINES" in text and "BAKER_hair" in text and "strandSet guides" in text and f"strands {N}" in text
