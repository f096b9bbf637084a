"""The ``baker`` command: parse, run, report. No algorithm lives here.

Exit codes: 0 success, 1 validation errors found, 2 bad input or usage, 130 interrupted (SIGINT, Ctrl-C), 143
terminated (SIGTERM). An interrupted or terminated run unwinds like an error: every output is written to a
temporary file beside its target and renamed only when complete (baker.gltf.atomic), so the unwinding removes the
temporary files and leaves any earlier output as it was.

SIGINT is always turned into KeyboardInterrupt while a command runs, also when baker was started with SIGINT ignored:
a shell without job control (``sh -c 'baker ... &'``, most CI scripts) starts background commands that way, and
Python then leaves SIGINT ignored, so ``kill -INT`` did nothing. The handlers are installed before the commands are
imported; a signal in the first few tenths of a second (the interpreter starting, ``import baker``) still ends the
process by the signal's default action: nothing written, a shell reports it as 130 / 143, but no message.
"""
from __future__ import annotations

import signal
import sys
import warnings


class Terminated(BaseException):
    """Raised in the main thread by the SIGTERM handler, so that ``finally`` blocks and context managers (the atomic
    writers' clean-up) run as they do for Ctrl-C. A BaseException, as KeyboardInterrupt is: ``except Exception``
    handlers around a reader do not swallow it."""


def _swallowing(frame) -> bool:
    """Whether an exception raised in ``frame`` would be printed and dropped rather than unwind the command: inside
    a ``__del__`` or a ctypes callback (llvmlite's object-cache hooks run while numba compiles; a KeyboardInterrupt
    there was reported as "Exception ignored on calling ctypes callback function" and left the compilation broken,
    exit 1 instead of 130), or inside numba's ``_numba_unpickle`` (called from a compiled dispatcher's C code, which
    turns an exception there into ``SystemError: ... returned a result with an exception set``)."""
    while frame is not None:
        code = frame.f_code
        parts = code.co_filename.replace("\\", "/").split("/")
        if code.co_name in ("__del__", "_numba_unpickle") or "llvmlite" in parts:
            return True
        frame = frame.f_back
    return False


def _raise_when_safe(signum, frame, exception) -> None:
    if _swallowing(frame):
        # send the signal again a moment later, when the main thread is (almost surely) back in baker's own code
        import os
        import threading

        threading.Timer(0.02, os.kill, (os.getpid(), signum)).start()
        return
    raise exception


def _terminate(signum, frame):
    _raise_when_safe(signum, frame, Terminated())


def _interrupt(signum, frame):
    _raise_when_safe(signum, frame, KeyboardInterrupt())


def _one_line_notes(show):
    """``warnings.showwarning`` printing a :class:`BakeNote` as ``baker: <label>: ...`` (what ``baker bake`` prints),
    so every command that loads an asset (inspect, preview, hair, ...) says a missing MTL the same way."""
    from baker.errors import BakeNote

    def showwarning(message, category, filename, lineno, file=None, line=None):
        if issubclass(category, BakeNote):
            print(f"baker: {category.label}: {message}", file=sys.stderr)
        else:
            show(message, category, filename, lineno, file, line)

    return showwarning


def _signal_cause(exc: BaseException):
    """The KeyboardInterrupt or Terminated at the root of ``exc``'s chain of causes, or None."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, (KeyboardInterrupt, Terminated)):
            return exc
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return None


def main(argv=None) -> int:
    previous = {}
    try:
        previous[signal.SIGTERM] = signal.signal(signal.SIGTERM, _terminate)
        previous[signal.SIGINT] = signal.signal(signal.SIGINT, _interrupt)
    except ValueError:  # not the main thread (main() called from a thread): leave signals alone
        pass
    from baker.errors import BakerError

    try:
        from baker import commands  # after the handlers: a signal while the commands load is handled too

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
    except SystemError as exc:  # a signal's exception wrapped by C code that called back into Python
        cause = _signal_cause(exc)
        if cause is None:
            raise
        print(f"baker: {'interrupted' if isinstance(cause, KeyboardInterrupt) else 'terminated'}", file=sys.stderr)
        return 130 if isinstance(cause, KeyboardInterrupt) else 143
    except BrokenPipeError:  # the reader of our output went away (`baker inspect x.glb | head`): not an error of ours
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # no second error when Python flushes at exit
        return 141
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, signal.SIG_DFL if handler is None else handler)


def entry() -> None:
    """The console command: :func:`main`, then exit with its code without the interpreter's teardown.

    Every output was written, closed and renamed before :func:`main` returned, so what the teardown would still do
    is collect and free the ~10^5 cyclic objects numba and LLVM leave: 0.25-0.7 s of every bake here (15% of a
    1024² thickness texture). The atexit handlers still run (not after a signal) and the streams are flushed; then the process ends
    (``os._exit``). Unlike ``gc.freeze`` this also holds with OpenImageIO loaded, whose nanobind module reports
    every object still alive at its teardown as a leak."""
    code = main()
    import atexit
    import os

    if code not in (130, 143):
        from baker import numba_warmup

        numba_warmup.finish()
        atexit._run_exitfuncs()
    # else: interrupted or terminated, with nothing written: end now rather than wait up to ~1.5 s for the warm-up
    # thread's numba initialisation (``os._exit`` runs no static destructor, so the thread cannot crash the exit)
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except BrokenPipeError:
        code = code or 141
    os._exit(code if isinstance(code, int) else 1)


if __name__ == "__main__":
    entry()
