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


def test_wrong_format_under_every_suffix(tmp_path):
    """Each input format's bytes (and a PNG's) under every other input suffix, then byte mutations of small OBJ, PLY
    and STL files, through bake, inspect and validate in this process: no traceback or time-out; a file of another
    format exits 2 with one line naming the file and what it is."""
    import random

    import trimesh

    fuzz = load_fuzz()
    tetra = trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
                            process=False)
    gltf, binary = fuzz.quad()
    contents = {"obj": tetra.export(file_type="obj").encode(), "ply": tetra.export(file_type="ply"),
                "stl": tetra.export(file_type="stl"), "glb": fuzz.glb_bytes(gltf, binary), "png": fuzz.png_1x1()}
    what = {"obj": "text", "ply": "a PLY mesh", "stl": "binary data", "glb": "a GLB (binary glTF) file",
            "png": "a PNG image"}
    suffixes = ("obj", "ply", "stl", "glb", "gltf", "usda", "usdz")
    problems = []
    for kind, data in contents.items():
        for suffix in suffixes:
            if kind == suffix or (kind, suffix) in (("obj", "stl"), ("stl", "obj"), ("glb", "gltf")):
                continue  # the same format; text facets an STL reader judges; a .gltf holding a GLB is read as one
            path = tmp_path / f"{kind}_as.{suffix}"
            path.write_bytes(data)
            for command in ("bake", "inspect", "validate"):
                if command == "validate" and kind == "glb":
                    continue  # validate reads a GLB under any name, as glTF-Validator does
                argv = ["bake", str(path), "-o", str(tmp_path / "out.glb"), "--bakes", "edges", "-q"] \
                    if command == "bake" else fuzz.argv_for(command, path, tmp_path)
                code, _, stderr, tb, _ = fuzz.run_in_process(argv, 20.0)
                lines = stderr.strip().splitlines()
                if tb or code != 2 or len(lines) != 1 or str(path) not in lines[0]:
                    problems.append(f"{command} {path.name}: exit {code} {tb or lines}")
                elif kind != "obj" and what[kind] not in lines[0] and command != "validate":
                    problems.append(f"{command} {path.name}: does not say {what[kind]!r}: {lines[0]}")
    assert not problems, "\n".join(problems)
    rng = random.Random(0)
    stats = {"exits": {}, "warnings": {}}
    findings = []
    for index in range(30):
        suffix = ("obj", "ply", "stl")[index % 3]
        data = contents[suffix]
        steps = []
        for _ in range(rng.randint(1, 2)):
            data, step = fuzz.mutate_bytes(rng, data, False)
            steps.append(step)
        case = fuzz.Case(index, f"tetra_{suffix}", f"tetra.{suffix}", {f"tetra.{suffix}": data}, steps)
        findings += fuzz.run_case(case, tmp_path / "cases", 20.0, False, stats)
    assert not findings, "\n".join(f"{f.signature()} {f.steps}" for f in findings)
