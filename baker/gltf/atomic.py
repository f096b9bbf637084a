"""Atomic file writes: write to a temporary name beside the target, then rename.

A crash, an error, Ctrl-C or SIGTERM half-way never leaves a partial output file behind, and an earlier file at the
target path stays as it was until the new one is complete. The temporary file lives in the destination folder (so the
rename is atomic on one file system) and is named ``.<name>.<random>.tmp<suffix>`` (the suffix kept, so writers that
pick a format by extension — OpenImageIO, USD — still do). SIGINT and SIGTERM are held back while a temporary file
is created, renamed or removed, so a signal cannot strike between creating a file and owning its clean-up.

:func:`atomic_files` does the same for several files that belong together (a ``.gltf`` and its ``.bin`` and images, a
USD stage and its texture folder, a glyph atlas and its metrics): every temporary file is written first, then all
are renamed in order (side files first, the main file last) with the signals held back, so a failed or killed run
leaves either every earlier file or every new one — never a new ``.bin`` beside the old ``.gltf``.
"""
from __future__ import annotations

import contextlib
import os
import signal
import tempfile
import threading
from pathlib import Path

from baker.errors import BakerError

_SIGNALS = {signal.SIGINT, signal.SIGTERM}


@contextlib.contextmanager
def deferred_signals():
    """Hold SIGINT and SIGTERM back for the duration of the block; a signal that arrives meanwhile is handled (by the
    handler that was installed) when the block ends. Python runs signal handlers in the main thread only, whichever
    thread the OS delivered the signal to, so the handlers are swapped for a recorder rather than the signal masked;
    outside the main thread this does nothing (no handler would run there anyway)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    pending: list[int] = []

    def hold(signum, frame):
        pending.append(signum)

    previous = {}
    try:
        for signum in _SIGNALS:
            previous[signum] = signal.signal(signum, hold)
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, signal.SIG_DFL if handler is None else handler)
        if pending:
            _deliver(pending[0], previous[pending[0]])


def _deliver(signum: int, handler) -> None:
    if callable(handler):
        handler(signum, None)  # Python's SIGINT handler raises KeyboardInterrupt; baker's SIGTERM one Terminated
    elif handler == signal.SIG_DFL:
        signal.raise_signal(signum)  # the default action (terminate), now that the files are in place
    # SIG_IGN, or None (a handler not installed from Python): dropped, as it would have been


def _make_parents(folder: Path) -> list[Path]:
    """Create ``folder`` and its missing parents; returns the ones created, deepest first."""
    created = []
    p = folder
    while not p.exists():
        created.append(p)
        p = p.parent
    folder.mkdir(parents=True, exist_ok=True)
    return created


def _temporary(path: Path) -> Path:
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp" + path.suffix, dir=path.parent)
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600 files; outputs get the usual permissions
    return Path(tmp)


def _discard(temps, created) -> None:
    for tmp in temps:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
    for folder in created:  # folders made for this write only, deepest first; kept if something else is inside
        with contextlib.suppress(OSError):
            folder.rmdir()


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path``; rename it onto ``path`` only if the block succeeds."""
    with atomic_files([path]) as temps:
        yield temps[0]


@contextlib.contextmanager
def atomic_files(paths):
    """Yield one temporary path per entry of ``paths`` (a list, in the same order); when the block succeeds, rename
    each onto its target in that order (put the main file last), with SIGINT/SIGTERM held back until all are in
    place. When it fails (any exception, KeyboardInterrupt, SIGTERM), remove every temporary file and every folder
    made for them."""
    paths = [Path(p) for p in paths]
    for path in paths:  # before anything is made: one line, not a traceback at the rename
        if path.is_dir():
            raise BakerError(path, "a directory: the output must name a file")
        blocking = next((p for p in reversed(path.parents) if p.exists() and not p.is_dir()), None)
        if blocking is not None:
            raise BakerError(path, f"cannot write the output here: {blocking} is a file, not a folder")
    temps: list[Path] = []
    created: list[Path] = []
    try:
        with deferred_signals():
            for path in paths:
                try:
                    created += _make_parents(path.parent)
                    temps.append(_temporary(path))
                except OSError as exc:  # a file where a folder should be, no permission, a read-only disk
                    raise BakerError(path, f"cannot write the output here: {exc.strerror or exc}") from None
        yield list(temps)
        with deferred_signals():
            for tmp, path in zip(temps, paths):
                os.replace(tmp, path)
    except BaseException:
        with deferred_signals():
            _discard(temps, created)
        raise


def write_bytes_atomic(path, data: bytes) -> None:
    with atomic_path(path) as tmp:
        Path(tmp).write_bytes(data)


def write_files_atomic(files) -> list[Path]:
    """Write ``files`` (a list of (path, bytes), the main file last) as one :func:`atomic_files` group; returns the
    paths."""
    files = list(files)
    with atomic_files([p for p, _ in files]) as temps:
        for tmp, (_, data) in zip(temps, files):
            tmp.write_bytes(data)
    return [Path(p) for p, _ in files]


def output_folder(path) -> Path:
    """``path`` as a folder to write into: refused when it exists and is not a folder."""
    folder = Path(path)
    if folder.exists() and not folder.is_dir():
        raise BakerError(folder, "exists and is not a folder")
    return folder
