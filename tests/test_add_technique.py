"""Adding a technique touches no file of baker: the steps of "How to add a technique" in ``docs/ARCHITECTURE.md``,
done here one by one on a throw-away technique in a temporary folder, then shown to the real CLI.

The technique, ``height``, writes each vertex's height above the lowest point of its mesh (``_HEIGHT``, scaled by
``--height-scale`` along ``--height-axis``) and ``BAKER_height`` on the material, and has a preview panel colouring
the surface by that height. Its truth is analytic: the height is the vertex coordinate minus the mesh's smallest one,
so the test checks it against the OBJ's own ``v`` lines and against the GLB read back with plain ``struct`` parsing,
not through baker; and the panel, unlit, must put every pixel on its colour ramp, higher up the screen where the
mesh is higher (a front view), inside the Lambert reference's silhouette (the sheet read back with Pillow).

Every step of the docs list is a ``STEP_*`` constant or a fixture below, named by its number; when the list changes,
this test changes with it.
"""
from __future__ import annotations

import json
import os
import shutil
import struct
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from scipy.ndimage import binary_erosion

REPO = Path(__file__).resolve().parents[1]
SPOT = REPO / "examples" / "spot" / "spot.obj"
PACKAGE = "baker_height"

# 1. a package with one frozen options dataclass (CLI flags ``--height-<option>``, recipe keys and API come from it)
STEP_1_OPTIONS = '''
"""Options of the height technique."""
from __future__ import annotations

from dataclasses import dataclass

from baker.options import opt


@dataclass(frozen=True)
class HeightOptions:
    """Options of the height bake (``--bakes height``)."""

    axis: str = opt("y", "the up axis of the mesh", choices=("x", "y", "z"))
    scale: float = opt(1.0, "units of the written height per mesh unit", min=0.0)
'''

# 2. the kernel: arrays in, a result dataclass out; no file, no glTF
STEP_2_KERNEL = '''
"""Height above the lowest point: h = (p . e_axis - min over the mesh) * scale, in mesh units times ``scale``."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

AXES = {"x": 0, "y": 1, "z": 2}


@dataclass(frozen=True)
class Heights:
    values: np.ndarray  # (n,) float64, >= 0
    lowest: float  # the mesh's smallest coordinate along the axis, mesh units


def height_above_lowest(positions: np.ndarray, lowest: float, axis: str, scale: float) -> Heights:
    """Height of each of ``positions`` (n, 3) above the coordinate ``lowest`` along ``axis``, times ``scale``."""
    return Heights(values=(positions[:, AXES[axis]] - lowest) * scale, lowest=float(lowest))
'''

# 3. the extension: NAME, write, read back into a typed object, check a document's use of it
STEP_3_EXTENSION = '''
"""``BAKER_height`` on a material and ``_HEIGHT`` on its primitives."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from baker.checks import check_vertex_attribute, is_number, pointer, primitives_using
from baker.gltf.vertex_attributes import padded

NAME = "BAKER_height"
ATTRIBUTE = "_HEIGHT"


@dataclass(frozen=True)
class HeightExtension:
    material: int
    attribute: str
    axis: str
    scale: float
    max_height: float


def write_vertex_heights(doc, mesh: int, primitive: int, heights: np.ndarray) -> int:
    accessor = doc.add_accessor(padded(heights), min_max=True)
    doc.json["meshes"][mesh]["primitives"][primitive]["attributes"][ATTRIBUTE] = accessor
    return accessor


def write_material(doc, material: int, *, axis: str, scale: float, max_height: float) -> None:
    ext = {"attribute": ATTRIBUTE, "axis": axis, "scale": float(scale), "maxHeight": float(max_height)}
    doc.set_material_extension(material, NAME, ext)


def read(doc) -> list:
    """Every material's BAKER_height as a :class:`HeightExtension`."""
    found = []
    for i, material in enumerate(doc.json.get("materials") or []):
        ext = (material.get("extensions") or {}).get(NAME)
        if isinstance(ext, dict):
            found.append(HeightExtension(i, ext["attribute"], ext["axis"], ext["scale"], ext["maxHeight"]))
    return found


def check(doc, places: list, issues) -> None:
    """The attribute exists on every primitive of the material, and its values lie in [0, maxHeight]."""
    for parts, ext in places:
        if len(parts) != 2 or parts[0] != "materials" or not isinstance(ext, dict):
            continue  # the schema pass reports it
        for m, p, prim in primitives_using(doc.json, parts[1]):
            values = check_vertex_attribute(doc, m, p, ext.get("attribute"), issues, code="BAKER_HEIGHT")
            if values is None or not is_number(ext.get("maxHeight")):
                continue
            if values.min() < 0 or values.max() > ext["maxHeight"] * (1 + 1e-6):
                where = pointer("accessors", prim["attributes"][ext["attribute"]])
                issues.error("BAKER_HEIGHT_OUT_OF_RANGE", f"heights span [{values.min():g}, {values.max():g}], "
                             f"outside [0, maxHeight {ext['maxHeight']:g}]", where)
'''

# 4. the step: kernel on the asset's cached geometry, results through the extension into the document
STEP_4_STEP = '''
"""Wire the height kernel to an Asset (``run``), and to the ``baker height-range`` command (``run_height_range``)."""
from __future__ import annotations

from baker.progress import QUIET

from baker_height import extension
from baker_height.kernel import height_above_lowest, AXES


def run(asset, options, seed: int = 0, progress=QUIET) -> None:
    doc = asset.doc
    lowest = {m: asset.mesh_triangles(m)[0][:, AXES[options.axis]].min() for m in range(len(asset.meshes()))}
    tallest = {}
    for material, members in asset.material_groups().items():
        for m, p in members:
            heights = height_above_lowest(asset.primitive(m, p).positions, lowest[m], options.axis, options.scale)
            extension.write_vertex_heights(doc, m, p, heights.values)
            tallest[material] = max(tallest.get(material, 0.0), float(heights.values.max()))
    for material, max_height in tallest.items():
        extension.write_material(doc, material, axis=options.axis, scale=options.scale, max_height=max_height)


def run_height_range(args) -> int:
    """``baker height-range IN``: the lowest and highest coordinate of the asset along the axis, as JSON."""
    import json

    import numpy as np

    from baker import readers

    asset = readers.read(args.input)
    values = np.concatenate([asset.mesh_triangles(m)[0][:, AXES[args.axis]] for m in range(len(asset.meshes()))])
    print(json.dumps({"lowest": float(values.min()), "highest": float(values.max())}))
    return 0
'''

# 5. a standalone command (optional): a light module with add_parser naming its work, ``run_<verb>`` in step.py
STEP_5_COMMAND = '''
"""``baker height-range IN``: the parser; the work is ``baker_height.step:run_height_range``."""
from __future__ import annotations

from baker.technique import lazy


def add_parser(sub) -> None:
    p = sub.add_parser("height-range", help="print the lowest and highest point of an asset along an axis")
    p.add_argument("input")
    p.add_argument("--axis", default="y", choices=("x", "y", "z"))
    p.set_defaults(func=lazy("baker_height.step:run_height_range"))
'''

# 6. a preview panel (optional): Panel objects of baker.preview.core, drawn by ``baker preview`` in ``order``
STEP_6_PANEL = '''
"""Preview panel of BAKER_height: the surface coloured by its baked height alone (unlit), from dark blue at height 0
to pale yellow at the material's ``maxHeight``."""
from __future__ import annotations

from baker.preview.core import DrawItem, Panel

from baker_height.extension import ATTRIBUTE, read

LOW, HIGH = (0.1, 0.15, 0.5), (1.0, 0.95, 0.6)  # the colours of height 0 and of maxHeight

# a technique from outside the repo has no module in runtime-shaders/, so its GLSL sits in the declarations
DECLARATIONS = f"""
uniform float u_maxHeight;
vec3 baker_height_color(float height, float maxHeight) {{
    float t = clamp(height / max(maxHeight, 1e-12), 0.0, 1.0);
    return mix(vec3{LOW}, vec3{HIGH}, t);
}}
"""


class HeightPanel(Panel):
    """``_HEIGHT`` normalized by the ``maxHeight`` of the item's material; items without BAKER_height get Lambert."""

    def read_item(self, doc, item: DrawItem) -> None:
        item.data["height"] = next((e for e in read(doc) if e.material == item.material_index), None)

    def applies(self, item: DrawItem) -> bool:
        return super().applies(item) and item.data.get("height") is not None

    def uniforms(self, item: DrawItem) -> dict:
        return {"u_maxHeight": item.data["height"].max_height}


PANELS = [HeightPanel("height", f"height ({ATTRIBUTE})", (), DECLARATIONS,
                      "color = baker_height_color(scalar, u_maxHeight);",
                      attribute=ATTRIBUTE, needs=(ATTRIBUTE,), order=15)]  # between thickness (10) and translucency (20)
'''

# 7. the Technique object, every heavy part named by a "module:attribute" string
STEP_7_INIT = '''
"""Height above the lowest point of the mesh, per vertex (a throw-away technique of tests/test_add_technique.py)."""
from baker.technique import Technique

from baker_height.options import HeightOptions

TECHNIQUE = Technique(
    name="height",
    summary="per-vertex height above the mesh's lowest point (_HEIGHT + BAKER_height)",
    options=HeightOptions,
    run="baker_height.step:run",
    extensions=("baker_height.extension",),
    panels="baker_height.panel:PANELS",
    commands=("baker_height.command",),
    schemas="baker_height:schemas",
)
'''

# 8. its schema, laid out like the repo's schemas/: <EXT>/schema/<kind>.<EXT>.schema.json (+ files it $refs)
STEP_8_SCHEMA = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "$id": "material.BAKER_height.schema.json",
    "title": "BAKER_height glTF Material Extension",
    "type": "object",
    "properties": {
        "attribute": {"type": "string", "pattern": "^_", "description": "The primitive attribute of the heights."},
        "axis": {"$ref": "axis.schema.json"},
        "scale": {"type": "number", "minimum": 0, "description": "Written height per mesh unit."},
        "maxHeight": {"type": "number", "minimum": 0, "description": "Largest height on the material's vertices."},
        "extensions": {}, "extras": {},
    },
    "required": ["attribute", "axis", "maxHeight"],
    "additionalProperties": False,
}
STEP_8_SCHEMA_REF = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "$id": "axis.schema.json",
    "type": "string", "enum": ["x", "y", "z"], "description": "The up axis of the mesh.",
}

# 9. the distribution's metadata: an entry point in the group baker.techniques names the TECHNIQUE object
STEP_9_METADATA = "Metadata-Version: 2.1\nName: baker-height\nVersion: 0.1\n"
STEP_9_ENTRY_POINTS = "[baker.techniques]\nheight = baker_height:TECHNIQUE\n"


# what each numbered step of the docs list must name, in order
DOCS_STEPS = {1: ("options.py",), 2: ("kernel.py",), 3: ("extension.py",), 4: ("step.py",), 5: ("command.py",),
              6: ("panel.py", "baker.preview.core"), 7: ("__init__.py", "panels="), 8: (".schema.json",),
              9: ("entry_points.txt",), 10: ("baker validate", "baker inspect", "baker preview")}


def test_the_docs_list_is_these_steps():
    text = (REPO / "docs" / "ARCHITECTURE.md").read_text()
    section = text.split("## How to add a technique")[1].split("\n## ")[0]
    items, current = {}, None
    for line in section.splitlines():
        head = line.split(". ", 1)[0]
        if head.isdigit():
            current = int(head)
            items[current] = line
        elif current is not None and line.startswith("   "):
            items[current] += " " + line.strip()
        else:
            current = None
    assert sorted(items) == sorted(DOCS_STEPS) and "tests/test_add_technique.py" in section
    for number, names in DOCS_STEPS.items():
        for name in names:
            assert name in items[number], f"step {number} of docs/ARCHITECTURE.md does not name {name}"
    assert all(f"STEP_{n}_" in Path(__file__).read_text() for n in range(1, 10))


@pytest.fixture(scope="module")
def plugin(tmp_path_factory) -> Path:
    """Steps 1-9 written into a temporary folder that is on no path of the repo."""
    root = tmp_path_factory.mktemp("site")
    package = root / PACKAGE
    package.mkdir()
    for name, text in [("options.py", STEP_1_OPTIONS), ("kernel.py", STEP_2_KERNEL),
                       ("extension.py", STEP_3_EXTENSION), ("step.py", STEP_4_STEP), ("command.py", STEP_5_COMMAND),
                       ("panel.py", STEP_6_PANEL), ("__init__.py", STEP_7_INIT)]:
        (package / name).write_text(textwrap.dedent(text).lstrip())
    schema = package / "schemas" / "BAKER_height" / "schema"
    schema.mkdir(parents=True)
    (schema / "material.BAKER_height.schema.json").write_text(json.dumps(STEP_8_SCHEMA, indent=2))
    (schema / "axis.schema.json").write_text(json.dumps(STEP_8_SCHEMA_REF, indent=2))
    info = root / f"{PACKAGE}-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(STEP_9_METADATA)
    (info / "entry_points.txt").write_text(STEP_9_ENTRY_POINTS)
    return root


def baker(plugin: Path, *args, check: bool = True) -> subprocess.CompletedProcess:
    """Step 10: the real CLI in a fresh interpreter, with the plugin's folder on PYTHONPATH (as ``pip install`` would
    put it on sys.path)."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(plugin), str(REPO)]))
    proc = subprocess.run([sys.executable, "-m", "baker.cli", *map(str, args)], capture_output=True, text=True,
                          env=env, cwd=plugin, timeout=600)
    if check:
        assert proc.returncode == 0, proc.stderr
    return proc


# ---------------------------------------------------------------------------------------------- an independent reader
def read_glb(path: Path) -> tuple[dict, bytes]:
    """(JSON, BIN chunk) of a GLB, by the container layout of the glTF 2.0 spec."""
    data = path.read_bytes()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    assert magic == b"glTF" and version == 2 and length == len(data)
    json_length, json_type = struct.unpack_from("<II", data, 12)
    assert json_type == 0x4E4F534A
    gltf = json.loads(data[20: 20 + json_length])
    bin_length, bin_type = struct.unpack_from("<II", data, 20 + json_length)
    assert bin_type == 0x004E4942
    start = 28 + json_length
    return gltf, data[start: start + bin_length]


def read_float_accessor(gltf: dict, blob: bytes, index: int) -> np.ndarray:
    accessor = gltf["accessors"][index]
    assert accessor["componentType"] == 5126
    width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[accessor["type"]]
    view = gltf["bufferViews"][accessor["bufferView"]]
    stride = view.get("byteStride", 4 * width)
    start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    rows = [struct.unpack_from(f"<{width}f", blob, start + i * stride) for i in range(accessor["count"])]
    return np.array(rows, np.float64).reshape(accessor["count"], width)


def obj_vertices(path: Path) -> np.ndarray:
    return np.array([line.split()[1:4] for line in path.read_text().splitlines() if line.startswith("v ")], float)


# ------------------------------------------------------------------------------------------------------------ the CLI
@pytest.fixture(scope="module")
def baked(plugin) -> Path:
    out = plugin / "out.glb"
    baker(plugin, "bake", SPOT, "-o", out, "--bakes", "height,thickness", "--height-scale", "2",
          "--thickness-rays", "4", "--thickness-texture-size", "16", "-q")
    return out


def shape_problems(folder: Path, package: str) -> list[str]:
    """What keeps the technique package in ``folder`` (importable as ``package``) from the shape every technique
    shares: the files of ``baker.technique.REQUIRED_FILES``; ``add_parser`` in command.py alone, each verb it adds
    naming ``run_<verb>`` of step.py as its work (and step.py defining it); the bake's ``run`` in step.py; the panels
    in panel.py."""
    import argparse
    import ast
    import importlib

    from baker.technique import REQUIRED_FILES, load

    problems = [f"{package}: no {name}" for name in REQUIRED_FILES if not (folder / name).is_file()]
    for module in sorted(folder.glob("*.py")):
        defined = {node.name for node in ast.parse(module.read_text()).body if isinstance(node, ast.FunctionDef)}
        if "add_parser" in defined and module.name != "command.py":
            problems.append(f"{package}: a parser outside command.py ({module.name})")
    technique = importlib.import_module(package).TECHNIQUE
    if technique.commands not in ((), (f"{package}.command",)):
        problems.append(f"{package}: commands {technique.commands} (one command.py holds every verb)")
    if technique.run is not None and technique.run != f"{package}.step:run":
        problems.append(f"{package}: the bake runs {technique.run}, not {package}.step:run")
    if technique.panels is not None and technique.panels != f"{package}.panel:PANELS":
        problems.append(f"{package}: panels {technique.panels}, not {package}.panel:PANELS")
    for reference in technique.commands:
        sub = argparse.ArgumentParser().add_subparsers()
        load(reference).add_parser(sub)
        for verb, parser in sub.choices.items():
            work = parser.get_default("func").__name__  # baker.technique.lazy names the reference it loads
            expected = f"{package}.step:run_{verb.replace('-', '_')}"
            if work != expected:
                problems.append(f"{package}: baker {verb} runs {work}, not {expected}")
            elif not callable(getattr(importlib.import_module(f"{package}.step"), expected.partition(":")[2], None)):
                problems.append(f"{package}: step.py has no {expected.partition(':')[2]}")
    return problems


def test_every_technique_folder_has_the_same_file_roles(plugin):
    """The built-in techniques and the plugin written by the docs' steps share one shape (the same file roles under
    the same names), so the steps describe every technique."""
    import baker.techniques

    root = Path(baker.techniques.__file__).parent
    folders = [(f, f"baker.techniques.{f.name}") for f in sorted(root.iterdir()) if (f / "__init__.py").is_file()]
    assert len(folders) >= 12
    sys.path.insert(0, str(plugin))
    try:
        problems = [p for folder, package in folders + [(plugin / PACKAGE, PACKAGE)]
                    for p in shape_problems(folder, package)]
    finally:
        sys.path.remove(str(plugin))
        for name in [n for n in sys.modules if n == PACKAGE or n.startswith(PACKAGE + ".")]:
            del sys.modules[name]  # the other tests meet the plugin in fresh interpreters only
    assert not problems, "\n".join(problems)


def test_help_lists_the_technique_its_command_and_flags(plugin):
    top = baker(plugin, "--help").stdout
    assert "height-range" in top and "lowest and highest point" in top
    bake = baker(plugin, "bake", "--help").stdout
    assert "height" in bake.split("known:")[1].split(")")[0]
    assert "--height-axis" in bake and "--height-scale" in bake and "the up axis of the mesh" in bake
    lowest = json.loads(baker(plugin, "height-range", SPOT).stdout)["lowest"]
    assert lowest == pytest.approx(obj_vertices(SPOT)[:, 1].min(), abs=1e-6)


def test_bake_writes_heights_equal_to_the_analytic_truth(baked):
    gltf, blob = read_glb(baked)
    assert {"BAKER_height", "BAKER_thickness"} <= set(gltf["extensionsUsed"])
    truth = obj_vertices(SPOT)[:, 1]
    for mesh in gltf["meshes"]:
        for prim in mesh["primitives"]:
            positions = read_float_accessor(gltf, blob, prim["attributes"]["POSITION"])
            heights = read_float_accessor(gltf, blob, prim["attributes"]["_HEIGHT"])[:, 0]
            np.testing.assert_allclose(heights, 2.0 * (positions[:, 1] - truth.min()), atol=1e-5)
            assert "_THICKNESS" in prim["attributes"]  # the other bake of the same run is there too
            ext = gltf["materials"][prim["material"]]["extensions"]["BAKER_height"]
            assert ext == {"attribute": "_HEIGHT", "axis": "y", "scale": 2.0,
                           "maxHeight": pytest.approx(2.0 * (truth.max() - truth.min()), rel=1e-5)}


def test_validate_passes_the_bake(plugin, baked):
    report = json.loads(baker(plugin, "validate", baked, "--no-khronos", "--format", "json").stdout)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert not [m for m in report["issues"]["messages"] if m["code"] == "BAKER_UNKNOWN_EXTENSION"]


def corrupted(baked: Path, name: str, change) -> Path:
    """A copy of ``baked`` with the JSON chunk edited by ``change(gltf)`` (same length: padded with spaces)."""
    data = bytearray(baked.read_bytes())
    json_length = struct.unpack_from("<I", data, 12)[0]
    gltf = json.loads(data[20: 20 + json_length])
    change(gltf)
    text = json.dumps(gltf, separators=(",", ":")).encode()
    assert len(text) <= json_length
    data[20: 20 + json_length] = text.ljust(json_length, b" ")
    out = baked.with_name(name)
    out.write_bytes(bytes(data))
    return out


def material_ext(gltf: dict) -> dict:
    return gltf["materials"][gltf["meshes"][0]["primitives"][0]["material"]]["extensions"]["BAKER_height"]


@pytest.mark.parametrize("name, change, code", [
    ("schema.glb", lambda gltf: material_ext(gltf).update(axis="w"), "BAKER_SCHEMA"),  # through axis.schema.json
    ("semantic.glb", lambda gltf: material_ext(gltf).update(maxHeight=material_ext(gltf)["maxHeight"] / 2),
     "BAKER_HEIGHT_OUT_OF_RANGE"),
])
def test_validate_fails_a_broken_copy(plugin, baked, name, change, code):
    broken = corrupted(baked, name, change)
    proc = baker(plugin, "validate", broken, "--no-khronos", "--format", "json", check=False)
    assert proc.returncode == 1, proc.stderr
    errors = [m for m in json.loads(proc.stdout)["issues"]["messages"] if m["severity"] == 0]
    assert [m["code"] for m in errors] == [code], errors


def test_inspect_lists_the_extension_and_the_attribute(plugin, baked):
    info = json.loads(baker(plugin, "inspect", baked, "--format", "json").stdout)
    assert "BAKER_height" in info["extensionsUsed"]
    assert all("BAKER_height" in m["extensions"] for m in info["materials"])
    baked_values = info["meshes"][0]["baked"]["_HEIGHT"]
    assert baked_values["min"] == pytest.approx(0.0, abs=1e-6) and baked_values["max"] > 0


def test_without_the_plugin_baker_does_not_know_it(plugin, baked, tmp_path):
    """The folder is all there is: the same files with the plugin off the path are an unknown bake and extension."""
    bare = tmp_path / "bare"
    bare.mkdir()
    shutil.copy(baked, bare / "out.glb")
    proc = baker(bare, "bake", SPOT, "-o", bare / "x.glb", "--bakes", "height", check=False)
    assert proc.returncode == 2 and "unknown bake(s) height" in proc.stderr
    proc = baker(bare, "validate", bare / "out.glb", "--no-khronos", "--format", "json", check=False)
    assert proc.returncode == 1  # an extension without its schema fails validation
    assert "BAKER_UNKNOWN_EXTENSION" in {m["code"] for m in json.loads(proc.stdout)["issues"]["messages"]}


# -------------------------------------------------------------------------------------------------------- the preview
VIEW, SIZE = "0,0", 160  # from +z at the mesh's mid-height: up the screen is up the y axis
LOW, HIGH = np.array([0.1, 0.15, 0.5]), np.array([1.0, 0.95, 0.6])  # the panel's colours of height 0 and maxHeight


def preview_sheet(plugin: Path, baked: Path, name: str, *panels: str) -> tuple[list[str], np.ndarray]:
    """(the panel names ``baker preview`` reports, in sheet order; the sheet as (H, W, 3) floats in [0, 1]), read back
    with Pillow."""
    from PIL import Image

    out = plugin / name
    args = ["--panels", ",".join(panels)] if panels else []
    proc = baker(plugin, "preview", baked, "-o", out, "--view", VIEW, "--size", SIZE, *args)
    line = proc.stderr.strip().splitlines()[-1]
    assert line.startswith("preview: ") and line.endswith(f" -> {out}"), proc.stderr
    names = line[len("preview: "): -len(f" -> {out}")].split(", ")
    return names, np.asarray(Image.open(out).convert("RGB"), np.float64) / 255.0


def sheet_panel(sheet: np.ndarray, names: list[str], name: str) -> np.ndarray:
    """The panel ``name`` of a contact sheet: up to three SIZE x SIZE panels a row, each under a label strip."""
    rows = -(-len(names) // 3)
    assert sheet.shape[1] == min(len(names), 3) * SIZE and sheet.shape[0] % rows == 0
    label = sheet.shape[0] // rows - SIZE
    r, c = divmod(names.index(name), 3)
    y = r * (SIZE + label) + label
    return sheet[y: y + SIZE, c * SIZE: (c + 1) * SIZE]


def covered(panel: np.ndarray) -> np.ndarray:
    """Pixels that are not the panel's background (its corner pixel)."""
    return np.abs(panel - panel[0, 0]).max(axis=2) > 0.02


@pytest.fixture(scope="module")
def height_panels(plugin, baked) -> tuple[np.ndarray, np.ndarray]:
    names, sheet = preview_sheet(plugin, baked, "pair.png", "lambert", "height")
    assert names == ["lambert", "height"]
    return sheet_panel(sheet, names, "lambert"), sheet_panel(sheet, names, "height")


def test_preview_draws_the_panel_alone_and_in_the_default_sheet(plugin, baked, height_panels):
    names, alone = preview_sheet(plugin, baked, "sheet.png", "height")
    assert names == ["height"] and alone.shape[1] == SIZE
    names, every = preview_sheet(plugin, baked, "every.png")
    # every panel with data, by Panel.order: height (15) between thickness (10) and translucency (20), although the
    # technique order (by name) puts height first
    assert names == ["lambert", "thickness", "height", "translucency"]
    # the camera frames the whole scene whichever panels are drawn: the same pixels in all three sheets
    for sheet, sheet_names in [(alone, ["height"]), (every, names)]:
        np.testing.assert_allclose(sheet_panel(sheet, sheet_names, "height"), height_panels[1], atol=2 / 255)


def test_preview_colours_the_surface_by_its_height(height_panels):
    lambert, height = height_panels
    mask = covered(lambert)
    assert 0.05 < mask.mean() < 0.8  # the mesh fills a sensible part of the frame
    # the same silhouette as the reference (up to its anti-aliased rim): the panel draws the surface and nothing else
    inside, near = binary_erosion(mask, iterations=2), ~binary_erosion(~mask, iterations=2)
    assert not (covered(height) & ~near).any() and covered(height)[inside].all()
    # unlit: every covered pixel lies on the LOW -> HIGH ramp; t is its height over maxHeight
    t = ((height - LOW) @ (HIGH - LOW)) / ((HIGH - LOW) @ (HIGH - LOW))
    ramp = LOW + np.clip(t, 0, 1)[..., None] * (HIGH - LOW)
    assert np.abs(height - ramp)[inside].max() < 0.02
    assert t[inside].min() > -0.02 and t[inside].max() < 1.02
    # higher on the mesh is higher on the screen at this view: the top half is brighter, t falls down the rows
    rows = np.broadcast_to(np.arange(SIZE)[:, None], mask.shape)
    top, bottom = inside & (rows < SIZE // 2), inside & (rows >= SIZE // 2)
    assert top.sum() > 100 and bottom.sum() > 100
    brightness = height.mean(axis=2)
    assert brightness[top].mean() > brightness[bottom].mean() + 0.15
    assert np.corrcoef(rows[inside], t[inside])[0, 1] < -0.95
    # the extremes: the topmost rows of the silhouette are near maxHeight, the lowest near 0
    covered_rows = np.flatnonzero(inside.any(axis=1))
    assert t[covered_rows[0]][inside[covered_rows[0]]].mean() > 0.9
    assert t[covered_rows[-1]][inside[covered_rows[-1]]].mean() < 0.1

