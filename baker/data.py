"""Where baker's data lives: the JSON schemas and the runtime GLSL, found through :mod:`importlib.resources`.

``schemas/`` and ``runtime-shaders/`` sit at the top of the repository, for people and other tools; the package
reaches them as ``baker/schemas`` and ``baker/runtime_shaders`` (links in a checkout, copies in a wheel, see
``[tool.setuptools.package-data]``), so a checkout, an editable install and a wheel installed anywhere all find the
same files, and none of them looks outside the installed package.
"""
from __future__ import annotations

from importlib.resources import files
from pathlib import Path

PACKAGE_ROOT = Path(str(files("baker")))
SCHEMA_ROOT = PACKAGE_ROOT / "schemas"
SHADER_ROOT = PACKAGE_ROOT / "runtime_shaders"
JS_ROOT = PACKAGE_ROOT / "js"
RECIPE_SCHEMA = SCHEMA_ROOT / "recipe" / "recipe.schema.json"
