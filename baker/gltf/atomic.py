"""Atomic file writes: write to a temporary name beside the target, then rename.

A crash or an error half-way never leaves a partial output file behind.
"""
from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

from baker.errors import BakerError


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path``; rename it onto ``path`` only if the block succeeds."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp" + path.suffix, dir=path.parent)
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600 files; outputs get the usual permissions
    try:
        yield Path(tmp)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def write_bytes_atomic(path, data: bytes) -> None:
    with atomic_path(path) as tmp:
        Path(tmp).write_bytes(data)


def output_folder(path) -> Path:
    """``path`` as a folder to write into: refused when it exists and is not a folder."""
    folder = Path(path)
    if folder.exists() and not folder.is_dir():
        raise BakerError(folder, "exists and is not a folder")
    return folder
