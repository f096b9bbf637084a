"""The built wheel carries its schemas and shaders and works with no checkout: installed into a fresh virtual
environment in a temporary folder, run from another folder, `baker bake`, `validate`, `preview` and `glyphs` work,
and validation fails an asset whose BAKER_thickness breaks its schema."""
from __future__ import annotations

import json
import os
import site
import struct
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

REPO = Path(__file__).parents[1]
SPOT = REPO / "examples" / "spot" / "spot.obj"
FONT = Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    result = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q",
                             "-w", str(out), str(REPO)], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    [path] = out.glob("baker-*.whl")
    return path


@pytest.fixture(scope="module")
def venv(wheel, tmp_path_factory) -> Path:
    """A fresh virtual environment holding only the wheel; the dependencies (numpy, usd-core, ...) come from this
    interpreter's site-packages through a .pth file, which adds paths but runs none of their .pth hooks (so an
    editable install of the checkout there stays invisible)."""
    root = tmp_path_factory.mktemp("venv")
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(root)], check=True)
    python = root / "bin" / "python"
    # no PYTHONPATH: a checkout on it (with its baker.egg-info) would look like baker is installed already
    clean = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    result = subprocess.run([sys.executable, "-m", "pip", "--python", str(python), "install", "--no-deps", "-q",
                             "--force-reinstall", str(wheel)], capture_output=True, text=True, env=clean)
    assert result.returncode == 0, result.stderr
    purelib = Path(subprocess.check_output([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()"
                                                             "['purelib'])"], text=True).strip())
    ours = {sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"], *site.getsitepackages()}
    (purelib / "zz_dependencies.pth").write_text("\n".join(sorted(p for p in ours if Path(p).is_dir())) + "\n")
    return root


def run(venv: Path, cwd: Path, *args):
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    return subprocess.run([str(venv / "bin" / "baker"), *map(str, args)], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=600)


def test_wheel_lists_every_schema_and_shader(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    schemas = {f"baker/schemas/{p.relative_to(REPO / 'schemas').as_posix()}" for p in (REPO / "schemas").rglob("*.json")}
    shaders = {f"baker/runtime_shaders/{p.relative_to(REPO / 'runtime-shaders').as_posix()}"
               for p in [*(REPO / "runtime-shaders").glob("*.glsl"), *(REPO / "runtime-shaders").glob("*.wgsl"),
                         *(REPO / "runtime-shaders" / "hosts").rglob("*.glsl")]}
    assert schemas and shaders and any(name.endswith(".wgsl") for name in shaders)
    assert schemas <= names, sorted(schemas - names)
    assert shaders <= names, sorted(shaders - names)
    assert "baker/js/khronos_validate.mjs" in names
    assert not [n for n in names if "node_modules" in n or n.startswith("tests/")]


def test_installed_wheel_bakes_validates_previews_and_makes_glyphs(venv, tmp_path):
    work = tmp_path / "elsewhere"
    work.mkdir()
    where = subprocess.run([str(venv / "bin" / "python"), "-c", "import baker, baker.data as d; "
                            "print(baker.__file__); print(d.SCHEMA_ROOT)"], cwd=work, capture_output=True, text=True,
                           env={k: v for k, v in os.environ.items() if k != "PYTHONPATH"})
    module, schemas = where.stdout.split()
    assert Path(module).is_relative_to(venv) and Path(schemas).is_relative_to(venv), where.stdout
    assert not Path(module).is_relative_to(REPO)

    baked = work / "spot.glb"
    result = run(venv, work, "bake", SPOT, "-o", baked, "--bakes", "thickness", "--thickness-rays", "8",
                 "--thickness-texture-size", "64", "-q")
    assert result.returncode == 0, result.stderr
    result = run(venv, work, "validate", baked, "--no-khronos")
    assert result.returncode == 0, result.stdout + result.stderr

    # corrupt BAKER_thickness: a string where the schema wants an integer ray count
    data = bytearray(baked.read_bytes())
    length = struct.unpack_from("<I", data, 12)[0]
    gltf = json.loads(data[20: 20 + length])
    gltf["materials"][0]["extensions"]["BAKER_thickness"]["rays"] = "many"
    text = json.dumps(gltf, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    rest = data[20 + length:]
    broken = work / "broken.glb"
    broken.write_bytes(b"glTF" + struct.pack("<II", 2, 20 + len(text) + len(rest)) +
                       struct.pack("<I", len(text)) + b"JSON" + text + rest)
    result = run(venv, work, "validate", broken, "--no-khronos", "--format", "json")
    assert result.returncode == 1, result.stdout + result.stderr
    report = json.loads(result.stdout)
    errors = [m for m in report["issues"]["messages"] if m["severity"] == 0]
    assert any("BAKER_thickness" in m.get("pointer", "") and "rays" in m.get("pointer", "") for m in errors), errors

    sheet = work / "sheet.png"
    result = run(venv, work, "preview", baked, "-o", sheet, "--size", "96", "-q")
    assert result.returncode == 0, result.stderr
    assert sheet.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

    assert FONT.is_file(), f"{FONT} is missing: scripts/test installs fonts-dejavu-core"
    result = run(venv, work, "glyphs", FONT, "-o", work / "atlas", "--charset", "str:baker", "--size", "24", "-q")
    assert result.returncode == 0, result.stderr
    assert json.loads((work / "atlas.json").read_text())["glyphs"]


def test_wheel_ships_compiled_kernels_and_a_first_run_compiles_nothing(wheel, venv, tmp_path):
    """The wheel carries numba's compiled kernels (baker/numba_seed, built by setup.py on this machine), a first
    `baker glyphs` with an empty $XDG_CACHE_HOME copies them into $XDG_CACHE_HOME/baker/numba/<version>-<seed id>
    and compiles nothing (every cache file there is byte-identical to the shipped one), a second run changes no
    cache file, and nothing is written into the package (it may be read-only); neither run prints the note a cold
    cache prints (tests/test_numba_cache.py)."""
    names = set(zipfile.ZipFile(wheel).namelist())
    assert "baker/numba_seed/SEED_ID" in names
    assert any(n.startswith("baker/numba_seed/baker.techniques.glyphs/") and n.endswith(".nbc") for n in names)
    cache = tmp_path / "cache"
    env = {**{k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "NUMBA_CACHE_DIR")},
           "XDG_CACHE_HOME": str(cache), "HOME": str(tmp_path), "BAKER_COMPILE_NOTE": "1"}
    package = Path(subprocess.check_output([str(venv / "bin" / "python"), "-c", "import baker, os; "
                                            "print(os.path.dirname(baker.__file__))"], text=True, env=env,
                                           cwd=tmp_path).strip())
    assert package.is_relative_to(venv)
    seed = package / "numba_seed"
    build = cache / "baker" / "numba" / f"0.1.0-{(seed / 'SEED_ID').read_text().strip()}"

    def files(root: Path) -> dict:
        return {p: p.stat().st_mtime_ns for p in root.rglob("*") if p.is_file()}

    def glyphs():
        result = subprocess.run([str(venv / "bin" / "baker"), "glyphs", str(FONT), "-o", str(tmp_path / "a"),
                                 "--charset", "str:cache", "--size", "16", "-q"], cwd=tmp_path, env=env,
                                capture_output=True, text=True, timeout=600)
        assert result.returncode == 0, result.stderr
        assert "compiling" not in result.stderr, result.stderr  # the note of a cold cache: nothing compiles here
        return files(cache / "baker" / "numba")

    installed = files(package)
    first = glyphs()
    assert any(p.suffix == ".nbc" and p.is_relative_to(build / "baker.techniques.glyphs") for p in first), first
    for path in first:
        assert path.is_relative_to(build), path
        shipped = seed / path.relative_to(build)
        assert shipped.is_file() and shipped.read_bytes() == path.read_bytes(), f"{path} was compiled, not shipped"
    assert glyphs() == first
    assert files(package) == installed


def test_build_backend_adds_the_dependencies_only_where_the_interpreter_lacks_them(monkeypatch):
    """`pip install .` in a fresh environment builds the wheel before installing anything: the build backend
    (scripts/numba_seed_backend.py) asks for the project's dependencies then, so setup.py can run baker to compile the
    kernels the wheel ships; with the dependencies installed (here) it asks for nothing more than setuptools does."""
    import tomllib

    sys.path.insert(0, str(REPO / "scripts"))
    try:
        import numba_seed_backend as backend
    finally:
        sys.path.remove(str(REPO / "scripts"))
    pyproject = tomllib.loads((REPO / "pyproject.toml").read_text())
    assert pyproject["build-system"]["build-backend"] == "numba_seed_backend"
    assert pyproject["build-system"]["backend-path"] == ["scripts"]
    dependencies = pyproject["project"]["dependencies"]
    assert backend.project_dependencies() == dependencies
    assert backend.interpreter_has(dependencies)  # this interpreter runs baker's tests: it has them
    assert not backend.interpreter_has(["numpy>=1.26", "no-such-distribution-baker-test>=1"])
    monkeypatch.setattr(backend.build_meta, "get_requires_for_build_wheel", lambda config_settings=None: ["wheel"])
    monkeypatch.delenv("BAKER_NUMBA_SEED", raising=False)
    assert backend.get_requires_for_build_wheel() == ["wheel"]
    monkeypatch.setattr(backend, "interpreter_has", lambda requirements: False)  # a fresh virtual environment
    assert backend.get_requires_for_build_wheel() == ["wheel", *dependencies]
    monkeypatch.setenv("BAKER_NUMBA_SEED", "0")  # a wheel without kernels needs nothing to run baker
    assert backend.get_requires_for_build_wheel() == ["wheel"]
