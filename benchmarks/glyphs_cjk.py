"""Large charsets: the 3,500 common Chinese characters from Noto Sans CJK SC, MSDF at 32 px/em, baker vs msdfgen.

    python benchmarks/glyphs_cjk.py [--count 3500] [--size 32] [--range 4] [--rounds 3] [--score 120]

Charset: level 1 of the 2013 Table of General Standard Chinese Characters (benchmarks/data/tgh2013_level1.txt, from
Unicode's Unihan kTGH field). Font: Debian fonts-noto-cjk's NotoSansCJK-Regular.ttc, face 2 (SC).

Rows, interleaved (baker, msdfgen, baker, msdfgen, ...: the machine is shared, so each round's ratio is reported and
the median ratio is the figure), best of --rounds:
- ``baker glyphs`` end to end: the command a user runs (process start, font reading, baking, PNG + JSON written), in
  a subprocess; peak RSS of that process;
- baker ``bake_atlas`` on 2 numba threads (outline preparation, edge colouring, distance kernel, sign and error
  correction, packing; font reading excluded); peak traced memory (tracemalloc, numpy arrays included) of a separate
  untimed run;
- msdfgen (npm ``@circuitly/msdfgen``, native libmsdfgen): ``generateMSDF`` per glyph (normalize, orientContours,
  edgeColoringSimple, generateMSDF with its error correction) in 2 node processes running at once on half the glyphs
  each (msdfgen on 2 threads), timed inside node (no process start, no JSON parsing): the slower half is the time.
  Same boxes, scale, range and colouring threshold as baker; RSS of the node processes as they finish.

Atlas efficiency: total glyph box area (each box = bounds + range/2, what the field needs) / atlas area.
Quality: mean coverage error (benchmarks/glyphs.py's score: 8x magnified median vs exact outline) of both on
--score glyphs spread over the charset.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baker.techniques.glyphs.kernel import bake_atlas  # noqa: E402
from baker.techniques.glyphs.options import GlyphOptions  # noqa: E402
from baker.techniques.glyphs.outline import load_fonts  # noqa: E402
from glyphs import NODE_MODULES, msdfgen_shape, score  # noqa: E402
import glyphs as glyph_bench  # noqa: E402

FONT = Path("/usr/share/fonts/opentype/noto/NotoSansCJK-Regular.ttc")
FACE = 2  # Noto Sans CJK SC
CHARSET = ROOT / "benchmarks" / "data" / "tgh2013_level1.txt"

NODE_SCRIPT = r"""
const fs = require('fs');
const msdfgen = require(process.argv[3] + '/@circuitly/msdfgen');
const jobs = JSON.parse(fs.readFileSync(process.argv[2], 'utf8'));
const t0 = process.hrtime.bigint();
const out = jobs.glyphs.map(g => msdfgen.generateMSDF(g.shape, g.options));
const t = Number(process.hrtime.bigint() - t0) / 1e9;
fs.writeFileSync(process.argv[2] + '.bin', Buffer.concat(out));
console.log(JSON.stringify({seconds: t, rss: process.memoryUsage().rss}));
"""


def charset(count: int) -> list:
    cps = [int(line[2:], 16) for line in CHARSET.read_text("utf-8").splitlines() if line.startswith("U+")]
    return cps[:count]


def run_msdfgen(jobs: list, workdir: Path) -> tuple[float, int, list]:
    """Two node processes at once, half the glyphs each: (slower half's seconds, peak RSS bytes, blocks)."""
    script = workdir / "run.js"
    script.write_text(NODE_SCRIPT)
    halves = [jobs[: len(jobs) // 2], jobs[len(jobs) // 2:]]
    procs = []
    for k, half in enumerate(halves):
        path = workdir / f"jobs{k}.json"
        path.write_text(json.dumps({"glyphs": half}))
        procs.append((path, subprocess.Popen(["node", str(script), str(path), str(NODE_MODULES)],
                                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)))
    seconds, rss, blocks = 0.0, 0, []
    for (path, proc), half in zip(procs, halves):
        out, err = proc.communicate(timeout=1800)
        if proc.returncode != 0:
            raise RuntimeError(f"msdfgen failed: {err.strip()[:300]}")
        report = json.loads(out)
        seconds, rss = max(seconds, report["seconds"]), max(rss, report["rss"])
        raw = np.frombuffer(Path(str(path) + ".bin").read_bytes(), np.uint8)
        offset = 0
        for job in half:
            w, h = job["options"]["width"], job["options"]["height"]
            blocks.append(raw[offset: offset + w * h * 3].reshape(h, w, 3)[::-1].astype(np.float64) / 255.0)
            offset += w * h * 3
    return seconds, rss, blocks


def run_cli(chars_file: Path, out: Path, size: float, rng: float) -> tuple[float, int]:
    """``baker glyphs`` in a subprocess: (wall seconds, peak RSS bytes of that child)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), NUMBA_NUM_THREADS="2")
    cmd = [sys.executable, "-m", "baker.cli", "glyphs", f"{FONT}#{FACE}", "--charset", f"file:{chars_file}",
           "--size", str(size), "--range", str(rng), "-o", str(out), "-q"]
    # the peak RSS comes from the child's own VmHWM (its address space after exec), read as it exits: the kernel's
    # ru_maxrss of a child spawned from this (large) process counts this process' pages until the exec
    hwm = out.with_name("vmhwm.txt")
    probe = ("import atexit, runpy, sys\n"
             "def hwm():\n"
             "    line = next(l for l in open('/proc/self/status') if l.startswith('VmHWM'))\n"
             f"    open({str(hwm)!r}, 'w').write(line.split()[1])\n"
             "atexit.register(hwm)\n"
             "sys.argv = ['baker'] + sys.argv[1:]\n"
             "runpy.run_module('baker.cli', run_name='__main__')\n")
    t = time.perf_counter()
    subprocess.run([sys.executable, "-c", probe] + cmd[3:], check=True, env=env)
    seconds = time.perf_counter() - t
    return seconds, int(hwm.read_text()) * 1024


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=3500)
    ap.add_argument("--size", type=float, default=32.0)
    ap.add_argument("--range", type=float, default=4.0)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--score", type=int, default=120, help="glyphs scored for quality (spread over the charset)")
    args = ap.parse_args(argv)
    if not FONT.is_file():
        print(f"font not found: {FONT} (apt install fonts-noto-cjk)", file=sys.stderr)
        return 2
    if shutil.which("node") is None or not (NODE_MODULES / "@circuitly" / "msdfgen" / "package.json").is_file():
        print(f"msdfgen not installed in {NODE_MODULES} (scripts/install-node-tools)", file=sys.stderr)
        return 2
    import numba

    numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
    glyph_bench.TIE = args.range / 255.0
    cps = charset(args.count)
    t = time.perf_counter()
    font = load_fonts([(str(FONT), FACE)], cps)
    t_read = time.perf_counter() - t
    assert not font.missing, f"{len(font.missing)} characters missing from the font"
    options = GlyphOptions(type="msdf", size=args.size, range=args.range)
    bake_atlas(load_fonts([(str(FONT), FACE)], cps[:20]), options)  # compile the kernels (numba cache)

    with tempfile.TemporaryDirectory() as d:
        work = Path(d)
        chars_file = work / "chars.txt"
        chars_file.write_text("".join(map(chr, cps)), "utf-8")
        jobs = None
        rounds = []
        for r in range(args.rounds):
            t = time.perf_counter()
            atlas = bake_atlas(font, options)
            t_kernel = time.perf_counter() - t
            if jobs is None:
                scale = args.size / font.metrics.units_per_em
                drawn = [(g, s) for g, s in zip(atlas.glyphs, font.glyphs) if g.atlas is not None]
                jobs = []
                for g, s in drawn:
                    l, b, rr, tt = g.atlas
                    left, bottom = g.plane[0] * args.size, g.plane[1] * args.size
                    jobs.append({"shape": msdfgen_shape(s.shape),
                                 "options": {"scale": scale, "range": args.range / scale,
                                             "translate": {"x": -left / scale, "y": -bottom / scale},
                                             "width": int(rr - l), "height": int(tt - b)}})
            t_msdf, rss_msdf, blocks = run_msdfgen(jobs, work)
            t_cli, rss_cli = run_cli(chars_file, work / "atlas", args.size, args.range)
            rounds.append((t_cli, t_kernel, t_msdf))
            print(f"round {r + 1}: baker glyphs {t_cli:.2f} s, bake_atlas {t_kernel:.2f} s, msdfgen (2 processes) "
                  f"{t_msdf:.2f} s: msdfgen/bake_atlas {t_msdf / t_kernel:.2f}, msdfgen/baker glyphs "
                  f"{t_msdf / t_cli:.2f}", file=sys.stderr)

    tracemalloc.start()  # peak memory in a separate, untimed run (tracing slows allocation)
    bake_atlas(font, options)
    kernel_peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    n = len(jobs)
    box_area = sum((g.atlas[2] - g.atlas[0]) * (g.atlas[3] - g.atlas[1]) for g, _ in drawn)
    efficiency = box_area / (atlas.width * atlas.height)
    pick = np.linspace(0, n - 1, min(args.score, n)).round().astype(int)
    items = [(drawn[k][0].codepoint, drawn[k][1].shape, scale, drawn[k][0].plane[0] * args.size,
              drawn[k][0].plane[1] * args.size) for k in pick]

    def block(g):
        l, b, rr, tt = (int(v) for v in g.atlas)
        return atlas.image[atlas.height - tt: atlas.height - b, l:rr].astype(np.float64) / 255.0

    baker_q = score([block(drawn[k][0]) for k in pick], items)
    msdf_q = score([blocks[k] for k in pick], items)
    best = [min(x[i] for x in rounds) for i in range(3)]
    ratio_kernel = statistics.median(m / k for _, k, m in rounds)
    ratio_cli = statistics.median(m / c for c, _, m in rounds)
    print(f"font: {FONT.name} face {FACE} ({font.family}), {n} glyphs (TGH 2013 level 1, first {args.count}), "
          f"{args.size:g} px/em, range {args.range:g} px, msdf; {os.cpu_count()} cores (shared); {args.rounds} "
          f"interleaved rounds, best of each; font read {t_read:.2f} s (outside bake_atlas)")
    print()
    print("| implementation | time (s) | glyphs/s | peak memory | mean error | max error |")
    print("|---|---:|---:|---:|---:|---:|")
    print(f"| `baker glyphs` end to end (2 threads) | {best[0]:.2f} | {n / best[0]:.0f} | {rss_cli / 2**20:.0f} MiB RSS "
          f"| {baker_q['mean'] * 100:.4f}% | {baker_q['max'] * 100:.3f}% |")
    print(f"| baker `bake_atlas` (numba, 2 threads) | {best[1]:.2f} | {n / best[1]:.0f} | {kernel_peak / 2**20:.0f} "
          f"MiB traced | same | same |")
    print(f"| msdfgen (2 node processes, native) | {best[2]:.2f} | {n / best[2]:.0f} | {rss_msdf / 2**20:.0f} MiB "
          f"RSS each | {msdf_q['mean'] * 100:.4f}% | {msdf_q['max'] * 100:.3f}% |")
    print()
    print(f"median over rounds: bake_atlas {ratio_kernel:.2f}x msdfgen's glyphs/s, `baker glyphs` end to end "
          f"{ratio_cli:.2f}x; atlas {atlas.width} x {atlas.height}, efficiency {efficiency * 100:.1f}% (glyph box "
          f"area / atlas area); quality on {len(pick)} glyphs")
    return 0


if __name__ == "__main__":
    sys.exit(main())
