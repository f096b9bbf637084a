"""The build backend (pyproject.toml): setuptools', asking for baker's own dependencies when a wheel is built
where the building interpreter lacks them.

setup.py compiles the numba kernels the wheel ships (scripts/seed_numba_cache.py runs every command), which needs
numpy, numba and the rest. `pip install .` in a fresh virtual environment builds the wheel before it installs any
dependency, in an isolated environment holding only the build requirements: there this backend adds the project's
dependencies to them, so the kernels compile (and the first run after the install is as fast as the second). Where
the interpreter has them already (`pip wheel .` in a development environment, the test suite) nothing is added and
setup.py runs the workload with that interpreter's own packages. An editable install builds no seed: nothing added.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

from setuptools import build_meta
from setuptools.build_meta import *  # noqa: F401,F403 - every other hook is setuptools' own

ROOT = Path(__file__).resolve().parents[1]


def project_dependencies() -> list[str]:
    return tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]


def interpreter_environment() -> dict:
    """os.environ without pip's isolation (its PYTHONPATH overlay and user-site switch): the interpreter's own
    site-packages."""
    return {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONNOUSERSITE", "PYTHONHOME")}


def interpreter_has(requirements: list[str]) -> bool:
    """Whether the building interpreter's own site-packages hold a distribution of every requirement (by name)."""
    names = [re.match(r"[A-Za-z0-9._-]+", r.strip()).group(0) for r in requirements]
    probe = ("import importlib.metadata as m, sys\n"
             "for name in sys.argv[1:]:\n"
             "    m.distribution(name)\n")
    return subprocess.run([sys.executable, "-c", probe, *names], env=interpreter_environment(),
                          capture_output=True, cwd=os.path.dirname(sys.executable)).returncode == 0


def get_requires_for_build_wheel(config_settings=None):
    required = build_meta.get_requires_for_build_wheel(config_settings)
    if os.environ.get("BAKER_NUMBA_SEED", "1") == "0":
        return required
    dependencies = project_dependencies()
    return required if interpreter_has(dependencies) else required + dependencies
