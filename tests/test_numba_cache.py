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
