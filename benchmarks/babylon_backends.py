"""@baker/babylon on Babylon.js's two backends in one headless Chromium: the viewer's Babylon.js page on the WebGL2
Engine (?engine=babylon, the peer) and on WebGPUEngine (?engine=babylon-webgpu), both drawn by SwiftShader.

    python benchmarks/babylon_backends.py [--repeat 3] [--size 640x480] [--frames 20]

The spot baked with every bake (as tests/test_babylon_webgpu.py bakes it), every technique at its default. Per
backend, from the page (window.__bakerTimings): the asset's load, then `ready` (the materials' shaders compiled and
two frames drawn: shader compile and pipeline creation); then the mean frame time over --frames frames, each waited
for on the device (benchmarks/babylon_backends.mjs). Pages alternate between the backends, --repeat times each; the
medians are reported with the WebGPU / WebGL2 ratio (ratios are what a shared machine's run means).
"""
from __future__ import annotations

import argparse
import json
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
VIEWER = ROOT / "examples" / "viewer"
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from browser import SPOT, SPOT_PAGE_OPTIONS, serve  # noqa: E402

ENGINES = {"babylon": "WebGL2 Engine (peer)", "babylon-webgpu": "WebGPUEngine"}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--size", default="640x480")
    parser.add_argument("--frames", type=int, default=20)
    args = parser.parse_args()
    width, height = (int(x) for x in args.size.split("x"))

    import baker
    from baker import registry
    from baker.pipeline import save

    build = subprocess.run(["npm", "run", "build"], cwd=VIEWER, capture_output=True, text=True)
    if build.returncode:
        raise SystemExit(build.stderr)
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        shutil.copy(VIEWER / "index.html", root / "index.html")
        shutil.copytree(VIEWER / "dist", root / "dist")
        save(baker.bake(SPOT, bakes=tuple(registry.bakes()), options=SPOT_PAGE_OPTIONS), root / "spot_all.glb")
        server, base = serve(root)
        # every technique on (?start=all) and translucency lit from behind: the viewer itself opens on one technique
        url = f"{base}/index.html?hud=0&src=spot_all.glb&time=1.3&start=all&on=backlight"
        jobs = [{"url": f"{url}&engine={engine}", "width": width, "height": height, "frames": args.frames}
                for _ in range(args.repeat) for engine in ENGINES]
        (root / "jobs.json").write_text(json.dumps(jobs))
        run = subprocess.run(["node", str(ROOT / "benchmarks" / "babylon_backends.mjs"), str(root / "jobs.json")],
                             capture_output=True, text=True, timeout=1800)
        server.shutdown()
    if run.returncode:
        raise SystemExit(run.stderr)
    results = [json.loads(line) for line in run.stdout.splitlines() if line.startswith("{")]
    errors = [r for r in results if "error" in r]
    if errors:
        raise SystemExit(f"a page failed: {errors[0]}")
    medians = {engine: {key: statistics.median(r[key] for r in results if r["url"].endswith(f"engine={engine}"))
                        for key in ("load", "ready", "frame")} for engine in ENGINES}
    peer = medians["babylon"]
    print(f"spot, every bake, {width}x{height}, median of {args.repeat} (ms; ratio to the WebGL2 Engine)")
    print("| backend | load | ready (compile + 2 frames) | frame | ready ratio | frame ratio |")
    print("|---|---:|---:|---:|---:|---:|")
    for engine, label in ENGINES.items():
        m = medians[engine]
        print(f"| {label} | {m['load']:.0f} | {m['ready']:.0f} | {m['frame']:.1f} | "
              f"{m['ready'] / peer['ready']:.2f}x | {m['frame'] / peer['frame']:.2f}x |")


if __name__ == "__main__":
    main()
