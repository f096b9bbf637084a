"""Progress bars for long work: shown on a terminal, silent with --quiet or when stderr is not a TTY."""
from __future__ import annotations

import contextlib
import sys


class Progress:
    def __init__(self, enabled: bool | None = None):
        self.enabled = sys.stderr.isatty() if enabled is None else enabled

    @contextlib.contextmanager
    def task(self, description: str, total: int):
        """Yield a callable ``advance(n)``; draws a tqdm bar when enabled."""
        if not self.enabled:
            yield lambda n=1: None
            return
        from tqdm import tqdm

        with tqdm(total=total, desc=description, unit="pt", file=sys.stderr, leave=False, dynamic_ncols=True) as bar:
            yield bar.update


QUIET = Progress(enabled=False)
