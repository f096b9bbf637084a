"""The Python API: what the CLI and ``baker build`` call.

>>> import baker.api as api
>>> asset = api.bake("spot.obj", bakes=["thickness", "edges"], options={"thickness": {"rays": 128}})
>>> api.save(asset, "spot.glb")
>>> api.validate("spot.glb")["issues"]["numErrors"]
0
"""
from __future__ import annotations

from baker.pipeline import bake, save


def validate(path, khronos: bool = True, allow_outside=None) -> dict:
    """The validation report of one glTF/GLB file (the shape of Khronos glTF-Validator's JSON)."""
    from baker.validate import validate_file

    return validate_file(path, khronos=khronos, allow_outside=allow_outside)


def build(recipe_path=None, *, jobs: int = 1, scheduler: str | None = None, fail_fast: bool = False,
          progress=None, max_memory: int | None = None) -> dict:
    """Bake every stale asset of a recipe (``baker.toml``); returns the build report. ``max_memory``: bytes each bake
    job may need (None: no limit)."""
    from baker.commands.build import build as run_build, find_recipe, load_recipe

    return run_build(load_recipe(find_recipe(recipe_path)), jobs=jobs, scheduler=scheduler, fail_fast=fail_fast,
                     progress=progress, max_memory=max_memory)


def run_command(argv) -> int:
    """Run any ``baker`` command in this process, e.g. ``run_command(["tam", "-o", "tam"])``; returns its exit code
    and raises :class:`~baker.errors.BakerError` for bad input (where the CLI would print one line and exit 2)."""
    from baker import commands

    return commands.run(list(argv))


__all__ = ["bake", "save", "validate", "build", "run_command"]
