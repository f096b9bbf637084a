"""@baker/babylon (runtime-shaders/babylon) against @baker/three in headless Chromium: the spot baked with every bake,
a `baker text` label and a `baker hair` groom load in the viewer's Babylon.js page (examples/viewer, ?engine=babylon)
with no console errors or WebGL warnings, report the same techniques as the three.js page, and draw each technique
like the three.js plugin does with the same camera and lights (the Babylon.js page takes the three.js page's view).
With the extensions switched off (?baker=0) the assets render as plain glTF PBR in both engines, alike.

How frames are compared (both 400 x 300, sRGB; measured on this machine, SwiftShader):
- the frame: mean absolute difference (max over RGB) over the pixels either engine covers, after a Gaussian blur of
  sigma 1.5 px (it forgives the two rasterizers' MSAA and sub-pixel placement of pixel-wide lines), below
  FRAME_MAD = 16/255, and SSIM of the blurred frames' luma above FRAME_SSIM = 0.95. The floor is the base PBR: the
  spot's material is glTF's default (metallic 1, roughness 1), all specular, and Babylon's PBR (its GGX terms and
  energy compensation are not three.js's) draws it 13/255 brighter on the object than three.js's MeshStandardMaterial
  (measured with ?baker=0, no baker code in either page); the hair groom's emitter 9/255, the text label 0. So the
  frame bound says "the same picture", and the technique is checked by its change:
- the technique's change: frame minus the frame with every technique off, in each engine (the base difference
  cancels); the mean |Babylon change - three.js change| over the pixels the three.js change touches (> 2/255) must
  stay below DELTA_RATIO = 0.35 of the mean three.js change there. Measured 0.02 (outline) to 0.22 (fur); a
  technique Babylon.js does not draw scores 1.0 (its change is then 0).
  A technique that replaces the lit colour (the curvature view) has the base difference inside its change: it
  passes instead when its frame matches within TIGHT_MAD = 2/255 (measured 0.0).
Failing frames leave three.png, babylon.png and diff.png (|difference| x 4) in .cache/test-artifacts/test_babylon/.
"""
from __future__ import annotations

import functools
import http.server
import json
import os
import shutil
import struct
import subprocess
import threading
import urllib.parse
from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage
from skimage.metrics import structural_similarity

import baker
from baker import registry
from baker.cli import main as baker_main
from baker.gltf.images import read_image, write_image
from baker.pipeline import save

ROOT = Path(__file__).parents[1]
VIEWER = ROOT / "examples" / "viewer"
SPOT = ROOT / "examples" / "spot" / "spot.obj"
FONT = Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
ARTIFACTS = ROOT / ".cache" / "test-artifacts" / "test_babylon"
W, H = 400, 300
BACKGROUND = np.array([0x29, 0x2B, 0x30]) / 255.0
FRAME_MAD = 16 / 255
FRAME_SSIM = 0.95
TIGHT_MAD = 2 / 255
DELTA_RATIO = 0.35
BLUR = 1.5
DEFAULT_OFF = {"curvature", "wireframe"}  # debug views, off until asked for (both plugins)


def _require_tools():
    problems = []
    if shutil.which("node") is None:
        problems.append("node")
    for package in ("playwright-core", "three", "@babylonjs/core", "@babylonjs/loaders"):
        if not (VIEWER / "node_modules" / package).is_dir():
            problems.append(f"examples/viewer/node_modules/{package} (scripts/install-node-tools)")
    if not Path(os.environ.get("CHROMIUM", "/usr/bin/chromium")).exists():
        problems.append("chromium (apt-get install chromium)")
    if problems:
        if os.environ.get("CI", "").lower() in ("1", "true", "yes"):
            pytest.fail(f"babylon test needs {', '.join(problems)} in CI (scripts/test installs them)")
        pytest.skip(f"missing {', '.join(problems)}")


def _gltf_json(path):
    data = Path(path).read_bytes()
    assert data[:4] == b"glTF"
    length = struct.unpack("<I", data[12:16])[0]
    return json.loads(data[20:20 + length])


def _techniques_in(doc):
    """The switches a glTF document's extensions imply, read from the document (not from either plugin)."""
    found = set()
    per_material = {"BAKER_thickness": "translucency", "BAKER_skin_lut": "skin", "BAKER_toon_ramp": "toon",
                    "BAKER_tonal_art_map": "tam", "BAKER_fur": "fur", "BAKER_curvature": "curvature"}
    for material in doc.get("materials", []):
        found |= {per_material[name] for name in material.get("extensions", {}) if name in per_material}
    for mesh in doc.get("meshes", []):
        for primitive in mesh["primitives"]:
            extensions = primitive.get("extensions", {})
            edges = extensions.get("BAKER_edges")
            if edges is not None and "finsOf" in edges:
                found.add("fins")
            elif edges is not None:
                if edges.get("outlineNormal") in primitive["attributes"]:
                    found.add("outline")
                if "wireframeMask" in edges:
                    found.add("wireframe")
            if "BAKER_hair" in extensions:
                found.add("hair")
    if any("BAKER_text" in node.get("extensions", {}) for node in doc.get("nodes", [])):
        found.add("text")
    return found


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The built viewer (both engines' bundles) and the three assets, served on the loopback."""
    _require_tools()
    build = subprocess.run(["npm", "run", "build"], cwd=VIEWER, capture_output=True, text=True, timeout=300)
    assert build.returncode == 0, build.stderr
    root = tmp_path_factory.mktemp("babylon-site")
    shutil.copy(VIEWER / "index.html", root / "index.html")
    (root / "dist").mkdir()
    for bundle in ("viewer.js", "babylon.js"):
        shutil.copy(VIEWER / "dist" / bundle, root / "dist" / bundle)
    bakes = tuple(registry.bakes())  # every bake there is
    asset = baker.bake(SPOT, bakes=bakes, options={
        "thickness": {"rays": 8, "per_texel": False},
        # a 20 mm cow: curvatures where the skin LUT departs from Lambert (at 1 m the pre-integration changes no pixel)
        "skin": {"width": 64, "height": 64, "penumbra_size": 32, "unit_scale": 20.0},
        "edges": {"fins": True},
        "tam": {"size": 64, "levels": 3},
        "fur": {"shells": 4, "texture_size": 64},
    })
    save(asset, root / "spot_all.glb")
    assert baker_main(["text", "Baker", "--font", str(FONT), "-o", str(root / "label.glb"), "--outline-width", "0.02",
                       "-q"]) == 0
    assert baker_main(["hair", str(SPOT), "-o", str(root / "hair.glb"), "--guides", "40", "--children", "4",
                       "--segments", "6", "-q"]) == 0
    assets = {name: _techniques_in(_gltf_json(root / name)) for name in ("spot_all.glb", "label.glb", "hair.glb")}

    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args):
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(Quiet, directory=str(root)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    yield {"url": f"http://127.0.0.1:{server.server_address[1]}", "assets": assets, "bakes": bakes}
    server.shutdown()


def _shoot(jobs, spec):
    spec.write_text(json.dumps(jobs))
    result = subprocess.run(["node", str(VIEWER / "test" / "screenshots.mjs"), str(spec)],
                            capture_output=True, text=True, timeout=600, cwd=VIEWER)
    assert result.returncode == 0, result.stderr
    infos = [json.loads(line) for line in result.stdout.strip().splitlines() if line.startswith("{")]
    assert len(infos) == len(jobs), result.stdout
    return infos


def _image(path):
    return read_image(path)[..., :3].astype(np.float32) / 255.0


def _blur(image):
    return ndimage.gaussian_filter(image, sigma=(BLUR, BLUR, 0))


def _luma(image):
    return image @ np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)


def _keep(name, three, babylon):
    """Failure artifacts: both frames and their difference x 4."""
    folder = ARTIFACTS / name
    folder.mkdir(parents=True, exist_ok=True)
    for label, image in (("three", three), ("babylon", babylon), ("diff", np.clip(np.abs(three - babylon) * 4, 0, 1))):
        write_image(folder / f"{label}.png", (image * 255 + 0.5).astype(np.uint8))
    return folder


def _frame_metrics(three, babylon):
    a, b = _blur(three), _blur(babylon)
    covered = (np.abs(three - BACKGROUND).max(axis=2) > 0.02) | (np.abs(babylon - BACKGROUND).max(axis=2) > 0.02)
    mad = float(np.abs(a - b).max(axis=2)[covered].mean()) if covered.any() else 0.0
    ssim = float(structural_similarity(_luma(a), _luma(b), data_range=1.0))
    return mad, ssim, covered


# translucency is lit from behind (the viewer's default when the asset has it); the other techniques from the front,
# where they show (under the back light the skin LUT, for one, changes hardly a pixel)
BACK_LIT = {"translucency"}


def _loads(url, techniques):
    """The page loads of one asset: (query, baseline shot key, [(shot key, on, off)]); each technique alone, and
    every technique off as its baseline."""
    every = sorted(techniques)
    alone = lambda t: (t, [t], [x for x in every if x != t])  # noqa: E731
    back = [t for t in every if t in BACK_LIT]
    front = [t for t in every if t not in BACK_LIT]
    loads = [("", "none", [("default", [], []), ("none", [], every)] + [alone(t) for t in back])]
    if back and front:
        loads.append(("&off=backlight", "none-front", [("none-front", [], every)] + [alone(t) for t in front]))
    elif front:
        loads[0][2].extend(alone(t) for t in front)
    return loads


@pytest.fixture(scope="module")
def frames(site, tmp_path_factory):
    """Every load on the three.js page (a shot per technique alone, every technique off, the defaults, and ?baker=0),
    then the same on the Babylon.js page with the three.js page's view (camera and light directions) of that load."""
    out = tmp_path_factory.mktemp("babylon-frames")
    loads, baselines = [], {}
    for name, techniques in site["assets"].items():
        for query, baseline, shots in _loads(name, techniques):
            loads.append((name, f"{site['url']}/index.html?hud=0&src={name}{query}", shots))
            baselines.update({(name, key): baseline for key, _, _ in shots})
        loads.append((name, f"{site['url']}/index.html?hud=0&src={name}&baker=0", [("plain", [], [])]))

    def jobs(engine, views=None):
        out_jobs = []
        for i, (name, url, shots) in enumerate(loads):
            if views is not None:
                url += f"&engine=babylon&view={urllib.parse.quote(json.dumps(views[i]))}"
            out_jobs.append({"url": url, "width": W, "height": H, "shots": [
                {"on": on, "off": off, "out": str(out / f"{engine}-{name}-{key}.png")} for key, on, off in shots]})
        return out_jobs

    three = _shoot(jobs("three"), out / "three.json")
    babylon = _shoot(jobs("babylon", [info["view"] for info in three]), out / "babylon.json")
    images = {(engine, name, key): _image(out / f"{engine}-{name}-{key}.png")
              for engine in ("three", "babylon") for name, _, shots in loads for key, _, _ in shots}
    return {"three": three, "babylon": babylon, "images": images, "loads": loads, "baselines": baselines}


def test_babylon_loads_every_asset_without_errors(site, frames):
    assert set(site["bakes"]) >= {"thickness", "curvature", "skin", "edges", "tam", "toon", "fur"}
    assert site["assets"] == {
        "spot_all.glb": {"translucency", "skin", "toon", "tam", "fins", "outline", "wireframe", "fur", "curvature"},
        "label.glb": {"text"}, "hair.glb": {"hair"}}  # the bakes wrote what the test is about
    for engine in ("three", "babylon"):
        for (name, url, _), info in zip(frames["loads"], frames[engine]):
            assert info["ready"] and not info["errors"] and not info["warnings"], (engine, info)
            if "baker=0" in url:
                assert info["techniques"] == [] and "no baked data found" in info["status"], (engine, info)
            else:
                assert set(info["techniques"]) == site["assets"][name], (engine, info)


def test_babylon_draws_each_technique_like_three(site, frames):
    images = frames["images"]
    failures, measured = [], {}
    for name, _, shots in frames["loads"]:
        for key, _, _ in shots:
            if key == "plain":
                continue
            three, babylon = images[("three", name, key)], images[("babylon", name, key)]
            mad, ssim, covered = _frame_metrics(three, babylon)
            assert covered.mean() > 0.005, (name, key)  # something is drawn
            problem = []
            if mad > FRAME_MAD or ssim < FRAME_SSIM:
                problem.append(f"frame MAD {mad * 255:.2f}/255, SSIM {ssim:.3f}")
            baseline = frames["baselines"][(name, key)]
            if key not in ("default", baseline):
                change_three = _blur(three) - _blur(images[("three", name, baseline)])
                change_babylon = _blur(babylon) - _blur(images[("babylon", name, baseline)])
                changed = np.abs(change_three).max(axis=2) > 2 / 255
                assert changed.sum() >= 100, (name, key, int(changed.sum()))  # the technique shows in three.js
                ratio = float(np.abs(change_babylon - change_three).max(axis=2)[changed].mean()
                              / np.abs(change_three).max(axis=2)[changed].mean())
                if ratio > DELTA_RATIO and mad > TIGHT_MAD:
                    problem.append(f"change error {ratio:.2f} of the three.js change")
                measured[(name, key)] = (round(mad * 255, 2), round(ssim, 3), round(ratio, 2))
            if problem:
                failures.append(f"{name} {key}: {', '.join(problem)} (artifacts: {_keep(f'{name}-{key}', three, babylon)})")
    print("measured (frame MAD x255, SSIM, change error):", measured)
    assert not failures, "\n".join(failures)
    assert {key for (_, key) in measured} == set().union(*site["assets"].values())


def test_babylon_without_extensions_is_standard_pbr(site, frames):
    """?baker=0: Babylon.js's glTF loader alone (the BAKER_* extensions ignored) draws the plain PBR asset like
    three.js's GLTFLoader alone; and the extensions do change the picture."""
    images = frames["images"]
    failures = []
    for name in site["assets"]:
        three, babylon = images[("three", name, "plain")], images[("babylon", name, "plain")]
        mad, ssim, covered = _frame_metrics(three, babylon)
        assert covered.mean() > 0.005, name
        if mad > FRAME_MAD or ssim < FRAME_SSIM:
            failures.append(f"{name} plain: MAD {mad * 255:.2f}/255, SSIM {ssim:.3f} "
                            f"(artifacts: {_keep(f'{name}-plain', three, babylon)})")
        with_baker = images[("babylon", name, "default")]
        assert (np.abs(with_baker - babylon).max(axis=2) > 4 / 255).sum() >= 100, name
    assert not failures, "\n".join(failures)
