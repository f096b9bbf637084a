"""Every runtime-shaders module is includable the same way, and every function in it has a numpy twin."""
from __future__ import annotations

import re

import pytest

from . import twins, twins_edges, twins_hair, twins_hatching, twins_skin, twins_text
from .glsl import REPO, read_module

TWINS = {
    "baker_translucency.glsl": twins,
    "baker_skin.glsl": twins_skin,
    "baker_edges.glsl": twins_edges,
    "baker_text.glsl": twins_text,
    "baker_hatching.glsl": twins_hatching,
    "baker_toon.glsl": twins_hatching,
    "baker_hair.glsl": twins_hair,
    "baker_fur.glsl": twins_hair,
}


def test_every_module_has_twins():
    modules = sorted(p.name for p in (REPO / "runtime-shaders").glob("*.glsl"))
    assert modules == sorted(TWINS), "a new runtime module needs its numpy twins (tests/gl/twins_*.py)"


@pytest.mark.parametrize("name", sorted(TWINS))
def test_module_is_includable(name):
    """No #version, no precision statement, no globals: the includer owns the header and the interface."""
    code = re.sub(r"//[^\n]*", "", read_module(name))
    code = re.sub(r"/\*.*?\*/", "", code, flags=re.S)
    assert not re.search(r"^\s*#\s*version", code, re.M)
    assert not re.search(r"^\s*precision\b", code, re.M)
    assert not re.search(r"^\s*(uniform|in|out|attribute|varying)\b", code, re.M)
    functions = re.findall(r"^\s*\w+\s+(baker_\w+)\s*\(", code, re.M)
    assert functions, "no baker_* function found"
    missing = sorted({f for f in functions if not hasattr(TWINS[name], f)})
    assert not missing, f"no numpy twin for {missing}"
