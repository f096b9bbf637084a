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


def declared_closure() -> set[str]:
    """The runtime dependencies and, recursively, what each requires outside any extra (markers evaluated here)."""
    from packaging.requirements import Requirement

    found, todo = set(), list(runtime_dependencies())
    while todo:
        name = normalized(todo.pop())
        if name in found:
            continue
        found.add(name)
        for text in metadata.requires(name) or ():
            requirement = Requirement(text)
            if requirement.marker is None or requirement.marker.evaluate({"extra": ""}):
                todo.append(requirement.name)
    return found


# Every reader module, what baker imports lazily for a format, and reads that take the fallback paths (trimesh's
# OBJ and STL readers on text that is not UTF-8, where trimesh would import charset_normalizer, which no declared
# dependency installs), run in a venv holding only the declared dependencies.
READ_EVERY_FORMAT = r'''
import importlib, pkgutil, struct, sys, tempfile, warnings
from pathlib import Path
import baker.readers
from baker.errors import BakerError
for info in pkgutil.iter_modules(baker.readers.__path__):
    importlib.import_module(f"baker.readers.{info.name}")
for name in ("trimesh.exchange.obj", "trimesh.exchange.ply", "trimesh.exchange.stl", "trimesh.exchange.gltf",
             "pxr.Usd", "pxr.UsdGeom", "pxr.UsdShade", "DracoPy", "meshopt", "fontTools.ttLib", "uharfbuzz",
             "OpenImageIO", "baker.gltf.compression", "baker.gltf.usd", "baker.techniques.glyphs.shaping"):
    importlib.import_module(name)
from baker import readers
folder = Path(tempfile.mkdtemp())
files = {
    "latin1.obj": "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nusemtl caf\xe9\nf 1 2 3\n".encode("latin-1"),
    "latin1.stl": ("solid caf\xe9\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
                   "endloop\nendfacet\nendsolid\n").encode("latin-1"),
    "header.stl": b"\xe9" * 80 + struct.pack("<I12fH", 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0),
    "ascii.ply": b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                 b"element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    "tri.usda": b'#usda 1.0\ndef Mesh "m" {\n  int[] faceVertexCounts = [3]\n  int[] faceVertexIndices = [0, 1, 2]\n'
                b'  point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]\n}\n',
}
for name, data in files.items():
    (folder / name).write_bytes(data)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        asset = readers.read(folder / name)
    assert sum(len(asset.primitive(m, p).faces) for m, _ in enumerate(asset.meshes())
               for p in asset.triangle_primitives(m)) == 1, name
(folder / "image.obj").write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(40))
try:
    readers.read(folder / "image.obj")
except BakerError as exc:
    assert "a PNG image" in str(exc), exc
print("read", len(files), "formats with", sorted({m.split(".")[0] for m in sys.modules}))
'''


def test_readers_need_only_declared_dependencies(tmp_path):
    """The venv: made with ``venv --without-pip``; its site-packages links to the installed files of the declared
    dependencies' closure only (what ``pip install baker`` would bring), so a reader that imports anything else,
    directly or through a library's lazy import, fails here with ImportError."""
    import subprocess
    import sys

    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(tmp_path / "venv")], check=True)
    site = next((tmp_path / "venv" / "lib").glob("python3*/site-packages"))
    linked = set()
    for distribution in sorted(declared_closure()):
        dist = metadata.distribution(distribution)
        for file in dist.files or ():
            top = file.parts[0]
            if top in ("..", "__pycache__") or top.endswith(".pth") or top in linked:
                continue
            target = Path(dist.locate_file(top))
            if target.exists():
                (site / top).symlink_to(target)
                linked.add(top)
    (site / "baker").symlink_to(REPO / "baker")
    python = tmp_path / "venv" / "bin" / "python"
    result = subprocess.run([str(python), "-I", "-c", READ_EVERY_FORMAT], capture_output=True, text=True,
                            cwd=tmp_path, timeout=300)
    assert result.returncode == 0, result.stderr[-3000:]
    assert "charset_normalizer" not in result.stdout
