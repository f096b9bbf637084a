"""What a technique declares about itself: the one object each ``baker/techniques/<name>/__init__.py`` exports.

Everything heavy (kernels, numba, the extension writers, the preview panels) is named by a ``"module:attribute"``
reference and imported only when used, so discovering every technique (``baker --help``) costs a few small imports.
"""
from __future__ import annotations

import importlib
import importlib.resources
from dataclasses import dataclass
from pathlib import Path


# The file roles of a technique's package, the same names in every folder (docs/ARCHITECTURE.md, "How to add a
# technique"): a bake's work is ``run`` in step.py, and the work of a verb that command.py adds is ``run_<verb>``
# (``-`` as ``_``) there too. Other modules are the steps of the kernel or of a command, named by what they do.
REQUIRED_FILES = ("__init__.py", "options.py", "kernel.py", "extension.py", "step.py")  # + command.py, panel.py


def load(reference: str):
    """The object a ``"package.module:attribute"`` (or ``"package.module"``) reference names, imported now."""
    module_name, _, attribute = reference.partition(":")
    module = importlib.import_module(module_name)
    return getattr(module, attribute) if attribute else module


def lazy(reference: str):
    """A function that imports ``reference`` on its first call and forwards the call to it (argparse ``func``)."""
    def call(*args, **kwargs):
        return load(reference)(*args, **kwargs)

    call.__qualname__ = call.__name__ = reference
    return call


@dataclass(frozen=True)
class Technique:
    """One technique of baker: a bake (``options`` + ``run``), extensions, preview panels and commands.

    ``requires`` names the techniques whose output this one reads when both are baked in one run; the pipeline runs
    those first, so the order of ``--bakes`` never changes the result.
    """

    name: str  # as the CLI spells it (``--bakes NAME``, ``--NAME-option``)
    summary: str  # one line for ``--help``
    options: type | None = None  # frozen dataclass of the bake's options (light: no numpy at import)
    run: str | None = None  # "module:function" (asset, options, seed, progress) -> None; None: not a bake
    extensions: tuple[str, ...] = ()  # references to extension objects: NAME, check, read, to_usd_primitive, ...
    panels: str | None = None  # "module:attribute" -> list of preview panels
    commands: tuple[str, ...] = ()  # light modules with ``add_parser(subparsers)`` (standalone commands)
    requires: tuple[str, ...] = ()
    # the bake splits the vertices of the primitives it covers (a new vertex layout): it runs after every bake that
    # does not, so that their per-vertex output never depends on whether it ran (tam's stroke texture coordinates)
    splits_vertices: bool = False
    # the bake can sample a high mesh through a cage (``baker bake --from HIGH``, :mod:`baker.texels.transfer`)
    transfers: bool = False
    # a folder laid out like the repo's ``schemas/`` (``<EXT>/schema/<kind>.<EXT>.schema.json``), for a technique
    # that brings its own: "package:folder" (a folder inside an importable package) or a path; None: the built-in
    # techniques, whose schemas live in the repo's top-level ``schemas/``
    schemas: str | None = None

    def bake(self, asset, options, seed: int = 0, progress=None) -> None:
        """Run the bake on ``asset``; one with nothing to cover on it (:class:`baker.errors.NothingToBake`) is a
        note on the asset, not a failure."""
        from baker.errors import NothingToBake

        try:
            load(self.run)(asset, options, seed=seed, progress=progress)
        except NothingToBake as exc:
            asset.note(f"{self.name}: nothing baked: {exc}")

    def extension_objects(self) -> list:
        return [load(reference) for reference in self.extensions]

    def schema_root(self) -> Path | None:
        """The folder ``schemas`` names, or None. "package:folder" resolves inside the installed package (imported
        now, which a technique's own package already is), so the schemas travel with it as package data."""
        if self.schemas is None:
            return None
        package, sep, folder = self.schemas.partition(":")
        if not sep:
            return Path(self.schemas)
        return Path(str(importlib.resources.files(package).joinpath(folder)))


# What the technique registry lends the shared layers, which may not import it (DESIGN.md's layers): baker.registry
# fills this in when it is imported (every command, baker.api and baker.validate import it). The USD reader asks it
# which members of a primitive extension are accessors ("primitive_accessors") and for the techniques' hooks that
# restore what USD attributes cannot carry ("material_readers").
USD_READ_HOOKS: dict = {}


def usd_read_hook(name: str) -> dict:
    """The registry's answer for ``name`` (see :data:`USD_READ_HOOKS`); empty before the registry is imported."""
    provider = USD_READ_HOOKS.get(name)
    return provider() if provider is not None else {}
