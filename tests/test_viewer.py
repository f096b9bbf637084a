"""The web viewer in headless Chromium: loads a baked asset without console errors, and draws `baker preview`'s
translucency panel (same GLSL module, same camera and uniforms) like the moderngl render, within a tolerance."""
from __future__ import annotations

import functools
import http.server
import json
import os
import shutil
import subprocess
import threading
from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage

import baker
from baker import preview as pv
from baker.io.images import read_image
from baker.pipeline import save

ROOT = Path(__file__).parents[1]
VIEWER = ROOT / "examples" / "viewer"
SPOT = ROOT / "examples" / "spot" / "spot.obj"
SIZE = 256


def _require_tools():
    problems = []
    if shutil.which("node") is None:
        problems.append("node")
    if not (VIEWER / "node_modules" / "playwright-core").is_dir():
        problems.append("examples/viewer/node_modules (npm ci)")
    if not Path(os.environ.get("CHROMIUM", "/usr/bin/chromium")).exists():
        problems.append("chromium (apt-get install chromium)")
    if problems:
        if os.environ.get("CI", "").lower() in ("1", "true", "yes"):
            pytest.fail(f"viewer test needs {', '.join(problems)} in CI (scripts/test installs them)")
        pytest.skip(f"missing {', '.join(problems)}")


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """A served folder with the built viewer, a baked asset, and the preview panel's shader and setup."""
    _require_tools()
    build = subprocess.run(["npm", "run", "build"], cwd=VIEWER, capture_output=True, text=True, timeout=300)
    assert build.returncode == 0, build.stderr
    root = tmp_path_factory.mktemp("site")
    shutil.copy(VIEWER / "index.html", root / "index.html")
    (root / "dist").mkdir()
    shutil.copy(VIEWER / "dist" / "viewer.js", root / "dist" / "viewer.js")
    asset = baker.bake(SPOT, options={"thickness": {"rays": 16, "per_texel": False}})
    save(asset, root / "spot.glb")

    items = pv.scene_items(asset)
    camera = pv.frame_camera(items, azimuth=150, elevation=15)
    panel = next(p for p in pv.PANELS if p.name == "translucency")
    (root / "panel.frag").write_text(pv.fragment_shader(panel))
    uniforms = {k: list(v) if isinstance(v, tuple) else v for k, v in panel.uniforms(items[0]).items()}
    setup = {
        "size": SIZE, "background": list(pv.BACKGROUND), "attribute": panel.attribute,
        "viewProjection": (camera.projection @ camera.view).T.reshape(-1).tolist(),  # column-major for three.js
        "eye": camera.eye.tolist(), "light": pv.light_direction(camera, panel.light).tolist(), "uniforms": uniforms,
    }
    (root / "setup.json").write_text(json.dumps(setup))
    ctx = pv.create_context()
    try:
        reference = pv.render_panel(ctx, panel, items, camera, SIZE)
    finally:
        ctx.release()

    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args):
            pass

    handler = functools.partial(Quiet, directory=str(root))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield {"url": f"http://127.0.0.1:{server.server_address[1]}", "root": root, "reference": reference}
    server.shutdown()


def _screenshot(url, out, width=SIZE, height=SIZE):
    result = subprocess.run(["node", str(VIEWER / "test" / "screenshot.mjs"), url, str(out), str(width), str(height)],
                            capture_output=True, text=True, timeout=180, cwd=VIEWER)
    assert result.returncode == 0, result.stderr
    info = json.loads(result.stdout.strip().splitlines()[-1])
    image = read_image(out)[..., :3].astype(np.float32) / 255.0
    return info, image


def test_viewer_loads_baked_asset_without_errors(site, tmp_path):
    info, image = _screenshot(f"{site['url']}/index.html?src=spot.glb", tmp_path / "viewer.png", 480, 360)
    assert info["ready"] and not info["errors"], info
    assert "translucency" in info["status"]
    background = np.array([0x29, 0x2B, 0x30]) / 255.0
    drawn = np.abs(image - background).max(axis=2) > 0.03
    assert 0.03 < drawn.mean() < 0.9  # the model is on screen


def test_viewer_matches_baker_preview(site, tmp_path):
    info, image = _screenshot(f"{site['url']}/index.html?panel=panel.frag&setup=setup.json&src=spot.glb",
                              tmp_path / "panel.png")
    assert info["ready"] and not info["errors"], info
    reference = site["reference"]
    background = np.array(pv.BACKGROUND)
    covered_ref = np.abs(reference - background).max(axis=2) > 0.02
    covered_web = np.abs(image - background).max(axis=2) > 0.02
    iou = (covered_ref & covered_web).sum() / (covered_ref | covered_web).sum()
    assert iou > 0.97, iou
    # compare away from silhouettes, where the two rasterizers' antialiasing differs
    interior = ndimage.binary_erosion(covered_ref & covered_web, iterations=2)
    diff = np.abs(image - reference)[interior]
    assert diff.mean() < 2 / 255, diff.mean() * 255
    assert np.percentile(diff, 99) < 8 / 255, np.percentile(diff, 99) * 255
