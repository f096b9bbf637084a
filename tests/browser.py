"""What the browser tests of the web runtimes share (tests/test_viewer.py: @baker/three, tests/test_babylon.py:
@baker/babylon against it): the tool check, the viewer's build, a loopback server for the built site, the screenshot
driver (examples/viewer/test/screenshots.mjs), the label and groom assets, and the switches a glTF document's
extensions imply, read from the document (not from either plugin)."""
from __future__ import annotations

import functools
import http.server
import json
import os
import shutil
import struct
import subprocess
import threading
from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage

import baker
from baker.cli import main as baker_main
from baker.pipeline import save

ROOT = Path(__file__).parents[1]
VIEWER = ROOT / "examples" / "viewer"
SPOT = ROOT / "examples" / "spot" / "spot.obj"
FONT = Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
BACKGROUND_RGB = (0x29, 0x2B, 0x30)  # the viewer's clear colour, 8-bit sRGB
# the spot with every bake of a surface or geometry technique on one mesh, small enough for a software renderer: the
# asset of the engine-comparison tests and the page benchmarks
SPOT_PAGE_OPTIONS = {
    "thickness": {"rays": 8, "per_texel": False},
    # a 5 mm cow (mesh unit = 5 mm): curvatures where the skin LUT departs from Lambert (at 1 m it changes no pixel;
    # at 20 mm only 32 pixels of the dielectric spot since mesh files get a non-metallic material)
    "skin": {"width": 64, "height": 64, "penumbra_size": 32, "unit_scale": 5.0},
    "edges": {"fins": True},
    "tam": {"size": 64, "levels": 3},
    "fur": {"fins": True, "shells": 4, "texture_size": 64},
    # the spot (y -0.74 to 0.95) under 2.5 m of water, within the fade: the caustics show on all of it
    "caustics": {"size": 64, "frames": 4, "waves": 16, "tile_size": 0.5, "water_level": 2.5, "depth": 2.5,
                 "fade_distance": 2.0},
}


def require_tools(test, packages=("playwright-core",)):
    """node, chromium and the viewer's node_modules `packages`: skipped without them, failed in CI."""
    problems = []
    if shutil.which("node") is None:
        problems.append("node")
    for package in packages:
        if not (VIEWER / "node_modules" / package).is_dir():
            problems.append(f"examples/viewer/node_modules/{package} (scripts/install-node-tools)")
    if not Path(os.environ.get("CHROMIUM", "/usr/bin/chromium")).exists():
        problems.append("chromium (apt-get install chromium)")
    if problems:
        if os.environ.get("CI", "").lower() in ("1", "true", "yes"):
            pytest.fail(f"{test} test needs {', '.join(problems)} in CI (scripts/test installs them)")
        pytest.skip(f"missing {', '.join(problems)}")


def build_viewer(root, bundles=("viewer.js",)):
    """`npm run build` of examples/viewer, then index.html and the `bundles` copied into the site folder `root`."""
    build = subprocess.run(["npm", "run", "build"], cwd=VIEWER, capture_output=True, text=True, timeout=300)
    assert build.returncode == 0, build.stderr
    shutil.copy(VIEWER / "index.html", root / "index.html")
    (root / "dist").mkdir()
    for bundle in bundles:
        shutil.copy(VIEWER / "dist" / bundle, root / "dist" / bundle)
    shutil.copytree(VIEWER / "dist" / "draco", root / "dist" / "draco")  # KHR_draco_mesh_compression's decoder


def serve(root):
    """A quiet HTTP server of the folder `root` on the loopback, in a daemon thread: (server, url)."""

    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args):
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(Quiet, directory=str(root)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server, f"http://127.0.0.1:{server.server_address[1]}"


def shoot(jobs, spec, webgpu: bool = False, timeout: float = 600):
    """Run the screenshot driver on `jobs` (written to the file `spec`): one info dict per job. webgpu: in a browser
    with a WebGPU adapter (examples/viewer/test/chromium.mjs), for the ?engine=*-webgpu pages."""
    spec.write_text(json.dumps(jobs))
    env = {**os.environ, "BAKER_WEBGPU": "1" if webgpu else "0"}
    result = subprocess.run(["node", str(VIEWER / "test" / "screenshots.mjs"), str(spec)],
                            capture_output=True, text=True, timeout=timeout, cwd=VIEWER, env=env)
    assert result.returncode == 0, result.stderr
    infos = [json.loads(line) for line in result.stdout.strip().splitlines() if line.startswith("{")]
    assert len(infos) == len(jobs), result.stdout
    return infos


def write_label_and_groom(root):
    """A `baker text` label (root/label.glb) and a small `baker hair` groom of the spot (root/hair.glb)."""
    assert baker_main(["text", "Baker", "--font", str(FONT), "-o", str(root / "label.glb"), "--outline-width", "0.02",
                       "-q"]) == 0
    assert baker_main(["hair", str(SPOT), "-o", str(root / "hair.glb"), "--guides", "40", "--children", "4",
                       "--segments", "6", "-q"]) == 0


# a 4 m square floor 1.5 m under the water (the baked depth), seen by the viewer's default camera; the frames small
CAUSTIC_FLOOR_OBJ = "v -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\nvn 0 1 0\nf 1//1 4//1 3//1 2//1\n"
CAUSTIC_OPTIONS = {"size": 64, "frames": 4, "waves": 16, "tile_size": 1.0, "water_level": 1.5, "depth": 1.5}


def write_caustic_floor(root):
    """A floor baked with ``--bakes caustics`` (root/floor.glb): the frames' period is 4 s, one frame a second."""
    obj = root / "floor.obj"
    obj.write_text(CAUSTIC_FLOOR_OBJ)
    save(baker.bake(obj, bakes=("caustics",), options={"caustics": CAUSTIC_OPTIONS}), root / "floor.glb")
    return "floor.glb"


def assert_caustics_move(early, late, off):
    """Frames (H, W, 3 in 0-1) of the caustic floor at two times of the loop and with the technique off: the caustic
    network shows (pixel-scale detail the smooth floor shade lacks; bright lines above and dark cells below the
    floor's shade) and it moves (the two times differ on much of the floor)."""
    import numpy as np
    from scipy import ndimage

    floor = np.abs(off - np.array(BACKGROUND_RGB) / 255.0).max(axis=2) > 0.03
    floor = ndimage.binary_erosion(floor, iterations=3)  # away from the floor's edges
    assert floor.mean() > 0.05, floor.mean()  # the floor is on screen
    luma = lambda image: image @ np.array([0.2126, 0.7152, 0.0722])  # noqa: E731

    def detail(image):  # local variation: a caustic network has it, a smooth Lambert shade does not
        gray = luma(image)
        return float(np.abs(gray - ndimage.uniform_filter(gray, 5))[floor].mean())

    print("detail off", detail(off), "early", detail(early), "late", detail(late))
    for frame in (early, late):
        change = luma(frame) - luma(off)
        assert detail(frame) > 4 * detail(off) + 1 / 255
        assert (change[floor] > 8 / 255).mean() > 0.05 and (change[floor] < -8 / 255).mean() > 0.05
    moved = np.abs(luma(early) - luma(late))[floor] > 8 / 255
    assert moved.mean() > 0.2, moved.mean()


def write_hair_cards(root):
    """Hair cards (root/cards.glb) of an independent groom (tests/techniques/cards_groom.py, written by pxr)."""
    from techniques.cards_groom import make_groom, write_groom_usd

    curves, widths = make_groom(strands=1500, clumps=48, seed=8)
    groom = write_groom_usd(root / "cards_groom.usda", curves, widths)
    assert baker_main(["cards", str(groom), "-o", str(root / "cards.glb"), "--cards", "48", "--atlas-size", "512",
                       "-q"]) == 0
    return "cards.glb"


CARD_DISTANCES = (1.0, 2.5, 6.0)  # ?distance= of the three hair-card frames


def assert_cards_alpha_tested(frames, off):
    """Frames (H, W, 3 in 0-1) of the hair cards at CARD_DISTANCES (?distance=), and the nearest with the technique
    off: the hair shows at every distance without thinning out (its drawn pixels x distance² stay within 20 % of
    the nearest frame's: what a mip chain that loses alpha-test coverage fails), the alpha test leaves gaps between
    strands inside the hair's outline (a card drawn opaque would fill it), and the Kajiya-Kay shading changes the
    picture. Returns the drawn pixels per distance."""
    import numpy as np
    from scipy import ndimage

    background = np.array(BACKGROUND_RGB) / 255.0
    drawn = [np.abs(frame - background).max(axis=2) > 0.03 for frame in frames]
    counts = [int(d.sum()) for d in drawn]
    print("hair pixels per distance", counts)
    assert all(c > 150 for c in counts), counts
    for count, distance in zip(counts, CARD_DISTANCES):
        assert 0.8 < count * distance ** 2 / counts[0] < 1.25, (counts, CARD_DISTANCES)
    near = drawn[0]
    outline = ndimage.binary_fill_holes(ndimage.binary_closing(near, iterations=4))
    gaps = (outline & ~near).sum() / outline.sum()
    print("gaps inside the outline", gaps)
    assert gaps > 0.05, gaps
    changed = (np.abs(frames[0] - off).max(axis=2) > 4 / 255) & near
    assert changed.mean() / near.mean() > 0.3
    return counts


def write_blurred_sphere(root, bakes=("normal-blur",), metallic: bool = False):
    """A 6 cm sphere with a 4 mm bump along the meridians (tests/techniques/test_normal_blur.py), baked; ``metallic``:
    a glossy metal (no diffuse term at all: what the blurred normals change must not show)."""
    from baker.gltf.document import GltfDocument
    from tests.techniques.test_normal_blur import bump_sphere

    stem = "blurred_metal" if metallic else "blurred"
    source = bump_sphere(root / f"{stem}_bump.glb", "v", segments=128, rings=96, size=512)
    if metallic:
        doc = GltfDocument.load(source)
        doc.json["materials"][0]["pbrMetallicRoughness"] = {"metallicFactor": 1.0, "roughnessFactor": 0.35}
        doc.save(source)
    options = {"skin": {"width": 64, "height": 64, "penumbra_size": 32}}
    save(baker.bake(source, bakes=bakes, options=options), root / f"{stem}.glb")
    return f"{stem}.glb"


MESHES = Path("/work/shared/assets/meshes")


def write_small_suzanne(root, extent=0.015):
    """Suzanne centred and scaled to ``extent`` metres (15 mm: convex radii of a few mm, where d'Eon's profile
    matters), baked with curvature and skin at their defaults: root/suzanne15.glb."""
    lines = (MESHES / "suzanne.obj").read_text().splitlines()
    points = np.array([[float(x) for x in line.split()[1:4]] for line in lines if line.startswith("v ")])
    centre, scale = (points.min(0) + points.max(0)) / 2, extent / (points.max(0) - points.min(0)).max()
    obj = root / "suzanne15.obj"
    obj.write_text("\n".join("v %.9g %.9g %.9g" % tuple((np.array([float(x) for x in line.split()[1:4]]) - centre)
                                                      * scale) if line.startswith("v ") else line
                             for line in lines) + "\n")
    save(baker.bake(obj, bakes=("curvature", "skin")), root / "suzanne15.glb")
    return "suzanne15.glb"


def terminator_redness(on, off, background):
    """(mean R - G with the technique on minus off, pixel count) over the terminator band of the picture without
    it: linear luminance 0.02-0.25 inside the object (issue 39's measure, on sRGB screenshots decoded to linear)."""
    def linear(c):
        return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)

    on, off, background = linear(on), linear(off), linear(np.asarray(background, np.float64))
    inside = ndimage.binary_erosion(np.abs(off - background).max(axis=2) > 0.01, iterations=2)
    luminance = off @ np.array([0.299, 0.587, 0.114])
    band = inside & (luminance > 0.02) & (luminance < 0.25)
    red = [(image[..., 0] - image[..., 1])[band].mean() for image in (on, off)]
    return float(red[0] - red[1]), int(band.sum())


def bpy_python():
    """Blender's Python: the bpy venv of scripts/install-bpy ($BAKER_BPY_PYTHON, as tests/test_blender.py finds it)."""
    python = os.environ.get("BAKER_BPY_PYTHON")
    if not python:
        done = subprocess.run([str(ROOT / "scripts" / "install-bpy")], capture_output=True, text=True)
        assert done.returncode == 0, f"scripts/install-bpy failed:\n{done.stderr[-2000:]}"
        python = done.stdout.strip().splitlines()[-1]
    return python


def write_blender_head(root):
    """A real normal-mapped asset (tests/blender/normal_mapped_head.py: Suzanne exported by Blender's own glTF exporter
    with TANGENT) baked with normal-blur, curvature and skin: root/head.glb. Blender is the bpy venv of
    scripts/install-bpy ($BAKER_BPY_PYTHON, as tests/test_blender.py finds it)."""
    python = bpy_python()
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    exported = root / "head_blender.glb"
    made = subprocess.run([python, str(ROOT / "tests" / "blender" / "normal_mapped_head.py"), str(exported), "256"],
                          capture_output=True, text=True, timeout=600, env=env)
    assert made.returncode == 0, made.stderr[-3000:]
    options = {"skin": {"width": 64, "height": 64, "penumbra_size": 32}}
    save(baker.bake(exported, bakes=("normal-blur", "curvature", "skin"), options=options), root / "head.glb")
    return "head.glb"


def bump_detail(image, channel, covered):
    """Pixel-scale variation of one channel: the bump's stripes, not the sphere's smooth shade."""
    import numpy as np
    from scipy import ndimage

    c = image[..., channel]
    return float(np.abs(c - ndimage.uniform_filter(c, 5))[covered].mean())


def gltf_json(path):
    """The JSON chunk of a GLB file."""
    data = Path(path).read_bytes()
    assert data[:4] == b"glTF"
    length = struct.unpack("<I", data[12:16])[0]
    return json.loads(data[20:20 + length])


def techniques_in(doc):
    """The switches a glTF document's extensions imply, read from the document (not from either plugin)."""
    found = set()
    per_material = {"BAKER_thickness": "translucency", "BAKER_skin_lut": "skin", "BAKER_toon_ramp": "toon",
                    "BAKER_tonal_art_map": "tam", "BAKER_fur": "fur", "BAKER_curvature": "curvature",
                    "BAKER_caustics": "caustics", "BAKER_hair_cards": "cards", "BAKER_normal_blur": "normalBlur"}
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
