"""Compiled kernels that a signal can interrupt.

Python runs a signal handler only when the main thread is back in the interpreter; a numba kernel called from the
main thread holds it for as long as it runs, and a parallel kernel on a loaded machine (its OpenMP threads waiting
for each other behind other processes) can run many times longer than its work. A kernel compiled with
``nogil=True`` is therefore called on a helper thread while the main thread waits on a lock, which a signal
interrupts at once (POSIX lock waits return to run the handler): the handler's exception (KeyboardInterrupt,
``Terminated``) unwinds the command while the abandoned kernel finishes its block in the background, writing only
into arrays nobody reads any more. The result is the kernel's own, bit for bit: nothing changes but who waits.
"""
from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager


def call(kernel, *args):
    """``kernel(*args)`` (a ``nogil`` compiled function) run on a daemon thread; waiting for it can be interrupted by
    a signal. Its exception, if it raises, is raised here."""
    outcome: dict = {}
    finished = threading.Event()

    def run():
        try:
            outcome["value"] = kernel(*args)
        except BaseException as exc:  # noqa: BLE001 - handed to the waiting thread, which raises it
            outcome["error"] = exc
        finally:
            finished.set()

    threading.Thread(target=run, name="baker-kernel", daemon=True).start()
    finished.wait()
    if "error" in outcome:
        raise outcome["error"]
    return outcome["value"]


@contextmanager
def thread_pool(threads: int):
    """A ``ThreadPoolExecutor`` for GIL-free kernels that, when the block is left by an exception (a signal's
    KeyboardInterrupt or ``Terminated``, or an error), cancels the queued work and returns without waiting for the
    calls already running: the plain ``with`` waits for them, seconds per batch on a loaded machine, before the
    command can report the signal."""
    pool = ThreadPoolExecutor(threads)
    try:
        yield pool
    except BaseException:
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown(wait=True)
