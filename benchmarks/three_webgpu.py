"""@baker/three per renderer and backend: shader compile (first frame) and frame time, in one headless Chromium.

    python benchmarks/three_webgpu.py [--repeat 3] [--frames 20] [--size 320x240]

The spot baked with every surface and geometry technique (tests/test_three_webgpu.py's options) on three pages of
the viewer: WebGLRenderer (?engine=three, the peer: @baker/three's onBeforeCompile / ShaderMaterial path),
WebGPURenderer on WebGPU (?engine=three-webgpu, TSL node materials with the WGSL modules) and on its WebGL2 backend
(&backend=webgl2, the same node materials with the GLSL modules), every technique on (?start=all). Per page
(examples/viewer/test/webgpu_bench.mjs): the first frame with the asset (its render call: shader generation,
program linking or pipeline creation, the submission), and the mean of --frames frames after it, each waited for on
the GPU (SwiftShader: Vulkan for WebGPU, GLES through ANGLE for WebGL; no GPU here, so the figures are CPU
rasterisation). Best of --repeat page loads; ratios against WebGLRenderer in the same run.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

import baker  # noqa: E402
from baker.pipeline import save  # noqa: E402
from browser import SPOT_PAGE_OPTIONS, SPOT, VIEWER, build_viewer, serve  # noqa: E402

PAGES = {"WebGLRenderer (GLSL, onBeforeCompile)": "", "WebGPURenderer, WebGPU (TSL + WGSL)": "&engine=three-webgpu",
         "WebGPURenderer, WebGL2 backend (TSL + GLSL)": "&engine=three-webgpu&backend=webgl2"}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--frames", type=int, default=20)
    parser.add_argument("--size", default="320x240")
    args = parser.parse_args()
    width, height = (int(x) for x in args.size.split("x"))
    with tempfile.TemporaryDirectory() as folder:
        root = Path(folder)
        build_viewer(root, ("viewer.js", "three_webgpu.js"))
        asset = baker.bake(SPOT, bakes=("thickness", "curvature", "skin", "edges", "tam", "toon", "fur", "caustics"),
                           options=SPOT_PAGE_OPTIONS)
        save(asset, root / "spot_all.glb")
        server, url = serve(root)
        try:
            # every technique on (?start=all) and translucency lit from behind: the viewer opens on one technique
            page = f"{url}/index.html?hud=0&src=spot_all.glb&time=1.3&start=all&on=backlight"
            jobs = [{"url": f"{page}{query}", "width": width, "height": height,
                     "frames": args.frames} for _ in range(args.repeat) for query in PAGES.values()]
            spec = root / "jobs.json"
            spec.write_text(json.dumps(jobs))
            done = subprocess.run(["node", str(VIEWER / "test" / "webgpu_bench.mjs"), str(spec)], cwd=VIEWER,
                                  capture_output=True, text=True, timeout=1800)
            if done.returncode != 0:
                sys.exit(f"webgpu_bench.mjs failed: {done.stderr[-2000:]}")
        finally:
            server.shutdown()
    results = [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]
    best = {}
    for (name, _), result in zip(list(PAGES.items()) * args.repeat, results):
        row = best.setdefault(name, {"backend": result["backend"], "first": float("inf"), "frame": float("inf")})
        row["first"] = min(row["first"], result["firstFrameMs"])
        row["frame"] = min(row["frame"], result["frameMs"])
    peer = best[next(iter(PAGES))]
    print(f"spot_all ({width}x{height}, every technique on), best of {args.repeat}, {args.frames} frames")
    print("| page | backend | first frame (ms) | vs WebGLRenderer | frame (ms) | vs WebGLRenderer |")
    print("|---|---|---:|---:|---:|---:|")
    for name, row in best.items():
        print(f"| {name} | {row['backend']} | {row['first']:.0f} | {row['first'] / peer['first']:.2f}x | "
              f"{row['frame']:.1f} | {row['frame'] / peer['frame']:.2f}x |")


if __name__ == "__main__":
    main()
