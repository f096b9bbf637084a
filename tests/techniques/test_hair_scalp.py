"""The scalp travels with the hair: ``baker hair`` writes its emitter mesh beside the strands, and ``baker guides``
and ``baker cards`` carry it to their outputs (or take ``--scalp MESH``); the cards summary states its fit against
``--fit`` and says when it is missed. Files are read with the tests' own GLB parser (test_guides.read_glb) and the
emitter with trimesh, never with baker's reader."""
from __future__ import annotations

import contextlib
import io
import json

import numpy as np
import pytest
from scipy.spatial import cKDTree

from baker.cli import main as cli_main
from baker.validate import validate_file
from techniques.test_guides import read_glb


def triangle_meshes(path):
    """[(mesh name, positions (n, 3), triangles (m, 3))] of the triangle primitives of a GLB (node transforms are
    identity in these files: checked)."""
    gltf, acc = read_glb(path)
    assert all(set(n) <= {"name", "mesh", "children"} for n in gltf["nodes"]), gltf["nodes"]
    out = []
    for mesh in gltf["meshes"]:
        for prim in mesh["primitives"]:
            if prim.get("mode", 4) == 4:
                out.append((mesh.get("name"), acc(prim["attributes"]["POSITION"]).astype(np.float64),
                            acc(prim["indices"]).astype(np.int64).reshape(-1, 3)))
    return out


@pytest.fixture(scope="module")
def grown(tmp_path_factory):
    """A sphere cap (the top of an icosphere, written as OBJ) grown with ``baker hair``: 40 guides x 8 children."""
    import trimesh

    folder = tmp_path_factory.mktemp("scalp")
    sphere = trimesh.creation.icosphere(subdivisions=3)
    cap = sphere.submesh([np.flatnonzero(sphere.triangles_center[:, 1] > 0.3)], append=True)
    cap.export(folder / "cap.obj")
    hair = folder / "hair.glb"
    assert cli_main(["hair", str(folder / "cap.obj"), "-o", str(hair), "--guides", "40", "--children", "8",
                     "--segments", "8", "--seed", "4", "-q"]) == 0
    return {"folder": folder, "cap": cap, "hair": hair}


def same_surface(mesh, cap):
    """The triangles written are the cap's: every vertex on a cap vertex, as many triangles, the same area."""
    _, positions, triangles = mesh
    distance, _ = cKDTree(cap.vertices).query(positions)
    assert distance.max() < 1e-5
    assert len(triangles) == len(cap.faces)
    a, b, c = (positions[triangles[:, k]] for k in range(3))
    assert np.linalg.norm(np.cross(b - a, c - a), axis=1).sum() / 2 == pytest.approx(cap.area, rel=1e-5)


def test_guides_carry_the_scalp_of_a_hair_file(grown):
    out = grown["folder"] / "guides.glb"
    assert cli_main(["guides", str(grown["hair"]), "-o", str(out), "--guides", "30", "-q"]) == 0
    (scalp,) = triangle_meshes(out)
    same_surface(scalp, grown["cap"])
    gltf, acc = read_glb(out)
    hair = next(m for m in gltf["meshes"] if m["name"] == "hair")
    children = hair["primitives"][1]
    binding = children["extensions"]["BAKER_hair"]["rootBinding"]
    # every child root is rebuilt from the written scalp's own triangle + barycentrics
    _, positions, triangles = scalp
    corners = positions[triangles[acc(binding["triangles"]).astype(np.int64)]]
    roots = np.einsum("sk,skd->sd", acc(binding["barycentrics"]).astype(np.float64), corners)
    v = children["extensions"]["BAKER_hair"]["verticesPerStrand"]
    written = acc(children["attributes"]["POSITION"]).astype(np.float64)[::v]
    assert np.abs(roots - written).max() < 1e-4
    assert validate_file(out, khronos=False)["issues"]["numErrors"] == 0


def run_json(args):
    with contextlib.redirect_stdout(io.StringIO()) as buffer:
        code = cli_main(args + ["--format", "json"])
    return code, (json.loads(buffer.getvalue()) if code == 0 else None)


def test_cards_carry_the_scalp_and_say_when_the_fit_is_missed(grown, capsys):
    out = grown["folder"] / "cards.glb"
    code, info = run_json(["cards", str(grown["hair"]), "-o", str(out), "--cards", "6", "--atlas-size", "256"])
    assert code == 0 and info["scalp"] == str(grown["hair"])
    names = [name for name, _, _ in triangle_meshes(out)]
    assert names[1:] == ["hair_cards"]  # the scalp, then the cards
    same_surface(triangle_meshes(out)[0], grown["cap"])
    report = validate_file(out, khronos=False)["issues"]
    assert report["numErrors"] == 0 and report["numWarnings"] == 0, report["messages"]
    # the fit against its target, in JSON: 6 cards for 360 strands miss 99 %; the text says MISSED
    fit = info["fit"]
    assert fit["within5Percent"] == info["cardDistance"]["within5Percent"] and fit["target"] == 0.9
    assert fit["met"] == (fit["within5Percent"] >= 0.9)
    code, strict = run_json(["cards", str(grown["hair"]), "-o", str(out), "--cards", "6", "--atlas-size", "256",
                             "--fit", "0.99"])
    assert code == 0 and strict["fit"]["target"] == 0.99 and strict["fit"]["met"] is False
    capsys.readouterr()
    assert cli_main(["cards", str(grown["hair"]), "-o", str(out), "--cards", "6", "--atlas-size", "256",
                     "--fit", "0.99"]) == 0
    text = capsys.readouterr().err
    share = 100 * strict["fit"]["within5Percent"]
    assert f"{share:.1f} % of strand points" in text and "target 99.0 %: MISSED" in text, text


def test_cards_take_scalp_from_option(grown, tmp_path, capsys):
    """A groom of curves only (USD BasisCurves, no mesh: no scalp) + ``--scalp OBJ``: the OBJ's mesh is written
    beside the cards; a missing --scalp file is one error line, exit 2."""
    from techniques.cards_groom import make_groom, write_groom_usd

    curves, widths = make_groom(strands=300, clumps=12, seed=2)
    groom = write_groom_usd(tmp_path / "groom.usda", curves, widths)
    out = tmp_path / "cards.glb"
    code, info = run_json(["cards", str(groom), "-o", str(out), "--cards", "6", "--atlas-size", "256"])
    assert code == 0 and info["scalp"] is None and [n for n, _, _ in triangle_meshes(out)] == ["hair_cards"]
    # a target below the share reached is met, and the text says so, without MISSED
    assert info["fit"]["within5Percent"] > 0.5 and info["fit"]["met"] is (info["fit"]["within5Percent"] >= 0.9)
    capsys.readouterr()
    assert cli_main(["cards", str(groom), "-o", str(out), "--cards", "6", "--atlas-size", "256", "--fit", "0.5"]) == 0
    text = capsys.readouterr().err
    assert "target 50.0 %: met" in text and "MISSED" not in text, text
    code, info = run_json(["cards", str(groom), "-o", str(out), "--cards", "6", "--atlas-size", "256",
                           "--scalp", str(grown["folder"] / "cap.obj")])
    assert code == 0 and info["scalp"] == str(grown["folder"] / "cap.obj")
    same_surface(triangle_meshes(out)[0], grown["cap"])
    capsys.readouterr()
    assert cli_main(["cards", str(groom), "-o", str(out), "--scalp", str(tmp_path / "none.obj")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "none.obj" in err[0] and "Traceback" not in err[0]
