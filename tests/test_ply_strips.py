"""PLY surfaces stored as ``tristrips`` with -1 restarts (the Stanford/Cyberware layout of igea.ply) bake as
triangles: the strip decoder against a brute-force one, and a cube written that way end to end."""
from __future__ import annotations

import json
import struct
import subprocess
import sys

import numpy as np
import pytest

from baker.geometry.strips import triangles_from_strips

CUBE = np.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)])


def cube_strips() -> list[int]:
    """One 4-vertex strip per face, corners (p0, p1, p3, p2) of the face's counter-clockwise loop seen from outside,
    joined by -1 restarts."""
    strips = []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            normal = np.zeros(3)
            normal[axis] = sign
            corners = np.flatnonzero(CUBE[:, axis] == sign)
            u, v = np.roll(np.eye(3), 1, axis=0)[axis], np.roll(np.eye(3), 2, axis=0)[axis]
            if np.dot(np.cross(u, v), normal) < 0:
                u, v = v, u
            loop = corners[np.argsort(np.arctan2(CUBE[corners] @ v, CUBE[corners] @ u))]
            strips += [int(loop[0]), int(loop[1]), int(loop[3]), int(loop[2]), -1]
    return strips[:-1]


CUBE_STRIPS = cube_strips()


def strips_by_hand(indices):
    faces, strip = [], []
    for v in list(indices) + [-1]:
        if v != -1:
            strip.append(v)
            continue
        for k in range(len(strip) - 2):
            a, b, c = strip[k], strip[k + 1], strip[k + 2]
            tri = (b, a, c) if k % 2 else (a, b, c)
            if len(set(tri)) == 3:
                faces.append(tri)
        strip = []
    return np.array(faces, np.int64).reshape(-1, 3)


@pytest.mark.parametrize("seed", range(5))
def test_decoder_matches_a_loop_over_strips(seed):
    rng = np.random.default_rng(seed)
    indices = rng.integers(0, 12, 400)
    indices[rng.random(400) < 0.05] = -1  # restarts, sometimes adjacent or at the ends
    assert np.array_equal(triangles_from_strips(indices), strips_by_hand(indices))


def test_short_and_empty_strips():
    assert triangles_from_strips([]).shape == (0, 3)
    assert triangles_from_strips([0, 1, -1, 2]).shape == (0, 3)
    assert triangles_from_strips([0, 0, 1, 2]).tolist() == [[1, 0, 2]]  # the degenerate first triangle is dropped


def write_ply(path, binary: bool):
    header = ["ply", "format " + ("binary_little_endian" if binary else "ascii") + " 1.0",
              f"element vertex {len(CUBE)}", "property float x", "property float y", "property float z",
              "element tristrips 1", "property list int int vertex_indices", "end_header"]
    head = ("\n".join(header) + "\n").encode()
    if binary:
        body = CUBE.astype("<f4").tobytes() + struct.pack("<i", len(CUBE_STRIPS)) + \
            np.array(CUBE_STRIPS, "<i4").tobytes()
    else:
        body = ("\n".join(" ".join(map(str, v)) for v in CUBE) + "\n" +
                " ".join(map(str, [len(CUBE_STRIPS)] + CUBE_STRIPS)) + "\n").encode()
    path.write_bytes(head + body)


def glb_triangles(path):
    """Positions and triangles of the first primitive, read from the GLB by hand (not with baker)."""
    data = path.read_bytes()
    json_length = struct.unpack_from("<I", data, 12)[0]
    gltf = json.loads(data[20: 20 + json_length])
    binary = data[20 + json_length + 8:]
    prim = gltf["meshes"][0]["primitives"][0]

    def accessor(i, dtype, width):
        acc = gltf["accessors"][i]
        view = gltf["bufferViews"][acc["bufferView"]]
        start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
        return np.frombuffer(binary, dtype, acc["count"] * width, start).reshape(acc["count"], width)

    kinds = {5121: np.uint8, 5123: np.uint16, 5125: np.uint32}
    positions = accessor(prim["attributes"]["POSITION"], np.float32, 3).astype(np.float64)
    indices = accessor(prim["indices"], kinds[gltf["accessors"][prim["indices"]]["componentType"]], 1)
    return positions, indices.reshape(-1, 3).astype(np.int64)


@pytest.mark.parametrize("binary", [True, False])
def test_cube_as_strips_bakes_closed_and_outward(tmp_path, binary):
    source = tmp_path / "cube.ply"
    write_ply(source, binary)
    out = tmp_path / "cube.glb"
    result = subprocess.run([sys.executable, "-m", "baker.cli", "bake", str(source), "-o", str(out), "--bakes",
                             "thickness", "--thickness-per-texel", "false", "--thickness-rays", "16", "-q"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    positions, faces = glb_triangles(out)
    assert len(faces) == 12
    a, b, c = (positions[faces[:, k]] for k in range(3))
    volume = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0
    assert volume == pytest.approx(8.0, rel=1e-6)  # closed, consistently wound, normals outward
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert (counts == 2).all()  # watertight: every edge shared by exactly two triangles


def test_strip_index_out_of_range_is_one_line(tmp_path):
    source = tmp_path / "bad.ply"
    write_ply(source, binary=True)
    data = bytearray(source.read_bytes())
    struct.pack_into("<i", data, len(data) - 4, 99)  # last strip index: no such vertex
    source.write_bytes(bytes(data))
    result = subprocess.run([sys.executable, "-m", "baker.cli", "bake", str(source), "-o", str(tmp_path / "o.glb")],
                            capture_output=True, text=True)
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and "out of range" in result.stderr
    assert not (tmp_path / "o.glb").exists()
