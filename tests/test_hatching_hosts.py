"""Issue 38 in the web hosts: the tam bake's stroke parameterization drives the hatching of @baker/three and
@baker/babylon on every renderer the viewer has (three.js WebGLRenderer and WebGPURenderer, Babylon.js's WebGL2 Engine
and WebGPUEngine), checked in the picture.

A torus (R 1, r 0.35) is turned so that its axis points at the viewer's camera (examples/viewer/src/ui.js
FRAME_DIRECTION, the framing every page uses; the Babylon.js pages take the three.js page's view), so its principal
directions project to the image's radial and circular directions around the centre. The strokes' orientation in
the frame (structure tensor, tests/techniques/test_tam_strokes.py's measure, as baker preview's test uses it) must
follow them within 12 degrees RMS with the default stroke set (`--tam-strokes field`), and the same TAM over an
xatlas unwrap (`--tam-strokes uv`, strokes wherever the charts point) must be at least twice as far off: the pages
read the stroke set, not TEXCOORD_0.
"""
from __future__ import annotations

import json
import urllib.parse

import numpy as np
import pytest
import trimesh

import baker
from baker.gltf.images import read_image
from baker.pipeline import save
from browser import BACKGROUND_RGB, build_viewer, require_tools, serve, shoot
from tests.techniques.test_direction_field import torus
from tests.techniques.test_tam_strokes import stroke_orientation_error

W, H = 480, 360
FRAME_DIRECTION = np.array([0.5, 0.25, 0.85]) / np.linalg.norm([0.5, 0.25, 0.85])  # examples/viewer/src/ui.js
MODES = ("field", "uv")
PAGES = {"three": "", "three-webgpu": "&engine=three-webgpu", "babylon": "&engine=babylon",
         "babylon-webgpu": "&engine=babylon-webgpu"}


def axis_to(direction: np.ndarray) -> np.ndarray:
    """The rotation taking +z to the unit vector ``direction`` (Rodrigues)."""
    z = np.array([0.0, 0.0, 1.0])
    v, c = np.cross(z, direction), float(z @ direction)
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return np.eye(3) + k + k @ k / (1.0 + c)


@pytest.fixture(scope="module")
def frames(tmp_path_factory):
    require_tools("hatching hosts")
    root = tmp_path_factory.mktemp("hatching-site")
    build_viewer(root, ("viewer.js", "babylon.js", "three_webgpu.js"))
    positions, faces, _, _ = torus(R=1.0, r=0.35)
    source = root / "torus.glb"
    trimesh.Trimesh(positions @ axis_to(FRAME_DIRECTION).T, faces, process=False).export(str(source))
    for mode in MODES:
        options = {"size": 128, "levels": 3, "scale": 768.0, "strokes": mode}
        save(baker.bake(str(source), bakes=["tam"], options={"tam": options}), root / f"torus_{mode}.glb")
    server, url = serve(root)
    try:
        page = lambda mode, engine: f"{url}/index.html?hud=0&src=torus_{mode}.glb{PAGES[engine]}"  # noqa: E731
        three = [{"url": page(mode, "three"), "width": W, "height": H, "out": str(root / f"three-{mode}.png")}
                 for mode in MODES]
        infos = dict(zip(MODES, shoot(three, root / "three.json", webgpu=True)))
        others = [(mode, engine) for mode in MODES for engine in PAGES if engine != "three"]
        jobs = []
        for mode, engine in others:
            view = f"&view={urllib.parse.quote(json.dumps(infos[mode]['view']))}" if engine.startswith("babylon") else ""
            jobs.append({"url": page(mode, engine) + view, "width": W, "height": H,
                         "out": str(root / f"{engine}-{mode}.png")})
        infos = {("three", mode): info for mode, info in infos.items()}
        infos.update(zip([(engine, mode) for mode, engine in others],
                         shoot(jobs, root / "others.json", webgpu=True, timeout=1200)))
    finally:
        server.shutdown()
    images = {key: read_image(root / f"{key[0]}-{key[1]}.png")[..., :3].astype(np.float64) / 255.0 for key in infos}
    return infos, images


def test_every_page_draws_the_hatching(frames):
    infos, _ = frames
    for (engine, mode), info in infos.items():
        assert info["ready"] and not info["errors"] and not info["warnings"], (engine, mode, info)
        assert "tam" in info["techniques"], (engine, mode, info)
        assert info["backend"] == ("webgpu" if engine.endswith("webgpu") else "webgl2"), (engine, mode, info)


@pytest.mark.parametrize("engine", list(PAGES))
def test_strokes_follow_the_principal_directions_in_the_picture(frames, engine):
    _, images = frames
    errors = {}
    for mode in MODES:
        errors[mode], pixels = stroke_orientation_error(images[(engine, mode)], np.array(BACKGROUND_RGB) / 255.0)
        assert pixels > 10000, (engine, mode, pixels)
    print(engine, "stroke orientation error (deg RMS)", errors)
    assert errors["field"] < 12.0, errors
    assert errors["uv"] > 2.0 * errors["field"], errors
