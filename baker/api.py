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


def hair_bsdf(tangent, light, view, **params):
    """The hair fibre BSDF a runtime computes from baked tables (``baker hair-lut``): sum_p M_p A_p N_p of Chiang et
    al. 2016's far field, the radiance toward ``view`` per unit radiance arriving from ``light`` (unit vectors away
    from the fibre, (n, 3) or (3,); ``tangent`` along the fibre), per RGB channel, shape (n, 3); integrated over light
    directions (no cosine) it is the fibre's albedo. ``params``: ``eumelanin``, ``pheomelanin`` (d'Eon et al. 2011
    concentrations, default 1.3 and 0), ``beta_m``, ``beta_n`` (roughness 0.05..1, default 0.3), ``alpha`` (cuticle
    tilt, degrees, default 2), ``eta`` (default 1.55), or ``sigma_a`` (RGB absorption per fibre radius), or ``color`` (linear RGB, Chiang et al.
    2016's inversion)."""
    from baker.techniques.hair_shading.tables import shade_from_tables

    return shade_from_tables(tangent, light, view, **params)


def hair_shade(tangent, light, view, fibres_crossed, **params):
    """:func:`hair_bsdf` with Zinke et al. 2008's dual scattering, as ``runtime-shaders/baker_hair_shading.glsl``
    computes it: the radiance toward ``view`` per unit irradiance from ``light`` at a fibre with ``fibres_crossed``
    fibres (scalar or (n,), >= 0; fractions fade the direct light) parallel to ``tangent`` between it and the light:
    the direct single scattering plus global (forward-scattered, Psi_G) and local (backscattered by the neighbours,
    Psi_G Psi_L) multiple scattering from the per-fibre averages of the dual-scattering table. Same ``params`` as
    :func:`hair_bsdf`, plus ``density_forward``, ``density_back`` (Zinke's d_f, d_b: default 1, for a count of
    the fibres actually crossed; Zinke used 0.7 with deep opacity maps)."""
    from baker.techniques.hair_shading.dual import shade_from_tables

    return shade_from_tables(tangent, light, view, fibres_crossed, **params)


def run_command(argv) -> int:
    """Run any ``baker`` command in this process, e.g. ``run_command(["tam", "-o", "tam"])``; returns its exit code
    and raises :class:`~baker.errors.BakerError` for bad input (where the CLI would print one line and exit 2)."""
    from baker import commands

    return commands.run(list(argv))


__all__ = ["bake", "save", "validate", "build", "hair_bsdf", "hair_shade", "run_command"]
