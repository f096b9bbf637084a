"""@baker/three on three.js's WebGPURenderer (runtime-shaders/three/src/node) in headless Chromium with WebGPU
(SwiftShader on Vulkan: --enable-unsafe-webgpu --enable-features=Vulkan --use-vulkan=swiftshader
--use-angle=swiftshader, examples/viewer/test/screenshots.mjs with BAKER_WEBGPU=1). The viewer's ?engine=three-webgpu page draws
every technique; the same page with &backend=webgl2 draws it on WebGPURenderer's WebGL2 backend, and the
WebGLRenderer page (?engine=three, the onBeforeCompile / ShaderMaterial path) draws it as before. Per technique:

- the page reports the backend drawing (window.__bakerBackend, read from the renderer): 'webgpu', 'webgl2' with
  &backend=webgl2 and on the WebGLRenderer page; every page lists the techniques the asset's extensions imply, the
  same on the three pages, with no console error or warning;
- the WebGPU frame matches the WebGL2 backend's frame of the same page, same asset, view, lights and caustic time:
  SSIM of the luma >= SSIM_BACKEND = 0.97 (measured 0.998 to 1.000);
- it matches the WebGLRenderer page's frame: SSIM >= SSIM_WEBGL = 0.97 (measured 0.992 (hair) to 0.9996), except where
  blending happens in another space (SSIM_WEBGL_BLENDED = 0.95, measured 0.966 fur, 0.973 wireframe): the fur fins,
  the blended shells and the premultiplied wireframe lines mix with the frame in WebGPURenderer's linear working
  colour and are encoded to sRGB after, where a WebGLRenderer ShaderMaterial writes its values as they are and
  mixes them in the canvas' sRGB values; the opaque pixels agree (the frames differ at partly covered pixels);
- the technique changes the picture: with it off (every other technique off too) at least 100 pixels change by more
  than 4/255, and the change the WebGPU page shows there is the WebGL2 backend's: on those pixels, after a Gaussian
  blur of sigma 1.5 px (it forgives the two APIs' sub-pixel placement of pixel-wide lines, as tests/test_babylon.py
  does), the mean |WebGPU change - WebGL2 change| stays below DELTA_RATIO = 0.35 of the mean WebGL2 change
  (measured 0.001 (text) to 0.14 (the Blender head's normal blur)).

A page without a WebGPU adapter (Chromium without the flags) says so on the page and in window.__bakerError.
Failing frames leave their images in .cache/test-artifacts/test_three_webgpu/.
"""
from __future__ import annotations


import numpy as np
import pytest
from scipy import ndimage
from skimage.metrics import structural_similarity

import baker
from baker.gltf.images import read_image, write_image
from baker.pipeline import save
from browser import (SPOT_PAGE_OPTIONS, ROOT, SPOT, VIEWER, build_viewer, gltf_json, require_tools, serve, shoot, techniques_in,
                     write_blender_head, write_blurred_sphere, write_hair_cards, write_label_and_groom)

ARTIFACTS = ROOT / ".cache" / "test-artifacts" / "test_three_webgpu"
W, H = 320, 240
SSIM_BACKEND = 0.97
SSIM_WEBGL = 0.97
SSIM_WEBGL_BLENDED = 0.95
BLENDED = {"fur", "wireframe"}
DELTA_RATIO = 0.35
BLUR = 1.5
TIME = "&time=1.3"  # the caustic animation held at one time on every page
ENGINES = {"webgpu": "&engine=three-webgpu", "gl2": "&engine=three-webgpu&backend=webgl2", "webgl": ""}
BACKENDS = {"webgpu": "webgpu", "gl2": "webgl2", "webgl": "webgl2"}
BACK_LIT = {"translucency"}  # lit from behind (?on=backlight), the others from the front (the viewer's default)
# the techniques whose frames are compared, where not all of an asset's: the Blender head (a real asset with vertex
# TANGENTs: the blurred normals through its tangent frame) is in metres, where the skin LUT changes no pixel
COMPARED = {"head.glb": {"normalBlur"}}


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The built viewer (the WebGL and WebGPU bundles) and the assets, baked once, served on the loopback."""
    require_tools("three-webgpu", ("playwright-core", "three"))
    root = tmp_path_factory.mktemp("three-webgpu-site")
    build_viewer(root, ("viewer.js", "three_webgpu.js"))
    asset = baker.bake(SPOT, bakes=("thickness", "curvature", "skin", "edges", "tam", "toon", "fur", "caustics"),
                       options=SPOT_PAGE_OPTIONS)
    save(asset, root / "spot_all.glb")
    write_label_and_groom(root)
    write_hair_cards(root)
    write_blurred_sphere(root)
    write_blender_head(root)
    names = ("spot_all.glb", "label.glb", "hair.glb", "cards.glb", "blurred.glb", "head.glb")
    assets = {name: techniques_in(gltf_json(root / name)) for name in names}
    server, url = serve(root)
    yield {"url": url, "root": root, "assets": assets}
    server.shutdown()


def _loads(assets):
    """(asset, query, [(technique or None, on, off)]): per load the shots taken in it; None is every technique off."""
    loads = []
    for name, techniques in assets.items():
        every = sorted(techniques)
        alone = lambda t: (t, [t], [x for x in every if x != t])  # noqa: E731
        compared = COMPARED.get(name, techniques)
        front = [t for t in every if t not in BACK_LIT and t in compared]
        back = [t for t in every if t in BACK_LIT and t in compared]
        if front:
            loads.append((name, "", [(None, [], every)] + [alone(t) for t in front]))
        if back:
            loads.append((name, "&on=backlight", [(None, [], every)] + [alone(t) for t in back]))
    return loads


@pytest.fixture(scope="module")
def frames(site, tmp_path_factory):
    """Every load on the three pages (WebGPU, its WebGL2 backend, WebGLRenderer) in one Chromium with WebGPU."""
    out = tmp_path_factory.mktemp("three-webgpu-frames")
    loads = _loads(site["assets"])
    jobs, keys = [], []
    for engine, query in ENGINES.items():
        for i, (name, extra, shots) in enumerate(loads):
            jobs.append({"url": f"{site['url']}/index.html?hud=0&src={name}{extra}{TIME}{query}", "width": W,
                         "height": H, "shots": [{"on": on, "off": off, "out": str(out / f"{engine}-{i}-{t}.png")}
                                                for t, on, off in shots]})
            keys.append((engine, i))
    infos = dict(zip(keys, shoot(jobs, out / "jobs.json", webgpu=True, timeout=1200)))
    images = {(engine, i, t): read_image(out / f"{engine}-{i}-{t}.png")[..., :3].astype(np.float32) / 255.0
              for engine in ENGINES for i, (_, _, shots) in enumerate(loads) for t, _, _ in shots}
    return {"loads": loads, "infos": infos, "images": images}


def _blur(image):
    return ndimage.gaussian_filter(image, sigma=(BLUR, BLUR, 0))


def _luma(image):
    return image @ np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)


def _ssim(a, b):
    return float(structural_similarity(_luma(a), _luma(b), data_range=1.0))


def _keep(label, images):
    folder = ARTIFACTS / label
    folder.mkdir(parents=True, exist_ok=True)
    for name, image in images.items():
        write_image(folder / f"{name}.png", (np.clip(image, 0, 1) * 255 + 0.5).astype(np.uint8))
    return folder


def test_three_webgpu_reports_its_backend_and_the_same_techniques(site, frames):
    assert site["assets"] == {
        "spot_all.glb": {"translucency", "skin", "toon", "tam", "fins", "outline", "wireframe", "fur", "curvature",
                         "caustics"},
        "label.glb": {"text"}, "hair.glb": {"hair"}, "cards.glb": {"cards"}, "blurred.glb": {"normalBlur"},
        "head.glb": {"normalBlur", "skin", "curvature"}}
    for (engine, i), info in frames["infos"].items():
        name = frames["loads"][i][0]
        assert info["ready"] and not info["error"], (engine, info)
        assert not info["errors"], (engine, info)
        assert not info["warnings"], (engine, info)
        assert info["backend"] == BACKENDS[engine], (engine, info)
        assert set(info["techniques"]) == site["assets"][name], (engine, info)
        assert info["techniques"] == frames["infos"][("webgl", i)]["techniques"], (engine, info)


def test_three_webgpu_draws_each_technique_like_webgl2(frames):
    images = frames["images"]
    failures, measured = [], {}
    for i, (name, _, shots) in enumerate(frames["loads"]):
        for technique, _, _ in shots:
            if technique is None:
                continue
            webgpu, gl2, webgl = (images[(e, i, technique)] for e in ENGINES)
            off = {e: images[(e, i, None)] for e in ENGINES}
            backend, across = _ssim(webgpu, gl2), _ssim(webgpu, webgl)
            changed = np.abs(webgpu - off["webgpu"]).max(axis=2) > 4 / 255
            change, change_gl2 = _blur(webgpu) - _blur(off["webgpu"]), _blur(gl2) - _blur(off["gl2"])
            ratio = float(np.abs(change - change_gl2).max(axis=2)[changed].mean()
                          / max(np.abs(change_gl2).max(axis=2)[changed].mean(), 1e-6)) if changed.any() else 1.0
            measured[f"{name}:{technique}"] = (round(backend, 4), round(across, 4), int(changed.sum()), round(ratio, 3))
            problems = []
            if backend < SSIM_BACKEND:
                problems.append(f"SSIM {backend:.3f} against the WebGL2 backend")
            bound = SSIM_WEBGL_BLENDED if technique in BLENDED else SSIM_WEBGL
            if across < bound:
                problems.append(f"SSIM {across:.3f} against WebGLRenderer")
            if changed.sum() < 100:
                problems.append(f"only {int(changed.sum())} pixels change with the technique off")
            if ratio > DELTA_RATIO:
                problems.append(f"change error {ratio:.2f} of the WebGL2 backend's change")
            if problems:
                folder = _keep(f"{name}-{technique}", {"webgpu": webgpu, "gl2": gl2, "webgl": webgl,
                                                       "webgpu_off": off["webgpu"]})
                failures.append(f"{name} {technique}: {'; '.join(problems)} (frames in {folder})")
    print("per technique (SSIM backend, SSIM WebGLRenderer, changed pixels, change error):", measured)
    assert {key.split(":")[1] for key in measured} == {
        "translucency", "skin", "toon", "tam", "fins", "outline", "wireframe", "fur", "curvature", "caustics", "text",
        "hair", "cards", "normalBlur"}, measured
    assert "head.glb:normalBlur" in measured, measured
    assert not failures, "\n".join(failures) + f"\nmeasured {measured}"


def test_three_webgpu_without_an_adapter_says_so(site, tmp_path):
    """Chromium without the WebGPU flags (and --disable-gpu) has no adapter: the page reports it, never a blank canvas
    that looks like a working page; the WebGL2 backend of the same page still draws."""
    jobs = [{"url": f"{site['url']}/index.html?hud=0&src=spot_all.glb&engine=three-webgpu", "width": W, "height": H},
            {"url": f"{site['url']}/index.html?hud=0&src=spot_all.glb&engine=three-webgpu&backend=webgl2",
             "width": W, "height": H}]
    no_adapter, fallback = shoot(jobs, tmp_path / "jobs.json")
    assert not no_adapter["ready"], no_adapter
    assert "no WebGPU adapter" in no_adapter["status"], no_adapter
    assert fallback["ready"] and not fallback["errors"], fallback
    assert set(fallback["techniques"]) == site["assets"]["spot_all.glb"], fallback
