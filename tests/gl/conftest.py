"""Fixtures for the headless GLSL tests: a glslangValidator path and an EGL (llvmpipe) moderngl context.

A missing tool or GPU stack skips the tests with the reason on a developer machine; under CI (``tests/ci.py``) it
fails instead, so CI cannot go green by silently not rendering.
"""
from __future__ import annotations

import shutil

import pytest

from ci import in_ci


def unavailable(reason: str):
    """Skip locally, fail under CI (``CI=true``): a runtime-shader test must never be skipped in CI."""
    if in_ci():
        pytest.fail(f"{reason} (CI=true: required in CI)", pytrace=False)
    pytest.skip(reason)


@pytest.fixture(scope="session")
def glslang_validator() -> str:
    path = shutil.which("glslangValidator")
    if path is None:
        unavailable("glslangValidator not found on PATH (apt package glslang-tools)")
    return path


@pytest.fixture(scope="session")
def gl_context():
    try:
        import moderngl
    except ImportError:
        unavailable("moderngl is not installed (pip install moderngl)")
    try:
        ctx = moderngl.create_standalone_context(backend="egl")
    except Exception as exc:  # no libEGL / no EGL device: moderngl raises plain Exception
        unavailable(f"no headless EGL OpenGL context: {exc}")
    yield ctx
    ctx.release()
