"""Unwrapping a mesh without UVs: its cost in whole bakes and the quality of the layout (issue 35).

    python benchmarks/unwrap.py [--mesh /work/shared/assets/meshes/stanford-bunny.obj] [--repeat 1]
                                [--section time,layout,error] [--unbounded] [--markdown]

- time: whole processes, interleaved, best of ``--repeat``: ``baker bake MESH --bakes thickness --thickness-per-texel
  false`` (per-vertex work only, no unwrap) against ``--bakes tam`` and ``--bakes thickness`` (each unwraps), and
  thickness at 1024^2 (the bunny's automatic size before thickness's stopped at 512^2).
- layout: :func:`baker.texels.texture_space.unwrap` as the bakes call it (padding for the automatic texture size S):
  its time, the charts, texel utilisation (texel centres covered at S x S / all texels), the L2 stretch of Sander et
  al., "Texture Mapping Progressive Meshes" (SIGGRAPH 2001), normalised so that 1 is no stretch, and the spread of
  the 3D-area / UV-area ratio (5th and 95th percentiles, 1 = the mean density). ``--unbounded`` also measures
  xatlas with unbounded charts (the layout before issue 35; minutes on the bunny).
- error: what a renderer reads from ``--bakes thickness`` (the written GLB: the PNG decoded by Pillow, bilinear with
  repeat wrapping at the points' UVs, times thicknessFactor; and the per-vertex ``_THICKNESS`` interpolated) at
  ``--points`` random surface points (area-weighted, seed 0), against a converged reference traced at the points
  themselves (``--reference-rays``, the bake's other options and smooth normals): relative RMS and 99th percentile
  of |error|, over the reference's RMS. Layout-agnostic, so it compares texture sizes and layouts; the texture's own
  resolution is part of its error. Textures at each of ``--sizes`` (0: the automatic size).
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
sys.path.insert(0, str(ROOT / "benchmarks"))
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
    from baker.texels import texture_space
    from baker import readers
    from baker.texels.targets import UNWRAP_COVERAGE, _statistics

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


def surface_points(positions: np.ndarray, faces: np.ndarray, count: int, seed: int = 0):
    """(triangle, barycentrics) of ``count`` points uniform on the surface."""
    from baker.texels.texture_space import triangle_areas

    rng = np.random.default_rng(seed)
    areas = triangle_areas(positions, faces)
    triangle = rng.choice(len(faces), size=count, p=areas / areas.sum())
    r1, r2 = rng.random(count), rng.random(count)
    s = np.sqrt(r1)
    return triangle, np.stack([1 - s, s * (1 - r2), s * r2], axis=1)


def reference_thickness(mesh: Path, triangle: np.ndarray, bary: np.ndarray, rays: int) -> np.ndarray:
    from baker import readers
    from baker.geometry.raycast import RayScene
    from baker.texels.targets import smooth_normals
    from baker.techniques.thickness.kernel import default_max_distance, local_thickness

    geometry = readers.read(mesh).primitive(0, 0)
    corners = geometry.faces[triangle]
    points = np.einsum("ki,kij->kj", bary, geometry.positions[corners])
    normals = np.einsum("ki,kij->kj", bary, smooth_normals(geometry)[corners])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    diagonal = default_max_distance(geometry.positions)
    return local_thickness(RayScene(geometry.positions, geometry.faces), points, normals, rays=rays,
                           max_distance=diagonal, bias=1e-5 * diagonal, seed=1)


def baked_at_points(glb: Path, triangle: np.ndarray, bary: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """(texture values, per-vertex values interpolated, texture size) of a baked GLB at the points. The unwrap
    keeps the triangles' order (it splits vertices only), so triangle k of the source is triangle k here."""
    from baker import readers
    from texel import baker_thickness_images

    asset = readers.read(glb)
    geometry = asset.primitive(0, 0)
    primitive = asset.meshes()[0]["primitives"][0]
    material = asset.doc.json["materials"][primitive["material"]]
    info = material["extensions"]["KHR_materials_volume"]["thicknessTexture"]
    image, = baker_thickness_images(glb)
    uv = np.einsum("ki,kij->kj", bary, geometry.texcoords[info.get("texCoord", 0)][geometry.faces[triangle]])
    size = image.shape[0]
    x, y = uv[:, 0] * size - 0.5, uv[:, 1] * size - 0.5  # texel centres at (i + 0.5) / size
    x0, y0 = np.floor(x).astype(np.int64), np.floor(y).astype(np.int64)
    fx, fy = x - x0, y - y0
    at = lambda r, c: image[r % size, c % size]  # noqa: E731 (the glTF default sampler repeats)
    texture = ((1 - fy) * ((1 - fx) * at(y0, x0) + fx * at(y0, x0 + 1))
               + fy * ((1 - fx) * at(y0 + 1, x0) + fx * at(y0 + 1, x0 + 1)))
    per_vertex = asset.doc.accessor(primitive["attributes"]["_THICKNESS"])[:, 0]  # VEC3 (x: the thickness)
    vertex = np.einsum("ki,ki->k", bary, per_vertex[geometry.faces[triangle]])
    return texture, vertex, size


def relative_errors(values: np.ndarray, reference: np.ndarray) -> tuple[float, float]:
    diff = np.abs(values - reference)
    scale = np.sqrt(np.mean(reference ** 2))
    return float(np.sqrt(np.mean(diff ** 2)) / scale), float(np.percentile(diff, 99) / scale)


def error_rows(mesh: Path, sizes: list[int], points: int, reference_rays: int) -> list:
    from baker import readers

    geometry = readers.read(mesh).primitive(0, 0)
    triangle, bary = surface_points(geometry.positions, geometry.faces, points)
    reference = reference_thickness(mesh, triangle, bary, reference_rays)
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for size in sizes:
            out = Path(folder) / f"thickness{size}.glb"
            forced = ["--thickness-texture-size", str(size)] if size else []
            seconds = bake_seconds(mesh, ["--bakes", "thickness", *forced], out)
            texture, vertex, written = baked_at_points(out, triangle, bary)
            if not rows:
                rms, p99 = relative_errors(vertex, reference)
                rows.append(["per-vertex `_THICKNESS`, interpolated", "-", "-", f"{rms:.4f}", f"{p99:.4f}"])
            rms, p99 = relative_errors(texture, reference)
            rows.append([f"texture {written}² ({'automatic' if not size else 'forced'})", f"{seconds:.1f}",
                         written, f"{rms:.4f}", f"{p99:.4f}"])
    return rows


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
    parser.add_argument("--sizes", default="0,1024")
    parser.add_argument("--points", type=int, default=4000)
    parser.add_argument("--reference-rays", type=int, default=2048)
    args = parser.parse_args()
    sections = set(args.section.split(","))
    if "time" in sections:
        # the last: the automatic thickness size before it stopped at 512^2 (the bunny's)
        runs = {"--bakes thickness --thickness-per-texel false": [], "--bakes tam": [], "--bakes thickness": [],
                "--bakes thickness --thickness-texture-size 1024": []}
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
    if "error" in sections:
        print()
        rows = error_rows(args.mesh, [int(s) for s in args.sizes.split(",")], args.points, args.reference_rays)
        print(table(["thickness, at surface points", "bake seconds", "size", "relative RMS", "p99 |error|"], rows,
                    args.markdown))


if __name__ == "__main__":
    main()
