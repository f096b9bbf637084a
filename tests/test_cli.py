"""The command line: inputs of every kind, one-line errors with exit code 2, no partial outputs."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

from baker.cli import main
from baker.gltf.document import GltfDocument
from conftest import assert_khronos_clean

FAST = ["--thickness-rays", "4", "--thickness-texture-size", "32", "-q"]


def run(*args):
    return subprocess.run([sys.executable, "-m", "baker.cli", *map(str, args)], capture_output=True, text=True)


@pytest.fixture(scope="module")
def sphere_glb(tmp_path_factory):
    path = tmp_path_factory.mktemp("cli") / "sphere.glb"
    trimesh.creation.icosphere(subdivisions=2).export(str(path))
    return path


@pytest.mark.parametrize("suffix", [".obj", ".ply", ".stl", ".glb", ".gltf"])
def test_every_mesh_format_bakes(tmp_path, suffix):
    src = tmp_path / f"in{suffix}"
    trimesh.creation.icosphere(subdivisions=2).export(str(src))
    out = tmp_path / "out.glb"
    assert main(["bake", str(src), "-o", str(out), *FAST]) == 0
    assert_khronos_clean(out)
    doc = GltfDocument.load(out)
    assert "_THICKNESS" in doc.json["meshes"][0]["primitives"][0]["attributes"]


def test_gltf_output_writes_bin_and_png(tmp_path, sphere_glb):
    out = tmp_path / "baked.gltf"
    assert main(["bake", str(sphere_glb), "-o", str(out), *FAST]) == 0
    assert_khronos_clean(out)
    gltf = json.loads(out.read_text())
    assert gltf["buffers"][0]["uri"] == "baked.bin" and (tmp_path / "baked.bin").is_file()
    uris = [img["uri"] for img in gltf["images"]]
    assert all((tmp_path / u).is_file() for u in uris) and all(u.endswith(".png") for u in uris)


def test_version_and_help():
    result = run("--version")
    assert result.returncode == 0 and result.stdout.startswith("baker ")
    result = run("bake", "--help")
    assert "--thickness-rays" in result.stdout and "--seed" in result.stdout


def _points_only_gltf(path):
    pos = np.zeros((3, 3), np.float32)
    gltf = {"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "mode": 0}]}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}],
            "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,"
                         + __import__("base64").b64encode(pos.tobytes()).decode()}]}
    path.write_text(json.dumps(gltf))


BAD_INPUTS = {
    "missing.glb": (None, "file not found"),
    "truncated.glb": ("truncated", "truncated GLB"),
    "broken.gltf": ("broken", "truncated JSON"),
    "points.gltf": ("points", "no triangle faces"),
    "empty.obj": ("empty_obj", "no triangle faces"),
    "model.fbx": ("fbx", "unsupported input type"),
}


@pytest.mark.parametrize("name", sorted(BAD_INPUTS))
def test_bad_input_is_one_line_exit_2_no_output(tmp_path, sphere_glb, name):
    kind, expected = BAD_INPUTS[name]
    src = tmp_path / name
    if kind == "truncated":
        src.write_bytes(sphere_glb.read_bytes()[:200])
    elif kind == "broken":
        src.write_text('{"asset": {"version": "2.0"}, "meshes": [')
    elif kind == "points":
        _points_only_gltf(src)
    elif kind == "empty_obj":
        src.write_text("# nothing\nv 0 0 0\nv 1 0 0\n")
    elif kind == "fbx":
        src.write_bytes(b"Kaydara FBX Binary")
    out = tmp_path / "out.glb"
    result = run("bake", src, "-o", out, "-q")
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("baker: error: ") and str(src) in lines[0] and expected in lines[0]
    assert not out.exists()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".out.glb")]  # no temp leftovers


def test_bad_option_value_is_an_error(tmp_path, sphere_glb):
    result = run("bake", sphere_glb, "-o", tmp_path / "o.glb", "--thickness-distribution", "gaussian")
    assert result.returncode == 2 and "distribution" in result.stderr
    assert not (tmp_path / "o.glb").exists()


@pytest.mark.parametrize("argv, synopsis", [
    (["bake", "spot.obj"], "usage: baker bake INPUT -o OUTPUT [options]"),
    (["bake", "spot.obj", "-o", "x.glb", "--no-such-flag"], "usage: baker bake INPUT -o OUTPUT"),
    (["inspect"], "usage: baker inspect FILE"),
    ([], "usage: baker COMMAND"),
    (["nosuch"], "usage: baker COMMAND"),
])
def test_usage_error_is_short(argv, synopsis):
    """A usage error is the command's synopsis, the error and where the full list is, never argparse's usage line of
    every technique's options (72 lines for ``baker bake`` before)."""
    result = run(*argv)
    lines = result.stderr.strip().splitlines()
    assert result.returncode == 2 and 2 <= len(lines) <= 4, result.stderr
    assert lines[0].startswith(synopsis), result.stderr
    assert "error:" in lines[1] and "--help" in lines[-1], result.stderr
    assert "Traceback" not in result.stderr and result.stdout == ""


def test_help_keeps_the_full_option_list():
    result = run("bake", "--help")
    assert result.returncode == 0 and "--thickness-rays" in result.stdout and "--curvature-" in result.stdout


def test_inspect_lists_baked_data(tmp_path, sphere_glb, capsys):
    out = tmp_path / "o.glb"
    assert main(["bake", str(sphere_glb), "-o", str(out), *FAST]) == 0
    assert main(["inspect", str(out)]) == 0
    text = capsys.readouterr().out
    assert "_THICKNESS" in text and "BAKER_thickness" in text and "KHR_materials_volume" in text
    assert main(["inspect", str(out), "--format", "json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["meshes"][0]["baked"]["_THICKNESS"]["min"] > 0


def test_quiet_and_non_tty_print_no_progress(tmp_path, sphere_glb):
    result = run("bake", sphere_glb, "-o", tmp_path / "o.glb", "--thickness-rays", "4",
                 "--thickness-texture-size", "32")
    assert result.returncode == 0
    assert "%|" not in result.stderr  # no tqdm bar when stderr is not a terminal


def test_readme_documents_every_option_and_command():
    import dataclasses

    from baker.registry import bakes

    readme = (Path(__file__).parents[1] / "README.md").read_text()
    for name, step in bakes().items():
        assert f"`{name}`" in readme
        for f in dataclasses.fields(step.options):
            assert f"`{f.name.replace('_', '-')}`" in readme, f"README lacks option {name}.{f.name}"
    for command in ("baker bake", "baker validate", "baker inspect", "scripts/test"):
        assert command in readme


def test_python_api_example_runs(tmp_path):
    example = Path(__file__).parents[1] / "examples" / "bake_api.py"
    spot = Path(__file__).parents[1] / "examples" / "spot" / "spot.obj"
    result = subprocess.run([sys.executable, str(example), str(spot), str(tmp_path)], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert "validation errors: 0" in result.stdout
    assert {"spot.glb", "spot.usdz", "spot_preview.png"} <= {p.name for p in tmp_path.iterdir()}


def test_inspect_lists_lines_strips_and_points(tmp_path, capsys):
    """A glTF of lines and points only: LINES chained into strands through shared vertices (two chains, 3 + 1
    segments), a LINE_STRIP (one strand), POINTS; inspect exits 0 and counts them."""
    positions = np.arange(3 * 12, dtype=np.float32).reshape(12, 3)
    lines = np.array([0, 1, 1, 2, 2, 3, 5, 6], np.uint16)  # 0-1-2-3 and 5-6
    data = positions.tobytes() + lines.tobytes()
    gltf = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
            "meshes": [{"name": "wires", "primitives": [
                {"attributes": {"POSITION": 0}, "indices": 1, "mode": 1},
                {"attributes": {"POSITION": 0}, "mode": 3},
                {"attributes": {"POSITION": 0}, "mode": 0}]}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 12, "type": "VEC3",
                           "min": positions.min(0).tolist(), "max": positions.max(0).tolist()},
                          {"bufferView": 1, "componentType": 5123, "count": len(lines), "type": "SCALAR"}],
            "bufferViews": [{"buffer": 0, "byteLength": positions.nbytes, "target": 34962},
                            {"buffer": 0, "byteOffset": positions.nbytes, "byteLength": lines.nbytes,
                             "target": 34963}],
            "buffers": [{"byteLength": len(data), "uri": "wires.bin"}]}
    (tmp_path / "wires.bin").write_bytes(data)
    path = tmp_path / "wires.gltf"
    path.write_text(json.dumps(gltf))
    assert main(["inspect", str(path), "--format", "json"]) == 0
    rows = json.loads(capsys.readouterr().out)["meshes"]
    got = [(r["modeName"], r["vertices"], r["triangles"], r["lines"], r["strands"], r["points"]) for r in rows]
    assert got == [("LINES", 12, 0, 4, 2, 0), ("LINE_STRIP", 12, 0, 11, 1, 0), ("POINTS", 12, 0, 0, 0, 12)]
    assert main(["inspect", str(path)]) == 0
    text = capsys.readouterr().out
    assert "LINE_STRIP" in text and "POINTS" in text
    assert main(["bake", str(path), "-o", str(tmp_path / "o.glb"), "-q"]) == 2  # a bake still needs triangles
    assert "no triangle faces" in capsys.readouterr().err


# ---------------------------------------------------------------------------------------------------- bad paths
# Every command that reads a file, given something that is not that file: exit 2 and ONE line naming the file and
# what it is (issue 47, item 2). Run in this process (main()), so the whole matrix takes a few seconds.
PNG_BYTES = (b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\x00\x00\x00\x02\x00\x00\x00\x02\x08\x02\x00\x00\x00\xfd\xd4\x9as"
             b"\x00\x00\x00\x0cIDATx\x9cc`\x80\x01\x00\x00\x0e\x00\x01\xa2\xd6\x8b\xe6\x00\x00\x00\x00IEND\xaeB`\x82")
BAD_PATH_COMMANDS = {  # command -> (argv for an input, suffixes it reads)
    "bake": (lambda f, o: ["bake", f, "-o", o / "o.glb", "-q"], ("obj", "ply", "stl", "glb", "gltf", "usda", "usdz")),
    "inspect": (lambda f, o: ["inspect", f], ("obj", "ply", "stl", "glb", "gltf", "usdc")),
    "preview": (lambda f, o: ["preview", f, "-o", o / "o.png", "-q"], ("obj", "glb", "usda")),
    "validate": (lambda f, o: ["validate", f, "--no-khronos"], ("obj", "ply", "glb", "gltf", "usda")),
    "lines": (lambda f, o: ["lines", f, "-o", o / "o.svg", "--quiet"], ("obj", "stl", "glb")),
    "hair": (lambda f, o: ["hair", f, "-o", o / "o.glb", "-q"], ("obj", "ply", "glb")),
    "guides": (lambda f, o: ["guides", f, "-o", o / "o.glb", "-q"], ("glb", "usdc", "tfx")),
    "cards": (lambda f, o: ["cards", f, "-o", o / "o.glb", "-q"], ("gltf", "usda", "tfx")),
    "glyphs": (lambda f, o: ["glyphs", f, "-o", o / "atlas", "-q"], ("ttf", "otf")),
    "text": (lambda f, o: ["text", "Hi", "--font", f, "-o", o / "o.glb", "-q"], ("ttf",)),
}


def make_bad_inputs(folder: Path, suffix: str) -> dict:
    """name -> (path, what the one line must say it is) of inputs that are not a ``suffix`` file."""
    import os
    import random

    folder.mkdir(parents=True, exist_ok=True)
    bad = {}
    directory = folder / f"adir.{suffix}"
    directory.mkdir()
    bad["directory"] = (directory, "a directory")
    png = folder / f"image.{suffix}"
    png.write_bytes(PNG_BYTES)
    bad["png"] = (png, "a PNG image")
    empty = folder / f"empty.{suffix}"
    empty.write_bytes(b"")
    bad["empty"] = (empty, "an empty file")
    noise = folder / f"noise.{suffix}"
    noise.write_bytes(random.Random(7).randbytes(2000))
    if suffix not in ("stl", "tfx"):  # raw bytes are what those formats hold: their readers check the counts
        bad["random"] = (noise, "binary data" if suffix in ("obj", "glb", "gltf", "ply", "usda", "usdc", "usdz",
                                                            "ttf", "otf") else "")
    pipe = folder / f"pipe.{suffix}"
    os.mkfifo(pipe)  # never opened: opening a FIFO blocks until a writer comes
    bad["fifo"] = (pipe, "a named pipe")
    dangling = folder / f"dangling.{suffix}"
    dangling.symlink_to(folder / "nowhere")
    bad["dangling link"] = (dangling, "a symbolic link to a missing file")
    bad["through a file"] = (png / f"x.{suffix}", "is a file, not a folder")  # unopenable, also for root
    return bad


BAD_PATH_CASES = [(command, suffix) for command, (_, suffixes) in BAD_PATH_COMMANDS.items() for suffix in suffixes]


@pytest.mark.parametrize("command,suffix", BAD_PATH_CASES, ids=[f"{c}-{s}" for c, s in BAD_PATH_CASES])
def test_bad_paths_are_one_line_exit_2(command, suffix, tmp_path, capsys):
    import signal

    argv_of, _ = BAD_PATH_COMMANDS[command]

    def blocked(signum, frame):
        raise AssertionError(f"{command} blocked on a bad {suffix} input (opened a FIFO?)")

    previous = signal.signal(signal.SIGALRM, blocked)
    try:
        for name, (path, what) in make_bad_inputs(tmp_path / "in", suffix).items():
            signal.alarm(30)
            code = main([str(a) for a in argv_of(path, tmp_path)])
            signal.alarm(0)
            err = capsys.readouterr().err.strip().splitlines()
            assert code == 2 and len(err) == 1, (name, code, err)
            assert err[0].startswith(f"baker: error: {path}: "), (name, err)
            assert what in err[0], (name, what, err)
            assert not list(tmp_path.glob("o.*")) and not list(tmp_path.glob("atlas*")), (name, "wrote output")
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def test_validate_says_what_it_reads(tmp_path, capsys):
    """An OBJ (or a PNG under any name) is not validated as broken JSON: one line saying what validate reads."""
    obj = tmp_path / "tri.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    assert main(["validate", str(obj), "--no-khronos"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"baker: error: {obj}: an OBJ mesh: validate reads .gltf/.glb (and baker's USD)"]
    png = tmp_path / "x.gltf"
    png.write_bytes(PNG_BYTES)
    assert main(["validate", str(png), "--no-khronos"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"baker: error: {png}: a PNG image, not a glTF (JSON) file"]
    assert "JSON" not in capsys.readouterr().out


def test_inspect_lists_tam_textures_and_summarises_edges(tmp_path, capsys):
    """spot baked with tam,edges (+ fins): inspect lists every tonal-art-map level texture at its level's size and
    gives BAKER_edges a summary whose numbers hold independently: a closed triangle mesh has 3F/2 edges, the
    creases are the edges whose stored dihedral angle reaches the crease angle, a fin is two triangles per edge."""
    spot = Path(__file__).parents[1] / "examples" / "spot" / "spot.obj"
    out = tmp_path / "spot.glb"
    assert main(["bake", str(spot), "-o", str(out), "--bakes", "tam,edges", "--edges-fins", "true",
                 "--edges-dihedral-angles", "true", "--tam-size", "64", "-q"]) == 0
    capsys.readouterr()
    assert main(["inspect", str(out), "--format", "json"]) == 0
    info = json.loads(capsys.readouterr().out)
    doc = GltfDocument.load(out)
    tam = doc.json["materials"][0]["extensions"]["BAKER_tonal_art_map"]
    expected = {}
    for level in tam["levels"]:
        for info_ in level.get("textures") or [level["texture"]]:
            expected[info_["index"]] = [level["size"], level["size"]]
    listed = {t["texture"]: t["size"] for t in info["materials"][0]["textures"]
              if t["slot"].startswith("BAKER_tonal_art_map.levels[")}
    assert listed == expected and len(listed) == len(doc.json["textures"]) >= 2
    rows = {(r["primitive"], name): data for r in info["meshes"] for name, data in r["extensions"].items()}
    edges = rows[(0, "BAKER_edges")]
    prim = doc.json["meshes"][0]["primitives"][0]
    triangles = doc.json["accessors"][prim["indices"]]["count"] // 3
    assert edges["edges"] == 3 * triangles // 2  # spot is closed and manifold
    ext = prim["extensions"]["BAKER_edges"]
    dihedral = np.abs(np.asarray(doc.accessor(ext["dihedralAngles"]), np.float64).reshape(-1))
    assert edges["crease"] == int((dihedral >= ext["creaseAngle"] - 1e-6).sum()) > 0
    assert edges["creaseAngleDeg"] == pytest.approx(np.degrees(ext["creaseAngle"]))
    visibility = rows[(0, "EXT_mesh_primitive_edge_visibility")]
    # every edge but the planar ones can draw: as a silhouette candidate, or always (hard: spot's creases)
    assert visibility["hard"] == edges["crease"]
    assert visibility["silhouette"] + visibility["hard"] + edges["planar"] == edges["edges"]
    assert visibility["silhouetteMates"] == visibility["silhouette"]
    fins = edges["finPrimitive"]
    assert rows[(fins, "BAKER_edges")] == {"finsOf": 0, "fins": edges["edges"]}
    assert main(["inspect", str(out)]) == 0
    text = capsys.readouterr().out
    assert f"edges {edges['edges']}  crease {edges['crease']}" in text
    assert "BAKER_tonal_art_map.levels[0].textures[0]" in text


def test_bad_output_paths_and_text_files_are_one_line(tmp_path, capsys, sphere_glb):
    """An output that is a directory or lies under a file, and a --text-file that is a directory, a FIFO or a PNG:
    exit 2, one line naming it, nothing written."""
    import os

    (tmp_path / "adir.glb").mkdir()
    (tmp_path / "image.png").write_bytes(PNG_BYTES)
    os.mkfifo(tmp_path / "pipe.txt")
    font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
    cases = [(["bake", sphere_glb, "-o", tmp_path / "adir.glb", "--bakes", "edges", "-q"], "adir.glb",
              "a directory"),
             (["bake", sphere_glb, "-o", tmp_path / "image.png" / "x.glb", "--bakes", "edges", "-q"], "x.glb",
              "image.png is a file, not a folder"),
             (["glyphs", font, "--text-file", tmp_path / "adir.glb", "-o", tmp_path / "a"], "adir.glb", "a directory"),
             (["glyphs", font, "--text-file", tmp_path / "pipe.txt", "-o", tmp_path / "a"], "pipe.txt", "named pipe"),
             (["glyphs", font, "--text-file", tmp_path / "image.png", "-o", tmp_path / "a"], "image.png",
              "a PNG image, not a UTF-8 text file")]
    for argv, name, what in cases:
        assert main([str(a) for a in argv]) == 2, argv
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and name in err[0] and what in err[0], err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["adir.glb", "image.png", "pipe.txt"]
    assert not list((tmp_path / "adir.glb").iterdir())
