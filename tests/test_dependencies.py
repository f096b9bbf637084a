"""Every runtime dependency earns its place: some module under baker/ imports it (a peer that only benchmarks or tests
use belongs in the `benchmark` or `test` extra). The imports are read from baker's source with the ast module and
matched to distributions through the installed packages' own top-level names (importlib.metadata)."""
from __future__ import annotations

import ast
import re
import tomllib
from importlib import metadata
from pathlib import Path

REPO = Path(__file__).parents[1]


def requirement_name(requirement: str) -> str:
    return re.split(r"[\s<>=!~;\[]", requirement, maxsplit=1)[0]


def normalized(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def literal_import(call: ast.Call) -> str | None:
    """The module a call such as ``__import__("meshopt")`` or ``import_module("x")`` imports, when it is a literal;
    a name passed to a helper that calls ``__import__`` counts too (compression.py's ``_import(doc, "meshopt", ...)``)."""
    name = getattr(call.func, "id", None) or getattr(call.func, "attr", None)
    if name not in ("__import__", "import_module", "_import"):
        return None
    literals = [a.value for a in call.args if isinstance(a, ast.Constant) and isinstance(a.value, str)]
    return literals[0] if literals else None


def imported_top_level_modules(root: Path) -> set[str]:
    """Top-level module names imported anywhere under ``root`` (at module level or inside functions)."""
    names = set()
    for path in root.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                names.update(alias.name.split(".")[0] for alias in node.names)
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names.add(node.module.split(".")[0])
            elif isinstance(node, ast.Call) and literal_import(node):  # __import__("DracoPy"), import_module("x")
                names.add(literal_import(node).split(".")[0])
    return names


def module_names_of(distribution: str) -> set[str]:
    """The top-level modules a distribution installs, from its file list (packages and lone modules, compiled
    extensions included; Python 3.11's packages_distributions() misses a lone ``.so`` such as xatlas's)."""
    names = set()
    for file in metadata.distribution(distribution).files or ():
        top = file.parts[0]
        if top.endswith((".dist-info", ".data", ".pth")) or top in ("..", "__pycache__"):
            continue
        names.add(top.split(".")[0] if len(file.parts) == 1 else top)
    return names


def runtime_dependencies() -> list[str]:
    project = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]
    return [requirement_name(r) for r in project["dependencies"]]


def test_every_runtime_dependency_is_imported_by_baker():
    imported = imported_top_level_modules(REPO / "baker")
    unused = {}
    for distribution in runtime_dependencies():
        modules = module_names_of(distribution)
        assert modules, f"{distribution} installs no module"
        if not modules & imported:
            unused[distribution] = sorted(modules)
    assert not unused, f"runtime dependencies no module under baker/ imports (move them to an extra): {unused}"


def test_benchmark_and_test_peers_are_not_runtime_dependencies():
    """The peers the issue named (pymeshlab, scikit-image, fast-simplification: 320 MB) stay out of `pip install`."""
    runtime = {normalized(d) for d in runtime_dependencies()}
    assert not runtime & {"pymeshlab", "scikit-image", "fast-simplification", "scikit-learn"}
    extras = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    assert "pymeshlab" in {normalized(requirement_name(r)) for r in extras["benchmark"]}
    assert "scikit-image" in {normalized(requirement_name(r)) for r in extras["test"]}
