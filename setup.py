"""The wheel build compiles baker's numba kernels and ships them (see baker/numba_cache.py): after setuptools copies
the package into the build folder, scripts/seed_numba_cache.py runs every command on small inputs with numba's cache
pointed at build/.../baker/numba_seed, so a first run after `pip install` loads kernels instead of compiling them.

`pip install .` in a fresh environment seeds too: the build backend (scripts/numba_seed_backend.py) asks pip for
the project's dependencies in the isolated build environment when the interpreter lacks them.
BAKER_NUMBA_SEED=0 builds without the seed (a quick wheel; its first run compiles). An editable install has none:
its kernels compile into the user cache on first use, as numba always did, and each command says so once
(baker/compile_note.py)."""
import os
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

ROOT = Path(__file__).resolve().parent


class BuildPyWithNumbaSeed(build_py):
    def run(self):
        super().run()
        if getattr(self, "editable_mode", False):
            return
        # the build folder outlives a build: a seed left by an earlier one must not ship with other sources
        shutil.rmtree(Path(self.build_lib) / "baker" / "numba_seed", ignore_errors=True)
        if os.environ.get("BAKER_NUMBA_SEED", "1") == "0":
            return
        # the workload runs with the building interpreter's own site-packages (numpy, numba, ...) where they are there
        # (pip's isolated build environment then holds only setuptools: its PYTHONPATH overlay and user-site switch
        # are dropped), else in that isolated environment, to which scripts/numba_seed_backend.py then added them
        sys.path.insert(0, str(ROOT / "scripts"))
        from numba_seed_backend import interpreter_environment, interpreter_has, project_dependencies

        env = interpreter_environment() if interpreter_has(project_dependencies()) else dict(os.environ)
        subprocess.run([sys.executable, str(ROOT / "scripts" / "seed_numba_cache.py"),
                        str(Path(self.build_lib).resolve())], env=env, check=True)


setup(cmdclass={"build_py": BuildPyWithNumbaSeed})
