"""Bakes run in dependency order (``Technique.requires``), so the order of ``--bakes`` never changes the output."""
from __future__ import annotations

import json
import struct
import subprocess
import sys
from pathlib import Path

import pytest

from baker import registry

SPOT = Path(__file__).parents[1] / "examples" / "spot" / "spot.obj"
FAST = ["--curvature-per-texel", "false", "--skin-width", "16", "--skin-height", "16", "--skin-penumbra", "false",
        "--thickness-rays", "4", "--thickness-per-texel", "false", "--tam-size", "32", "--tam-levels", "1"]


def bake(tmp_path, bakes: str, name: str) -> Path:
    out = tmp_path / name
    result = subprocess.run([sys.executable, "-m", "baker.cli", "bake", str(SPOT), "-o", str(out), "--bakes", bakes,
                             "-q", *FAST], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    return out


def glb_json(path: Path) -> dict:
    data = path.read_bytes()
    length, kind = struct.unpack_from("<II", data, 12)
    assert kind == 0x4E4F534A  # "JSON": read the container by hand, not with baker
    return json.loads(data[20: 20 + length])


def test_skin_reads_curvature_whichever_order_they_are_listed_in(tmp_path):
    first = bake(tmp_path, "skin,curvature", "a.glb")
    second = bake(tmp_path, "curvature,skin", "b.glb")
    assert first.read_bytes() == second.read_bytes()
    for material in glb_json(first)["materials"]:
        assert material["extensions"]["BAKER_skin_lut"]["curvatureAttribute"] == "_CURVATURE"


def test_independent_bakes_in_any_order_give_the_same_bytes(tmp_path):
    assert bake(tmp_path, "tam,thickness,edges", "a.glb").read_bytes() == \
        bake(tmp_path, "edges,tam,thickness", "b.glb").read_bytes()


def test_order_puts_requirements_first_and_ties_by_name():
    assert registry.bake_order(["skin", "curvature", "thickness"]) == ["curvature", "skin", "thickness"]
    assert registry.bake_order(["thickness", "edges"]) == ["edges", "thickness"]
    assert registry.bake_order(["skin"]) == ["skin"]  # a requirement not asked for is not added


def test_unknown_bake_is_one_line_and_exit_2(tmp_path):
    result = subprocess.run([sys.executable, "-m", "baker.cli", "bake", str(SPOT), "-o", str(tmp_path / "o.glb"),
                             "--bakes", "thickness,nope"], capture_output=True, text=True)
    assert result.returncode == 2
    assert result.stderr.strip().splitlines() == [result.stderr.strip()]
    assert "unknown bake(s) nope" in result.stderr
    assert not (tmp_path / "o.glb").exists()


@pytest.mark.parametrize("name", sorted(registry.bakes()))
def test_every_requirement_is_a_bake(name):
    assert set(registry.bakes()[name].requires) <= set(registry.bakes())
