"""@baker/babylon on Babylon.js's WebGPUEngine (examples/viewer/?engine=babylon-webgpu) against the same page on its
WebGL2 Engine (?engine=babylon), in one headless Chromium with a WebGPU adapter (SwiftShader on Vulkan:
shoot(webgpu=True) gives the driver the four flags; its WebGL2 pages draw through ANGLE's SwiftShader).

The assets: the spot baked with every bake (translucency, skin, toon, hatching, fins, outline, wireframe, fur,
caustics, curvature view), a `baker text` label (MSDF text), a `baker hair` groom (ribbons), hair cards and a
normal-mapped sphere baked with normal-blur (tests/browser.py writes them). Per technique, the frame with that
technique alone on:
- on WebGPU matches the WebGL2 frame of the same page (same asset, view, lights and caustic time): SSIM of the
  luma >= SSIM_MIN = 0.97, or the per-technique bound of TOLERANCE with its reason;
- on WebGPU differs from the WebGPU frame with every technique off (the technique changes the picture there).
The WebGPU page must report window.__bakerBackend === 'webgpu' (the WebGL2 page 'webgl2'), no console errors or
WebGPU/WGSL/Babylon warnings, and the same techniques as the WebGL2 page (those the file's extensions imply). No
compiler is fetched: the machine has no network, so a GLSL material on WebGPU (glslang from a CDN) fails the page.
Failing frames leave webgl2.png, webgpu.png and diff.png (|difference| x 4) in .cache/test-artifacts/.
"""
from __future__ import annotations

import numpy as np
import pytest
from skimage.metrics import structural_similarity

import baker
from baker import registry
from baker.gltf.images import read_image, write_image
from baker.pipeline import save
from browser import (SPOT_PAGE_OPTIONS, BACKGROUND_RGB, ROOT, SPOT, build_viewer, gltf_json, require_tools, serve, shoot,
                     techniques_in, write_blurred_sphere, write_hair_cards, write_label_and_groom)

ARTIFACTS = ROOT / ".cache" / "test-artifacts" / "test_babylon_webgpu"
W, H = 320, 240  # small frames: SwiftShader on two shared cores
BACKGROUND = np.array(BACKGROUND_RGB) / 255.0
SSIM_MIN = 0.97
# technique -> (SSIM bound, why it is below SSIM_MIN); measured values are printed by the test
TOLERANCE: dict[str, tuple[float, str]] = {}
CHANGED = 4 / 255  # a pixel the technique changed
CHANGED_PIXELS = 100

TIME = "&time=1.3"  # the caustic animation held at one time of its loop, so the two backends' frames compare
BACK_LIT = {"translucency"}  # lit from behind (?on=backlight), the others from the front (the viewer's default)
ENGINES = ("babylon", "babylon-webgpu")


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The built viewer and the five assets (baked once for the module), served on the loopback."""
    require_tools("babylon-webgpu", ("playwright-core", "@babylonjs/core", "@babylonjs/loaders"))
    root = tmp_path_factory.mktemp("babylon-webgpu-site")
    build_viewer(root, ("viewer.js", "babylon.js"))
    save(baker.bake(SPOT, bakes=tuple(registry.bakes()), options=SPOT_PAGE_OPTIONS), root / "spot_all.glb")
    write_label_and_groom(root)
    names = ["spot_all.glb", "label.glb", "hair.glb", write_hair_cards(root), write_blurred_sphere(root)]
    assets = {name: techniques_in(gltf_json(root / name)) for name in names}
    server, url = serve(root)
    yield {"url": url, "assets": assets, "root": root}
    server.shutdown()


def _loads(name, techniques):
    """The page loads of one asset: (query, [(shot key, on, off)]): every technique off ('none', per light setup)
    and each technique alone."""
    every = sorted(techniques)
    alone = lambda t: (t, [t], [x for x in every if x != t])  # noqa: E731
    back = [t for t in every if t in BACK_LIT]
    front = [t for t in every if t not in BACK_LIT]
    loads = []
    if back:
        loads.append(("&on=backlight", [("none", [], every)] + [alone(t) for t in back]))
    if front:
        loads.append(("", [("none-front", [], every)] + [alone(t) for t in front]))
    return loads


def _image(path):
    return read_image(path)[..., :3].astype(np.float32) / 255.0


def _luma(image):
    return image @ np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)


@pytest.fixture(scope="module")
def frames(site, tmp_path_factory):
    """Every load of every asset on both engines' pages (one browser), plus each asset's ?baker=0 load on WebGPU."""
    out = tmp_path_factory.mktemp("babylon-webgpu-frames")
    loads = [(name, query, shots) for name, techniques in site["assets"].items()
             for query, shots in _loads(name, techniques)]
    jobs, keys = [], []
    for engine in ENGINES:
        for name, query, shots in loads:
            jobs.append({"url": f"{site['url']}/index.html?hud=0&src={name}{query}{TIME}&engine={engine}",
                         "width": W, "height": H, "shots": [
                             {"on": on, "off": off, "out": str(out / f"{engine}-{name}-{key}.png")}
                             for key, on, off in shots]})
            keys.append((engine, name, query))
    for name in site["assets"]:
        jobs.append({"url": f"{site['url']}/index.html?hud=0&src={name}&baker=0{TIME}&engine=babylon-webgpu",
                     "width": W, "height": H, "out": str(out / f"plain-{name}.png")})
        keys.append(("plain", name, ""))
    infos = dict(zip(keys, shoot(jobs, out / "jobs.json", webgpu=True)))
    images = {(engine, name, key): _image(out / f"{engine}-{name}-{key}.png")
              for engine in ENGINES for name, _, shots in loads for key, _, _ in shots}
    images.update({("plain", name, "plain"): _image(out / f"plain-{name}.png") for name in site["assets"]})
    return {"infos": infos, "images": images, "loads": loads}


def test_webgpu_page_draws_on_webgpu_with_the_webgl2_pages_techniques(site, frames):
    assert site["assets"] == {
        "spot_all.glb": {"translucency", "skin", "toon", "tam", "fins", "outline", "wireframe", "fur", "curvature",
                         "caustics"},
        "label.glb": {"text"}, "hair.glb": {"hair"}, "cards.glb": {"cards"}, "blurred.glb": {"normalBlur"}}
    for (engine, name, query), info in frames["infos"].items():
        assert info["ready"] and not info["errors"] and not info["warnings"] and not info["error"], (engine, name, info)
        assert info["backend"] == ("webgl2" if engine == "babylon" else "webgpu"), (engine, info)
        if engine == "plain":  # ?baker=0: Babylon's loader alone, the extensions ignored
            assert info["techniques"] == [] and "no baked data found" in info["status"], info
        else:
            assert set(info["techniques"]) == site["assets"][name], (engine, name, info)
            assert info["techniques"] == frames["infos"][("babylon", name, query)]["techniques"]  # same order too


def _keep(name, webgl2, webgpu):
    folder = ARTIFACTS / name
    folder.mkdir(parents=True, exist_ok=True)
    for label, image in (("webgl2", webgl2), ("webgpu", webgpu), ("diff", np.clip(np.abs(webgl2 - webgpu) * 4, 0, 1))):
        write_image(folder / f"{label}.png", (image * 255 + 0.5).astype(np.uint8))
    return folder


def test_each_technique_on_webgpu_matches_webgl2_and_changes_the_picture(site, frames):
    images = frames["images"]
    measured, failures = {}, []
    for name, _, shots in frames["loads"]:
        baseline = shots[0][0]
        for key, _, _ in shots:
            webgl2, webgpu = images[("babylon", name, key)], images[("babylon-webgpu", name, key)]
            covered = (np.abs(webgpu - BACKGROUND).max(axis=2) > 0.02).mean()
            assert covered > 0.005, (name, key, covered)  # something is drawn
            ssim = float(structural_similarity(_luma(webgl2), _luma(webgpu), data_range=1.0))
            bound = TOLERANCE.get(key, (SSIM_MIN, ""))[0]
            changed = -1
            if key != baseline:
                changed = int((np.abs(webgpu - images[("babylon-webgpu", name, baseline)]).max(axis=2) > CHANGED).sum())
                if changed < CHANGED_PIXELS:
                    failures.append(f"{name} {key}: the technique changes {changed} pixels on WebGPU")
            measured[(name, key)] = (round(ssim, 4), changed)
            if ssim < bound:
                failures.append(f"{name} {key}: SSIM {ssim:.4f} < {bound} (artifacts: {_keep(f'{name}-{key}', webgl2, webgpu)})")
    print("measured (SSIM WebGPU vs WebGL2, pixels changed from every technique off):", measured)
    assert not failures, "\n".join(failures)
    assert {key for (_, key) in measured} >= set().union(*site["assets"].values())  # every technique was compared


def test_extensions_off_on_webgpu_is_standard_pbr_and_differs(site, frames):
    """?baker=0 on WebGPU: the plain glTF PBR asset, like every technique off on the WebGL2 page (the standard
    material on both backends), and unlike the default page (the extensions do change the picture)."""
    images = frames["images"]
    for name, techniques in site["assets"].items():
        plain = images[("plain", name, "plain")]
        assert (np.abs(plain - BACKGROUND).max(axis=2) > 0.02).mean() > 0.005, name
        loads = [shots for n, _, shots in frames["loads"] if n == name]
        on = [images[("babylon-webgpu", name, key)] for shots in loads for key, _, _ in shots[1:]]
        assert any((np.abs(frame - plain).max(axis=2) > CHANGED).sum() >= CHANGED_PIXELS for frame in on), name


def test_missing_webgpu_adapter_is_reported_not_a_blank_page(site, tmp_path):
    """A browser without the WebGPU flags (the driver's default: no adapter) says so on the page and in
    window.__bakerError; the page is never reported ready."""
    [info] = shoot([{"url": f"{site['url']}/index.html?src=label.glb&engine=babylon-webgpu", "width": W, "height": H}],
                   tmp_path / "jobs.json")
    assert not info["ready"] and info["backend"] is None, info
    assert "WebGPU" in info["error"] and "WebGPU" in info["status"], info


def test_native_attribute_layout_draws_like_the_blender_layout_on_webgpu(site, frames, tmp_path):
    """The spot's bakes in ``--attribute-layout native`` (SCALAR / VEC2 custom attributes: WGSL declares each by its
    accessor's component count) load on WebGPU without errors, with the same techniques, and draw every technique as
    the default (VEC3) layout does there: mean |difference| (max over RGB, after a Gaussian blur of 1.5 px) below
    2/255, as tests/test_babylon.py asks of the WebGL2 page."""
    from scipy import ndimage

    native = "spot_native.glb"
    save(baker.bake(SPOT, bakes=tuple(registry.bakes()), options=SPOT_PAGE_OPTIONS, attribute_layout="native"),
         site["root"] / native)
    techniques = techniques_in(gltf_json(site["root"] / native))
    assert techniques == site["assets"]["spot_all.glb"]
    loads = _loads(native, techniques)
    jobs = [{"url": f"{site['url']}/index.html?hud=0&src={native}{query}{TIME}&engine=babylon-webgpu",
             "width": W, "height": H, "shots": [{"on": on, "off": off, "out": str(tmp_path / f"{key}.png")}
                                                for key, on, off in shots]} for query, shots in loads]
    for info in shoot(jobs, tmp_path / "jobs.json", webgpu=True):
        assert info["ready"] and not info["errors"] and not info["warnings"] and info["backend"] == "webgpu", info
        assert set(info["techniques"]) == techniques, info
    blur = lambda image: ndimage.gaussian_filter(image, sigma=(1.5, 1.5, 0))  # noqa: E731
    failures = []
    for _, shots in loads:
        for key, _, _ in shots:
            padded, compact = frames["images"][("babylon-webgpu", "spot_all.glb", key)], _image(tmp_path / f"{key}.png")
            mad = float(np.abs(blur(padded) - blur(compact)).max(axis=2).mean())
            if mad > 2 / 255:
                failures.append(f"{key}: MAD {mad * 255:.2f}/255 (artifacts: {_keep(f'native-{key}', padded, compact)})")
    assert not failures, "\n".join(failures)
