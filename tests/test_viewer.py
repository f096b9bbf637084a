"""The web viewer in headless Chromium: loads a baked asset without console errors, and draws `baker preview`'s
translucency panel (same GLSL module, same camera and uniforms) like the moderngl render, within a tolerance.
Then every technique of @baker/three (runtime-shaders/three): assets with many bakes, a `baker text` label and a
`baker hair` groom load with no console errors (three.js reports shader compile errors there), the status lists
every technique the asset's extensions imply, and switching each one (?off= / ?on=) changes the picture."""
from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest
from scipy import ndimage

import baker
from baker.preview import core as pv
from baker.gltf.images import read_image
from baker.pipeline import save
from browser import (BACKGROUND_RGB, CARD_DISTANCES, SPOT, VIEWER, assert_cards_alpha_tested,
                     assert_caustics_move, build_viewer, bump_detail, gltf_json, require_tools, serve, shoot,
                     techniques_in, write_blender_head, write_blurred_sphere, write_caustic_floor, write_hair_cards,
                     write_label_and_groom)
from conftest import assert_khronos_clean, clipped_fractions

SIZE = 256


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """A served folder with the built viewer, a baked asset, and the preview panel's shader and setup."""
    require_tools("viewer")
    root = tmp_path_factory.mktemp("site")
    # the Babylon.js and three.js WebGPURenderer pages for the first-picture tests
    build_viewer(root, ("viewer.js", "babylon.js", "three_webgpu.js"))
    asset = baker.bake(SPOT, options={"thickness": {"rays": 16, "per_texel": False}})
    save(asset, root / "spot.glb")

    items = pv.scene_items(asset)
    camera = pv.frame_camera(items, azimuth=150, elevation=15)
    panel = next(p for p in pv.all_panels() if p.name == "translucency")
    (root / "panel.frag").write_text(pv.fragment_shader(panel))
    panel.prepare(items)  # the light's exposure, as the preview's draw sets it
    uniforms = {k: list(v) if isinstance(v, tuple) else v for k, v in panel.uniforms(items[0]).items()}
    # the material inputs every surface panel reads (spot has no textures: its base colour factor alone)
    uniforms.update({"u_baseColorFactor": list(pv.surface_material(items[0].material, 0).base_color),
                     "u_hasBaseColorTexture": 0, "u_hasNormalTexture": 0, "u_normalScale": 1.0, "u_hasTangent": 0})
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

    server, url = serve(root)
    yield {"url": url, "root": root, "reference": reference}
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
    background = np.array(BACKGROUND_RGB) / 255.0
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


# ------------------------------------------------------------------------------------------ every technique
W, H = 400, 300


@pytest.fixture(scope="module")
def assets(site):
    """Small, fast bakes of every technique, written next to the viewer."""
    root = site["root"]
    asset = baker.bake(SPOT, bakes=("thickness", "curvature", "skin", "edges", "tam", "toon", "fur"), options={
        "thickness": {"rays": 8, "per_texel": False},
        # a 5 mm cow: curvatures where the skin LUT departs from Lambert (at 1 m skin alone changes no pixel)
        "skin": {"width": 64, "height": 64, "penumbra_size": 32, "unit_scale": 5.0},
        "edges": {"fins": True},
        "tam": {"size": 64, "levels": 3},
        "fur": {"fins": True, "shells": 4, "texture_size": 64},
    })
    save(asset, root / "spot_all.glb")
    write_label_and_groom(root)
    names = ["spot_all.glb", "label.glb", "hair.glb"]
    for name in names:
        assert_khronos_clean(root / name)
    return {name: techniques_in(gltf_json(root / name)) for name in names}


def _shoot(jobs, tmp_path):
    infos = shoot(jobs, tmp_path / "jobs.json")
    images = [read_image(job["out"])[..., :3].astype(np.float32) / 255.0 for job in jobs]
    return infos, images


def test_viewer_switches_every_technique(site, assets, tmp_path):
    expected_all = {"spot_all.glb": {"translucency", "skin", "toon", "tam", "fins", "outline", "wireframe", "fur",
                                     "curvature"},
                    "label.glb": {"text"}, "hair.glb": {"hair"}}
    assert assets == expected_all  # the bakes wrote what the test is about
    jobs, keys = [], []
    for name, techniques in assets.items():
        # every technique off, then each one switched on; translucency lit from behind (?on=backlight), where it
        # shows, the others under the viewer's front key light
        for light in ("front", "back") if "translucency" in techniques else ("front",):
            base = f"{site['url']}/index.html?hud=0&src={name}&start=none" + ("&on=backlight" if light == "back" else "")
            jobs.append({"url": base, "out": str(tmp_path / f"{name}-{light}.png"), "width": W, "height": H})
            keys.append((name, None, light))
            for technique in sorted(t for t in techniques if (t == "translucency") == (light == "back")):
                sep = "," if light == "back" else "&on="
                jobs.append({"url": f"{base}{sep}{technique}", "out": str(tmp_path / f"{name}-{technique}.png"),
                             "width": W, "height": H})
                keys.append((name, technique, light))
    infos, images = _shoot(jobs, tmp_path)
    shots = dict(zip(keys, zip(infos, images)))
    background = np.array(BACKGROUND_RGB) / 255.0
    changed = {}
    for (name, technique, light), (info, image) in shots.items():
        assert info["ready"] and not info["errors"] and not info["warnings"], info
        assert set(info["techniques"]) == assets[name], info
        assert info["enabled"] == ([] if technique is None else [technique]), info
        for t in assets[name]:
            assert t in info["status"], info
        if technique is None:
            drawn = np.abs(image - background).max(axis=2) > 0.03
            assert 0.01 < drawn.mean() < 0.9, (name, drawn.mean())  # the asset is on screen
            continue
        base = shots[(name, None, light)][1]
        changed[(name, technique)] = int((np.abs(image - base).max(axis=2) > 4 / 255).sum())
    print("pixels changed by each switch", changed)
    # every switch changes a visible part of the picture (>= 100 pixels of 120,000)
    assert all(n >= 100 for n in changed.values()), changed


def test_viewer_without_baked_data_reports_none(site, tmp_path):
    """A plain glTF (no BAKER_* extension) loads with no switches: the plugins add nothing they did not find."""
    plain = baker.bake(SPOT, bakes=())
    save(plain, site["root"] / "plain.glb")
    infos, images = _shoot([{"url": f"{site['url']}/index.html?src=plain.glb", "out": str(tmp_path / "plain.png"),
                             "width": W, "height": H}], tmp_path)
    assert infos[0]["ready"] and not infos[0]["errors"], infos[0]
    assert infos[0]["techniques"] == [] and "no baked data found" in infos[0]["status"]


# ------------------------------------------------------------------------------------------ the first picture
MARKERS = {"front": (0.9, 0.1, 0.1), "back": (0.1, 0.2, 0.9)}  # Kd of the cubes in front of / behind the cow


def write_standing_cow(root):
    """The spot turned to face +Z (glTF's front; the OBJ's face looks along -Z: its horns at z -0.41 to -0.16, the
    rump at z +1.05) and standing on y = 0, white (the glTF default base colour: the brightest a Lambert surface
    gets), with a small red cube just in front of its face and a blue one just behind its rump:
    root/standing.obj and its .mtl."""
    lines = SPOT.read_text().splitlines()
    points = np.array([[float(x) for x in line.split()[1:4]] for line in lines if line.startswith("v ")])
    turned = points * [-1.0, 1.0, -1.0]
    turned[:, 1] -= turned[:, 1].min()
    out = ["mtllib standing.mtl", "usemtl body"]
    out += ["v %.6f %.6f %.6f" % tuple(p) for p in turned]
    out += [line for line in lines if line.startswith(("vt ", "vn "))]
    out += [line for line in lines if line.startswith("f ")]
    vertices = len(turned)
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], np.float64) * 0.06
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    front, back = turned[:, 2].max(), turned[:, 2].min()
    # each cube at the height of the part it faces (the snout, the rump), 0.1 away from it
    for name, z, near in (("front", front + 0.1, turned[:, 2] > front - 0.1), ("back", back - 0.1, turned[:, 2] < back + 0.1)):
        out.append(f"usemtl {name}")
        out += ["v %.6f %.6f %.6f" % tuple(c + [0.0, turned[near, 1].mean(), z]) for c in corners]
        out += ["f " + " ".join(str(vertices + 1 + i) for i in quad) for quad in quads]
        vertices += 8
    (root / "standing.obj").write_text("\n".join(out) + "\n")
    mtl = ["newmtl body", "Kd 1 1 1"] + [f"newmtl {n}\nKd {r} {g} {b}" for n, (r, g, b) in MARKERS.items()]
    (root / "standing.mtl").write_text("\n".join(mtl) + "\n")
    return root / "standing.obj"


def test_viewer_opens_on_a_readable_first_picture(site, tmp_path):
    """The first frame of a white mesh standing on y = 0, with the panel shown, on the three.js page and the
    Babylon.js page (WebGL2): the camera looks at its front (glTF's +Z: the red cube in front of the face shows, the
    blue one behind the rump does not), the asset is framed (its pixels centred, filling a sensible part of the
    canvas, not cut at an edge), the panel's rectangle is beside the canvas (never over it), only the first technique
    of the list is on, and at most 2% of the asset's pixels are clipped black or white, in the first frame and with
    every technique off; the same for spot standing on y = 0 baked with caustics only, which the viewer opens on
    (before the caustic stage compressed its added light into the headroom, 4.7-6.7% of it clipped to white)."""
    assert_first_picture(site, tmp_path, {"three": "", "babylon": "&engine=babylon"}, webgpu=False)


def test_viewer_opens_on_a_readable_first_picture_on_webgpu(site, tmp_path):
    """The same first frame and plain frame (every technique off) on the WebGPU pages: three.js's WebGPURenderer
    (?engine=three-webgpu) and Babylon.js's WebGPUEngine (?engine=babylon-webgpu), in a Chromium with a WebGPU adapter
    (SwiftShader on Vulkan); each page reports window.__bakerBackend 'webgpu'."""
    require_tools("viewer on WebGPU", ("playwright-core", "three", "@babylonjs/core"))
    assert_first_picture(site, tmp_path, {"three-webgpu": "&engine=three-webgpu",
                                          "babylon-webgpu": "&engine=babylon-webgpu"}, webgpu=True)


def write_standing_spot(root):
    """spot moved up so its lowest point is at y = 0 (as most assets are modelled), baked with caustics only at the
    default water (which the viewer opens on): root/standing_caustics.glb."""
    lines = SPOT.read_text().splitlines()
    lowest = min(float(line.split()[2]) for line in lines if line.startswith("v "))
    moved = [f"v {line.split()[1]} {float(line.split()[2]) - lowest:.6f} {line.split()[3]}" if line.startswith("v ")
             else line for line in lines]
    (root / "standing_spot.obj").write_text("\n".join(moved) + "\n")
    save(baker.bake(root / "standing_spot.obj", bakes=("caustics",), seed=1,
                    options={"caustics": {"size": 128, "frames": 2}}), root / "standing_caustics.glb")


def assert_first_picture(site, tmp_path, engines, webgpu):
    """The first-picture checks on the pages of ``engines`` (name -> query), in a browser with WebGPU or not: the
    standing cow (translucency, toon, edges) and the standing spot baked with caustics only (the viewer opens on
    them: their added light is compressed into the headroom, a bright line not clipped to white)."""
    root = site["root"]
    if not (root / "standing.glb").exists():  # baked once for both tests
        asset = baker.bake(write_standing_cow(root), bakes=("thickness", "toon", "edges"),
                           options={"thickness": {"rays": 8, "per_texel": False}})
        save(asset, root / "standing.glb")
        write_standing_spot(root)
    assets = {"standing.glb": sorted(techniques_in(gltf_json(root / "standing.glb"))),
              "standing_caustics.glb": sorted(techniques_in(gltf_json(root / "standing_caustics.glb")))}
    assert assets == {"standing.glb": ["outline", "toon", "translucency", "wireframe"],
                      "standing_caustics.glb": ["caustics"]}
    opened = {"standing.glb": ["translucency"], "standing_caustics.glb": ["caustics"]}  # the first of the list, alone
    width, height = 640, 400
    pages = [(name, asset) for asset in assets for name in engines]
    jobs = [{"url": f"{site['url']}/index.html?src={asset}{engines[name]}", "width": width, "height": height,
             "out": str(tmp_path / f"first-{name}-{asset}.png"),
             "shots": [{"on": [], "off": assets[asset], "out": str(tmp_path / f"off-{name}-{asset}.png")}]}
            for name, asset in pages]
    infos = shoot(jobs, tmp_path / "jobs.json", webgpu=webgpu)
    background = np.array(BACKGROUND_RGB) / 255.0
    for (name, asset), info in zip(pages, infos):
        assert info["ready"] and not info["errors"] and not info["warnings"], info
        assert info["backend"] == ("webgpu" if webgpu else "webgl2"), info
        assert info["enabled"] == opened[asset], info
        panel, canvas = info["rects"]["panel"], info["rects"]["canvas"]
        assert panel[0] + panel[2] <= canvas[0] + 0.5 and canvas[0] + canvas[2] <= width + 0.5, info["rects"]
        first, off = (read_image(tmp_path / f"{k}-{name}-{asset}.png")[..., :3].astype(np.float32) / 255.0
                      for k in ("first", "off"))
        assert first.shape[:2] == (round(canvas[3]), round(canvas[2]))
        for frame in (first, off):
            covered = np.abs(frame - background).max(axis=2) > 0.03
            white, black = clipped_fractions(frame, covered)
            print(name, asset, "clipped white", white, "black", black)
            assert white <= 0.02 and black <= 0.02, (name, asset, white, black)
            rows, cols = np.nonzero(covered)
            h, w = covered.shape
            # framed: the asset's box centred, within the canvas, filling a sensible part of it
            assert rows.min() > 0 and cols.min() > 0 and rows.max() < h - 1 and cols.max() < w - 1
            assert abs((rows.min() + rows.max()) / 2 - h / 2) < 0.12 * h
            assert abs((cols.min() + cols.max()) / 2 - w / 2) < 0.12 * w
            assert 0.45 < (rows.max() - rows.min()) / h < 0.95, (rows.min(), rows.max())
            if asset != "standing.glb":
                continue
            # the front: the red cube in front of the face shows, the blue one behind the rump is hidden
            red = (frame[..., 0] > 0.4) & (frame[..., 1] < 0.25) & (frame[..., 2] < 0.25)
            blue = (frame[..., 2] > 0.4) & (frame[..., 0] < 0.25)
            assert red.sum() > 40 and blue.sum() < 5, (name, int(red.sum()), int(blue.sum()))


def test_viewer_draws_moving_caustics_on_a_floor(site, tmp_path):
    """A floor baked with ``--bakes caustics``: the caustic network shows (the frame differs from the floor with the
    technique off, with the fine detail a smooth Lambert shade lacks), and it moves: two times of the loop differ
    where the caustics are."""
    name = write_caustic_floor(site["root"])
    assert techniques_in(gltf_json(site["root"] / name)) == {"caustics"}
    base = f"{site['url']}/index.html?hud=0&src={name}"
    shots = {"early": "&time=0.5", "late": "&time=2.5", "off": "&time=0.5&off=caustics"}
    jobs = [{"url": base + query, "out": str(tmp_path / f"{key}.png"), "width": W, "height": H}
            for key, query in shots.items()]
    infos, images = _shoot(jobs, tmp_path)
    for info in infos:
        assert info["ready"] and not info["errors"] and not info["warnings"], info
        assert info["techniques"] == ["caustics"] and "caustics" in info["status"], info
    early, late, off = (dict(zip(shots, images))[key] for key in shots)
    assert_caustics_move(early, late, off)


def test_viewer_draws_alpha_tested_hair_cards_at_three_distances(site, tmp_path):
    """`baker cards` output: the cards show alpha-tested (gaps between strands inside the hair's outline) at the
    framing distance, 2.5x and 6x it without thinning out (drawn pixels x distance² within 20 %), with no console
    error, and the Kajiya-Kay switch changes the picture."""
    name = write_hair_cards(site["root"])
    assert techniques_in(gltf_json(site["root"] / name)) == {"cards"}
    assert_khronos_clean(site["root"] / name)
    base = f"{site['url']}/index.html?hud=0&src={name}"
    shots = {**{key: f"&distance={d}" for key, d in zip(("near", "middle", "far"), CARD_DISTANCES)},
             "off": "&off=cards"}
    jobs = [{"url": base + query, "out": str(tmp_path / f"{key}.png"), "width": W, "height": H}
            for key, query in shots.items()]
    infos, images = _shoot(jobs, tmp_path)
    for info in infos:
        assert info["ready"] and not info["errors"] and not info["warnings"], info
        assert info["techniques"] == ["cards"] and "cards" in info["status"], info
    frames = dict(zip(shots, images))
    assert_cards_alpha_tested([frames["near"], frames["middle"], frames["far"]], frames["off"])


def test_viewer_shades_diffuse_with_the_blurred_normals(site, tmp_path):
    """BAKER_normal_blur in three.js: with the technique on, the bump's detail drops in red (d'Eon's widest
    channel: gain 0.5 at 4 mm) far more than in blue (gain 0.97); switched off, the picture is the plain
    normal-mapped material's; without baker (?baker=0) it is the same as off."""
    name = write_blurred_sphere(site["root"])
    assert techniques_in(gltf_json(site["root"] / name)) == {"normalBlur"}
    base = f"{site['url']}/index.html?hud=0&src={name}"
    shots = {"on": "", "off": "&off=normalBlur", "plain": "&baker=0"}
    jobs = [{"url": base + query, "out": str(tmp_path / f"{key}.png"), "width": W, "height": H}
            for key, query in shots.items()]
    infos, images = _shoot(jobs, tmp_path)
    for key, info in zip(shots, infos):
        assert info["ready"] and not info["errors"] and not info["warnings"], info
    on, off, plain = images
    assert infos[0]["techniques"] == ["normalBlur"]
    background = np.array(BACKGROUND_RGB) / 255.0
    covered = ndimage.binary_erosion(np.abs(off - background).max(axis=2) > 0.03, iterations=4)
    assert covered.mean() > 0.05
    red_on, red_off = bump_detail(on, 0, covered), bump_detail(off, 0, covered)
    blue_on, blue_off = bump_detail(on, 2, covered), bump_detail(off, 2, covered)
    print("red", red_on, red_off, "blue", blue_on, blue_off)
    assert red_on < 0.75 * red_off and blue_on > 0.85 * blue_off
    assert np.abs(off - plain)[covered].max() <= 2 / 255


def test_viewer_normal_blur_leaves_the_specular_term_alone(site, tmp_path):
    """On a glossy metal (glTF: no diffuse term) the blurred diffuse normals change nothing: the specular term keeps
    the material's own normal map, so the frames with the technique on and off are the same."""
    name = write_blurred_sphere(site["root"], metallic=True)
    base = f"{site['url']}/index.html?hud=0&src={name}"
    jobs = [{"url": base + query, "out": str(tmp_path / f"{key}.png"), "width": W, "height": H}
            for key, query in (("on", ""), ("off", "&off=normalBlur"))]
    infos, (on, off) = _shoot(jobs, tmp_path)
    for info in infos:
        assert info["ready"] and not info["errors"] and not info["warnings"], info
        assert info["techniques"] == ["normalBlur"], info
    background = np.array(BACKGROUND_RGB) / 255.0
    covered = np.abs(off - background).max(axis=2) > 0.03
    assert covered.mean() > 0.05 and bump_detail(off, 1, covered) > 0.002  # the bump shows in the highlights
    assert np.abs(on - off).max() <= 1 / 255


def test_viewer_softens_the_blender_heads_diffuse(site, tmp_path):
    """The real asset: Blender's normal-mapped head baked with normal-blur, curvature and skin. three.js finds all
    three; with the blurred normals on, the ridges' pixel-scale detail in red drops against the frame with them off
    (skin stays on in both: its LUT then reads the per-channel N.L)."""
    name = write_blender_head(site["root"])
    assert techniques_in(gltf_json(site["root"] / name)) == {"normalBlur", "skin", "curvature"}
    # every technique on and the back light, as the viewer opened before it opened on the first technique alone
    base = f"{site['url']}/index.html?hud=0&src={name}&start=all&on=backlight"
    jobs = [{"url": base + query, "out": str(tmp_path / f"{key}.png"), "width": W, "height": H}
            for key, query in (("on", ""), ("off", "&off=normalBlur"))]
    infos, (on, off) = _shoot(jobs, tmp_path)
    for info in infos:
        assert info["ready"] and not info["errors"] and not info["warnings"], info
        assert set(info["techniques"]) == {"normalBlur", "skin", "curvature"}, info
    background = np.array(BACKGROUND_RGB) / 255.0
    covered = ndimage.binary_erosion(np.abs(off - background).max(axis=2) > 0.03, iterations=4)
    assert covered.mean() > 0.05
    red = bump_detail(on, 0, covered), bump_detail(off, 0, covered)
    print("head red detail on/off", red)
    assert red[0] < 0.85 * red[1]
