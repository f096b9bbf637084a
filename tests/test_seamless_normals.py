"""Normals baker computes for a mesh file without any are smooth across UV and material seams: read back from the
written GLB (test_mesh_inputs.glb_floats, no baker code), split copies of a position carry one normal, a UV sphere's
normals are radial at its seam and poles as everywhere else, and OBJ smoothing groups (``s``) are the only creases."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from baker.cli import main
from test_mesh_inputs import glb_floats

ROOT = Path(__file__).parents[1]


def bake_read(path: Path, tmp_path: Path) -> tuple[np.ndarray, np.ndarray]:
    """(positions, normals) of every primitive of the GLB ``baker bake`` writes for ``path``, concatenated."""
    out = tmp_path / (path.stem + ".glb")
    assert main(["bake", str(path), "-o", str(out), "--bakes", "edges", "-q"]) == 0
    gltf, floats = glb_floats(out)
    floats = dict(floats)
    positions, normals = [], []
    for mesh in gltf["meshes"]:
        for prim in mesh["primitives"]:
            if "POSITION" in prim["attributes"] and prim.get("mode", 4) == 4:
                positions.append(floats[prim["attributes"]["POSITION"]])
                normals.append(floats[prim["attributes"]["NORMAL"]])
    assert all("matrix" not in n and "rotation" not in n and "scale" not in n for n in gltf["nodes"])
    return np.concatenate(positions).astype(np.float64), np.concatenate(normals).astype(np.float64)


def angle_degrees(a, b) -> np.ndarray:
    """Angles between vectors, from the cross product's length: arccos of a dot product near 1 loses float32's
    digits (a float32 unit vector against itself would be 0.01 degrees off)."""
    return np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), (a * b).sum(axis=-1)))


def spread_by_position(positions, normals) -> tuple[int, float]:
    """(positions held by more than one vertex, largest angle in degrees between normals at one position)."""
    _, inverse, counts = np.unique(positions, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.reshape(-1)
    shared = np.flatnonzero(counts[inverse] > 1)
    worst = 0.0
    for group in np.unique(inverse[shared]):
        n = normals[inverse == group]
        worst = max(worst, float(angle_degrees(n[:, None], n[None]).max()))
    return int((counts > 1).sum()), worst


def test_spot_without_normals_is_smooth_across_uv_and_material_seams(tmp_path):
    text = (ROOT / "examples" / "spot" / "spot.obj").read_text()
    lines = [line for line in text.splitlines() if not line.startswith("vn ")]
    assert not any("//" in line or line.count("/") > 2 * len(line.split()) for line in lines if line.startswith("f "))
    plain = tmp_path / "spot.obj"
    plain.write_text("\n".join(lines) + "\n")
    shared, worst = spread_by_position(*bake_read(plain, tmp_path))
    assert shared > 200 and worst < 1.0, (shared, worst)  # before: 262 positions, up to 67.8 degrees apart

    # the same faces in two materials (two meshes of the output): still one smooth surface
    faces = [i for i, line in enumerate(lines) if line.startswith("f ")]
    half = faces[len(faces) // 2]
    split = ["mtllib m.mtl", "usemtl red"] + lines[:half] + ["usemtl blue"] + lines[half:]
    (tmp_path / "m.mtl").write_text("newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n")
    (tmp_path / "two.obj").write_text("\n".join(split) + "\n")
    positions, normals = bake_read(tmp_path / "two.obj", tmp_path)
    shared_two, worst = spread_by_position(positions, normals)
    assert shared_two > shared and worst < 1.0, (shared_two, worst)


def uv_sphere_obj(segments=48, rings=24, colours=False) -> str:
    """A UV sphere as DCC tools write it: a column of vertices at u = 0 and again at u = 1 (the seam) and a pole
    vertex per segment (each with its own u), no normals."""
    out, uv = [], []
    for r in range(rings + 1):
        theta = np.pi * r / rings
        for s in range(segments + 1):
            phi = 2 * np.pi * (s % segments) / segments
            p = (np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta))
            out.append("v %.9f %.9f %.9f" % p + (" 0.5 0.5 0.5" if colours else ""))
            uv.append(f"vt {s / segments:.9f} {1 - r / rings:.9f}")
    index = lambda r, s: r * (segments + 1) + s + 1  # noqa: E731
    faces = []
    for r in range(rings):
        for s in range(segments):
            a, b, c, d = index(r, s), index(r + 1, s), index(r + 1, s + 1), index(r, s + 1)
            if r == 0:
                faces.append(f"f {a}/{a} {b}/{b} {c}/{c}")
            elif r == rings - 1:
                faces.append(f"f {a}/{a} {b}/{b} {d}/{d}")
            else:
                faces.append(f"f {a}/{a} {b}/{b} {c}/{c} {d}/{d}")
    return "\n".join(out + uv + faces) + "\n"


@pytest.mark.parametrize("colours", [False, True], ids=["direct-reader", "trimesh-reader"])
def test_uv_sphere_normals_are_radial_at_the_seam_and_poles(tmp_path, colours):
    path = tmp_path / "sphere.obj"
    path.write_text(uv_sphere_obj(colours=colours))
    positions, normals = bake_read(path, tmp_path)
    radial = positions / np.linalg.norm(positions, axis=1, keepdims=True)
    error = angle_degrees(normals, radial)
    seam = np.abs(positions[:, 1]) < 1e-6  # the u = 0 / u = 1 column (and its half-way opposite), poles included
    assert seam.sum() > 40
    # a ring's normals lean off the radius by the same (small) angle at the seam as elsewhere: no seam crease
    assert error.max() < 0.5, error.max()
    z = np.round(positions[:, 2], 5)
    for level in np.unique(z[seam]):
        ring = z == level
        assert np.ptp(error[ring]) < 1e-3, (level, error[ring & seam], error[ring & ~seam])
    assert spread_by_position(positions, normals)[1] < 1e-3  # the seam's and the poles' copies agree


CUBE = "".join(f"v {x} {y} {z}\n" for z in (0, 1) for y in (0, 1) for x in (0, 1))
SIDES = ["1 2 6 5", "2 4 8 6", "4 3 7 8", "3 1 5 7"]  # -y, +x, +y, -x
CAPS = ["1 3 4 2", "5 6 8 7"]  # -z, +z


@pytest.mark.parametrize("layout", ["none", "one-group", "off", "sides-and-caps"])
def test_obj_smoothing_groups_are_the_only_creases(tmp_path, layout):
    body = {"none": [f"f {f}" for f in SIDES + CAPS],
            "one-group": ["s 1"] + [f"f {f}" for f in SIDES + CAPS],
            "off": ["s off"] + [f"f {f}" for f in SIDES + CAPS],
            "sides-and-caps": ["s 1"] + [f"f {f}" for f in SIDES] + ["s 2"] + [f"f {f}" for f in CAPS]}[layout]
    path = tmp_path / "cube.obj"
    path.write_text(CUBE + "\n".join(body) + "\n")
    positions, normals = bake_read(path, tmp_path)
    centred = positions - 0.5
    if layout in ("none", "one-group"):  # one smooth surface: every corner points out along the diagonal
        expected = centred / np.linalg.norm(centred, axis=1, keepdims=True)
        assert len(positions) == 8
    elif layout == "off":  # every face flat: each vertex's normal is its face's, 4 copies a face
        assert len(positions) == 24
        faces_of = {}
        for axis in range(3):
            for side in (-0.5, 0.5):
                on = np.isclose(centred[:, axis], side) & np.isclose(normals[:, axis], 2 * side)
                faces_of[axis, side] = int(on.sum())
        assert set(faces_of.values()) == {4}, faces_of
        return
    else:  # sides smooth among themselves (normals in the xy plane), caps among themselves (+-z)
        assert len(positions) == 16
        side = np.abs(normals[:, 2]) < 1e-6
        assert side.sum() == 8
        expected = np.where(side[:, None], centred * [1, 1, 0], centred * [0, 0, 1])
        expected /= np.linalg.norm(expected, axis=1, keepdims=True)
    assert np.abs(normals - expected).max() < 1e-6


def test_trimesh_path_gives_the_direct_readers_normals_across_materials(tmp_path):
    """A file without normals in two materials: trimesh's reading gets the same welded normals, bit for bit."""
    from test_obj_reader import assert_same_document

    lines = (ROOT / "examples" / "spot" / "spot.obj").read_text().splitlines()
    faces = [i for i, line in enumerate(lines) if line.startswith("f ")]
    half = faces[len(faces) // 3]
    (tmp_path / "m.mtl").write_text("newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n")
    path = tmp_path / "two.obj"
    path.write_text("\n".join(["mtllib m.mtl", "usemtl red"] + lines[:half] + ["usemtl blue"] + lines[half:]) + "\n")
    assert_same_document(path)


@pytest.mark.parametrize("line", ["s 1 2", "s on", "s -1"])
def test_unusual_smoothing_lines_fall_back_to_trimesh(tmp_path, line):
    from baker.readers.obj import read_obj_groups

    path = tmp_path / "odd.obj"
    path.write_text(CUBE + line + "\n" + "\n".join(f"f {f}" for f in SIDES + CAPS) + "\n")
    assert read_obj_groups(path, {}) is None
    path.write_text(CUBE + "vn 0 0 1\n" + line + "\n" + "\n".join(
        "f " + " ".join(f"{i}//1" for i in f.split()) for f in SIDES + CAPS) + "\n")
    assert read_obj_groups(path, {}) is not None  # with normals the s lines decide nothing
