"""A bake's output does not depend on which other bakes ran: each bake alone (with those it ``requires``) and all of
them in one run write the same data for it (read back from the written files), on a mesh with its own UVs and on one that must be unwrapped."""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import baker
from baker.errors import BakeNote
from baker import readers
from baker.gltf.document import GltfDocument
from baker.pipeline import save
from baker.registry import bakes

SPOT = Path(__file__).parents[1] / "examples" / "spot" / "spot.obj"
FAST = {
    "thickness": {"rays": 8, "texture_size": 64},
    "curvature": {"per_texel": True, "texture_size": 64},
    "skin": {"width": 32, "height": 32, "penumbra_size": 16},
    "edges": {"fins": True},
    "tam": {"size": 32, "levels": 1},
    "fur": {"fins": True, "shells": 4, "texture_size": 32, "hairs": 100},
    "caustics": {"size": 32, "frames": 2, "waves": 8},
}
# primitive extension members that are not accessors (the fins primitive's index and its mesh's)
NOT_ACCESSORS = {"fins", "finsOf"}
# accessors of vertex indices: compared as the positions they name (an unwrap splits and renumbers vertices)
VERTEX_INDICES = {"edges", "oppositeVertices"}
# normal-blur needs a normal map, which neither mesh has (it notes so); fur unwraps a mesh without UVs as the
# texture bakes do
BAKES = sorted(bakes())


def uv_less_spot(folder: Path) -> Path:
    """spot.obj without its ``vt`` lines (faces keep positions and normals): a mesh every texture bake unwraps."""
    lines = []
    for line in SPOT.read_text().splitlines():
        if line.startswith("vt "):
            continue
        if line.startswith("f "):
            corners = [c.split("/") for c in line.split()[1:]]
            line = "f " + " ".join(f"{c[0]}//{c[2]}" if len(c) == 3 and c[2] else c[0] for c in corners)
        lines.append(line)
    path = folder / "spot_no_uv.obj"
    path.write_text("\n".join(lines) + "\n")
    return path


def bake_file(source: Path, names: list[str], out: Path) -> GltfDocument:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BakeNote)  # normal-blur's note that there is no normal map
        asset = baker.bake(source, bakes=names, options={k: v for k, v in FAST.items() if k in names})
    save(asset, out)
    return GltfDocument.load(out)


def resolved(doc: GltfDocument, value, accessors: bool, positions=None):
    """An extension's JSON with its references replaced by what they point at (textures by their encoded images,
    accessors by their data, a primitive by :func:`primitive_key`): what a reader sees, whatever the indices are.
    Where ``accessors``, the top-level integer members are accessors too (a primitive extension's, whose vertex
    indices become the ``positions`` they name)."""
    if isinstance(value, dict):
        out = {}
        for key, item in value.items():
            if key in ("index", "texture") and isinstance(item, int):
                out[key] = doc.image_bytes(doc.json["textures"][item]["source"])
            elif (key == "accessor" or accessors and key not in NOT_ACCESSORS) and isinstance(item, int) \
                    and not isinstance(item, bool):
                data = doc.accessor(item)
                out[key] = (positions[data] if key in VERTEX_INDICES and accessors else data).tolist()
            elif key == "primitive" and isinstance(value.get("mesh"), int):
                out[key] = primitive_key(value["mesh"], item, doc.json["meshes"][value["mesh"]]["primitives"][item])
            else:
                out[key] = resolved(doc, item, False)
        return out
    if isinstance(value, list):
        return [resolved(doc, item, False) for item in value]
    return value


def primitive_key(m: int, p: int, prim: dict) -> tuple:
    """A primitive of the input by its place; one a bake added (fins) by its attribute names, which say which bake
    added it, whatever other bakes added before it."""
    return (m, p) if p < INPUT_PRIMITIVES else (m, "added", tuple(sorted(prim["attributes"])))


INPUT_PRIMITIVES = 1  # spot is one primitive


def corner_attributes(doc: GltfDocument, input_names: set) -> dict:
    """Per primitive, each attribute a bake added, one value per triangle corner (seam splits aside)."""
    out = {}
    for m, mesh in enumerate(doc.json["meshes"]):
        for p, prim in enumerate(mesh["primitives"]):
            corners = doc.accessor(prim["indices"]).reshape(-1) if "indices" in prim else slice(None)
            for name, index in prim["attributes"].items():
                if name not in input_names:
                    out[(*primitive_key(m, p, prim), name)] = doc.accessor(index)[corners]
    return out


def extension_data(doc: GltfDocument, names: set) -> dict:
    out = {}
    for i, material in enumerate(doc.json.get("materials", [])):
        for name, value in (material.get("extensions") or {}).items():
            if name in names:
                out[("material", i, name)] = resolved(doc, value, False)
    for m, mesh in enumerate(doc.json["meshes"]):
        for p, prim in enumerate(mesh["primitives"]):
            for name, value in (prim.get("extensions") or {}).items():
                if name in names:
                    positions = doc.accessor(prim["attributes"]["POSITION"])
                    out[("primitive", *primitive_key(m, p, prim), name)] = resolved(doc, value, True, positions)
    for name, value in (doc.json.get("extensions") or {}).items():
        if name in names:
            out[("root", name)] = resolved(doc, value, False)
    return out


def assert_same(alone, together, what):
    assert alone.keys() <= together.keys(), (what, sorted(set(alone) - set(together)))
    for key, value in alone.items():
        if isinstance(value, np.ndarray):
            other = together[key]
            if value.shape != other.shape and value.shape[:1] == other.shape[:1]:
                # the blender layout pads a mesh's custom attributes to the widest data the run's bakes write
                # (SCALAR for thickness alone, VEC3 with curvature's directions): the same data, zeros beyond it
                value, other = value.reshape(len(value), -1), other.reshape(len(other), -1)
                width = min(value.shape[1], other.shape[1])
                assert not value[:, width:].any() and not other[:, width:].any(), (what, key, "padding")
                value, other = value[:, :width], other[:, :width]
            assert np.array_equal(value, other), (what, key)
        else:
            assert value == together[key], (what, key)


@pytest.mark.parametrize("with_uvs", [True, False], ids=["spot", "spot-without-uvs"])
def test_each_bake_alone_writes_what_it_writes_with_all_others(tmp_path, with_uvs):
    source = SPOT if with_uvs else uv_less_spot(tmp_path)
    names = BAKES
    plain = readers.read(source).doc
    assert len(plain.json["meshes"]) == 1 and len(plain.json["meshes"][0]["primitives"]) == INPUT_PRIMITIVES
    input_names = set(plain.json["meshes"][0]["primitives"][0]["attributes"])
    together = bake_file(source, names, tmp_path / "all.glb")
    together_attributes = corner_attributes(together, input_names)
    compared = 0
    for name in names:
        # a bake that reads another's output (skin reads curvature) runs with it, as it is meant to
        alone = bake_file(source, [name, *bakes()[name].requires], tmp_path / f"{name}.glb")
        extensions = {ext.NAME for ext in bakes()[name].extension_objects()}
        alone_data = extension_data(alone, extensions)
        assert_same(corner_attributes(alone, input_names), together_attributes, name)
        assert_same(alone_data, extension_data(together, extensions), name)
        compared += len(alone_data)
    assert compared >= len(names) - 1  # every bake but normal-blur (no normal map here) wrote extension data
