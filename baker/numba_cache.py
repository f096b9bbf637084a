"""Where numba keeps baker's compiled kernels, and the compiled kernels a wheel ships (its seed).

numba's own locators key a cache folder on the absolute path of the source folder, so kernels compiled anywhere else
(the wheel build) never match an install. :class:`BakerCacheLocator`, put first in numba's locator list when
``numba.core.caching`` is imported (see :mod:`baker`), keys them on the file's place inside the package instead:

    $XDG_CACHE_HOME/baker/numba/<baker version>-<seed id>/<module folder>/<module>.<function>-<line>.py311.nbi|nbc

and stamps each file with a hash of its content (a wheel install does not keep mtimes). The wheel build runs a
representative workload with ``BAKER_NUMBA_SEED_BUILD`` naming ``baker/numba_seed`` in the build folder (setup.py),
so the wheel carries the compiled kernels; the first time a module folder's kernels are looked up, its seed folder is
copied into the user cache (the package folder may be read-only). numba still checks each entry's key (signature,
bytecode hash, numba version, target triple, CPU name and features), so a seed built on another CPU or numba misses
and that kernel compiles as before, into the same user folder. numba raises its ``numba:compile`` event only then
(a cache miss): :class:`CompileNoteListener` turns the first one of a command into its one-line note
(:mod:`baker.compile_note`).
"""
from __future__ import annotations

import functools
import hashlib
import os
import shutil
import tempfile
from pathlib import Path

from numba.core import event
from numba.core.caching import CacheImpl, _CacheLocator

from baker import compile_note
from baker.version import __version__

PACKAGE = Path(__file__).resolve().parent
SEED = PACKAGE / "numba_seed"
SEED_ID_FILE = "SEED_ID"  # one line: a hash of the seed's files, written by the wheel build (setup.py)
SEED_BUILD_VARIABLE = "BAKER_NUMBA_SEED_BUILD"


def user_cache_root() -> Path:
    """``$XDG_CACHE_HOME/baker/numba`` (``~/.cache/baker/numba`` without it)."""
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "baker" / "numba"


@functools.lru_cache(maxsize=None)
def build_folder() -> Path:
    """The user cache folder of this build: the version and the shipped seed's id ("source" for a checkout), so a new
    wheel never reads another build's entries and its seed is copied once."""
    try:
        seed_id = (SEED / SEED_ID_FILE).read_text().strip()
    except OSError:
        seed_id = "source"
    return user_cache_root() / f"{__version__}-{seed_id}"


@functools.lru_cache(maxsize=None)
def _content_hash(path: str, mtime_ns: int, size: int) -> str:
    # mtime and size in the key only re-hash a file edited while the process runs
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def module_folder(py_file: str) -> str | None:
    """The cache folder name of a baker source file: its package path ("baker.techniques.glyphs"), None outside."""
    try:
        relative = Path(py_file).resolve().relative_to(PACKAGE)
    except ValueError:
        return None
    return ".".join(("baker", *relative.parent.parts))


def copy_seed(folder: str, target: Path) -> None:
    """Copy the shipped seed of one module folder into ``target`` if it is missing: into a temporary sibling, then
    renamed, so a concurrent process sees either nothing or the whole folder."""
    source = SEED / folder
    if target.exists() or not source.is_dir():
        return
    target.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{folder}-", dir=target.parent))
    try:
        shutil.copytree(source, staging, dirs_exist_ok=True)
        os.rename(staging, target)
    except OSError:  # another process renamed first (the folder is not empty): theirs is the same seed
        shutil.rmtree(staging, ignore_errors=True)


class BakerCacheLocator(_CacheLocator):
    """numba cache locator for kernels defined in baker's own modules (others go to numba's locators)."""

    def __init__(self, py_func, py_file: str, cache_path: Path):
        self._py_file = py_file
        self._lineno = py_func.__code__.co_firstlineno
        self._cache_path = str(cache_path)

    def get_cache_path(self):
        return self._cache_path

    def get_source_stamp(self):
        stat = os.stat(self._py_file)
        return _content_hash(self._py_file, stat.st_mtime_ns, stat.st_size)

    def get_disambiguator(self):
        return str(self._lineno)

    @classmethod
    def from_function(cls, py_func, py_file):
        folder = module_folder(py_file)
        if folder is None:
            return None
        seed_build = os.environ.get(SEED_BUILD_VARIABLE)
        if seed_build:
            cache_path = Path(seed_build) / folder
        else:
            cache_path = build_folder() / folder
            try:
                copy_seed(folder, cache_path)
            except OSError:  # an unwritable cache: numba's next locator decides, the kernel compiles
                return None
        self = cls(py_func, py_file, cache_path)
        try:
            self.ensure_cache_path()
        except OSError:
            return None
        return self


class CompileNoteListener(event.Listener):
    """numba raises ``numba:compile`` only when a kernel is not in its cache: the first one of baker's prints the
    command's note (:mod:`baker.compile_note`)."""

    def on_start(self, ev):
        dispatcher = (ev.data or {}).get("dispatcher")
        if (getattr(getattr(dispatcher, "py_func", None), "__module__", None) or "").startswith("baker."):
            compile_note.compiling()

    def on_end(self, ev):
        pass


_compile_listener: list = []  # the registered listener, once


def register() -> None:
    """Put :class:`BakerCacheLocator` first in numba's locator list and listen for compilations (both idempotent).
    Every ``cache=True`` kernel decorated afterwards uses it; importing this module does it, which :mod:`baker` makes
    happen as ``numba.core.caching`` is imported."""
    if BakerCacheLocator not in CacheImpl._locator_classes:
        CacheImpl._locator_classes.insert(0, BakerCacheLocator)
    if not _compile_listener:
        _compile_listener.append(CompileNoteListener())
        event.register("numba:compile", _compile_listener[0])


register()
