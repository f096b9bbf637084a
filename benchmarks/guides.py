"""Groom -> guides: `baker guides` vs a naive baseline and k-means on flattened strands, same run, same groom.

    python benchmarks/guides.py [--strands 50000] [--guides 500 2000] [--mesh PATH] [--keep DIR]

The groom is made here and written as USD by pxr directly (not by baker): ``--strands`` roots on the scalp of a
head-like mesh (Suzanne from ../shared/assets, the faces looking up or back), grouped in clumps whose tips pull
together, curls per clump (some straight, some tight), lengths varying over the scalp and per strand, 8..64
vertices per curve, per-vertex widths, split over 4 BasisCurves prims (one with a transform).

Rows per N (all errors: per-vertex distance between a strand resampled to 32 vertices and its reconstruction
``root + sum w_i (guide_i(t) - guideRoot_i)``, relative to the strand's length; RMS over all vertices and max):
- baker guides: the command a user runs (subprocess, wall clock, peak RSS), errors rebuilt from the written .glb;
  the solver time alone is printed from its ``--format json`` summary;
- naive: N random strands as guides, each strand weighted by barycentric coordinates of its 3 nearest guide roots;
- k-means: scikit-learn ``KMeans`` (k-means++, one init) on the flattened 32 x 3 strand coordinates; the cluster
  centroids are the guides and each strand follows its own cluster's centroid (weight 1).
"""
from __future__ import annotations

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baker.techniques.hair.guide_solver import reconstruct, reconstruction_error, resample_strands  # noqa: E402

DEFAULT_MESH = ROOT.parent / "shared" / "assets" / "meshes" / "suzanne.obj"
if not DEFAULT_MESH.is_file():
    DEFAULT_MESH = Path("/work/shared/assets/meshes/suzanne.obj")


def make_groom(mesh_path: Path, strands: int, seed: int = 7):
    """(points (P, 3), counts (S,), widths (P,)) of a dense clumped, curly groom on the mesh's scalp."""
    import trimesh
    from scipy.spatial import cKDTree

    rng = np.random.default_rng(seed)
    mesh = trimesh.load(mesh_path, force="mesh")
    v, f = np.asarray(mesh.vertices), np.asarray(mesh.faces)
    size = float(np.linalg.norm(v.max(0) - v.min(0)))
    normals = mesh.face_normals
    scalp = np.flatnonzero(normals @ (np.array([0.0, 1.0, -0.6]) / math.hypot(1.0, 0.6)) > 0.25)
    area = mesh.area_faces[scalp]
    tri = scalp[rng.choice(len(scalp), strands, p=area / area.sum())]
    r = rng.random((strands, 2))
    flip = r.sum(axis=1) > 1
    r[flip] = 1 - r[flip]
    bary = np.column_stack([1 - r.sum(axis=1), r])
    roots = np.einsum("sk,skd->sd", bary, v[f[tri]])
    normal = normals[tri]
    # clumps: centres among the roots, every strand joins its nearest centre
    n_clumps = max(strands // 80, 1)
    centre = rng.choice(strands, n_clumps, replace=False)
    _, clump = cKDTree(roots[centre]).query(roots)
    curl_amp = np.where(rng.random(n_clumps) < 0.4, 0.0, rng.uniform(0.02, 0.09, n_clumps))
    curl_freq = rng.uniform(2.0, 7.0, n_clumps)
    curl_phase = rng.uniform(0, 2 * math.pi, n_clumps)
    clumpiness = rng.uniform(0.3, 0.9, n_clumps)
    # length: a smooth field over the scalp times a per-strand factor
    field = 0.75 + 0.25 * np.sin(3.0 * roots[:, 0] / size * 2 * math.pi) * np.cos(2.0 * roots[:, 2] / size * 2 * math.pi)
    lengths = 0.55 * size * field * rng.uniform(0.75, 1.1, strands)
    counts = rng.integers(8, 65, strands)
    s_of = np.repeat(np.arange(strands), counts)
    t = np.concatenate([np.linspace(0.0, 1.0, c) for c in counts.tolist()])
    down = np.array([0.0, -1.0, 0.0])

    def path(root, n, length, tt):  # out along the normal, then falling under gravity
        return root + length[:, None] * (n * (0.3 * tt)[:, None] + down * (0.85 * tt * tt)[:, None]
                                         + np.array([0.0, 0.0, -0.25]) * (tt * tt * tt)[:, None])

    c = clump[s_of]
    own = path(roots[s_of], normal[s_of], lengths[s_of], t)
    lead = path(roots[centre][c], normal[centre][c], lengths[s_of], t)
    pull = (clumpiness[c] * t ** 1.5)[:, None]
    p = own + (lead - own) * pull
    e1 = np.cross(normal[s_of], down)
    e1 /= np.maximum(np.linalg.norm(e1, axis=1, keepdims=True), 1e-9)
    e2 = np.cross(e1, down)
    phase = 2 * math.pi * curl_freq[c] * t + curl_phase[c] + 0.3 * rng.standard_normal(strands)[s_of]
    amp = (curl_amp[c] * lengths[s_of] * np.minimum(t / 0.2, 1.0))[:, None]
    p += amp * (np.cos(phase)[:, None] * e1 + np.sin(phase)[:, None] * e2)
    # per-strand wobble (low frequency: strands stay smooth curves), growing towards the tip
    wobble_f, wobble_p = rng.uniform(1.0, 3.0, (2, strands)), rng.uniform(0, 2 * math.pi, (2, strands))
    for k, e in enumerate((e1, e2)):
        p += (0.015 * size * t * np.sin(2 * math.pi * wobble_f[k][s_of] * t + wobble_p[k][s_of]))[:, None] * e
    widths = 0.004 * size * (1.0 - 0.85 * t) * rng.uniform(0.6, 1.0, strands)[s_of]
    return p, counts, widths


def write_usd_groom(path: Path, points, counts, widths, parts: int = 4) -> None:
    """Write with pxr directly: ``parts`` BasisCurves prims; the last has a translation the reader must honour."""
    from pxr import Gf, Usd, UsdGeom, Vt

    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    starts = np.concatenate([[0], np.cumsum(counts)])
    split = np.linspace(0, len(counts), parts + 1).astype(int)
    for k in range(parts):
        a, b = split[k], split[k + 1]
        lo, hi = starts[a], starts[b]
        curves = UsdGeom.BasisCurves.Define(stage, f"/Groom/part{k}")
        curves.CreateTypeAttr(UsdGeom.Tokens.linear)
        pts = points[lo:hi]
        if k == parts - 1:
            offset = np.array([0.0, 0.5, 0.0])
            curves.AddTranslateOp().Set(Gf.Vec3d(*offset))
            pts = pts - offset
        curves.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(pts.astype(np.float32)))
        curves.CreateCurveVertexCountsAttr(Vt.IntArray([int(x) for x in counts[a:b]]))
        curves.CreateWidthsAttr(Vt.FloatArray.FromNumpy(widths[lo:hi].astype(np.float32)))
        curves.SetWidthsInterpolation(UsdGeom.Tokens.vertex)
    stage.GetRootLayer().Save()


def read_glb_children(path: Path):
    """(guides (N, V, 3), children (S, V, 3), ids, weights) from a written .glb: JSON + BIN chunk, no baker."""
    import struct

    data = path.read_bytes()
    _, _, _ = struct.unpack_from("<4sII", data, 0)
    json_len, _ = struct.unpack_from("<I4s", data, 12)
    gltf = json.loads(data[20:20 + json_len])
    bin_start = 20 + json_len + 8
    blob = data[bin_start:]
    sizes = {"SCALAR": 1, "VEC3": 3}
    types = {5126: "<f4", 5125: "<u4"}

    def accessor(i):
        a = gltf["accessors"][i]
        view = gltf["bufferViews"][a["bufferView"]]
        n = a["count"] * sizes[a["type"]]
        arr = np.frombuffer(blob, types[a["componentType"]], n, view.get("byteOffset", 0) + a.get("byteOffset", 0))
        return arr.reshape(a["count"], -1)

    prims = gltf["meshes"][-1]["primitives"]
    out = {}
    for prim in prims:
        ext = prim["extensions"]["BAKER_hair"]
        pos = accessor(prim["attributes"]["POSITION"]).reshape(ext["strandCount"], ext["verticesPerStrand"], 3)
        out[ext["strandSet"]] = (pos, ext)
    children, ext = out["children"]
    return (out["guides"][0].astype(np.float64), children.astype(np.float64),
            accessor(ext["guides"]["ids"]).astype(np.int64), accessor(ext["guides"]["weights"]).astype(np.float64))


def naive(strands, lengths, n, rng):
    from scipy.spatial import cKDTree

    from baker.techniques.hair.kernel import barycentric_weights

    t = time.perf_counter()
    roots = strands[:, 0]
    guides = np.sort(rng.choice(len(strands), n, replace=False))
    _, ids = cKDTree(roots[guides]).query(roots, k=3)
    g = roots[guides]
    weights = barycentric_weights(roots, g[ids[:, 0]], g[ids[:, 1]], g[ids[:, 2]])
    seconds = time.perf_counter() - t
    return seconds, reconstruction_error(strands, reconstruct(strands[guides], roots, ids, weights), lengths)


def kmeans(strands, lengths, n, seed):
    from sklearn.cluster import KMeans

    t = time.perf_counter()
    flat = strands.reshape(len(strands), -1)
    km = KMeans(n_clusters=n, n_init=1, random_state=seed, max_iter=100).fit(flat)
    seconds = time.perf_counter() - t
    centroids = km.cluster_centers_.reshape(n, strands.shape[1], 3)
    ids = np.repeat(km.labels_[:, None], 3, axis=1)
    weights = np.zeros((len(strands), 3))
    weights[:, 0] = 1.0
    return seconds, reconstruction_error(strands, reconstruct(centroids, strands[:, 0], ids, weights), lengths)


def run_baker(groom: Path, out: Path, n: int):
    cmd = [sys.executable, "-c", "import sys; from baker.cli import main; sys.exit(main())", "guides", str(groom),
           "-o", str(out), "--guides", str(n), "--format", "json", "--quiet"]
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    t = time.perf_counter()
    done = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    seconds = time.perf_counter() - t
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return seconds, json.loads(done.stdout), max(peak, before) / 1024.0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--strands", type=int, default=50000)
    ap.add_argument("--guides", type=int, nargs="+", default=[500, 2000])
    ap.add_argument("--mesh", type=Path, default=DEFAULT_MESH)
    ap.add_argument("--keep", type=Path, default=None, help="folder to keep the groom and outputs in")
    ap.add_argument("--no-kmeans", action="store_true")
    args = ap.parse_args()
    folder = args.keep or Path(tempfile.mkdtemp(prefix="baker-guides-"))
    folder.mkdir(parents=True, exist_ok=True)
    points, counts, widths = make_groom(args.mesh, args.strands)
    groom = folder / "groom.usdc"
    write_usd_groom(groom, points, counts, widths)
    strands, lengths, _ = resample_strands(points, counts, 32)
    print(f"groom: {len(counts)} strands, {len(points)} points ({counts.min()}..{counts.max()} per curve), "
          f"lengths {lengths.min():.3f}..{lengths.max():.3f}, {groom.stat().st_size / 1e6:.1f} MB USD")
    print("| N | method | time (s) | RMS error | max error | RMS vs naive | peak RSS (MB) |")
    print("|---|---|---|---|---|---|---|")
    rng = np.random.default_rng(0)
    for n in args.guides:
        out = folder / f"guides_{n}.glb"
        seconds, info, peak = run_baker(groom, out, n)
        guides, children, ids, weights = read_glb_children(out)
        # relative to the length of each child as written (children are in LOD order: lengths from the file)
        child_lengths = np.linalg.norm(np.diff(children, axis=1), axis=2).sum(axis=1)
        mine = reconstruction_error(children, reconstruct(guides, children[:, 0], ids, weights), child_lengths)
        t_naive, e_naive = naive(strands, lengths, n, rng)
        rows = [("baker guides (end to end)", seconds, mine, peak),
                (f"  solver alone: {info['seconds']['solve']:.1f} s, LOD order {info['seconds']['lods']:.1f} s",
                 None, None, None),
                ("naive: random guides + barycentric 3 nearest roots", t_naive, e_naive, None)]
        if not args.no_kmeans:
            t_km, e_km = kmeans(strands, lengths, n, 0)
            rows.append(("k-means (scikit-learn) on flattened strands, centroid guides", t_km, e_km, None))
        for name, t, e, mem in rows:
            if e is None:
                print(f"| {n} | {name} | | | | | |")
                continue
            print(f"| {n} | {name} | {t:.1f} | {100 * e['rms']:.2f} % | {100 * e['max']:.1f} % | "
                  f"{e['rms'] / e_naive['rms']:.2f} | {'' if mem is None else f'{mem:.0f}'} |")
        sys.stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
