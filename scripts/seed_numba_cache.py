"""Fill BUILD_LIB/baker/numba_seed with numba's compiled kernels: every baker command once on small inputs, run from
BUILD_LIB, with BAKER_NUMBA_SEED_BUILD naming the seed folder (baker/numba_cache.py), then BUILD_LIB/baker/numba_seed/
SEED_ID (a hash of the seed's files: the user cache folder the seed is copied into). Called by setup.py's build_py.

    python scripts/seed_numba_cache.py BUILD_LIB

The kernels are compiled for this machine's CPU (numba keys each entry on its name and features); on another CPU
they miss and compile on first use, as without a seed. A command that fails (no EGL for preview, no DejaVu font)
is reported and left out: its kernels compile on first use."""
from __future__ import annotations

import hashlib
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SPOT = ROOT / "examples" / "spot" / "spot.obj"
FONT = Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
ALL_BAKES = "thickness,curvature,skin,edges,tam,toon,fur,caustics"


CUBE_POSITIONS = [(x, y, z) for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)]
CUBE_FACES = [(0, 3, 2), (0, 1, 3), (4, 7, 5), (4, 6, 7), (0, 5, 1), (0, 4, 5), (2, 7, 6), (2, 3, 7), (0, 6, 4),
              (0, 2, 6), (1, 7, 3), (1, 5, 7)]  # counter-clockwise seen from outside


def meshes_without_normals(work: Path) -> tuple[Path, Path]:
    """A cube as OBJ and as binary PLY, without normals: the readers compute smooth ones (the compiled
    angle-weighted normals, in float64 for OBJ and float32 for PLY), as they do for a scan."""
    obj = work / "cube.obj"
    obj.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in CUBE_POSITIONS) +
                   "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in CUBE_FACES))
    ply = work / "cube.ply"
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(CUBE_POSITIONS)}\nproperty float x\n"
              f"property float y\nproperty float z\nelement face {len(CUBE_FACES)}\n"
              "property list uchar int vertex_indices\nend_header\n").encode()
    ply.write_bytes(header + b"".join(struct.pack("<3f", *p) for p in CUBE_POSITIONS) +
                    b"".join(struct.pack("<B3i", 3, *f) for f in CUBE_FACES))
    return obj, ply


def workload(work: Path) -> list[list[str]]:
    """The commands, in order (later ones read earlier outputs): the README's and the benchmarks' commands first."""
    baked = work / "spot_all.glb"
    hair = work / "hair.glb"
    cube_obj, cube_ply = meshes_without_normals(work)
    commands = [
        ["bake", SPOT, "-o", baked, "--bakes", ALL_BAKES, "--fur-fins", "true", "-q"],  # fins: their kernels too
        ["bake", SPOT, "-o", work / "spot_thickness.glb", "--bakes", "thickness", "-q"],
        ["bake", SPOT, "-o", work / "spot_blur.glb", "--bakes", "normal-blur", "-q"],
        ["text", "Hello", "--font", FONT, "-o", work / "label.glb", "-q"],
        ["glyphs", FONT, "-o", work / "atlas", "-q"],
        ["hair", SPOT, "-o", hair, "--guides", "64", "--children", "4", "-q"],
        ["guides", hair, "-o", work / "guides.glb", "--guides", "16", "-q"],
        ["cards", hair, "-o", work / "cards.glb", "--cards", "8", "--atlas-size", "256", "-q"],
        ["lines", SPOT, "-o", work / "spot.svg"],
        ["tam", "-o", work / "tam", "-q"],
        ["caustics", "-o", work / "caustics", "-q"],
        ["hair-lut", "-o", work / "hair_lut", "-q"],
        ["inspect", baked],
        ["validate", baked, "--no-khronos", "-q"],
        ["preview", baked, "-o", work / "sheet.png", "--size", "96", "-q"],
        ["bake", cube_obj, "-o", work / "cube_obj.glb", "--bakes", "edges", "-q"],
        ["bake", cube_ply, "-o", work / "cube_ply.glb", "--bakes", "edges", "-q"],
    ]
    return [[str(a) for a in c] for c in commands]


def seed_id(seed: Path) -> str:
    digest = hashlib.sha256()
    for path in sorted(p for p in seed.rglob("*") if p.is_file()):
        digest.update(f"{path.relative_to(seed).as_posix()}\0".encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


def main(build_lib: str) -> int:
    build_lib = Path(build_lib).resolve()
    seed = build_lib / "baker" / "numba_seed"
    shutil.rmtree(seed, ignore_errors=True)
    seed.mkdir(parents=True)
    # build_lib first; a PYTHONPATH already set is pip's isolated build environment holding the dependencies
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(build_lib), os.environ.get("PYTHONPATH")])),
           "BAKER_NUMBA_SEED_BUILD": str(seed), "BAKER_COMPILE_NOTE": "0"}
    # run from elsewhere: `python -c` puts the current folder (the checkout, where pip builds) first on sys.path
    where = subprocess.run([sys.executable, "-c", "import baker; print(baker.__file__)"], env=env,
                           capture_output=True, text=True, cwd=tempfile.gettempdir())
    if where.returncode != 0 or not Path(where.stdout.strip()).is_relative_to(build_lib):
        print(f"seed_numba_cache: {sys.executable} cannot import baker's dependencies from {build_lib} "
              f"({where.stderr.strip().splitlines()[-1:] or where.stdout.strip()}); build with the project's "
              "dependencies installed (pip wheel --no-build-isolation, or BAKER_NUMBA_SEED=0 for a wheel without "
              "compiled kernels)", file=sys.stderr)
        return 1
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as d:
        for command in workload(Path(d)):
            began = time.perf_counter()
            result = subprocess.run([sys.executable, "-m", "baker.cli", *command], cwd=d, env=env,
                                    capture_output=True, text=True)
            status = "ok" if result.returncode == 0 else f"FAILED (exit {result.returncode}), its kernels compile " \
                                                         f"on first use: {result.stderr.strip()[-400:]}"
            print(f"seed_numba_cache: baker {command[0]} {time.perf_counter() - began:.1f} s {status}",
                  file=sys.stderr)
    identity = seed_id(seed)
    (seed / "SEED_ID").write_text(identity + "\n")
    size = sum(p.stat().st_size for p in seed.rglob("*") if p.is_file())
    print(f"seed_numba_cache: {len(list(seed.rglob('*.nbc')))} kernels, {size / 2**20:.1f} MiB, id {identity}, "
          f"{time.perf_counter() - start:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
