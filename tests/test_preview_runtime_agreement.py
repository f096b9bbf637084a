"""`baker preview` and the web viewer agree on what a technique changes: per technique, the fraction of the asset's
pixels its preview panel changes (against the plain Lambert reference of the same view) and the fraction the viewer
changes when the technique is switched on (against every technique off, in headless Chromium) are alike, the
viewer's at least half the preview's. A preview that shows an effect the runtime never draws fails here.

Caustics on both assets: spot (y -0.74 to 0.95) and spot standing on y = 0 (an asset modelled on the ground, as
most are), baked with the default water, which must light the asset in both; the caustics panel clips no more than
2 % of the asset's pixels to black or white. Translucency (lit from behind in both), toon, skin, the shell outline,
the wireframe, hatching and fur on spot only (they do not depend on where the asset stands): hatching multiplies the
lit colour by the TAM's brightness with the key light from the front in both (the hosts' stage), and fur draws its
shells over the base surface in both (measured at this threshold: viewer 1.01 x the preview's change for hatching,
0.92 x for fur; before the panels drew the hosts' stages, ink on paper under the grazing light and a darkened skin
under the shells, 0.57 x and 0.27 x). One browser, three pages."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import baker
from baker import readers
from baker.gltf.document import GltfDocument
from baker.gltf.images import read_image
from baker.pipeline import save
from baker.preview import core as pv
from baker.techniques.caustics.panel import LOOP_FRACTION
from browser import (BACKGROUND_RGB, SPOT, build_viewer, gltf_json, require_tools, serve, shoot,
                     techniques_in)

SIZE = 192  # both pictures; the preview's default view (azimuth 30, elevation 15) is the viewer's framing direction
NOTICEABLE = 8 / 255  # a pixel changes when a channel moves by more than this
# the preview panel -> the viewer switches that draw the same thing
SWITCHES = {"caustics": ("caustics",), "translucency": ("translucency",), "toon": ("toon",), "skin": ("skin",),
            "outline": ("outline",), "wireframe": ("wireframe",), "hatching": ("tam",), "fur": ("fur",)}
BACK_LIT = {"translucency"}  # drawn with the light behind the asset (the viewer's back light, the panel's "back")
OPTIONS = {"caustics": {"size": 128, "frames": 2},  # the water at its defaults (level, depth, tile, fade)
           "thickness": {"rays": 8, "per_texel": False},
           "skin": {"width": 64, "height": 64, "penumbra_size": 32, "unit_scale": 5.0},
           "tam": {"size": 64, "levels": 3}, "fur": {"shells": 6, "texture_size": 64}}
BAKES = {"spot": ("caustics", "thickness", "toon", "skin", "edges", "tam", "fur"), "standing": ("caustics",)}


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


def preview_panels(path):
    """The preview's panels of SWITCHES present in the file, each with the Lambert reference under the panel's own
    light (the same view as `baker preview`'s default, which is the viewer's framing direction)."""
    scene = pv.gather_scene(readers.read(path))
    camera = pv.frame_camera(scene)
    chosen = [p for p in pv.all_panels() if p.name in SWITCHES and p.available(scene)]
    ctx = pv.create_context()
    try:
        panels = {p.name: (pv.render_panel(ctx, p, scene, camera, SIZE),
                           pv.render_panel(ctx, dataclasses.replace(pv.REFERENCE, light=p.light), scene, camera, SIZE))
                  for p in chosen}
    finally:
        scene.release()
        ctx.release()
    return panels


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
            panels = preview_panels(root / f"{name}.glb")
            shown = [p for p in SWITCHES if p in panels]
            time = LOOP_FRACTION * caustics["period"]  # the preview's still of the loop
            for back in (False, True):  # a page with the viewer's back light (on when translucency is baked)
                chosen = [p for p in shown if (p in BACK_LIT) == back]
                if not chosen:
                    continue
                light = "back" if back else "front"
                shots = [{"on": [], "off": found, "out": str(root / f"{name}-{light}-off.png")}]
                shots += [{"on": list(SWITCHES[p]), "off": [t for t in found if t not in SWITCHES[p]],
                           "out": str(root / f"{name}-{light}-{p}.png")} for p in chosen]
                jobs.append({"url": f"{url}/index.html?hud=0&src={name}.glb&time={time}"
                                    f"{'&on=backlight' if back else '&off=backlight'}", "width": SIZE, "height": SIZE,
                             "shots": shots, "name": name})
            result[name] = {"caustics": caustics, "panels": panels, "shown": shown, "found": found, "root": root}
        infos = shoot(jobs, root / "jobs.json")
    finally:
        server.shutdown()
    for job, info in zip(jobs, infos):
        assert info["ready"] and not info["errors"] and not info["warnings"], info
        assert sorted(info["techniques"]) == result[job["name"]]["found"], info
    for name, entry in result.items():
        picture = lambda file: read_image(root / file)[..., :3].astype(np.float64) / 255.0  # noqa: E731
        entry["viewer"] = {p: (picture(f"{name}-{light}-{p}.png"), picture(f"{name}-{light}-off.png"))
                           for p in entry["shown"] for light in ["back" if p in BACK_LIT else "front"]}
    return result


def changes(entry, panel):
    """(preview change, viewer change) of one technique on one asset."""
    preview_change, _ = changed_fraction(*entry["panels"][panel], pv.BACKGROUND)
    viewer_change, _ = changed_fraction(*entry["viewer"][panel], np.array(BACKGROUND_RGB) / 255.0)
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
    panel, reference = entry["panels"]["caustics"]
    _, asset = changed_fraction(panel, reference, pv.BACKGROUND)
    clipped = ((panel.max(axis=2) <= 0.0) | (panel.min(axis=2) >= 1.0))[asset].mean()
    print(name, "caustics change: preview", preview_change, "viewer", viewer_change, "clipped", clipped)
    assert preview_change >= 1 / 3 and viewer_change >= 1 / 3
    assert viewer_change >= 0.5 * preview_change
    assert clipped <= 0.02


@pytest.mark.parametrize("panel", ["translucency", "toon", "skin", "outline", "wireframe", "hatching", "fur"])
def test_technique_change_agrees_on_spot(measured, panel):
    """Each technique's viewer change is at least half its preview change (and both show something): translucency,
    toon, skin, outline, wireframe, hatching (the TAM's strokes over the lit surface) and fur (the shells' strands
    over the base surface)."""
    entry = measured["spot"]
    assert panel in entry["shown"], entry["shown"]
    preview_change, viewer_change = changes(entry, panel)
    print(panel, "change: preview", preview_change, "viewer", viewer_change, "ratio", viewer_change / preview_change)
    assert preview_change > 0.05 and viewer_change >= 0.5 * preview_change
