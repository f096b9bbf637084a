"""Glyph atlases: baker vs msdfgen (npm ``@circuitly/msdfgen``, a prebuilt N-API build of libmsdfgen), same run.

    python benchmarks/glyphs.py [--font PATH] [--size 48] [--range 4] [--repeat 3] [--coloring notch|inktrap|simple|distance]

Both generate the MSDF of every printable ASCII glyph of the font at the same scale, range and box (baker's boxes:
the glyph bounds grown by range/2, on the pixel grid of the origin), with the same edge-coloring threshold (3 rad).
Rows (best of --repeat, wall clock):
- baker: ``bake_atlas`` (outline preparation, edge coloring, distance kernel, sign and error correction, packing;
  font reading excluded) with numba on 2 threads, and on 1 thread;
- msdfgen: ``generateMSDF`` per glyph inside one node process (normalize, orientContours, edgeColoringSimple,
  generateMSDF with its default error correction), timed inside node: no process start or JSON parsing.
Quality is scored by the same code for both (``baker.techniques.glyphs.quality``): each glyph's 8-bit field magnified 8x
with bilinear sampling and the median, thresholded at 0.5, vs a supersampled nonzero rasterization of the font's
outline; "ties" are wrong pixels within one 8-bit step of the outline, which the rounding of 0.5 decides.

msdfgen must be installed: ``npm install --prefix .cache/node @circuitly/msdfgen``.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baker.techniques.glyphs.options import GlyphOptions
from baker.techniques.glyphs.kernel import bake_atlas  # noqa: E402
from baker.techniques.glyphs.outline import load_font  # noqa: E402
from baker.techniques.glyphs.quality import glyph_errors  # noqa: E402
from common import best_of  # noqa: E402

DEFAULT_FONT = Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
NODE_MODULES = ROOT / ".cache" / "node" / "node_modules"

NODE_SCRIPT = r"""
const fs = require('fs');
const msdfgen = require(process.argv[3] + '/@circuitly/msdfgen');
const jobs = JSON.parse(fs.readFileSync(process.argv[2], 'utf8'));
const repeat = parseInt(process.argv[4]);
let best = Infinity, outputs = null;
for (let r = 0; r < repeat; r++) {
  const t0 = process.hrtime.bigint();
  const out = jobs.glyphs.map(g => msdfgen.generateMSDF(g.shape, g.options));
  const t = Number(process.hrtime.bigint() - t0) / 1e9;
  if (t < best) { best = t; outputs = out; }
}
fs.writeFileSync(process.argv[2] + '.bin', Buffer.concat(outputs));
console.log(JSON.stringify({seconds: best}));
"""


def msdfgen_shape(shape) -> dict:
    kinds = {1: "linear", 2: "quadratic", 3: "cubic"}
    contours = []
    for c in range(shape.contour_count):
        edges = []
        for s in range(shape.contour_start[c], shape.contour_start[c + 1]):
            d = int(shape.degree[s])
            edges.append({"type": kinds[d], "points": [{"x": float(x), "y": float(y)}
                                                        for x, y in shape.points[s, : d + 1]]})
        contours.append({"edges": edges})
    return {"contours": contours, "inverseYAxis": False}


def score(blocks: list, items: list) -> dict:
    """Per-glyph errors of standalone glyph blocks ((h, w, 3) float, row 0 at the top)."""
    errs = []
    for values, (cp, shape, scale, left, bottom) in zip(blocks, items):
        h, w = values.shape[:2]
        (e,) = glyph_errors(values, [(cp, shape, scale, (0.0, 0.0, float(w), float(h)), (left, bottom))], tie=TIE)
        errs.append(e)
    error = np.array([e.error for e in errs])
    nontie = np.array([(e.wrong - e.ties) / e.pixels for e in errs])
    worst = errs[int(error.argmax())]
    return {"mean": error.mean(), "max": error.max(), "worst": chr(worst.codepoint), "nontie": nontie.mean(),
            "errors": errs}


TIE = 0.0


def main(argv=None) -> int:
    global TIE
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--font", default=str(DEFAULT_FONT))
    ap.add_argument("--size", type=float, default=48.0)
    ap.add_argument("--range", type=float, default=4.0)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--coloring", default=GlyphOptions().coloring, choices=("notch", "inktrap", "simple", "distance"),
                    help="baker's edge coloring (msdfgen's npm build has edgeColoringSimple only)")
    args = ap.parse_args(argv)
    if not Path(args.font).is_file():
        print(f"font not found: {args.font}", file=sys.stderr)
        return 2
    TIE = args.range / 255.0
    import numba

    font = load_font(args.font, "ascii")
    options = GlyphOptions(type="msdf", size=args.size, range=args.range, coloring=args.coloring)
    bake_atlas(font, options)  # compile the kernels
    rows = []
    t2, atlas = best_of(args.repeat, lambda: bake_atlas(font, options))
    numba.set_num_threads(1)
    t1, _ = best_of(args.repeat, lambda: bake_atlas(font, options))
    numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
    t_sdf, sdf_atlas = best_of(args.repeat, lambda: bake_atlas(font, GlyphOptions(type="sdf", size=args.size,
                                                                                  range=args.range)))
    scale = args.size / font.metrics.units_per_em
    shapes = {g.codepoint: g.shape for g in font.glyphs}
    drawn = [g for g in atlas.glyphs if g.atlas is not None]
    n = len(drawn)

    def blocks_of(a):
        out = []
        for g in a.glyphs:
            if g.atlas is None:
                continue
            l, b, r, t = (int(v) for v in g.atlas)
            out.append(a.image[a.height - t: a.height - b, l:r].astype(np.float64) / 255.0)
        return out

    items = [(g.codepoint, shapes[g.codepoint], scale, g.plane[0] * args.size, g.plane[1] * args.size)
             for g in drawn]
    baker_q = score(blocks_of(atlas), items)
    sdf_q = score(blocks_of(sdf_atlas), items)
    rows.append(("baker msdf (numba, 2 threads)", t2, baker_q))
    rows.append(("baker msdf (numba, 1 thread)", t1, baker_q))
    rows.append(("baker sdf (2 threads), for reference", t_sdf, sdf_q))

    reason = None
    if shutil.which("node") is None:
        reason = "node is not on PATH"
    elif not (NODE_MODULES / "@circuitly" / "msdfgen" / "package.json").is_file():
        reason = f"@circuitly/msdfgen is not installed in {NODE_MODULES} (npm install --prefix .cache/node @circuitly/msdfgen)"
    if reason is None:
        jobs = []
        for g in drawn:
            l, b, r, t = g.atlas
            w, h = int(r - l), int(t - b)
            left, bottom = g.plane[0] * args.size, g.plane[1] * args.size
            jobs.append({"shape": msdfgen_shape(shapes[g.codepoint]),
                         "options": {"scale": scale, "range": args.range / scale,
                                     "translate": {"x": -left / scale, "y": -bottom / scale}, "width": w, "height": h}})
        with tempfile.TemporaryDirectory() as d:
            job_path = Path(d) / "jobs.json"
            job_path.write_text(json.dumps({"glyphs": jobs}))
            script = Path(d) / "run.js"
            script.write_text(NODE_SCRIPT)
            proc = subprocess.run(["node", str(script), str(job_path), str(NODE_MODULES), str(args.repeat)],
                                  capture_output=True, text=True, timeout=600)
            if proc.returncode != 0:
                reason = f"msdfgen failed: {proc.stderr.strip()[:300]}"
            else:
                seconds = json.loads(proc.stdout)["seconds"]
                raw = np.frombuffer((Path(str(job_path) + ".bin")).read_bytes(), np.uint8)
                blocks, offset = [], 0
                for job in jobs:
                    w, h = job["options"]["width"], job["options"]["height"]
                    block = raw[offset: offset + w * h * 3].reshape(h, w, 3)[::-1]  # msdfgen rows are bottom-up
                    offset += w * h * 3
                    blocks.append(block.astype(np.float64) / 255.0)
                rows.append(("msdfgen 1.x (@circuitly/msdfgen, native, 1 thread)", seconds, score(blocks, items)))

    print(f"font: {Path(args.font).name}, {n} ASCII glyphs with outlines, {args.size:g} px/em, range {args.range:g} "
          f"px; baker coloring {args.coloring}; {os.cpu_count()} cores; best of {args.repeat}")
    print()
    print("| implementation | time (s) | glyphs/s | mean error | max error (glyph) | mean error without ties |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, t, q in rows:
        print(f"| {name} | {t:.4f} | {n / t:.0f} | {q['mean'] * 100:.4f}% | {q['max'] * 100:.3f}% ({q['worst']}) | "
              f"{q['nontie'] * 100:.4f}% |")
    print()
    if reason:
        print(f"msdfgen not run: {reason}")
    else:
        m = rows[-1]
        print(f"baker vs msdfgen: {m[1] / t2:.2f}x the glyphs/s on 2 threads, {m[1] / t1:.2f}x on 1 thread; "
              f"mean error {baker_q['mean'] * 100:.4f}% vs {m[2]['mean'] * 100:.4f}%")
    return 0


if __name__ == "__main__":
    sys.exit(main())
