"""The fixed-seed short fuzz run (scripts/fuzz.py): 200 mutated GLB/glTF cases through ``bake --bakes edges``,
``inspect`` and ``validate --no-khronos``, in this process. No traceback, no time-out, no exit code other than
0/1/2, nothing left behind by a failed bake. A failure lists each distinct finding with its case number; reproduce
one with ``scripts/fuzz.py --seed 0 --only K --keep DIR``."""
from __future__ import annotations

import importlib.util
import sys
import time
from pathlib import Path

from baker import validate
from conftest import assert_khronos_clean

ROOT = Path(__file__).resolve().parents[1]
CASES, SEED = 200, 0


def load_fuzz():
    spec = importlib.util.spec_from_file_location("baker_fuzz", ROOT / "scripts" / "fuzz.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


def test_fixed_seed_fuzz_finds_nothing():
    fuzz = load_fuzz()
    start = time.perf_counter()
    report = fuzz.fuzz(cases=CASES, seed=SEED, timeout=20.0)
    elapsed = time.perf_counter() - start
    assert report["cases"] == CASES
    # every command really ran on every case: an exit code was recorded 3 x CASES times
    assert sum(report["exits"].values()) == 3 * CASES
    assert not report["findings"], fuzz.format_report(report)
    assert elapsed < 120, f"the short fuzz run took {elapsed:.0f} s (budget 60 s on 2 cores)"


def test_seeds_are_valid(tmp_path):
    """The unmutated seeds pass baker's checks and Khronos glTF-Validator, and bake, inspect and validate exit 0."""
    fuzz = load_fuzz()
    seeds = fuzz.make_seeds(tmp_path / "seeds")
    assert {s.main for s in seeds} == {"spot.glb", "spot.gltf", "quad.gltf", "quad.glb"}
    for seed in seeds:
        path = tmp_path / "seeds" / seed.name / seed.main
        assert_khronos_clean(path)
        report = validate.validate_file(path)
        assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
        stats = {"exits": {}, "warnings": {}}
        case = fuzz.Case(0, seed.name, seed.main, dict(seed.files))
        assert fuzz.run_case(case, tmp_path / "cases", 60.0, False, stats) == []
        assert set(stats["exits"]) == {"bake 0", "inspect 0", "validate 0"}, stats["exits"]


def test_cases_are_reproducible(tmp_path):
    """Case k of a seed is the same bytes every time, whatever ran before it."""
    fuzz = load_fuzz()
    gltf, binary = fuzz.quad()
    seeds = [fuzz.Seed("quad_glb", "quad.glb", {"quad.glb": fuzz.glb_bytes(gltf, binary)}),
             fuzz.Seed("quad_gltf", "quad.gltf", {"quad.gltf": b"{}", "quad.bin": binary})] * 2
    a = [fuzz.make_case(seeds, 7, k).files for k in range(30)]
    b = [fuzz.make_case(seeds, 7, k).files for k in reversed(range(30))][::-1]
    assert a == b
    assert len({tuple(sorted(f.items())) for f in a}) > 20  # and they differ from each other
