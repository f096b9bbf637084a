"""The layer rules of docs/ARCHITECTURE.md, read from the source: shared layers import no technique and nothing above
them, no module imports another's underscore name, no import cycles (function-level imports count), and the CLI's
parser imports no numpy-heavy module."""
from __future__ import annotations

import ast
import dataclasses
import subprocess
import sys
from pathlib import Path

PACKAGE = Path(__file__).parents[1] / "baker"
SHARED = ("baker.readers", "baker.geometry", "baker.texels", "baker.gltf", "baker.checks", "baker.diffusion_profile")
ABOVE = ("baker.techniques", "baker.cli", "baker.commands", "baker.pipeline", "baker.registry", "baker.api",
         "baker.preview", "baker.validate")


def modules() -> dict[str, Path]:
    found = {}
    for path in PACKAGE.rglob("*.py"):  # rglob does not enter the linked data folders
        parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        found[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return found


def imports(name: str, path: Path, known: dict) -> list[tuple[str, str]]:
    """(imported module, imported name) for every import in the file, relative ones resolved."""
    out = []
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(package.split(".")[: len(package.split(".")) - node.level + 1] + ([base] if base else []))
            for alias in node.names:
                target = f"{base}.{alias.name}"
                out.append((target, "") if target in known else (base, alias.name))
        elif isinstance(node, ast.Import):
            out += [(alias.name, "") for alias in node.names]
    return [(m, n) for m, n in out if m.split(".")[0] == "baker"]


def test_shared_layers_import_nothing_above_them():
    known = modules()
    bad = [(name, target) for name, path in known.items() if name.startswith(SHARED)
           for target, _ in imports(name, path, known) if target.startswith(ABOVE)]
    assert not bad


def test_no_underscore_names_across_modules():
    known = modules()
    bad = [(name, target, symbol) for name, path in known.items() for target, symbol in imports(name, path, known)
           if symbol.startswith("_") and not symbol.startswith("__") and target != name]
    assert not bad


def test_no_import_cycles():
    known = modules()
    graph = {name: {t for t, _ in imports(name, path, known) if t in known and t != name} for name, path in known.items()}
    state, stack = {}, []

    def visit(node):  # depth-first search; a grey node reached again closes a cycle
        state[node] = "grey"
        stack.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == "grey":
                raise AssertionError("import cycle: " + " -> ".join(stack[stack.index(nxt):] + [nxt]))
            if nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = "black"

    for name in sorted(graph):
        if name not in state:
            visit(name)


def test_building_the_parser_imports_no_heavy_module():
    probe = ("import sys\nfrom baker import commands\ncommands.build_parser()\n"
             "print(sorted({m.split('.')[0] for m in sys.modules} & {'numpy', 'numba', 'scipy', 'trimesh', 'pxr', "
             "'moderngl', 'PIL', 'embreex'}))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_edge_settings_match_the_edges_options():
    from baker.geometry.edges import EdgeSettings
    from baker.techniques.edges.options import EdgesOptions

    settings, options = EdgeSettings(), EdgesOptions()
    for f in dataclasses.fields(EdgeSettings):
        assert getattr(settings, f.name) == getattr(options, f.name), f.name


def test_validate_and_inspect_import_no_kernel(tmp_path):
    """`baker validate` and `baker inspect` read and check; they never need a numba kernel (fast start)."""
    spot = Path(__file__).parents[1] / "examples" / "spot" / "spot.obj"
    baked = tmp_path / "all.glb"
    subprocess.run([sys.executable, "-m", "baker.cli", "bake", str(spot), "-o", str(baked), "-q", "--bakes",
                    "thickness,curvature,skin,edges,tam,toon,fur", "--thickness-rays", "4", "--thickness-per-texel",
                    "false", "--curvature-per-texel", "false", "--tam-size", "32", "--tam-levels", "1",
                    "--fur-texture-size", "32", "--fur-fins", "true", "--fur-shells", "2", "--edges-fins", "true"],
                   check=True)
    probe = ("import sys, io, contextlib\nfrom baker.validate import validate_file\nfrom baker.commands.inspect import "
             f"main\nassert validate_file({str(baked)!r}, khronos=False)['issues']['numErrors'] == 0\n"
             f"with contextlib.redirect_stdout(io.StringIO()):\n    main({str(baked)!r})\n"
             "print(sorted({m.split('.')[0] for m in sys.modules} & {'numba', 'scipy', 'trimesh', 'pxr', 'moderngl'}))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]"
