"""BAKER_hair_shading drawn by the hosts: the strands of a small `baker hair` groom on a ball, blond (eumelanin 0.3)
and black (eumelanin 8), shaded by runtime-shaders/baker_hair_shading.glsl in @baker/three (WebGLRenderer) and
@baker/babylon (WebGL2 Engine), by baker_hair_shading.wgsl in @baker/three on WebGPURenderer (TSL) and @baker/babylon
on WebGPUEngine, in headless Chromium through the viewer, and in the preview's hair panel (moderngl).

Lit from behind (the viewer's ?on=backlight: the key light behind the ball facing the camera; the preview's "back"
light), blond hair glows: the fibre model's forward scattering (TT and Zinke's global multiple scattering) lets the
light through, so the frame's mean luminance above the background is clearly above the Kajiya-Kay frame's (which has
no transmission) and above the black groom's, and above the blond groom's own front-lit frame. Black hair absorbs
what it transmits: it stays far below the blond glow. The ball, background and camera are the same in the frames
compared, so whole-frame means compare the hair alone. (WebGPURenderer blends the partly covered ribbons in linear
colour, WebGLRenderer in the written values: its glow is about twice as bright; both backends of WebGPURenderer
agree.)
"""
from __future__ import annotations

import dataclasses
import shutil
import time

import numpy as np
import pytest
import trimesh
from PIL import Image

from baker import readers
from baker.cli import main
from baker.preview import core as pv
from browser import BACKGROUND_RGB, build_viewer, require_tools, serve, shoot

GROOM = ["--guides", "50", "--children", "4", "--segments", "5", "--length", "0.6", "--root-width", "0.012",
         "--tip-width", "0.004", "-q"]
MELANIN = {"blond": "0.3", "black": "8"}
LUMA = np.array([0.2126, 0.7152, 0.0722])
# the viewer's page: the panel takes 240 px of the width, the canvas the remaining 160 x 160
PAGE = {"width": 400, "height": 160}
ENGINE_QUERY = {"three": "", "three-webgpu": "&engine=three-webgpu", "three-webgpu-webgl2": "&engine=three-webgpu&backend=webgl2",
                "babylon": "&engine=babylon", "babylon-webgpu": "&engine=babylon-webgpu"}
# (groom, light, shading) of the frames each host draws
FRAMES = [("blond", "back", "fibre"), ("blond", "back", "kajiyaKay"), ("black", "back", "fibre"),
          ("blond", "front", "fibre")]


@pytest.fixture(scope="module")
def grooms(tmp_path_factory):
    root = tmp_path_factory.mktemp("hair_shading")
    ball = root / "ball.obj"
    trimesh.creation.icosphere(subdivisions=2, radius=0.5).export(str(ball))
    for name, eumelanin in MELANIN.items():
        assert main(["hair", str(ball), "-o", str(root / f"{name}.glb"), "--hair-eumelanin", eumelanin, *GROOM]) == 0
    return root


def excess(image) -> float:
    """Mean luminance above the background's over the frame (linear in the 8-bit sRGB values, as displayed)."""
    return float((np.asarray(image, float) @ LUMA).mean() - (np.array(BACKGROUND_RGB) / 255.0) @ LUMA)


def assert_glows(measured: dict, label: str) -> None:
    """measured[(groom, light, shading)] = excess luminance: the blond groom glows lit from behind, black does not."""
    print(label, {"/".join(k): round(v, 4) for k, v in measured.items()})
    glow = measured["blond", "back", "fibre"]
    assert glow > 1.3 * measured["blond", "back", "kajiyaKay"], measured
    assert glow > 1.3 * measured["blond", "front", "fibre"], measured
    assert glow > 2.0 * measured["black", "back", "fibre"], measured


def test_preview_hair_panel_glows_blond_not_black(grooms):
    started = time.perf_counter()
    panels = {p.name: p for p in pv.all_panels()}
    measured = {}
    ctx = pv.create_context()
    try:
        for groom in MELANIN:
            scene = pv.gather_scene(readers.read(grooms / f"{groom}.glb", require_triangles=False), pv.all_panels())
            camera = pv.frame_camera(scene, 30, 15)
            for _, light, shading in (f for f in FRAMES if f[0] == groom):
                drawn = dataclasses.replace(panels["hair" if shading == "fibre" else "hair-kajiya-kay"], light=light)
                measured[groom, light, shading] = excess(pv.render_panel(ctx, drawn, scene, camera, 128))
            scene.release()
    finally:
        ctx.release()
    assert_glows(measured, f"preview ({time.perf_counter() - started:.1f} s)")


@pytest.fixture(scope="module")
def site(grooms):
    """The built viewer (three.js and Babylon.js pages) and the two grooms, served on the loopback."""
    require_tools("hair shading")
    root = grooms / "site"
    root.mkdir()
    build_viewer(root, ("viewer.js", "babylon.js", "three_webgpu.js"))
    for groom in MELANIN:
        shutil.copy(grooms / f"{groom}.glb", root / f"{groom}.glb")
    server, url = serve(root)
    yield url
    server.shutdown()


# three-webgpu-webgl2: WebGPURenderer's WebGL2 backend (the TSL wrapper's GLSL, the tables passed as sampler2D)
@pytest.mark.parametrize("engine", ["three", "three-webgpu", "three-webgpu-webgl2", "babylon", "babylon-webgpu"])
def test_web_hosts_glow_blond_not_black(site, engine, tmp_path):
    started = time.perf_counter()
    jobs = []
    for groom, light, shading in FRAMES:
        query = f"src={groom}.glb" + ("&on=backlight" if light == "back" else "")
        query += ("&hairShading=kajiyaKay" if shading == "kajiyaKay" else "") + ENGINE_QUERY[engine]
        jobs.append({"url": f"{site}/index.html?{query}", "out": str(tmp_path / f"{groom}-{light}-{shading}.png"), **PAGE})
    infos = shoot(jobs, tmp_path / "jobs.json", webgpu="webgpu" in engine)
    measured = {}
    for frame, job, info in zip(FRAMES, jobs, infos):
        assert not info["errors"] and not info["warnings"], info
        assert info["techniques"] == ["hair"], info
        assert info["backend"] == ("webgpu" if engine.endswith("webgpu") else "webgl2"), info
        measured[frame] = excess(np.asarray(Image.open(job["out"]).convert("RGB")) / 255.0)
    assert_glows(measured, f"{engine} ({time.perf_counter() - started:.1f} s)")
