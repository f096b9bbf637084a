"""baker's numba cache locator: kernels of baker's modules are cached under $XDG_CACHE_HOME/baker/numba/<build>/
<module folder>, keyed on the file's place in the package and its content (not its path or mtime, which an install
changes), and a shipped seed folder is copied in once. The wheel round trip is in tests/test_wheel.py."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from baker import numba_cache
from baker.numba_cache import BakerCacheLocator
from baker.techniques.glyphs import sdf

REPO = Path(__file__).parents[1]


def test_locator_is_first_and_names_the_package_folder(monkeypatch, tmp_path):
    from numba.core.caching import CacheImpl

    assert CacheImpl._locator_classes[0] is BakerCacheLocator
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    numba_cache.build_folder.cache_clear()
    try:
        locator = BakerCacheLocator.from_function(sdf.segment_bounds, sdf.__file__)
        expected = tmp_path / "baker" / "numba" / f"{numba_cache.__version__}-source" / "baker.techniques.glyphs"
        assert Path(locator.get_cache_path()) == expected and expected.is_dir()
        assert locator.get_disambiguator() == str(sdf.segment_bounds.__code__.co_firstlineno)
        # a module outside the package is left to numba's own locators
        assert BakerCacheLocator.from_function(test_locator_is_first_and_names_the_package_folder, __file__) is None
    finally:
        numba_cache.build_folder.cache_clear()


def test_source_stamp_is_the_content_not_the_mtime(tmp_path):
    def f():
        return 1

    a, b, c = tmp_path / "a.py", tmp_path / "b.py", tmp_path / "c.py"
    a.write_text("x = 1\n")
    b.write_text("x = 1\n")
    c.write_text("x = 2\n")
    os.utime(b, (1, 1))
    stamps = [BakerCacheLocator(f, str(p), tmp_path).get_source_stamp() for p in (a, b, c)]
    assert stamps[0] == stamps[1] != stamps[2]


def test_seed_is_copied_once_and_never_over_a_user_folder(monkeypatch, tmp_path):
    seed = tmp_path / "seed"
    (seed / "baker.geometry").mkdir(parents=True)
    (seed / "baker.geometry" / "k-1.py311.nbi").write_bytes(b"index")
    monkeypatch.setattr(numba_cache, "SEED", seed)
    target = tmp_path / "user" / "baker.geometry"
    numba_cache.copy_seed("baker.geometry", target)
    assert (target / "k-1.py311.nbi").read_bytes() == b"index"
    (target / "k-1.py311.nbi").write_bytes(b"recompiled")  # the user folder is numba's from now on
    numba_cache.copy_seed("baker.geometry", target)
    assert (target / "k-1.py311.nbi").read_bytes() == b"recompiled"
    assert sorted(p.name for p in target.parent.iterdir()) == ["baker.geometry"]  # no staging folder left behind
    numba_cache.copy_seed("baker.missing", tmp_path / "user" / "baker.missing")  # nothing shipped: nothing made
    assert not (tmp_path / "user" / "baker.missing").exists()


def test_registered_when_numba_is_imported_after_baker(tmp_path):
    probe = ("import baker, sys; assert 'numba' not in sys.modules; import numba.core.caching as c; "
             "print(c.CacheImpl._locator_classes[0].__module__)")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, cwd=tmp_path,
                         env={**os.environ, "PYTHONPATH": str(REPO)})
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "baker.numba_cache"


def test_a_command_says_once_that_it_compiles_and_a_warm_cache_says_nothing(tmp_path):
    """A source checkout compiles kernels on first use: the first compilation of a baker kernel prints the armed
    command's note (one line, before the kernel compiles), a second compilation in the same command prints nothing
    more, and a second process with the same cache, which loads the kernels, prints nothing. A kernel called with
    no note armed (the Python API) prints nothing."""
    probe = ("import sys, numpy as np\n"
             "from baker import compile_note\n"
             "if sys.argv[1] == 'armed':\n"
             "    compile_note.expect(['bake', 'in.obj', '--bakes', 'toon,edges'])\n"
             "from baker.geometry.welding import position_cells, weld_cells\n"
             "print('compiling', file=sys.stderr, flush=True)\n"
             "position_cells(np.zeros((2, 3)), 1.0)\n"
             "weld_cells(np.zeros((2, 3), np.int64))\n")
    env = {**os.environ, "PYTHONPATH": str(REPO), "XDG_CACHE_HOME": str(tmp_path), "BAKER_COMPILE_NOTE": "1"}
    env.pop("NUMBA_CACHE_DIR", None)

    def stderr(mode: str) -> list[str]:
        out = subprocess.run([sys.executable, "-c", probe, mode], capture_output=True, text=True, cwd=tmp_path,
                             env=env, timeout=300)
        assert out.returncode == 0, out.stderr
        return out.stderr.splitlines()

    from baker.compile_note import BAKE_SECONDS

    seconds = BAKE_SECONDS["toon"] + BAKE_SECONDS["edges"]
    note = f"baker: note: compiling the numba kernels for toon, edges once (~{seconds} s; later runs reuse them)"
    assert stderr("armed") == ["compiling", note]
    assert stderr("armed") == ["compiling"]  # warm: loaded, nothing said
    env["XDG_CACHE_HOME"] = str(tmp_path / "other")
    assert stderr("api") == ["compiling"]  # cold, but no command armed the note
    env["XDG_CACHE_HOME"] = str(tmp_path / "third")
    env["BAKER_COMPILE_NOTE"] = "0"
    assert stderr("armed") == ["compiling"]


def test_compile_note_estimates_name_the_command_and_its_bakes():
    from baker import compile_note

    assert compile_note.estimate(["bake", "x.obj", "-o", "y.glb"]) == ("thickness", compile_note.BAKE_SECONDS["thickness"])
    what, seconds = compile_note.estimate(["bake", "x.obj", "--bakes=edges,curvature", "-q"])
    assert what == "edges, curvature" and seconds == compile_note.BAKE_SECONDS["edges"] + \
        compile_note.BAKE_SECONDS["curvature"]
    assert compile_note.estimate(["glyphs", "font.ttf", "-o", "a"]) == ("glyphs", compile_note.COMMAND_SECONDS["glyphs"])
    assert compile_note.estimate(["inspect", "a.glb"]) is None and compile_note.estimate([]) is None
