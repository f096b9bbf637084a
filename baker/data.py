"""Where baker's data lives: the JSON schemas (``schemas/``) and the runtime GLSL (``runtime-shaders/``).

One place to find them, so validation, the preview and the tests agree (today both sit at the top of the checkout).
"""
from __future__ import annotations

from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[1]
SCHEMA_ROOT = REPO_ROOT / "schemas"
SHADER_ROOT = REPO_ROOT / "runtime-shaders"
RECIPE_SCHEMA = SCHEMA_ROOT / "recipe" / "recipe.schema.json"
