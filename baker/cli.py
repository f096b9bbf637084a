"""The ``baker`` command: parse, run, report. No algorithm lives here.

Exit codes: 0 success, 1 validation errors found, 2 bad input or usage, 130 interrupted (SIGINT, Ctrl-C), 143
terminated (SIGTERM). An interrupted or terminated run unwinds like an error: every output is written to a
temporary file beside its target and renamed only when complete (baker.gltf.atomic), so the unwinding removes the
temporary files and leaves any earlier output as it was.
"""
from __future__ import annotations

import signal
import sys
import warnings

from baker import commands
from baker.errors import BakeNote, BakerError


class Terminated(BaseException):
    """Raised in the main thread by the SIGTERM handler, so that ``finally`` blocks and context managers (the atomic
    writers' clean-up) run as they do for Ctrl-C. A BaseException, as KeyboardInterrupt is: ``except Exception``
    handlers around a reader do not swallow it."""


def _terminate(signum, frame):
    raise Terminated()


def _one_line_notes(show):
    """``warnings.showwarning`` printing a :class:`BakeNote` as ``baker: <label>: ...`` (what ``baker bake`` prints),
    so every command that loads an asset (inspect, preview, hair, ...) says a missing MTL the same way."""
    def showwarning(message, category, filename, lineno, file=None, line=None):
        if issubclass(category, BakeNote):
            print(f"baker: {category.label}: {message}", file=sys.stderr)
        else:
            show(message, category, filename, lineno, file, line)

    return showwarning


def main(argv=None) -> int:
    previous = None
    try:
        previous = signal.signal(signal.SIGTERM, _terminate)
    except ValueError:  # not the main thread (main() called from a thread): leave signals alone
        pass
    try:
        with warnings.catch_warnings():  # restores showwarning
            warnings.showwarning = _one_line_notes(warnings.showwarning)
            return commands.run(sys.argv[1:] if argv is None else argv)
    except BakerError as exc:
        print(f"baker: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("baker: interrupted", file=sys.stderr)
        return 130
    except Terminated:
        print("baker: terminated", file=sys.stderr)
        return 143
    except BrokenPipeError:  # the reader of our output went away (`baker inspect x.glb | head`): not an error of ours
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # no second error when Python flushes at exit
        return 141
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


def entry() -> None:
    """The console command: :func:`main`, then exit with its code without the interpreter's teardown.

    Every output was written, closed and renamed before :func:`main` returned, so what the teardown would still do
    is collect and free the ~10^5 cyclic objects numba and LLVM leave: 0.25-0.7 s of every bake here (15% of a
    1024² thickness texture). The atexit handlers still run and the streams are flushed; then the process ends
    (``os._exit``). Unlike ``gc.freeze`` this also holds with OpenImageIO loaded, whose nanobind module reports
    every object still alive at its teardown as a leak."""
    code = main()
    from baker import numba_warmup

    numba_warmup.finish()
    import atexit
    import os

    atexit._run_exitfuncs()
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except BrokenPipeError:
        code = code or 141
    os._exit(code if isinstance(code, int) else 1)


if __name__ == "__main__":
    entry()
