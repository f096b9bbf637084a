"""The one CI rule of tests/conftest.py: under CI a skipped test fails the run; elsewhere it is reported as a skip."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

TESTS = Path(__file__).parent


@pytest.mark.parametrize("ci, expected", [("true", 1), ("", 0)])
def test_a_skip_fails_under_ci(tmp_path, ci, expected):
    for name in ("conftest.py", "ci.py"):
        shutil.copy(TESTS / name, tmp_path / name)
    (tmp_path / "test_probe.py").write_text("import pytest\n\n\ndef test_needs_a_tool():\n"
                                            "    pytest.skip('the tool is missing')\n\n\ndef test_fine():\n"
                                            "    assert True\n")
    env = {**os.environ, "CI": ci}
    result = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", str(tmp_path)],
                            cwd=tmp_path, env=env, capture_output=True, text=True)
    assert result.returncode == expected, result.stdout
    if expected:
        assert "skipped under CI, which counts as a failure: Skipped: the tool is missing" in result.stdout
        assert "1 failed, 1 passed" in result.stdout
    else:
        assert "1 passed, 1 skipped" in result.stdout
