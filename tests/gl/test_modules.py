"""Every runtime-shaders module is includable the same way, and every function in it has a numpy twin."""
from __future__ import annotations

import re

import pytest

from . import (twins_caustics, twins_edges, twins_fur, twins_hair, twins_hair_cards, twins_hair_shading,
               twins_hatching, twins_normal_blur, twins_skin, twins_text, twins_toon, twins_translucency)
from .glsl import REPO, read_module

TWINS = {  # one twin module per runtime module: baker_<name>.glsl -> twins_<name>.py
    "baker_caustics.glsl": twins_caustics,
    "baker_edges.glsl": twins_edges,
    "baker_fur.glsl": twins_fur,
    "baker_hair.glsl": twins_hair,
    "baker_hair_cards.glsl": twins_hair_cards,
    "baker_hair_shading.glsl": twins_hair_shading,
    "baker_hatching.glsl": twins_hatching,
    "baker_normal_blur.glsl": twins_normal_blur,
    "baker_skin.glsl": twins_skin,
    "baker_text.glsl": twins_text,
    "baker_toon.glsl": twins_toon,
    "baker_translucency.glsl": twins_translucency,
}


def test_every_module_has_twins():
    modules = sorted(p.name for p in (REPO / "runtime-shaders").glob("*.glsl"))
    assert modules == sorted(TWINS), "a new runtime module needs its numpy twins (tests/gl/twins_*.py)"
    for name, twins in TWINS.items():
        assert twins.__name__.rsplit(".", 1)[-1] == "twins_" + name[len("baker_"):-len(".glsl")], name


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
