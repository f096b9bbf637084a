"""Write every corpus case into a folder: ``python tests/corpus/make_corpus.py OUT``.

Cases come from the ``cases_*.py`` modules of this folder (each defines ``CASES``); one sub-folder per case, with an
``outside/secret.bin`` beside the case folders that no case may read.
"""
from __future__ import annotations

import importlib
import sys
from pathlib import Path

HERE = Path(__file__).parent
SECRET = b"BAKER-CORPUS-SECRET-" * 16


def all_cases() -> list:
    cases = []
    for path in sorted(HERE.glob("cases_*.py")):
        cases += importlib.import_module(f"corpus.{path.stem}").CASES
    names = [c.name for c in cases]
    duplicates = {n for n in names if names.count(n) > 1}
    assert not duplicates, f"two corpus cases share a name: {duplicates}"
    return cases


def write(root: Path, http: str = "http://127.0.0.1:9/") -> dict:
    """Write every case under ``root``; returns {case name: (case, input path)}."""
    outside = root / "outside"
    outside.mkdir(parents=True, exist_ok=True)
    (outside / "secret.bin").write_bytes(SECRET)
    env = {"outside": outside, "http": http}
    made = {}
    for case in all_cases():
        folder = root / "cases" / case.name
        folder.mkdir(parents=True, exist_ok=True)
        made[case.name] = (case, case.make(folder, env))
    return made


if __name__ == "__main__":
    sys.path.insert(0, str(HERE.parent))
    for name, (case, path) in write(Path(sys.argv[1])).items():
        print(f"{name}: {path} ({case.rule})")
