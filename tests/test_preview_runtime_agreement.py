"""`baker preview` and the web viewer agree on what a technique changes: per technique, the fraction of the asset's
pixels its preview panel changes (against the plain Lambert reference of the same view) and the fraction the viewer
changes when the technique is switched on (against every technique off, in headless Chromium) are alike, the
viewer's at least half the preview's. A preview that shows an effect the runtime never draws fails here.

Five assets, each baked once: spot (y -0.74 to 0.95); spot standing on y = 0 (caustics only: an asset modelled on
the ground, as most are); the Stanford bunny (y 0.03-0.19, decimated by vertex clustering for speed); a homer-like
character standing on the ground (the cow scaled to homer's 0.84 height, its feet on y = 0); and Suzanne exported by
Blender 4.5's own glTF exporter (subdivision applied, a Principled material: tests/blender/principled_suzanne.py).
Caustics on all five, baked with the default water, which must light the asset: the change covers a third of the
asset's pixels or more in both pictures. Translucency (lit from behind in both), toon, skin, the shell outline, the
wireframe, hatching and fur on all but the standing spot: hatching multiplies the lit colour by the TAM's brightness
and the caustics redistribute the key light, each with the key light from the front in both (the hosts' stage;
under the sheet's grazing side light the caustics changed 15 % of the homer-like cow's pixels in the preview against
60 % in the viewer), and fur draws its shells over the base surface in both. No preview panel, and neither the
viewer's first frame (the page as it opens, 640 x 400) nor its plain frame (every technique off), clips more than
2 % of the asset's pixels to black or white. One browser, 14 pages; measured ratios (viewer / preview) are printed.
"""
from __future__ import annotations

import dataclasses
import os
import resource
import subprocess
import time as clock
from pathlib import Path

import numpy as np
import pytest

import baker
from baker import readers
from baker.gltf.document import GltfDocument
from baker.gltf.images import read_image
from baker.pipeline import save
from baker.preview import core as pv
from baker.techniques.caustics.panel import LOOP_FRACTION
from browser import (BACKGROUND_RGB, ROOT, SPOT, bpy_python, build_viewer, gltf_json, require_tools, serve, shoot,
                     techniques_in)
from conftest import clipped_fractions

SIZE = 192  # both pictures; the preview's default view (azimuth 30, elevation 15) is the viewer's framing direction
FIRST = (640, 400)  # the viewer's first frame: the page as it opens (side panel beside the canvas)
NOTICEABLE = 8 / 255  # a pixel changes when a channel moves by more than this
CLIPPED = 0.02  # the most of an asset's pixels a picture may clip to black or white
# the preview panel -> the viewer switches that draw the same thing
SWITCHES = {"caustics": ("caustics",), "translucency": ("translucency",), "toon": ("toon",), "skin": ("skin",),
            "outline": ("outline",), "wireframe": ("wireframe",), "hatching": ("tam",), "fur": ("fur",)}
BACK_LIT = {"translucency"}  # drawn with the light behind the asset (the viewer's back light, the panel's "back")
OPTIONS = {"caustics": {"size": 128, "frames": 2},  # the water at its defaults (level, depth, tile, fade)
           "thickness": {"rays": 8, "per_texel": False},
           "skin": {"width": 64, "height": 64, "penumbra_size": 32, "unit_scale": 5.0},
           "tam": {"size": 64, "levels": 3}, "fur": {"shells": 6, "texture_size": 64}}
EVERY = ("caustics", "thickness", "toon", "skin", "edges", "tam", "fur")
# spot; spot standing on y = 0; the Stanford bunny (y 0.03-0.19, decimated); a homer-like character standing on the
# ground (the cow scaled to homer's 0.84 height, its feet on y = 0); Suzanne as Blender's glTF exporter writes her
BAKES = {"spot": EVERY, "standing": ("caustics",), "bunny": EVERY, "homer": EVERY, "blender": EVERY}
EVERY_TECHNIQUE = [name for name, bakes in BAKES.items() if bakes == EVERY]
MESHES = Path("/work/shared/assets/meshes")
BUNNY_CELL = 0.0035  # metres: the bunny's decimation grid
HOMER_HEIGHT = 0.841  # homer's y 0.156-0.997


def moved_obj(source, path, scale=1.0):
    """The OBJ ``source`` scaled by ``scale`` about the origin and moved up so its lowest point is at y = 0 (as an
    asset modelled standing on the ground)."""
    lines = Path(source).read_text().splitlines()
    lowest = min(float(line.split()[2]) for line in lines if line.startswith("v "))
    moved = []
    for line in lines:
        if line.startswith("v "):
            _, x, y, z = line.split()[:4]
            line = f"v {float(x) * scale:.6f} {(float(y) - lowest) * scale:.6f} {float(z) * scale:.6f}"
        moved.append(line)
    path.write_text("\n".join(moved) + "\n")
    return path


def standing_spot(path):
    """spot moved up so its lowest point is at y = 0."""
    return moved_obj(SPOT, path)


def homer_like(path):
    """The cow (y -3.6 to 2.8) scaled to homer's height and standing on y = 0."""
    heights = [float(line.split()[2]) for line in (MESHES / "cow.obj").read_text().splitlines()
               if line.startswith("v ")]
    return moved_obj(MESHES / "cow.obj", path, HOMER_HEIGHT / (max(heights) - min(heights)))


def small_bunny(path, cell=BUNNY_CELL):
    """The Stanford bunny where it stands (y 0.03-0.19), decimated by vertex clustering (Rossignac and Borrel 1993):
    the vertices in each ``cell``-metre grid cube merged at their mean, the triangles that collapse dropped (69,451
    triangles -> about 11,000): the bake, the preview and SwiftShader stay quick, the shape stays the bunny's."""
    lines = (MESHES / "stanford-bunny.obj").read_text().splitlines()
    points = np.array([[float(x) for x in line.split()[1:4]] for line in lines if line.startswith("v ")])
    faces = np.array([[int(x.split("/")[0]) - 1 for x in line.split()[1:4]] for line in lines if line.startswith("f ")])
    _, cluster = np.unique(np.floor(points / cell).astype(np.int64), axis=0, return_inverse=True)
    cluster = cluster.ravel()
    merged = np.zeros((cluster.max() + 1, 3))
    np.add.at(merged, cluster, points)
    merged /= np.bincount(cluster)[:, None]
    faces = cluster[faces]
    faces = faces[(faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])]
    _, first = np.unique(np.sort(faces, axis=1), axis=0, return_index=True)  # one of each merged duplicate
    faces = faces[np.sort(first)]
    path.write_text("".join("v %.6f %.6f %.6f\n" % tuple(p) for p in merged)
                    + "".join("f %d %d %d\n" % tuple(f + 1) for f in faces))
    return path


def blender_suzanne(path):
    """Suzanne with a subdivision modifier applied and a Principled material, written by Blender 4.5's glTF exporter
    (tests/blender/principled_suzanne.py in the bpy venv)."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    made = subprocess.run([bpy_python(), str(ROOT / "tests" / "blender" / "principled_suzanne.py"), str(path)],
                          capture_output=True, text=True, timeout=300, env=env)
    assert made.returncode == 0, made.stderr[-3000:]
    return path


def heights(path):
    """(lowest, highest) y of a source asset: its OBJ vertices, or its GLB's POSITION bounds (no node transforms)."""
    if path.suffix == ".obj":
        ys = [float(line.split()[2]) for line in path.read_text().splitlines() if line.startswith("v ")]
        return min(ys), max(ys)
    doc = gltf_json(path)
    assert all("matrix" not in n and "rotation" not in n and "scale" not in n and "translation" not in n
               for n in doc["nodes"])
    bounds = [doc["accessors"][p["attributes"]["POSITION"]] for m in doc["meshes"] for p in m["primitives"]]
    return min(b["min"][1] for b in bounds), max(b["max"][1] for b in bounds)


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
    """Per asset (each baked once): the source, the baked file's BAKER_caustics, the preview's panels, the viewer's
    pictures with every technique off and with each one on (set explicitly: whatever the viewer starts with), and
    the viewer's first frame (the page as it opens) with its plain frame (every technique off)."""
    require_tools("preview/runtime agreement")
    root = tmp_path_factory.mktemp("agreement")
    build_viewer(root)
    sources = {"spot": SPOT, "standing": standing_spot(root / "standing.obj"), "bunny": small_bunny(root / "bunny.obj"),
               "homer": homer_like(root / "homer.obj"), "blender": blender_suzanne(root / "suzanne_blender.glb")}
    jobs, result = [], {}
    server, url = serve(root)
    try:
        for name, source in sources.items():
            started = clock.monotonic()
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
            if name in EVERY_TECHNIQUE:  # the page as it opens, and with every technique off
                jobs.append({"url": f"{url}/index.html?src={name}.glb", "width": FIRST[0], "height": FIRST[1],
                             "out": str(root / f"{name}-first.png"), "name": name,
                             "shots": [{"on": [], "off": found, "out": str(root / f"{name}-plain.png")}]})
            result[name] = {"caustics": caustics, "panels": panels, "shown": shown, "found": found,
                            "source": source}
            print(name, "baked and previewed in", round(clock.monotonic() - started, 1), "s")
        started, cpu = clock.monotonic(), resource.getrusage(resource.RUSAGE_CHILDREN)
        infos = shoot(jobs, root / "jobs.json")
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        print(len(jobs), "viewer pages in", round(clock.monotonic() - started, 1), "s, CPU",
              round(after.ru_utime + after.ru_stime - cpu.ru_utime - cpu.ru_stime, 1), "s (node and Chromium)")
    finally:
        server.shutdown()
    for job, info in zip(jobs, infos):
        assert info["ready"] and not info["errors"] and not info["warnings"], info
        assert sorted(info["techniques"]) == result[job["name"]]["found"], info
    for name, entry in result.items():
        picture = lambda file: read_image(root / file)[..., :3].astype(np.float64) / 255.0  # noqa: E731
        entry["viewer"] = {p: (picture(f"{name}-{light}-{p}.png"), picture(f"{name}-{light}-off.png"))
                           for p in entry["shown"] for light in ["back" if p in BACK_LIT else "front"]}
        if name in EVERY_TECHNIQUE:
            entry["first"], entry["plain"] = picture(f"{name}-first.png"), picture(f"{name}-plain.png")
    return result


def changes(entry, panel):
    """(preview change, viewer change) of one technique on one asset."""
    preview_change, _ = changed_fraction(*entry["panels"][panel], pv.BACKGROUND)
    viewer_change, _ = changed_fraction(*entry["viewer"][panel], np.array(BACKGROUND_RGB) / 255.0)
    return preview_change, viewer_change


@pytest.mark.parametrize("name", list(BAKES))
def test_default_water_lights_the_whole_asset(measured, name):
    """The default water level puts all of the asset under water, and the runtime's fade (baker_caustics_fade: 1 at
    the baked depth, 0 at fadeDistance from it and above the water) keeps at least half the caustic on its top and
    bottom."""
    ext = measured[name]["caustics"]
    for y in heights(measured[name]["source"]):
        depth = ext["waterLevel"] - y
        fade = 1.0 - abs(depth - ext["depth"]) / ext["fadeDistance"]
        print(name, "y", y, "depth below the water", depth, "fade", fade)
        assert depth > 0 and fade >= 0.5 - 1e-6


@pytest.mark.parametrize("name", list(BAKES))
def test_caustics_change_agrees(measured, name):
    """The caustics change a third of the asset or more in both pictures, and the viewer's change is at least half
    the preview's."""
    preview_change, viewer_change = changes(measured[name], "caustics")
    print(name, "caustics change: preview", preview_change, "viewer", viewer_change,
          "ratio", viewer_change / preview_change)
    assert preview_change >= 1 / 3 and viewer_change >= 1 / 3
    assert viewer_change >= 0.5 * preview_change


@pytest.mark.parametrize("name, panel", [(name, panel) for name in EVERY_TECHNIQUE for panel in SWITCHES
                                         if panel != "caustics"])
def test_technique_change_agrees(measured, name, panel):
    """Each technique's viewer change is at least half its preview change (and both show something): translucency,
    toon, skin, outline, wireframe, hatching (the TAM's strokes over the lit surface) and fur (the shells' strands
    over the base surface)."""
    entry = measured[name]
    assert panel in entry["shown"], entry["shown"]
    preview_change, viewer_change = changes(entry, panel)
    print(name, panel, "change: preview", preview_change, "viewer", viewer_change,
          "ratio", viewer_change / preview_change)
    assert preview_change > 0.05 and viewer_change >= 0.5 * preview_change


@pytest.mark.parametrize("name", EVERY_TECHNIQUE)
def test_nothing_clips(measured, name):
    """No preview panel, and neither the viewer's first frame nor its plain frame (every technique off), clips more
    than CLIPPED of the asset's pixels to black or white."""
    entry = measured[name]
    pictures = {f"panel {p}": (on, pv.BACKGROUND) for p, (on, _) in entry["panels"].items()}
    pictures.update({k: (entry[k], np.array(BACKGROUND_RGB) / 255.0) for k in ("first", "plain")})
    clipped = {}
    for key, (image, background) in pictures.items():
        covered = np.abs(image - np.asarray(background)).max(axis=2) > 0.02
        clipped[key] = clipped_fractions(image, covered)
    print(name, "clipped (white, black):", {k: (round(w, 4), round(b, 4)) for k, (w, b) in clipped.items()})
    assert all(w <= CLIPPED and b <= CLIPPED for w, b in clipped.values()), clipped
