"""Shared test helpers and the one CI rule.

Khronos glTF-Validator: every test that writes a .gltf/.glb should call ``assert_khronos_clean(path)`` on it. The
validator is required wherever the tests run (``scripts/install-node-tools`` installs it): a check that cannot run
fails, it never passes by checking nothing.

Under CI (:func:`ci.in_ci`) a skipped test is a failed test: CI cannot go green by not running something.
"""
from __future__ import annotations

import os

import pytest

from baker import validate
from ci import in_ci

# the note a cold numba cache prints (baker/compile_note.py) would land in whichever test compiles a kernel first:
# off for the suite (subprocesses inherit it); tests/test_numba_cache.py turns it on where it checks it
os.environ.setdefault("BAKER_COMPILE_NOTE", "0")


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    report = outcome.get_result()
    if report.skipped and in_ci() and not hasattr(report, "wasxfail"):
        reason = report.longrepr[2] if isinstance(report.longrepr, tuple) else str(report.longrepr)
        report.outcome = "failed"
        report.longrepr = f"skipped under CI, which counts as a failure: {reason}"


def khronos_validate(path) -> dict:
    """Khronos glTF-Validator's report on ``path`` (as it prints it); fails the test when it cannot run."""
    reason = validate.khronos_unavailable()
    if reason:
        pytest.fail(f"Khronos glTF-Validator is required (run scripts/install-node-tools): {reason}")
    return validate.khronos_report(path)


def assert_khronos_clean(path) -> dict:
    """Assert Khronos glTF-Validator finds no errors in ``path``; returns its report."""
    report = khronos_validate(path)
    errors = [m for m in report["issues"]["messages"] if m["severity"] == 0]
    assert not errors, f"Khronos glTF-Validator errors in {path}:\n" + "\n".join(
        f"  {m['code']} {m.get('pointer', '-')}: {m['message']}" for m in errors)
    return report


# a channel at or above this (8-bit) is clipped white; every channel at or below CLIPPED_BLACK is clipped black
CLIPPED_WHITE, CLIPPED_BLACK = 254, 3


def clipped_fractions(image, covered) -> tuple[float, float]:
    """(clipped white, clipped black) shares of the pixels ``covered`` (H, W bool) of an 8-bit picture (H, W, 3;
    integers 0-255 or floats 0-1): white where any channel is at 254 or more (a highlight or a shade lost), black
    where every channel is at 3 or less."""
    import numpy as np

    pixels = np.asarray(image)
    pixels = np.round(pixels * 255.0) if pixels.dtype.kind == "f" else pixels.astype(np.float64)
    pixels = pixels[..., :3][covered]
    if not len(pixels):
        return 0.0, 0.0
    return float((pixels.max(axis=1) >= CLIPPED_WHITE).mean()), float((pixels.max(axis=1) <= CLIPPED_BLACK).mean())
