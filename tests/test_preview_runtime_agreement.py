"""`baker preview` and the web viewer agree on what a technique changes: per technique, the fraction of the asset's
pixels its preview panel changes (against the plain Lambert reference of the same view) and the fraction the viewer
changes when the technique is switched on (against every technique off, in headless Chromium) are alike, the
viewer's at least half the preview's. A preview that shows an effect the runtime never draws fails here.

Caustics on both assets: spot (y -0.74 to 0.95) and spot standing on y = 0 (an asset modelled on the ground, as
most are), baked with the default water, which must light the asset in both; the caustics panel clips no more than
2 % of the asset's pixels to black or white. Toon, skin, the shell outline and the wireframe on spot only (they do
not depend on where the asset stands); hatching and fur are left out to keep the test near 40 s (one browser, two
pages, eight screenshots)."""
from __future__ import annotations

import numpy as np
import pytest

import baker
from baker.gltf.document import GltfDocument
from baker.gltf.images import read_image
from baker.pipeline import save
from baker.preview.core import BACKGROUND, preview
from baker.techniques.caustics.panel import LOOP_FRACTION
from browser import (BACKGROUND_RGB, SPOT, build_viewer, gltf_json, require_tools, serve, shoot,
                     techniques_in)

SIZE = 192  # both pictures; the preview's default view (azimuth 30, elevation 15) is the viewer's framing direction
NOTICEABLE = 8 / 255  # a pixel changes when a channel moves by more than this
# the preview panel -> the viewer switches that draw the same thing
SWITCHES = {"caustics": ("caustics",), "toon": ("toon",), "skin": ("skin",), "outline": ("outline",),
            "wireframe": ("wireframe",)}
OPTIONS = {"caustics": {"size": 128, "frames": 2},  # the water at its defaults (level, depth, tile, fade)
           "skin": {"width": 64, "height": 64, "penumbra_size": 32, "unit_scale": 5.0}}
BAKES = {"spot": ("caustics", "toon", "skin", "edges"), "standing": ("caustics",)}


def standing_spot(path):
    """spot moved up so its lowest point is at y = 0 (as an asset modelled standing on the ground)."""
    lines = SPOT.read_text().splitlines()
    lowest = min(float(line.split()[2]) for line in lines if line.startswith("v "))
    moved = []
    for line in lines:
        if line.startswith("v "):
            _, x, y, z = line.split()[:4]
            line = f"v {x} {float(y) - lowest:.6f} {z}"
        moved.append(line)
    path.write_text("\n".join(moved) + "\n")
    return path


def changed_fraction(on, off, background):
    """Fraction of the asset's pixels (those of `off` away from the background) that change noticeably."""
    asset = np.abs(off - np.asarray(background)).max(axis=2) > 0.02
    return float((np.abs(on - off).max(axis=2) > NOTICEABLE).sum() / asset.sum()), asset


@pytest.fixture(scope="module")
def measured(tmp_path_factory):
    """Per asset: the baked file's BAKER_caustics, the preview's panels, and the viewer's pictures with every
    technique off and with each one on (set explicitly: whatever the viewer starts with)."""
    require_tools("preview/runtime agreement")
    root = tmp_path_factory.mktemp("agreement")
    build_viewer(root)
    sources = {"spot": SPOT, "standing": standing_spot(root / "standing.obj")}
    jobs, result = [], {}
    server, url = serve(root)
    try:
        for name, source in sources.items():
            save(baker.bake(source, bakes=BAKES[name], seed=1,
                            options={k: v for k, v in OPTIONS.items() if k in BAKES[name]}), root / f"{name}.glb")
            doc = GltfDocument.load(root / f"{name}.glb")
            caustics = doc.json["materials"][0]["extensions"]["BAKER_caustics"]
            found = sorted(techniques_in(gltf_json(root / f"{name}.glb")))
            sheet = preview(root / f"{name}.glb", size=SIZE, panels=["lambert", *SWITCHES])
            panels = {n: sheet.sheet[y: y + s, x: x + s].astype(np.float64) / 255.0 for n, _, (y, x, s) in sheet.panels}
            shown = [p for p in SWITCHES if p in panels]
            shots = [{"on": [], "off": found, "out": str(root / f"{name}-off.png")}]
            shots += [{"on": list(SWITCHES[p]), "off": [t for t in found if t not in SWITCHES[p]],
                       "out": str(root / f"{name}-{p}.png")} for p in shown]
            time = LOOP_FRACTION * caustics["period"]  # the preview's still of the loop
            jobs.append({"url": f"{url}/index.html?hud=0&src={name}.glb&time={time}", "width": SIZE,
                         "height": SIZE, "shots": shots})
            result[name] = {"caustics": caustics, "panels": panels, "shown": shown, "found": found, "root": root}
        infos = shoot(jobs, root / "jobs.json")
    finally:
        server.shutdown()
    for (name, entry), info in zip(result.items(), infos):
        assert info["ready"] and not info["errors"] and not info["warnings"], info
        assert sorted(info["techniques"]) == entry["found"], info
        entry["viewer"] = {p: read_image(root / f"{name}-{p}.png")[..., :3].astype(np.float64) / 255.0
                           for p in ["off", *entry["shown"]]}
    return result


def changes(entry, panel):
    """(preview change, viewer change) of one technique on one asset."""
    panels, viewer = entry["panels"], entry["viewer"]
    preview_change, _ = changed_fraction(panels[panel], panels["lambert"], BACKGROUND)
    viewer_change, _ = changed_fraction(viewer[panel], viewer["off"], np.array(BACKGROUND_RGB) / 255.0)
    return preview_change, viewer_change


@pytest.mark.parametrize("name", ["spot", "standing"])
def test_default_water_lights_the_whole_asset(measured, name):
    """The default water level puts all of the asset under water, and the runtime's fade (baker_caustics_fade: 1 at
    the baked depth, 0 at fadeDistance from it and above the water) keeps at least half the caustic on its top and
    bottom."""
    ext = measured[name]["caustics"]
    lines = (SPOT if name == "spot" else measured[name]["root"] / "standing.obj").read_text().splitlines()
    heights = [float(line.split()[2]) for line in lines if line.startswith("v ")]
    for y in (min(heights), max(heights)):
        depth = ext["waterLevel"] - y
        fade = 1.0 - abs(depth - ext["depth"]) / ext["fadeDistance"]
        print(name, "y", y, "depth below the water", depth, "fade", fade)
        assert depth > 0 and fade >= 0.5 - 1e-6


@pytest.mark.parametrize("name", ["spot", "standing"])
def test_caustics_change_agrees_and_never_clips(measured, name):
    """The caustics change a third of the asset or more in both pictures, the viewer's change is at least half the
    preview's, and the panel clips at most 2 % of the asset's pixels to black or white."""
    entry = measured[name]
    preview_change, viewer_change = changes(entry, "caustics")
    panel = entry["panels"]["caustics"]
    _, asset = changed_fraction(panel, entry["panels"]["lambert"], BACKGROUND)
    clipped = ((panel.max(axis=2) <= 0.0) | (panel.min(axis=2) >= 1.0))[asset].mean()
    print(name, "caustics change: preview", preview_change, "viewer", viewer_change, "clipped", clipped)
    assert preview_change >= 1 / 3 and viewer_change >= 1 / 3
    assert viewer_change >= 0.5 * preview_change
    assert clipped <= 0.02


@pytest.mark.parametrize("panel", ["toon", "skin", "outline", "wireframe"])
def test_technique_change_agrees_on_spot(measured, panel):
    """Each technique's viewer change is at least half its preview change (and both show something)."""
    entry = measured["spot"]
    assert panel in entry["shown"], entry["shown"]
    preview_change, viewer_change = changes(entry, panel)
    print(panel, "change: preview", preview_change, "viewer", viewer_change, "ratio", viewer_change / preview_change)
    assert preview_change > 0.05 and viewer_change >= 0.5 * preview_change
