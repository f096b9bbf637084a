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
- Error of what a user gets, at each of ``--error-sizes``: baker's texture as written (the PNG decoded by Pillow, green
  channel over the bit depth's maximum, times ``thicknessFactor``) against a converged reference of 1024 rays per
  texel (``--thickness-rays 1024 --thickness-tolerance 0 --seed 1``, every ray traced), as relative RMS and 99th
  percentile of |error| over the reference's RMS, on the texels the UV layout covers and on the whole image (dilation
  copies the charts' edge texels into the padding, which bilinear filtering and mip levels read); the default beside
  every texel tracing its rays (``--thickness-tolerance 0``), both also with ``--thickness-texture-bits 8``. Cycles
  (its float image, covered texels) against 128 AO samples x 8 render samples, the node's maximum. baker's default
  traces 12 rays per texel and takes its per-vertex prior where they agree with it, plus its neighbours' deviation
  from it (a window of texels: the error depends on the texture's size, so it is measured at each size asked).
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

from baker import readers  # noqa: E402
from baker.texels.texture_space import rasterize_uv  # noqa: E402
from baker.gltf.document import GltfDocument  # noqa: E402
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
    """Every thickness texture of a baked GLB as a user's renderer gets it, in mesh units: the PNG decoded by Pillow
    (not baker's own reader), its green channel (KHR_materials_volume reads green) over the bit depth's maximum,
    times the material's thicknessFactor."""
    import io

    from PIL import Image

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
        image = Image.open(io.BytesIO(doc.image_bytes(doc.json["textures"][info["index"]]["source"])))
        sixteen = image.mode in ("I;16", "I;16B", "I") or image.info.get("bitdepth") == 16
        pixels = np.asarray(image)
        pixels = pixels if pixels.ndim == 2 else pixels[..., 1]  # grayscale is R = G = B
        images.append(pixels.astype(np.float64) / (65535.0 if sixteen else 255.0) * factor)
    return images


def first_primitive(mesh: Path):
    return readers.read(mesh).primitive(0, 0)


def uv_mask(mesh: Path, size: int) -> np.ndarray:
    """The texels the mesh's UV layout covers, by baker's rasterizer (the same layout both bakers write)."""
    geometry = first_primitive(mesh)
    return rasterize_uv(geometry.texcoords[0], geometry.faces, size, size).mask


def errors(values: np.ndarray, reference: np.ndarray, mask: np.ndarray) -> tuple[float, float]:
    """Relative RMS error and 99th percentile of the absolute error, both over the reference's RMS, on ``mask``."""
    diff = np.abs(values[mask] - reference[mask])
    scale = np.sqrt(np.mean(reference[mask] ** 2))
    return float(np.sqrt(np.mean(diff ** 2)) / scale), float(np.percentile(diff, 99) / scale)


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

        measured = {}
        for e in [int(s) for s in args.error_sizes.split(",")]:
            mask = uv_mask(mesh, e)
            whole = np.ones_like(mask)
            if ("baker", e) not in times:
                bake_baker(mesh, e, args.rays, tmp / f"b{e}.glb")
                bake_cycles(python, mesh, e, args.rays, 1, distance, tmp / f"c{e}.npy")
            # the reference traces every ray of every texel (tolerance 0: no per-vertex prior), another seed
            bake_baker(mesh, e, REFERENCE_RAYS, tmp / "b_ref.glb", "--thickness-tolerance", "0", "--seed", "1")
            bake_baker(mesh, e, args.rays, tmp / f"b{e}_fixed.glb", "--thickness-tolerance", "0")
            bake_baker(mesh, e, args.rays, tmp / f"b{e}_8.glb", "--thickness-texture-bits", "8")
            bake_baker(mesh, e, args.rays, tmp / f"b{e}_fixed8.glb", "--thickness-tolerance", "0",
                       "--thickness-texture-bits", "8")
            bake_cycles(python, mesh, e, 128, REFERENCE_RAYS // 128, distance, tmp / "c_ref.npy")
            [reference] = baker_thickness_images(tmp / "b_ref.glb")
            for name, file in (("default", f"b{e}.glb"), ("fixed", f"b{e}_fixed.glb"), ("default 8", f"b{e}_8.glb"),
                               ("fixed 8", f"b{e}_fixed8.glb")):
                [image] = baker_thickness_images(tmp / file)
                measured[e, name] = errors(image, reference, mask) + errors(image, reference, whole)
            measured[e, "cycles"] = errors(np.load(tmp / f"c{e}.npy"), np.load(tmp / "c_ref.npy"), mask)

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
    print(f"Error of the texture as written (PNG decoded by Pillow, green / max x thicknessFactor) against a "
          f"{REFERENCE_RAYS}-ray bake (`--thickness-tolerance 0`, seed 1): relative RMS and 99th percentile of "
          f"|error| / RMS of the reference, on the texels the UV layout covers and on the whole image (the padding "
          f"holds copies of the charts' edges)")
    print()
    print("| texture | bake | covered RMS | covered p99 | whole image RMS | whole image p99 |")
    print("|---|---|---:|---:|---:|---:|")
    labels = {"default": "baker default (16-bit PNG)", "fixed": f"baker, every texel {args.rays} rays "
              "(`--thickness-tolerance 0`)", "default 8": "baker default, `--thickness-texture-bits 8`",
              "fixed 8": f"baker {args.rays} rays, 8 bits", "cycles": f"Cycles, {args.rays} samples (float image)"}
    for (e, name), values in measured.items():
        cells = [f"{v:.4f}" for v in values] + ["", ""][:4 - len(values)]
        bold = "**" if name == "default" else ""
        print(f"| {e}² | {labels[name]} | {bold}{cells[0]}{bold} | {bold}{cells[1]}{bold} | {cells[2]} | {cells[3]} |")
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
