"""Shared plumbing of the runtime-shader tests: the includer's headers, and glslangValidator on one stage."""
from __future__ import annotations

import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]

# what an includer puts before a module: WebGL2 (with highp samplers, as runtime-shaders/README.md asks) and desktop
HEADERS = {
    "300 es": "#version 300 es\nprecision highp float;\nprecision highp int;\nprecision highp sampler2D;\n",
    "330 core": "#version 330 core\n",
}


def read_module(name: str) -> str:
    return (REPO / "runtime-shaders" / name).read_text()


def read_host(name: str, **parts: str) -> str:
    """A host wrapper of ``runtime-shaders/hosts/`` as ``baker preview`` reads it (placeholders filled, empty when
    not given); the test puts the header and the module before it."""
    from baker.preview.core import host_text

    return host_text(name, **parts)


def assert_compiles(validator: str, tmp_path: Path, version: str, name: str, stage: str, text: str) -> None:
    """Compile one stage (``vert``/``frag``, from the file suffix) with glslangValidator; fail with its log."""
    path = tmp_path / f"{name}.{stage}"
    path.write_text(text)
    run = subprocess.run([validator, str(path)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, f"#version {version} {name}.{stage}:\n{run.stdout}{run.stderr}"
