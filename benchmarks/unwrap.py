"""Unwrapping a mesh without UVs: its cost in whole bakes and the quality of the layout (issue 35).

    python benchmarks/unwrap.py [--mesh /work/shared/assets/meshes/stanford-bunny.obj] [--repeat 1]
                                [--section time,layout] [--unbounded] [--markdown]

- time: whole processes, interleaved, best of ``--repeat``: ``baker bake MESH --bakes thickness --thickness-per-texel
  false`` (per-vertex work only, no unwrap) against ``--bakes tam`` and ``--bakes thickness`` (each unwraps).
- layout: :func:`baker.geometry.texture_space.unwrap` as the bakes call it (padding for the automatic texture size S):
  its time, the charts, texel utilisation (texel centres covered at S x S / all texels), the L2 stretch of Sander et
  al., "Texture Mapping Progressive Meshes" (SIGGRAPH 2001), normalised so that 1 is no stretch, and the spread of
  the 3D-area / UV-area ratio (5th and 95th percentiles, 1 = the mean density). ``--unbounded`` also measures
  xatlas with unbounded charts (the layout before issue 35; minutes on the bunny).
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
BUNNY = Path("/work/shared/assets/meshes/stanford-bunny.obj")


def bake_seconds(mesh: Path, args: list[str], out: Path) -> float:
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "baker", "bake", str(mesh), "-o", str(out), "-q", *args], check=True,
                   env=env)
    return time.perf_counter() - start


def stretch(positions: np.ndarray, uv: np.ndarray, faces: np.ndarray) -> tuple[float, float, float]:
    """(L2 stretch, 5th and 95th percentile of the normalised 3D/UV area ratio) of the parameterisation."""
    q, s, t = positions[faces], uv[faces][..., 0], uv[faces][..., 1]
    uv_area = 0.5 * ((s[:, 1] - s[:, 0]) * (t[:, 2] - t[:, 0]) - (s[:, 2] - s[:, 0]) * (t[:, 1] - t[:, 0]))
    keep = np.abs(uv_area) > 0
    q, s, t, uv_area = q[keep], s[keep], t[keep], uv_area[keep]
    # Sander et al. 2001: S_s, S_t are the partial derivatives of the map from UV to the surface
    d_s = (q[:, 0] * (t[:, 1] - t[:, 2])[:, None] + q[:, 1] * (t[:, 2] - t[:, 0])[:, None]
           + q[:, 2] * (t[:, 0] - t[:, 1])[:, None]) / (2 * uv_area[:, None])
    d_t = (q[:, 0] * (s[:, 2] - s[:, 1])[:, None] + q[:, 1] * (s[:, 0] - s[:, 2])[:, None]
           + q[:, 2] * (s[:, 1] - s[:, 0])[:, None]) / (2 * uv_area[:, None])
    area = 0.5 * np.linalg.norm(np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]), axis=1)
    per_triangle = ((d_s ** 2).sum(1) + (d_t ** 2).sum(1)) / 2
    uv_total = np.abs(uv_area).sum()
    l2 = np.sqrt((per_triangle * area).sum() / area.sum()) * np.sqrt(uv_total / area.sum())
    ratio = (area / np.abs(uv_area)) / (area.sum() / uv_total)
    low, high = np.percentile(ratio, [5, 95])
    return float(l2), float(low), float(high)


def layout_row(mesh: Path, unbounded: bool) -> list:
    from baker.geometry import texture_space
    from baker import readers
    from baker.geometry.texture_target import UNWRAP_COVERAGE, _statistics

    geometry = readers.read(mesh).primitive(0, 0)
    size = texture_space.size_for_density(_statistics([geometry], None, UNWRAP_COVERAGE))
    limit = texture_space.CHART_LIMIT_FROM_FACES
    if unbounded:
        texture_space.CHART_LIMIT_FROM_FACES = 1 << 62
    try:
        start = time.perf_counter()
        (vmap, faces, uv), = texture_space.unwrap([(geometry.positions, geometry.faces)], resolution=size)
        seconds = time.perf_counter() - start
    finally:
        texture_space.CHART_LIMIT_FROM_FACES = limit
    covered = len(texture_space.rasterize_uv(uv, faces, size, size).rows)
    l2, low, high = stretch(geometry.positions[vmap], uv, faces)
    return ["unbounded charts (before)" if unbounded else "bounded charts", f"{seconds:.1f} s", size,
            f"{covered / size ** 2:.3f}", f"{l2:.3f}", f"{low:.2f}-{high:.2f}"]


def table(header: list, rows: list, markdown: bool) -> str:
    if markdown:
        lines = ["| " + " | ".join(map(str, header)) + " |", "|" + "---|" * len(header)]
        return "\n".join(lines + ["| " + " | ".join(map(str, r)) + " |" for r in rows])
    return "\n".join("  ".join(str(c) for c in r) for r in [header, *rows])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mesh", type=Path, default=BUNNY)
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--section", default="time,layout")
    parser.add_argument("--unbounded", action="store_true")
    parser.add_argument("--markdown", action="store_true")
    args = parser.parse_args()
    sections = set(args.section.split(","))
    if "time" in sections:
        runs = {"--bakes thickness --thickness-per-texel false": [], "--bakes tam": [], "--bakes thickness": []}
        with tempfile.TemporaryDirectory() as folder:
            for _ in range(args.repeat):
                for command, times in runs.items():
                    times.append(bake_seconds(args.mesh, command.split(), Path(folder) / "out.glb"))
        base = min(runs["--bakes thickness --thickness-per-texel false"])
        print(table(["command", "seconds (best)", "x per-vertex"],
                    [[f"`{c}`", f"{min(t):.1f}", f"{min(t) / base:.2f}"] for c, t in runs.items()], args.markdown))
        print()
    if "layout" in sections:
        rows = [layout_row(args.mesh, False)] + ([layout_row(args.mesh, True)] if args.unbounded else [])
        print(table(["unwrap", "time", "size S", "texel utilisation", "L2 stretch", "3D/UV area p5-p95"], rows,
                    args.markdown))


if __name__ == "__main__":
    main()
