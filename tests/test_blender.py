"""Blender (``bpy`` 4.5 from PyPI, in its own venv made by ``scripts/install-bpy``) opens every baked asset.

Stock Blender first, no add-on: every bake of examples/spot alone, all together, ``baker hair`` and ``baker text``
import without error, and each baked custom attribute arrives as a Blender mesh attribute whose values equal the
glTF accessor's (vertices matched by position). That is what the one-width layout of
:mod:`baker.gltf.vertex_attributes` exists for: with mixed widths Blender's importer fails (``do_primitives``
``ValueError``). Blender runs as a subprocess on the helper scripts in ``tests/blender/``.
"""
from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

from baker.cli import main as baker_main
from baker.gltf.document import GltfDocument

ROOT = Path(__file__).resolve().parents[1]
SPOT = ROOT / "examples" / "spot" / "spot.obj"
HELPERS = Path(__file__).parent / "blender"
FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
BAKES = ("thickness", "curvature", "edges", "fur", "skin", "tam", "toon")


@pytest.fixture(scope="session")
def blender_python() -> str:
    """The bpy venv's python: $BAKER_BPY_PYTHON (scripts/test sets it) or whatever scripts/install-bpy makes."""
    python = os.environ.get("BAKER_BPY_PYTHON")
    if not python:
        done = subprocess.run([str(ROOT / "scripts" / "install-bpy")], capture_output=True, text=True)
        assert done.returncode == 0, f"scripts/install-bpy failed:\n{done.stderr[-2000:]}"
        python = done.stdout.strip().splitlines()[-1]
    assert Path(python).is_file(), python
    return python


def run_blender(python: str, script: str, *args, timeout: int = 600) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    done = subprocess.run([python, str(HELPERS / script), *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, env=env)
    assert done.returncode == 0, f"{script} failed ({done.returncode}):\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}"
    return done


def bake(*argv) -> None:
    assert baker_main([*map(str, argv), "--quiet"]) in (0, None), argv


@pytest.fixture(scope="session")
def baked(tmp_path_factory) -> dict:
    """{label: .glb} for every bake of spot alone, all bakes together (with edge fins), hair and text."""
    out = tmp_path_factory.mktemp("blender_baked")
    files = {}
    for name in BAKES:
        files[name] = out / f"spot_{name}.glb"
        bake("bake", SPOT, "--bakes", name, "-o", files[name])
    files["edges_fins"] = out / "spot_edges_fins.glb"
    bake("bake", SPOT, "--bakes", "edges", "--edges-fins", "true", "-o", files["edges_fins"])
    files["all"] = out / "spot_all.glb"
    bake("bake", SPOT, "--bakes", ",".join(BAKES), "--edges-fins", "true", "-o", files["all"])
    files["hair"] = out / "spot_hair.glb"
    bake("hair", SPOT, "--guides", "40", "--children", "3", "-o", files["hair"])
    files["text"] = out / "text.glb"
    bake("text", "Baker AV", "--font", FONT, "-o", files["text"])
    return files


@pytest.fixture(scope="session")
def stock_report(blender_python, baked, tmp_path_factory) -> dict:
    report = tmp_path_factory.mktemp("blender_stock") / "report.json"
    run_blender(blender_python, "import_report.py", "--out", report, "--", *baked.values())
    return json.loads(report.read_text())


def custom_attributes(path) -> dict:
    """{mesh name: {attribute: [(positions (n, 3), values (n, k)) per primitive]}} of the baked file itself; a
    primitive of the mesh without the attribute gets zeros, as Blender's importer fills them."""
    doc = GltfDocument.load(path)
    found = {}
    for mesh in doc.json.get("meshes", []):
        prims = [(doc.accessor(prim["attributes"]["POSITION"]).astype(np.float32), prim["attributes"])
                 for prim in mesh["primitives"]]
        names = {n for _, attrs in prims for n in attrs if n.startswith("_")}
        per = found.setdefault(mesh.get("name", ""), {})
        for name in sorted(names):
            width = next(doc.accessor(attrs[name]).reshape(len(pos), -1).shape[1] for pos, attrs in prims
                         if name in attrs)
            per[name] = [(pos, doc.accessor(attrs[name]).reshape(len(pos), -1) if name in attrs
                          else np.zeros((len(pos), width), np.float32)) for pos, attrs in prims]
    return found


def assert_values_follow_positions(name, blender_positions, blender_values, gltf_parts) -> None:
    """Every Blender vertex carries the value of a glTF vertex at its position (Blender may merge, split or reorder
    vertices; it moves neither positions nor custom attribute values off their float32 values, so compare exactly)."""
    width = gltf_parts[0][1].shape[1]
    blender_values = np.asarray(blender_values, np.float32)
    assert blender_values.shape[1] == width, f"{name}: width {blender_values.shape[1]}, glTF {width}"
    pairs = lambda pos, val: {a + b for a, b in zip(map(bytes, np.ascontiguousarray(pos, np.float32)),
                                                      map(bytes, np.ascontiguousarray(val, np.float32)))}
    table = set().union(*(pairs(pos, val) for pos, val in gltf_parts))
    got = pairs(np.asarray(blender_positions, np.float32), blender_values)
    missing = got - table
    assert not missing, f"{name}: {len(missing)} Blender (position, value) pairs match no glTF vertex"


@pytest.mark.parametrize("label", [*BAKES, "edges_fins", "all", "hair", "text"])
def test_stock_blender_imports_every_bake(label, baked, stock_report):
    entry = stock_report[str(baked[label])]
    assert entry["error"] is None, f"stock Blender failed to import {label}: {entry['error']}"
    meshes = [o for o in entry["objects"] if o["type"] == "MESH"]
    assert meshes, f"{label}: no mesh object imported"
    expected = custom_attributes(baked[label])
    for obj in meshes:
        mesh_name = next((m for m in expected if m and obj["mesh"].startswith(m)), None)
        if mesh_name is None and len(expected) == 1:
            mesh_name = next(iter(expected))
        attrs = expected.get(mesh_name, {})
        for name, parts in attrs.items():
            assert name in obj["attributes"], f"{label}: {obj['name']} lacks {name} in Blender"
            got = obj["attributes"][name]
            assert got["domain"] == "POINT" and got["data_type"] == "FLOAT_VECTOR", (name, got["data_type"])
            assert_values_follow_positions(f"{label}/{name}", obj["positions"], got["values"], parts)
    baked_names = {n for attrs in expected.values() for n in attrs}
    imported = {n for o in meshes for n in o["attributes"] if n.startswith("_")}
    assert baked_names <= imported, f"{label}: Blender dropped {sorted(baked_names - imported)}"
