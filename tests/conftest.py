"""Shared test helpers.

Khronos glTF-Validator: every test that writes a .gltf/.glb should call ``assert_khronos_clean(path)`` on it.
When CI=true the validator is required (install it with ``scripts/install-node-tools``); elsewhere, without node or
the npm package, the check is skipped (the rest of the test still runs).
"""
from __future__ import annotations

import pytest

from baker import validate
from ci import in_ci


def khronos_validate(path) -> dict | None:
    """Khronos glTF-Validator's report on ``path`` (as it prints it), or None when it is not installed outside CI."""
    reason = validate.khronos_unavailable()
    if reason:
        if in_ci():
            pytest.fail(f"Khronos glTF-Validator is required in CI: {reason}")
        return None
    return validate.khronos_report(path)


def assert_khronos_clean(path) -> dict | None:
    """Assert Khronos glTF-Validator finds no errors in ``path``; returns its report (None when not installed)."""
    report = khronos_validate(path)
    if report is None:
        return None
    errors = [m for m in report["issues"]["messages"] if m["severity"] == 0]
    assert not errors, f"Khronos glTF-Validator errors in {path}:\n" + "\n".join(
        f"  {m['code']} {m.get('pointer', '-')}: {m['message']}" for m in errors)
    return report
