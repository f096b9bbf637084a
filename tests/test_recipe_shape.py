"""`baker build` checks the recipe's shape (schemas/recipe/recipe.schema.json) before any work: every malformed recipe
is exit 2 and one line naming the recipe, the line, the JSON pointer and the problem; nothing is written."""
from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from jsonschema import Draft202012Validator

SPOT = Path(__file__).parents[1] / "examples" / "spot" / "spot.obj"
SCHEMA = Path(__file__).parents[1] / "schemas" / "recipe" / "recipe.schema.json"

CASES = [
    ('[[build]]\noutput = "x"\n', ["line 1", "/build", "must be a table", "[[...]]", "write [build]"]),
    ('[build]\nbakez = ["edges"]\n', ["line 2", "/build/bakez", "unknown key", "known: output, format, bakes, seed"]),
    ('[bild]\n', ["line 1", "/bild", "unknown key"]),
    ('[build]\nbakes = "thickness"\n', ["line 2", "/build/bakes", "must be an array, not a string"]),
    ('[build]\nformat = "fbx"\n', ["line 2", "/build/format", "'fbx'"]),
    ('[build]\nseed = -1\n', ["line 2", "/build/seed", "minimum"]),
    ('[options]\nthickness = 3\n', ["/options/thickness", "must be a table"]),
    ('[[assets]]\nbakes = ["edges"]\n', ["/assets/0", "'inputs' is a required property"]),
    ('[[assets]]\ninputs = ["*.obj"]\nbake = ["edges"]\n', ["line 3", "/assets/0/bake", "unknown key"]),
    ('[[assets]]\ninputs = ["models/*.glb"]\n', ["line 2", "match no file"]),
    ('[build]\nbakes = ["nope"]\n[[assets]]\ninputs = ["*.obj"]\n', ["unknown bake(s) nope"]),
    ('[[assets]]\ninputs = ["*.obj"]\n[assets.options.thickness]\nrayz = 3\n', ["unknown option 'rayz'"]),
    ('[[commands]]\nargs = ["-o", "{output}"]\n', ["/commands/0", "'command' is a required property"]),
    ('[build\n', ["broken TOML"]),
]


@pytest.mark.parametrize("recipe, words", CASES, ids=[c[0].splitlines()[0] + f"-{i}" for i, c in enumerate(CASES)])
def test_malformed_recipe_is_one_line_and_exit_2(tmp_path, recipe, words):
    shutil.copy(SPOT, tmp_path / "spot.obj")
    (tmp_path / "baker.toml").write_text(recipe)
    before = sorted(p.name for p in tmp_path.iterdir())
    result = subprocess.run([sys.executable, "-m", "baker.cli", "build"], cwd=tmp_path, capture_output=True, text=True)
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in result.stderr, result.stderr
    assert lines[0].startswith("baker: error: baker.toml: ")
    for word in words:
        assert word in lines[0], lines[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # no output, no lock file


def test_the_example_recipe_and_the_readme_recipe_fit_the_schema():
    import tomllib

    validator = Draft202012Validator(json.loads(SCHEMA.read_text()))
    Draft202012Validator.check_schema(validator.schema)
    example = Path(__file__).parents[1] / "examples" / "baker.toml"
    assert not list(validator.iter_errors(tomllib.loads(example.read_text())))
    from baker.commands import build

    recipe = build.__doc__.split("::", 1)[1].split("\n\n")[1]  # the recipe shown in the module's docstring
    assert not list(validator.iter_errors(tomllib.loads("\n".join(line.split("  #")[0] for line in
                                                                   recipe.splitlines()))))


def test_an_unexpected_failure_keeps_its_traceback_in_the_report(tmp_path, monkeypatch):
    """A bug (not bad input) in one task: the table gets one line, the JSON report the whole traceback, and the
    other tasks still build."""
    import baker.pipeline
    from baker.commands.build import build, load_recipe

    shutil.copy(SPOT, tmp_path / "spot.obj")
    shutil.copy(SPOT, tmp_path / "cow.obj")
    (tmp_path / "baker.toml").write_text('[build]\nbakes = ["edges"]\n[[assets]]\ninputs = ["*.obj"]\n')
    real_bake = baker.pipeline.bake

    def flaky_bake(path, **kwargs):
        if Path(path).name == "cow.obj":
            raise ZeroDivisionError("a bug deep inside a kernel")
        return real_bake(path, **kwargs)

    monkeypatch.setattr(baker.pipeline, "bake", flaky_bake)
    report = build(load_recipe(tmp_path / "baker.toml"), jobs=1)
    assert report["baked"] == ["baked/spot.glb"]
    assert report["failed"] == [("baked/cow.glb", "ZeroDivisionError: a bug deep inside a kernel")]
    trace = report["tracebacks"]["baked/cow.glb"]
    assert trace.startswith("Traceback (most recent call last):") and "flaky_bake" in trace
    assert "ZeroDivisionError: a bug deep inside a kernel" in trace
