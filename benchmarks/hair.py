"""Child strands per second: baker vs a vectorized-numpy twin vs a naive per-strand loop, same run.

    python benchmarks/hair.py [--mesh PATH] [--guides 2000] [--children 50] [--repeat 3]

Guides are grown once on the mesh (default Spot, examples/spot); then ``guides x children`` (default 100 000)
children are interpolated. Rows (best of --repeat, wall clock):
- baker, full: roots sampled on the surface, 3-nearest-guide barycentric weights, shape transfer, follow offsets,
  clumping, follow-the-leader length restoration (numba, 2 threads), then collision against the emitter (Embree ray
  parity + closest-point slide) and the nearest-first sort, i.e. everything ``generate_hair`` does for children;
- baker, no collision: the same without the collision pass and sort (the interpolation kernel alone);
- numpy twin: the same interpolation with follow-the-leader written as a numpy loop over vertices, vectorized over
  strands (what one writes without numba);
- naive per strand: a Python loop per child doing the same math with small numpy arrays (the straightforward port
  of a per-strand DCC script), timed on a subset and reported per strand.
All rows produce the same strands (checked: max difference printed).
End to end: ``baker hair MESH -o OUT.glb`` with the same guides, children and shape options (the command a user
runs: load, guides grown, children, collision, sort, GLB written; best of --repeat, process start to file written),
next to the full kernel row, with its peak RSS and bytes per child strand.
"""
from __future__ import annotations

import argparse
import math
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baker import readers  # noqa: E402
from baker.geometry.frames import orthonormal_basis  # noqa: E402
from baker.techniques.hair import kernel as hair  # noqa: E402
from baker.techniques.hair.grow import emitter_from_asset  # noqa: E402
from common import baker_cli, best_of, run_command  # noqa: E402

DEFAULT_MESH = ROOT / "examples" / "spot" / "spot.obj"


def numpy_ftl(pos, rest):
    for k in range(1, pos.shape[1]):
        d = pos[:, k] - pos[:, k - 1]
        pos[:, k] = pos[:, k - 1] + d * (rest / np.maximum(np.linalg.norm(d, axis=1), 1e-30))[:, None]


def naive_children(guides, guide_rest, roots, croots, cnormals, spacing, spread, clump, phi, radius, scale):
    """One child at a time: nearest 3 guides by brute force, barycentric weights, shape, offset, clump, FTL."""
    out = np.empty((len(croots), guides.shape[1], 3))
    t = np.linspace(0.0, 1.0, guides.shape[1])
    for c in range(len(croots)):
        p = croots[c]
        d2 = ((roots - p) ** 2).sum(axis=1)
        ids = np.argsort(d2, kind="stable")[:3]
        w = hair.barycentric_weights(p[None], roots[ids[0]][None], roots[ids[1]][None], roots[ids[2]][None])[0]
        shape = sum(w[i] * (guides[ids[i]] - guides[ids[i], 0]) for i in range(3))
        tangent, bitangent = orthonormal_basis(cnormals[c][None])
        offset = (math.cos(phi[c]) * tangent[0] + math.sin(phi[c]) * bitangent[0]) * radius[c]
        strand = p + shape + t[:, None] * offset
        if clump > 0:
            dom = ids[np.argmax(w)]
            target = p + (guides[dom] - guides[dom, 0]) + (guides[dom, 0] - p) * t[:, None]
            strand = strand + (clump * t)[:, None] * (target - strand)
        rest = float(np.dot(w, guide_rest[ids])) * scale[c]
        for k in range(1, len(strand)):
            d = strand[k] - strand[k - 1]
            strand[k] = strand[k - 1] + d * rest / max(np.linalg.norm(d), 1e-30)
        out[c] = strand
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh", default=str(DEFAULT_MESH))
    ap.add_argument("--guides", type=int, default=2000)
    ap.add_argument("--children", type=int, default=50, help="children per guide")
    ap.add_argument("--naive", type=int, default=2000, help="children timed for the naive per-strand row")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    opts = hair.HairOptions(guides=args.guides, children=0, length=0.3, clump=0.3, spread=0.5)
    asset = readers.read(args.mesh)
    emitter = emitter_from_asset(asset, opts)
    result = hair.generate_hair(emitter, opts, seed=0)
    guides, rest = result.guides.positions, result.guides.rest_lengths
    roots = guides[:, 0]
    n = args.guides * args.children
    rng = np.random.default_rng(1)
    ctri, cbary, _ = hair.masked_surface_points(emitter, n, rng)
    f, v = emitter.faces, emitter.vertices
    croots = np.einsum("sk,skd->sd", cbary, v[f[ctri]])
    cnormals = hair._unit(hair.corner_interpolate(emitter.normals[f], ctri, cbary))
    inside = hair.InsideTest(v, emitter.colliders)
    surface = hair.SurfaceLookup(v, emitter.colliders)
    margin = 1e-3 * opts.length

    def interpolate(seed=2):
        return hair.interpolate_children(guides, rest, roots, croots, cnormals, result.spacing, spread=opts.spread,
                                         clump=opts.clump, thinning=0.0, rng=np.random.default_rng(seed))

    def full():
        pos, crest, ids, w = interpolate()
        hair.push_out(pos, crest, inside, surface, margin, root_normals=cnormals)
        order = hair.depth_order(pos, surface)
        return pos[order]

    interpolate()  # compile
    rows = []
    t_full, _ = best_of(args.repeat, full)
    rows.append(("baker, full (interpolation + collision + sort)", t_full, n))
    t_interp, (pos, crest, ids, w) = best_of(args.repeat, interpolate)
    rows.append(("baker, no collision (interpolation + follow-the-leader)", t_interp, n))

    # the same random draws as interpolate_children (phi, radius; no thinning draws consumed when thinning = 0)
    r2 = np.random.default_rng(2)
    phi = r2.random(n) * 2 * math.pi
    radius = np.sqrt(r2.random(n)) * opts.spread * result.spacing

    def numpy_twin():
        from scipy.spatial import cKDTree

        _, ids2 = cKDTree(roots).query(croots, k=3)
        w2 = hair.barycentric_weights(croots, roots[ids2[:, 0]], roots[ids2[:, 1]], roots[ids2[:, 2]])
        shapes = guides - guides[:, :1]
        t = np.linspace(0.0, 1.0, guides.shape[1])
        p = croots[:, None] + np.einsum("ck,ckvd->cvd", w2, shapes[ids2])
        tangent, bitangent = orthonormal_basis(cnormals)
        offset = (np.cos(phi)[:, None] * tangent + np.sin(phi)[:, None] * bitangent) * radius[:, None]
        p += t[None, :, None] * offset[:, None, :]
        dom = ids2[np.arange(n), w2.argmax(axis=1)]
        target = croots[:, None] + shapes[dom] + (guides[dom, :1] - croots[:, None]) * t[None, :, None]
        p += (opts.clump * t)[None, :, None] * (target - p)
        numpy_ftl(p, np.einsum("ck,ck->c", w2, rest[ids2]))
        return p

    t_numpy, p_numpy = best_of(args.repeat, numpy_twin)
    rows.append(("numpy twin (vectorized over strands, no numba), no collision", t_numpy, n))
    m = min(args.naive, n)
    t_naive, p_naive = best_of(1, lambda: naive_children(guides, rest, roots, croots[:m], cnormals[:m],
                                                         result.spacing, opts.spread, opts.clump, phi[:m],
                                                         radius[:m], np.ones(m)))
    rows.append((f"naive per-strand Python loop ({m} strands timed), no collision", t_naive, m))

    print(f"mesh: {Path(args.mesh).name}, {len(f)} triangles; {args.guides} guides x {args.children} = {n} children, "
          f"{guides.shape[1]} vertices each; 2 cores; best of {args.repeat}\n")
    print("| implementation | time (s) | strands/s | baker (no collision) speed-up |")
    print("|---|---:|---:|---:|")
    base = n / t_interp
    for name, t, count in rows:
        rate = count / t
        print(f"| {name} | {t:.3f} | {rate:,.0f} | {base / rate:.2f}x |")
    print(f"\nmax |baker - numpy twin| = {np.abs(pos - p_numpy).max():.2e}, "
          f"max |baker - naive| = {np.abs(pos[:m] - p_naive).max():.2e} (mesh units)")

    runs = []
    for _ in range(args.repeat):
        with tempfile.TemporaryDirectory() as out:
            runs.append(run_command(baker_cli("hair", args.mesh, "-o", Path(out) / "hair.glb", "-q", "--seed", "0",
                                              "--guides", args.guides, "--children", args.children,
                                              "--length", opts.length, "--clump", opts.clump,
                                              "--spread", opts.spread)))
    best = min(runs, key=lambda r: r["wall"])
    peak = max(r["peak"] for r in runs)
    print("\n| end to end | time (s) | strands/s | time vs kernel (baker, full) | peak RSS (MB) | bytes per child |")
    print("|---|---:|---:|---:|---:|---:|")
    print(f"| `baker hair {Path(args.mesh).name} -o hair.glb --guides {args.guides} --children {args.children}` | "
          f"{best['wall']:.3f} | {n / best['wall']:,.0f} | {best['wall'] / t_full:.2f}x | {peak / 1e6:.0f} | "
          f"{peak / n:,.0f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
