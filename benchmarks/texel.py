"""Texture-space bakes: baker's thickness texture vs Blender Cycles' inside-AO bake, whole processes, same run; and
the default bake of a many-material prop against its per-vertex-only bake.

    python benchmarks/texel.py [--mesh examples/spot/spot.obj] [--sizes 512,1024,2048] [--rays 64] [--repeat 2]
                               [--error-sizes 512,1024] [--markdown]

Rows:
- baker: ``baker bake MESH -o out.glb --bakes thickness --thickness-texture-size S --thickness-rays R`` (the command a
  user runs, fresh process: start-up, read, per-vertex and per-texel rays, PNG, GLB).
- Cycles (bpy 4.5, ``scripts/install-bpy``): ``benchmarks/texel_cycles.py`` in a fresh Blender Python: OBJ import, a
  material whose Ambient Occlusion node has ``inside`` and ``only_local`` on and ``samples`` = R, feeding an Emission
  shader, render samples 1, ``bpy.ops.object.bake(type="EMIT")`` into an S x S float image on the CPU, saved as .npy.
  Cycles computes occlusion, baker the mean chord; the rays per texel, the work, are the same.
- Error: relative RMS over the texels the UV layout covers, at each of ``--error-sizes``, each bake against its own converged
  reference of 1024 rays per texel (baker: ``--thickness-rays 1024 --thickness-tolerance 0``, every ray traced;
  Cycles: 128 AO samples x 8 render samples, the node's maximum). baker's default takes its per-vertex prior where
  a texel's first rays agree with it and adds its neighbours' deviation from it (a window of texels: the error
  depends on the texture's size, so it is measured at each size asked); the error with every texel tracing all its
  rays is printed beside it.
- Many materials: 7 UV spheres of radius 1 (960 triangles each, 7 materials) in one GLB; the default
  ``--bakes thickness`` (texture sizes chosen by baker) against ``--thickness-per-texel false`` (per vertex only);
  the texels the default wrote, in total.

Times are the best of ``--repeat`` interleaved rounds (the machine's speed swings between minutes); peak memory is
the process's maximum resident set.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baker.geometry.asset import Asset  # noqa: E402
from baker.geometry.texture_space import rasterize_uv  # noqa: E402
from baker.gltf.document import GltfDocument  # noqa: E402
from baker.gltf.images import decoded_texture  # noqa: E402
from common import baker_cli, run_command  # noqa: E402

SPOT = ROOT / "examples" / "spot" / "spot.obj"
CYCLES_SCRIPT = Path(__file__).with_name("texel_cycles.py")
REFERENCE_RAYS = 1024


def bpy_python() -> str:
    """Blender's Python: $BAKER_BPY_PYTHON, else the venv scripts/install-bpy makes (or reuses)."""
    if os.environ.get("BAKER_BPY_PYTHON"):
        return os.environ["BAKER_BPY_PYTHON"]
    return subprocess.run([str(ROOT / "scripts" / "install-bpy")], check=True, capture_output=True,
                          text=True).stdout.strip()


def baker_thickness_images(path: Path) -> list[np.ndarray]:
    """Every thickness texture of a baked GLB, in mesh units (texel value x the material's thickness factor)."""
    doc = GltfDocument.load(path)
    images = []
    for material in doc.json.get("materials", []):
        extensions = material.get("extensions") or {}
        volume = extensions.get("KHR_materials_volume") or {}
        own = extensions.get("BAKER_thickness") or {}
        info = volume.get("thicknessTexture") or (own.get("thicknessTexture") if isinstance(
            own.get("thicknessTexture"), dict) else None)
        if not info:
            continue
        factor = float(volume.get("thicknessFactor", own.get("thicknessFactor", 1.0)))
        pixels = decoded_texture(doc, info["index"])
        pixels = pixels if pixels.ndim == 2 else pixels[..., 1 if pixels.shape[2] > 1 else 0]  # green, or gray
        images.append(pixels.astype(np.float64) * factor)
    return images


def first_primitive(mesh: Path):
    return Asset.load(mesh).primitive(0, 0)


def uv_mask(mesh: Path, size: int) -> np.ndarray:
    """The texels the mesh's UV layout covers, by baker's rasterizer (the same layout both bakers write)."""
    geometry = first_primitive(mesh)
    return rasterize_uv(geometry.texcoords[0], geometry.faces, size, size).mask


def relative_rms(values: np.ndarray, reference: np.ndarray, mask: np.ndarray) -> float:
    diff = values[mask] - reference[mask]
    return float(np.sqrt(np.mean(diff ** 2)) / np.sqrt(np.mean(reference[mask] ** 2)))


def bake_baker(mesh: Path, size: int, rays: int, out: Path, *extra) -> dict:
    return run_command(baker_cli("bake", mesh, "-o", out, "--bakes", "thickness", "--thickness-texture-size", size,
                                 "--thickness-rays", rays, "-q", *extra))


def bake_cycles(python: str, mesh: Path, size: int, samples: int, render_samples: int, distance: float,
                out: Path) -> dict:
    return run_command([python, CYCLES_SCRIPT, mesh, size, samples, render_samples, distance, out],
                       env={k: v for k, v in os.environ.items() if k != "PYTHONPATH"})


def uv_sphere(rings: int = 16, segments: int = 32) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A latitude-longitude sphere of radius 1 as a DCC exports it: vertices split along the seam and at the poles,
    UVs (u = longitude, v = latitude) in [0, 1] without overlap; 2 x segments x (rings - 1) triangles."""
    theta = np.pi * np.arange(rings + 1) / rings
    phi = 2.0 * np.pi * np.arange(segments + 1) / segments
    t, p = np.meshgrid(theta, phi, indexing="ij")
    positions = np.stack([np.sin(t) * np.cos(p), np.cos(t), -np.sin(t) * np.sin(p)], -1).reshape(-1, 3)
    uv = np.stack(np.meshgrid(np.arange(segments + 1) / segments, np.arange(rings + 1) / rings), -1).reshape(-1, 2)
    index = np.arange((rings + 1) * (segments + 1)).reshape(rings + 1, segments + 1)
    a, b = index[:-1, :-1], index[1:, :-1]
    c, d = index[1:, 1:], index[:-1, 1:]
    upper = np.stack([a, b, c], -1)[1:]  # the top row's (a, b, c) would be degenerate at the pole: skipped
    lower = np.stack([a, c, d], -1)[:-1]  # likewise the bottom row's
    faces = np.concatenate([upper.reshape(-1, 3), lower.reshape(-1, 3)])
    return positions, faces, uv


def sphere_scene(path: Path, count: int = 7) -> None:
    """``count`` spheres of radius 1 with 960 triangles each, one material each, in a row, as one GLB."""
    import trimesh

    scene = trimesh.Scene()
    positions, faces, uv = uv_sphere()
    assert len(faces) == 960
    for i in range(count):
        sphere = trimesh.Trimesh(positions + [3.0 * i, 0.0, 0.0], faces, process=False,
                                 visual=trimesh.visual.TextureVisuals(
                                     uv=uv, material=trimesh.visual.material.PBRMaterial(name=f"m{i}")))
        assert sphere.volume > 0  # outward winding
        scene.add_geometry(sphere, geom_name=f"sphere{i}")
    scene.export(str(path))


def texel_count(path: Path) -> int:
    return sum(image.shape[0] * image.shape[1] for image in baker_thickness_images(path))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh", default=str(SPOT))
    ap.add_argument("--sizes", default="512,1024,2048")
    ap.add_argument("--rays", type=int, default=64)
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--error-sizes", default="512,1024")
    ap.add_argument("--markdown", action="store_true")
    args = ap.parse_args(argv)
    mesh, sizes = Path(args.mesh), [int(s) for s in args.sizes.split(",")]
    python = bpy_python()
    loaded = first_primitive(mesh)
    diagonal = float(np.linalg.norm(np.ptp(loaded.positions, axis=0)))
    distance = 0.1 * diagonal  # Cycles' AO distance: a tenth of the diagonal leaves the occlusion varied

    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        times = {(who, size): [] for who in ("baker", "cycles") for size in sizes}
        for _ in range(args.repeat):  # interleaved: both peers see the same machine
            for size in sizes:
                times["baker", size].append(bake_baker(mesh, size, args.rays, tmp / f"b{size}.glb"))
                times["cycles", size].append(bake_cycles(python, mesh, size, args.rays, 1, distance,
                                                         tmp / f"c{size}.npy"))

        errors = {}
        for e in [int(s) for s in args.error_sizes.split(",")]:
            mask = uv_mask(mesh, e)
            if ("baker", e) not in times:
                bake_baker(mesh, e, args.rays, tmp / f"b{e}.glb")
                bake_cycles(python, mesh, e, args.rays, 1, distance, tmp / f"c{e}.npy")
            # the reference traces every ray of every texel (tolerance 0: no per-vertex prior)
            bake_baker(mesh, e, REFERENCE_RAYS, tmp / "b_ref.glb", "--thickness-tolerance", "0")
            bake_baker(mesh, e, args.rays, tmp / f"b{e}_fixed.glb", "--thickness-tolerance", "0")
            bake_cycles(python, mesh, e, 128, REFERENCE_RAYS // 128, distance, tmp / "c_ref.npy")
            [baker_test] = baker_thickness_images(tmp / f"b{e}.glb")
            [baker_ref] = baker_thickness_images(tmp / "b_ref.glb")
            [baker_fixed] = baker_thickness_images(tmp / f"b{e}_fixed.glb")
            errors[e] = (relative_rms(baker_test, baker_ref, mask), relative_rms(baker_fixed, baker_ref, mask),
                         relative_rms(np.load(tmp / f"c{e}.npy"), np.load(tmp / "c_ref.npy"), mask))

        scene = tmp / "spheres.glb"
        sphere_scene(scene)
        multi = {"default": [], "per-vertex only": []}
        for _ in range(args.repeat):
            multi["default"].append(run_command(baker_cli("bake", scene, "-o", tmp / "s_default.glb", "--bakes",
                                                          "thickness", "--thickness-rays", args.rays, "-q")))
            multi["per-vertex only"].append(run_command(baker_cli("bake", scene, "-o", tmp / "s_vertex.glb",
                                                                  "--bakes", "thickness", "--thickness-rays", args.rays,
                                                                  "--thickness-per-texel", "false", "-q")))
        texels = texel_count(tmp / "s_default.glb")

    def best(runs):
        return min(r["wall"] for r in runs), max(r["peak"] for r in runs)

    print(f"mesh: {mesh.name}, {len(loaded.faces)} triangles; {args.rays} rays per texel; best of {args.repeat} "
          f"interleaved rounds; 2 cores; peer: Blender Cycles {python}")
    print()
    print("| texture | baker whole process (s) | peak (MB) | Cycles whole process (s) | peak (MB) | baker / Cycles |")
    print("|---|---:|---:|---:|---:|---:|")
    for size in sizes:
        tb, mb = best(times["baker", size])
        tc, mc = best(times["cycles", size])
        print(f"| {size}² | {tb:.2f} | {mb / 2**20:.0f} | {tc:.2f} | {mc / 2**20:.0f} | **{tb / tc:.2f}x** |")
    print()
    print(f"| texture | relative RMS error vs {REFERENCE_RAYS} rays: baker default | baker, every texel "
          f"{args.rays} rays (`--thickness-tolerance 0`) | Cycles, {args.rays} samples |")
    print("|---|---:|---:|---:|")
    for e, (error_baker, error_fixed, error_cycles) in errors.items():
        print(f"| {e}² | {error_baker:.4f} | {error_fixed:.4f} | {error_cycles:.4f} |")
    print()
    td, _ = best(multi["default"])
    tv, _ = best(multi["per-vertex only"])
    print("| 7 spheres, 7 materials (960 triangles each) | whole process (s) |")
    print("|---|---:|")
    print(f"| default `--bakes thickness` | {td:.2f} |")
    print(f"| `--thickness-per-texel false` | {tv:.2f} |")
    print(f"| ratio | **{td / tv:.2f}x** |")
    print(f"texels written by the default: {texels} ({texels / 512**2:.2f} x 512²; the goal is at most 7 x 512²)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
