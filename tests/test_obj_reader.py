"""The direct OBJ reader (baker/readers/obj.py) against the trimesh path it replaces, an independent reader:

- every OBJ the tests write (material quads, degenerate meshes, the corpus' tetrahedra, trimesh's own export), the
  repository's spot and the shared meshes give the same document through both paths: names, materials, accessor
  JSON and every accessor's values, bit for bit;
- forms trimesh reads differently (quads only, mixed polygons, v//vn, vt with w, repeated usemtl sections, 'o'
  names, CRLF) the same; negative indices give the same triangles (up to vertex order);
- what the direct reader does not take falls back to trimesh, decided by the scan: lines, points, free-form
  statements, vertex colours;
- bad indices (0, past the end, negative past the start) are refused naming the line;
- ``baker bake`` of an OBJ imports neither trimesh nor scipy.spatial/sparse.
"""
from __future__ import annotations

import ast
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

from baker.errors import BakerError
from baker import readers
from baker.readers.mtl import read_obj_materials
from baker.readers.obj import non_finite_location, read_direct, read_obj_groups
from baker.readers.trimesh_scene import LibraryResolver, doc_from_trimesh_scene, load_trimesh
from test_materials import QUAD_OBJ
from test_mesh_inputs import DEGENERATE, _obj

ROOT = Path(__file__).parents[1]
TETRA = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
GRID = "".join(f"v {x} {y} {0.1 * x * y}\n" for y in range(4) for x in range(4)) + \
       "".join(f"vt {x / 3} {y / 3} 0\n" for y in range(4) for x in range(4)) + "vn 0 0 1\nvn 0.1 0 2\n"


def quad(x, y, form="v/vt/vn", n=1):
    a, b, c, d = (y * 4 + x + 1, y * 4 + x + 2, y * 4 + x + 6, y * 4 + x + 5)
    if form == "v":
        return f"{a} {b} {c} {d}"
    if form == "v//vn":
        return f"{a}//{n} {b}//{n} {c}//{n} {d}//{n}"
    return " ".join(f"{i}/{i}/{n}" for i in (a, b, c, d))


def trimesh_document(path):
    materials, libraries = read_obj_materials(path)
    loaded = load_trimesh(path, resolver=LibraryResolver(libraries))
    return doc_from_trimesh_scene(path, loaded, materials, non_finite_location)


def assert_same_document(path, order_free=False):
    direct = read_direct(Path(path), read_obj_materials(Path(path))[0])
    assert direct is not None, "fell back to trimesh"
    reference = trimesh_document(Path(path))
    for item in reference.json["meshes"] + reference.json["nodes"]:  # trimesh names some meshes by the whole path
        item["name"] = item["name"].replace(str(path), Path(path).name)
    for key in ("scenes", "nodes", "materials") + (() if order_free else ("meshes", "accessors")):
        assert direct.json.get(key) == reference.json.get(key), key
    assert len(direct.json["meshes"]) == len(reference.json["meshes"])
    for mine, theirs in zip(direct.json["meshes"], reference.json["meshes"]):
        (p,), (q,) = mine["primitives"], theirs["primitives"]
        assert sorted(p["attributes"]) == sorted(q["attributes"]) and p["material"] == q["material"]
        faces_p, faces_q = direct.accessor(p["indices"]).reshape(-1, 3), reference.accessor(q["indices"]).reshape(-1, 3)
        if not order_free:
            assert np.array_equal(faces_p, faces_q)
            for name in p["attributes"]:
                assert np.array_equal(direct.accessor(p["attributes"][name]), reference.accessor(q["attributes"][name]))
            continue
        # up to vertex order: every triangle's corners carry the same attribute values
        for name in p["attributes"]:
            a = direct.accessor(p["attributes"][name])[faces_p]
            b = reference.accessor(q["attributes"][name])[faces_q]
            assert np.allclose(a, b, atol=1e-6), name


def write(tmp_path, name, text, mtl=None):
    if mtl:
        (tmp_path / "m.mtl").write_text(mtl)
    path = tmp_path / name
    path.write_bytes(text.encode())
    return path


MTL = "newmtl a\nKd 1 0 0\nNs 10\nnewmtl b\nKd 0 1 0\nnewmtl c d\nKd 0 0 1\n"
CASES = {
    "quad-materials": (QUAD_OBJ.format(mtl="m.mtl", first="a", second="b"), MTL),
    "quad-no-mtllib": ("\n".join(line for line in QUAD_OBJ.format(mtl="m.mtl", first="a", second="b").splitlines()
                                 if not line.startswith("mtllib")) + "\n", None),
    "quad-one-material": (QUAD_OBJ.format(mtl="m.mtl", first="a", second="a"), "newmtl a\nKd 1 0 0\n"),
    "quads-only": (GRID + "".join(f"f {quad(x, y)}\n" for y in range(3) for x in range(3)), None),
    "quads-v": (GRID + "".join(f"f {quad(x, y, 'v')}\n" for y in range(3) for x in range(3)), None),
    "quads-vn": (GRID + "".join(f"f {quad(x, y, 'v//vn', 1 + (x + y) % 2)}\n" for y in range(3) for x in range(3)),
                 None),
    "mixed-polygons": (GRID + "f 1/1/1 2/2/1 6/6/2\nf 2/2/1 3/3/1 7/7/1 6/6/1\nf 3/3/2 4/4/2 8/8/2 12/12/2 11/11/2 7/7/2\n"
                       "f 9/9/1 10/10/1 14/14/1 13/13/1\n", None),
    "sections-repeat": ("mtllib m.mtl\n" + GRID + "usemtl b\n" + "".join(f"f {quad(x, 0)}\n" for x in range(3))
                        + "usemtl a\nf 5/5/1 6/6/1 10/10/1\nusemtl b\nf 6/6/1 7/7/1 11/11/1\nusemtl c d\n"
                        + "f 9/9/1 10/10/1 14/14/1\n", MTL),
    "faces-before-usemtl": ("mtllib m.mtl\n" + GRID + "f 1/1/1 2/2/1 6/6/1\nusemtl a\nf 2/2/1 3/3/1 7/7/1\n", MTL),
    "object-name": ("# exported\no Cube.001\n" + GRID + "s off\ng grp\nf 1/1/1 2/2/1 6/6/1\no Other\nf 2/2/1 3/3/1 7/7/1\n",
                    None),
    "object-two-sections": ("o Cube\n" + GRID + "usemtl x\nf 1/1/1 2/2/1 6/6/1\nusemtl y\nf 2/2/1 3/3/1 7/7/1\n", None),
    "object-after-usemtl": ("mtllib m.mtl\n" + GRID + "usemtl a\no Late\nf 1/1/1 2/2/1 6/6/1\n", "newmtl a\n"),
    "crlf-no-final-newline": ((GRID + "f 1/1 2/2 6/6\nf 2/2 3/3 7/7\n\n  \nf 3/3 4/4 8/8").replace("\n", "\r\n"), None),
    "unused-and-degenerate": (GRID + "f 1 2 3\nf 1 1 2\nf 5 5 5\nf 6 7 11\n", None),
    "tetra": (TETRA + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n", None),
    **{f"degenerate-{k}": (v, None) for k, v in DEGENERATE.items()},
    "no-uv": (_obj([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
                   uvs=False), None),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_direct_reader_matches_trimesh(tmp_path, name):
    text, mtl = CASES[name]
    assert_same_document(write(tmp_path, "in.obj", text, mtl))


def test_trimesh_export_and_meshes_match(tmp_path):
    sphere = tmp_path / "sphere.obj"
    trimesh.creation.icosphere(subdivisions=2).export(str(sphere))  # what test_cli bakes
    paths = [sphere, ROOT / "examples" / "spot" / "spot.obj"]
    paths += sorted(Path("/work/shared/assets/meshes").glob("*.obj"))  # when this machine has them
    for path in paths:
        assert_same_document(path)


def test_negative_indices_are_relative(tmp_path):
    # every vertex before the faces: trimesh's reading agrees (its vertex order differs)
    path = write(tmp_path, "neg.obj", GRID + "f -16/-16/-2 -15/-15/-2 -11/-11/-1\nf 2/2/1 3/3/1 -10/-10/-1\n")
    assert_same_document(path, order_free=True)
    # interleaved: -1 is the vertex just above the face (trimesh would take the file's last one)
    path = write(tmp_path, "inter.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nv 6 5 5\nv 5 6 5\nf -3 -2 -1\n")
    (group,) = read_obj_groups(path, {})
    assert group.positions[group.faces].tolist() == [[[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[5, 5, 5], [6, 5, 5], [5, 6, 5]]]


@pytest.mark.parametrize("face, words", [("f 1 2 9", ("line 5", "index 9", "4 'v' lines")),
                                         ("f 0 1 2", ("line 5", "index 0")),
                                         ("f 1/1 2/7 3/1", ("line 5", "index 7", "'vt'")),
                                         ("f -1 -2 -5", ("line 5", "index -5", "above it"))])
def test_bad_face_index_names_the_line(tmp_path, face, words):
    path = write(tmp_path, "bad.obj", TETRA + face + "\nvt 0 0\n")
    with pytest.raises(BakerError) as caught:
        readers.read(path)
    assert all(w in str(caught.value) for w in ("bad.obj", *words)), str(caught.value)


@pytest.mark.parametrize("text", [TETRA + "l 1 2 3\nf 1 2 3\n", TETRA + "p 1\nf 1 2 3\n",
                                  "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n",
                                  TETRA + "cstype bspline\nf 1 2 3\n", TETRA + "vp 0.5\nf 1 2 3\n",
                                  TETRA + "f 1 2\nf 1 2 3\n", TETRA + "f 1 2/1 3\nvt 0 0\n",
                                  TETRA + "f 1 2 3 # tail\n", TETRA + " f 1 2 3\n", TETRA, TETRA + "f 1 2 \\\n 3\n"])
def test_unusual_files_fall_back_to_trimesh(tmp_path, text):
    assert read_obj_groups(write(tmp_path, "odd.obj", text), {}) is None


def test_bake_of_an_obj_imports_no_trimesh(tmp_path):
    code = ("import sys; from baker.cli import main; "
            f"code = main(['bake', {str(ROOT / 'examples/spot/spot.obj')!r}, '-o', {str(tmp_path / 'x.glb')!r}, "
            "'--bakes', 'thickness', '--thickness-texture-size', '64', '--thickness-rays', '4', '-q']); "
            "print(code, sorted(m for m in sys.modules if m.split('.')[0] in ('trimesh', 'scipy')))")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
    code, modules = result.stdout.split("\n")[0].split(" ", 1)
    assert code == "0", result.stdout + result.stderr
    # scipy.ndimage (texture dilation, texels/texture_space.py) is the thickness texture's own; nothing else
    assert not [m for m in ast.literal_eval(modules) if m.startswith(("trimesh", "scipy.spatial", "scipy.sparse"))], modules
