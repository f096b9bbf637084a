"""``baker build``: recipes, incremental cache, --check, failures, parallel and Dask builds byte-identical."""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
import trimesh

from baker.commands.build import LOCK_NAME, build, check, load_recipe
from baker.cli import main
from baker.errors import BakerError
from conftest import assert_khronos_clean

FAST = """
[build]
output = "baked"
format = "glb"
bakes = ["thickness"]
seed = 7

[options.thickness]
rays = 4
texture_size = 32
"""


@pytest.fixture
def project(tmp_path):
    models = tmp_path / "models"
    (models / "sub").mkdir(parents=True)
    trimesh.creation.icosphere(subdivisions=2).export(str(models / "ball.obj"))
    trimesh.creation.box().export(str(models / "sub" / "box.glb"))
    (tmp_path / "baker.toml").write_text(FAST + """
[[assets]]
inputs = ["models/**/*.obj", "models/**/*.glb"]

[[assets]]
inputs = ["models/sub/*.glb"]
[assets.options.thickness]
rays = 8

[[commands]]
command = "preview"
args = ["{input}", "-o", "{output}", "--size", "48", "-q"]
input = "models/sub/box.glb"
output = "previews/box.png"
""")
    return tmp_path


def _files(root: Path) -> dict:
    return {p.relative_to(root).as_posix(): p.read_bytes() for p in sorted(root.rglob("*"))
            if p.is_file() and ("baked" in p.parts or "previews" in p.parts)}


def test_build_then_everything_cached(project):
    recipe = load_recipe(project / "baker.toml")
    assert [t.output for t in recipe.tasks] == ["baked/models/ball.glb", "baked/models/sub/box.glb", "previews/box.png"]
    box = recipe.tasks[1]
    assert box.options["thickness"]["rays"] == 8 and recipe.tasks[0].options["thickness"]["rays"] == 4
    report = build(recipe)
    assert sorted(report["baked"]) == ["baked/models/ball.glb", "baked/models/sub/box.glb", "previews/box.png"]
    assert not report["failed"] and not report["skipped"]
    for out in ("baked/models/ball.glb", "baked/models/sub/box.glb"):
        assert_khronos_clean(project / out)
    lock = json.loads((project / LOCK_NAME).read_text())
    assert [e["output"] for e in lock["entries"]] == sorted(e["output"] for e in lock["entries"])
    again = build(load_recipe(project / "baker.toml"))
    assert not again["baked"] and len(again["skipped"]) == 3
    assert check(load_recipe(project / "baker.toml"), khronos=False) == []


def test_one_changed_input_rebakes_one_asset(project):
    build(load_recipe(project / "baker.toml"))
    trimesh.creation.icosphere(subdivisions=3).export(str(project / "models" / "ball.obj"))
    stale = check(load_recipe(project / "baker.toml"), khronos=False)
    assert [(p["output"], p["problem"]) for p in stale] == [("baked/models/ball.glb", "stale")]
    report = build(load_recipe(project / "baker.toml"))
    assert report["baked"] == ["baked/models/ball.glb"] and len(report["skipped"]) == 2


def test_option_change_rebakes(project):
    build(load_recipe(project / "baker.toml"))
    text = (project / "baker.toml").read_text().replace("rays = 8", "rays = 16")
    (project / "baker.toml").write_text(text)
    report = build(load_recipe(project / "baker.toml"))
    assert report["baked"] == ["baked/models/sub/box.glb"]


def test_check_finds_missing_modified_and_invalid(project, capsys):
    recipe_path = str(project / "baker.toml")
    assert main(["build", "--recipe", recipe_path, "--check", "--no-khronos"]) == 1  # nothing built yet
    assert main(["build", "--recipe", recipe_path, "-q"]) == 0
    assert main(["build", "--recipe", recipe_path, "--check", "--no-khronos"]) == 0
    capsys.readouterr()
    (project / "previews" / "box.png").unlink()
    glb = project / "baked" / "models" / "ball.glb"
    glb.write_bytes(glb.read_bytes()[:-4] + b"\0\0\0\0")
    assert main(["build", "--recipe", recipe_path, "--check", "--format", "json", "--no-khronos"]) == 1
    problems = {p["output"]: p["problem"] for p in json.loads(capsys.readouterr().out)["problems"]}
    assert problems == {"baked/models/ball.glb": "modified", "previews/box.png": "missing"}


def test_invalid_output_is_reported(project):
    build(load_recipe(project / "baker.toml"))
    lock_path = project / LOCK_NAME
    glb = project / "baked" / "models" / "sub" / "box.glb"
    data = bytearray(glb.read_bytes())
    at = data.find(b'"rays":8')
    data[at: at + 8] = b'"rays":0'  # violates the schema (rays >= 1)
    glb.write_bytes(bytes(data))
    # record the tampered bytes as built, so only validation can catch it
    import hashlib

    lock = json.loads(lock_path.read_text())
    for entry in lock["entries"]:
        if entry["output"] == "baked/models/sub/box.glb":
            entry["outputs"]["baked/models/sub/box.glb"] = hashlib.sha256(bytes(data)).hexdigest()
    lock_path.write_text(json.dumps(lock))
    problems = check(load_recipe(project / "baker.toml"), khronos=False)
    assert [(p["output"], p["problem"]) for p in problems] == [("baked/models/sub/box.glb", "invalid")]


def test_unknown_key_names_file_and_line(project, capsys):
    path = project / "baker.toml"
    path.write_text(path.read_text().replace("rays = 4", "rays = 4\nray_count = 9"))
    line = path.read_text().splitlines().index("ray_count = 9") + 1
    with pytest.raises(BakerError) as err:
        load_recipe(path)
    assert str(path) in str(err.value) and f"line {line}:" in str(err.value) and "ray_count" in str(err.value)
    assert main(["build", "--recipe", str(path)]) == 2
    assert f"line {line}:" in capsys.readouterr().err


def test_failing_asset_does_not_stop_the_others(project):
    (project / "models" / "broken.glb").write_bytes(b"glTF\x02\x00\x00\x00")
    report = build(load_recipe(project / "baker.toml"))
    assert [o for o, _ in report["failed"]] == ["baked/models/broken.glb"]
    assert "truncated GLB" in report["failed"][0][1]
    assert len(report["baked"]) == 3
    assert not (project / "baked" / "models" / "broken.glb").exists()
    fast = build(load_recipe(project / "baker.toml"), fail_fast=True)  # the good ones are cached now
    assert len(fast["failed"]) == 1


def test_max_memory_limits_each_bake_job(project, capsys):
    """``baker build --max-memory``: a bake job estimated above the limit fails with the reason; the rest of the
    recipe (the preview command, which takes its own ``--max-memory``) still runs."""
    from baker.commands.build import job_memory_limit
    from baker.memory import parse_limit

    assert main(["build", "--recipe", str(project / "baker.toml"), "--max-memory", "1M", "-q"]) == 1
    table = capsys.readouterr().out
    assert "--max-memory" in table and not (project / "baked").exists()
    assert (project / "previews" / "box.png").is_file()
    assert job_memory_limit(None, 4, None) == parse_limit(None) // 4  # the default is shared by the jobs
    assert job_memory_limit(None, 4, "tcp://elsewhere:8786") is None and job_memory_limit("2G", 4, None) == 2 << 30


def test_parallel_and_dask_builds_are_byte_identical(project, tmp_path_factory):
    build(load_recipe(project / "baker.toml"))
    serial = _files(project)
    parallel = tmp_path_factory.mktemp("parallel")
    dask_root = tmp_path_factory.mktemp("dask")
    for root in (parallel, dask_root):
        shutil.copytree(project / "models", root / "models")
        shutil.copy(project / "baker.toml", root / "baker.toml")
    report = build(load_recipe(parallel / "baker.toml"), jobs=2)
    assert len(report["baked"]) == 3
    assert _files(parallel) == serial

    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None) as cluster:
        report = build(load_recipe(dask_root / "baker.toml"), scheduler=cluster.scheduler_address)
    assert len(report["baked"]) == 3 and not report["failed"]
    assert _files(dask_root) == serial


SHARED = Path(__file__).resolve().parents[2] / "shared" / "assets" / "meshes"


def make_thirty(root: Path) -> None:
    """30 assets: each shared mesh as 5 scaled/rotated copies, as .glb and .obj."""
    import numpy as np

    meshes = sorted(SHARED.glob("*.obj"))
    rng = np.random.default_rng(0)
    (root / "assets").mkdir(parents=True, exist_ok=True)
    for path in meshes:
        base = trimesh.load(str(path), process=False, force="mesh")
        for k in range(30 // len(meshes)):
            m = base.copy()
            angle = rng.uniform(0, 2 * np.pi)
            m.apply_transform(trimesh.transformations.rotation_matrix(angle, rng.normal(size=3)))
            m.apply_scale(rng.uniform(0.5, 2.0))
            m.export(str(root / "assets" / f"{path.stem}_{k}.{'glb' if k % 2 else 'obj'}"))


THIRTY = """
[build]
output = "baked"
bakes = ["thickness"]

[options.thickness]
rays = 4
per_texel = false

[[assets]]
inputs = ["assets/*.glb", "assets/*.obj"]
"""


@pytest.mark.skipif(not SHARED.is_dir(), reason="../shared/assets is not beside the checkout")
def test_thirty_assets_one_touched_rebakes_exactly_one(tmp_path):
    project, clean = tmp_path / "project", tmp_path / "clean"
    for root in (project, clean):
        make_thirty(root)
        (root / "baker.toml").write_text(THIRTY)
    assert len(load_recipe(project / "baker.toml").tasks) == 30
    first = build(load_recipe(project / "baker.toml"), jobs=2)
    assert len(first["baked"]) == 30 and not first["failed"]
    # touch one input: same mesh, one vertex moved
    target = project / "assets" / "spot_1.glb"
    mesh = trimesh.load(str(target), force="mesh", process=False)
    mesh.vertices[0] += 1e-3
    mesh.export(str(target))
    second = build(load_recipe(project / "baker.toml"))
    assert second["baked"] == ["baked/assets/spot_1.glb"] and len(second["skipped"]) == 29
    # the incremental result equals a clean build of the same inputs, byte for byte
    shutil.copy(target, clean / "assets" / "spot_1.glb")
    build(load_recipe(clean / "baker.toml"), jobs=2)
    assert _files(project) == _files(clean)
    assert (project / LOCK_NAME).read_bytes() == (clean / LOCK_NAME).read_bytes()


def test_example_recipe_builds_and_checks(tmp_path):
    # examples/baker.toml: a per-glob override and a command whose input is a baked output (built after it)
    examples = Path(__file__).parents[1] / "examples"
    shutil.copytree(examples / "spot", tmp_path / "spot")
    text = (examples / "baker.toml").read_text().replace("rays = 64", "rays = 8").replace("texture_size = 512",
                                                                                          "texture_size = 64")
    (tmp_path / "baker.toml").write_text(text)
    assert check(load_recipe(tmp_path / "baker.toml"), khronos=False)[-1]["problem"] == "missing"
    report = build(load_recipe(tmp_path / "baker.toml"))
    assert report["baked"] == ["out/spot/spot.glb", "out/spot_preview.png"] and not report["failed"]
    lock = {e["output"]: e for e in json.loads((tmp_path / LOCK_NAME).read_text())["entries"]}
    assert lock["out/spot/spot.glb"]["bakes"] == ["thickness", "curvature", "skin", "edges", "tam", "toon"]
    assert lock["out/spot/spot.glb"]["options"]["tam"]["style"] == "cross-hatching"
    assert check(load_recipe(tmp_path / "baker.toml"), khronos=False) == []
    assert_khronos_clean(tmp_path / "out" / "spot" / "spot.glb")


CACHE_PROBE = r"""
import json, trimesh
from baker.geometry.raycast import RayScene
from baker.techniques.thickness import kernel
mesh = trimesh.creation.icosphere(2)
scene = RayScene(mesh.vertices, mesh.faces)
assert scene.direct is not None, "the direct Embree path is not available"
kernel.local_thickness(scene, mesh.vertices, mesh.vertex_normals, rays=4)
stats = kernel._thickness_direct.stats
print(json.dumps({"hits": len(stats.cache_hits), "misses": len(stats.cache_misses)}))
"""


def test_direct_embree_thickness_kernel_loads_from_numba_cache():
    # the kernel calls Embree by symbol name, so a fresh process (a `build --jobs` worker) loads it from the disk
    # cache instead of compiling it again; the first run fills the cache if the checkout's is cold
    import os
    import subprocess
    import sys

    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    runs = [json.loads(subprocess.run([sys.executable, "-c", CACHE_PROBE], env=env, capture_output=True, text=True,
                                      check=True).stdout) for _ in range(2)]
    assert runs[1] == {"hits": 1, "misses": 0}, runs


def test_parent_warms_kernels_only_while_the_stamp_is_missing(monkeypatch):
    from baker.commands import build as build_module

    calls = []
    monkeypatch.setattr(build_module, "warm_kernels", lambda bakes: calls.append(list(bakes)))
    bakes = ["test-stamp-probe"]  # a name no real build uses, so the real stamps are untouched
    stamp = build_module.warm_stamp(bakes)
    stamp.unlink(missing_ok=True)
    try:
        build_module.warm_kernels_once(bakes)
        build_module.warm_kernels_once(bakes)
        assert calls == [bakes] and stamp.is_file()
        monkeypatch.setenv("NUMBA_CACHE_DIR", "/elsewhere")  # another cache folder is a different, cold cache
        assert build_module.warm_stamp(bakes) == Path("/elsewhere") / stamp.name
    finally:
        stamp.unlink(missing_ok=True)
