"""The WGSL runtime modules (runtime-shaders/baker_*.wgsl) against the GLSL ones: one WGSL module beside every GLSL
module with the same functions, each compiling in Chromium's WebGPU without a message, and every function agreeing
with the numpy twin its GLSL function is rendered against (tests/gl/twins_*.py) on the same inputs, evaluated in a
WebGPU compute pass (a fragment pass for the functions that sample with implicit derivatives) in headless Chromium
on SwiftShader. No adapter fails the test: it is never skipped."""
from __future__ import annotations

import re

import numpy as np
import pytest

from browser import require_tools

from .glsl import REPO, read_module
from .wgsl import job, read_wgsl, run_jobs
from .wgsl_cases import all_cases

MODULES = sorted(p.stem[len("baker_"):] for p in (REPO / "runtime-shaders").glob("baker_*.glsl"))
CASES = all_cases()


def _strip_comments(text: str) -> str:
    return re.sub(r"/\*.*?\*/", "", re.sub(r"//[^\n]*", "", text), flags=re.S)


def glsl_functions(name: str) -> set:
    return set(re.findall(r"^\s*[\w ]+?\s+(baker_\w+)\s*\(", _strip_comments(read_module(f"baker_{name}.glsl")), re.M))


def wgsl_functions(name: str) -> set:
    return set(re.findall(r"^\s*fn\s+(baker_\w+)\s*\(", _strip_comments(read_wgsl(f"baker_{name}.wgsl")), re.M))


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    """Every module compiled alone, all of them concatenated, and every case run: one Chromium launch."""
    require_tools("WGSL")
    jobs = [{"name": f"validate:{name}", "code": read_wgsl(f"baker_{name}.wgsl"), "stage": "validate"}
            for name in MODULES]
    jobs.append({"name": "validate:all", "stage": "validate",
                 "code": "\n".join(read_wgsl(f"baker_{name}.wgsl") for name in MODULES)})
    jobs += [job(case) for case in CASES]
    return run_jobs(jobs, tmp_path_factory.mktemp("wgsl") / "jobs.json")


def _no_messages(result):
    assert "error" not in result, result["error"]
    assert result["messages"] == [], "\n".join(f"{m['type']} {m['line']}:{m['column']}: {m['message']}"
                                               for m in result["messages"])


def test_every_wgsl_module_has_a_glsl_module():
    wgsl = sorted(p.stem[len("baker_"):] for p in (REPO / "runtime-shaders").glob("baker_*.wgsl"))
    assert wgsl == MODULES


@pytest.mark.parametrize("name", MODULES)
def test_wgsl_module_has_the_glsl_functions(name):
    """The same function names as the GLSL module, and a case (tests/gl/wgsl_cases.py) for every one of them."""
    assert (REPO / "runtime-shaders" / f"baker_{name}.wgsl").is_file(), f"no WGSL twin of baker_{name}.glsl"
    assert wgsl_functions(name) == glsl_functions(name)
    tested = {case.function for case in CASES if case.module == name}
    assert tested == wgsl_functions(name), f"functions without a case: {sorted(wgsl_functions(name) - tested)}"


@pytest.mark.parametrize("name", MODULES)
def test_wgsl_module_compiles_without_messages(results, name):
    """createShaderModule + getCompilationInfo(): no error, no warning, no info."""
    _no_messages(results[f"validate:{name}"])


def test_wgsl_modules_concatenate(results):
    """Pasted together, the modules clash in no name (WGSL has no include guard)."""
    _no_messages(results["validate:all"])


@pytest.mark.parametrize("name", MODULES)
def test_wgsl_agrees_with_the_twins(results, name):
    cases = [case for case in CASES if case.module == name]
    assert cases
    failures = []
    for case in cases:
        result = results[case.name]
        _no_messages(result)
        got = result["outputs"].reshape(case.count, -1).astype(np.float64)
        want = np.asarray(case.reference(case.inputs), np.float32).reshape(case.count, -1).astype(np.float64)
        assert got.shape == want.shape, case.name
        assert np.isfinite(want).all(), f"{case.name}: the twin is not finite on these inputs"
        absolute, relative = case.tolerance
        error = np.abs(got - want)
        bad = ~(error <= absolute + relative * np.abs(want))
        scale = np.maximum(np.abs(want), 1e-30)
        worst_relative = (error / scale)[np.abs(want) > absolute].max(initial=0)
        print(f"{case.name}: max abs {error.max():.3g}, max rel {worst_relative:.3g}"
              f" (tolerance {absolute:g} + {relative:g} |x|{', ' + case.why if case.why else ''})")
        if bad.any():
            row = int(np.argwhere(bad)[0][0])
            failures.append(f"{case.name}: {int(bad.any(axis=1).sum())} of {case.count} samples differ, e.g. "
                            f"sample {row}: WGSL {got[row].tolist()} twin {want[row].tolist()} inputs "
                            f"{ {k: np.asarray(v)[row].tolist() for k, v in case.inputs.items()} }")
    assert not failures, "\n".join(failures)
