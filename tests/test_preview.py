"""``baker preview``: panels render with the runtime shaders and show their effect (pixel statistics per panel)."""
from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage

import baker
from baker.cli import main
from baker.gltf.images import read_image
from baker.pipeline import save
from baker.preview.core import BACKGROUND, preview
from conftest import assert_khronos_clean

SPOT = Path(__file__).parents[1] / "examples" / "spot" / "spot.obj"


@pytest.fixture(scope="module")
def baked_spot(tmp_path_factory):
    out = tmp_path_factory.mktemp("preview") / "spot.glb"
    save(baker.bake(SPOT, options={"thickness": {"rays": 32, "per_texel": False}}), out)
    return out


def _panel(result, name):
    for n, _, (y, x, size) in result.panels:
        if n == name:
            return result.sheet[y: y + size, x: x + size].astype(np.float64) / 255.0
    raise AssertionError(f"no panel {name}")


def _covered(image):
    return np.abs(image - np.array(BACKGROUND)).max(axis=2) > 0.02


def test_translucency_is_brighter_where_thin(baked_spot):
    result = preview(baked_spot, size=256, azimuth=150, elevation=15)
    assert [n for n, _, _ in result.panels] == ["lambert", "thickness", "translucency"]
    thickness, translucent = _panel(result, "thickness"), _panel(result, "translucency")
    mask = _covered(_panel(result, "lambert"))
    assert 0.05 < mask.mean() < 0.8  # the model fills a sensible part of the frame
    # the thickness panel is mix(orange, blue, t): blue grows with normalized thickness
    t = (thickness[..., 2] - 0.1) / 0.8
    brightness = translucent.mean(axis=2)
    corr = np.corrcoef(t[mask], brightness[mask])[0, 1]
    assert corr < -0.3, corr
    # the thickness panel's scale is fixed (0 to a round length), not stretched: thin and thick by quartile
    low, high = np.percentile(t[mask], [25, 75])
    thin, thick = mask & (t < low), mask & (t > high)
    assert thin.sum() > 50 and thick.sum() > 50
    assert brightness[thin].mean() > 1.5 * brightness[thick].mean()


def test_panels_need_their_data(tmp_path):
    import trimesh

    src = tmp_path / "plain.glb"
    trimesh.creation.icosphere(subdivisions=2).export(str(src))
    result = preview(src, size=64)
    assert [n for n, _, _ in result.panels] == ["lambert"]


def test_cli_writes_png_and_rejects_bad_output(baked_spot, tmp_path):
    out = tmp_path / "sheet.png"
    assert main(["preview", str(baked_spot), "-o", str(out), "--size", "96", "-q"]) == 0
    image = read_image(out)
    assert image.shape[1] == 3 * 96 and image.shape[2] == 3
    assert main(["preview", str(baked_spot), "-o", str(tmp_path / "sheet.glb"), "-q"]) == 2
    assert not (tmp_path / "sheet.glb").exists()


# ---------------------------------------------------------------------------------------------------- every technique
BAKES = ["thickness", "curvature", "skin", "edges", "tam", "toon", "fur", "caustics"]
OPTIONS = {"thickness": {"rays": 16, "per_texel": False},
           "skin": {"width": 64, "height": 64, "samples": 32, "unit_scale": 2.0},  # spot as a 2 mm miniature: wide scattering
           "tam": {"size": 64, "levels": 3, "candidates": 4, "scale": 256.0},
           "toon": {"bands": 3},
           "fur": {"fins": True, "shells": 6, "texture_size": 64, "hairs": 200},
           "caustics": {"size": 64, "frames": 2, "waves": 16, "tile_size": 0.5}}
SIZE = 192


@pytest.fixture(scope="module")
def baked_all(tmp_path_factory):
    out = tmp_path_factory.mktemp("preview_all") / "spot.glb"
    save(baker.bake(SPOT, bakes=BAKES, seed=1, options=OPTIONS), out)
    assert_khronos_clean(out)
    return out


@pytest.fixture(scope="module")
def sheet(baked_all):
    return preview(baked_all, size=SIZE, azimuth=60, elevation=15)


def test_skin_label_says_which_lut_rows_the_asset_reads(baked_all, sheet):
    """The skin panel's label gives the rows of the LUT's curvature axis that the asset's baked curvature (5th-95th
    percentile, concave as flat) reads, and the scale the bake assumed (spot as a 2 mm miniature)."""
    from baker.gltf.document import GltfDocument

    doc = GltfDocument.load(baked_all)
    skin = doc.json["materials"][0]["extensions"]["BAKER_skin_lut"]
    prim = doc.json["meshes"][0]["primitives"][0]
    count = len(doc.accessor(prim["attributes"]["POSITION"]))
    curvature = doc.accessor(prim["attributes"][skin["curvatureAttribute"]]).reshape(count, -1)[:, 0]
    lut = np.maximum(curvature, 0) * skin["curvatureScale"]
    lo, hi = skin["curvatureRange"]
    rows = [(np.percentile(lut, q) - lo) / (hi - lo) * 100 for q in (5, 95)]
    label = next(label for name, label, _ in sheet.panels if name == "skin")
    print(label, rows)
    assert f"LUT rows {max(rows[0], 0):.0f}-{min(rows[1], 100):.0f}%" in label
    assert "1 unit = 2 mm" in label
    assert ("clamped" in label) == (np.percentile(lut, 95) > hi)


def _lum(image):
    return image @ np.array([0.299, 0.587, 0.114])


def test_every_baked_technique_gets_its_panel(sheet):
    assert [n for n, _, _ in sheet.panels] == ["lambert", "thickness", "translucency", "skin", "toon", "caustics",
                                               "hatching", "outline", "wireframe", "fur"]


def test_hatching_darkens_from_lit_to_shadowed_side(baked_all, sheet):
    """The hatching panel is the reference's lit colour times the TAM's brightness, as the web hosts draw it (the key
    light from the front, as the viewer's): never brighter than the front-lit reference, and the strokes' share of
    the shade (1 - panel / reference) grows from the lit to the shadowed side, near the tone asked for."""
    from baker import readers
    from baker.preview import core as pv

    scene = pv.gather_scene(readers.read(baked_all))
    ctx = pv.create_context()
    try:
        front = pv.render_panel(ctx, dataclasses.replace(pv.REFERENCE, light="front"), scene,
                                pv.frame_camera(scene, azimuth=60, elevation=15), SIZE)
    finally:
        scene.release()
        ctx.release()
    lambert, hatching = _lum(front.astype(np.float64)), _lum(_panel(sheet, "hatching"))
    inside = ndimage.binary_erosion(_covered(_panel(sheet, "lambert")), iterations=2)
    assert (hatching[inside] <= lambert[inside] + 2 / 255).all()
    darkness = 1.0 - hatching / np.maximum(lambert, 1e-6)
    # lambert = 0.8 (0.15 + 0.85 max(N.L, 0)): lit N.L > 0.7, half-lit N.L ~ 0.15-0.45, shadow N.L <= 0
    lit, half, shadow = inside & (lambert > 0.6), inside & (lambert > 0.2) & (lambert < 0.42), \
        inside & (lambert < 0.125)
    means = [float(darkness[m].mean()) for m in (lit, half, shadow)]
    print("hatching darkness lit/half/shadow", means, [int(m.sum()) for m in (lit, half, shadow)])
    assert all(m.sum() > 50 for m in (lit, half, shadow))
    assert means[0] + 0.05 < means[1] < means[2] - 0.05
    # Praun's blend keeps the mean tone near the darkness asked for: 1 - (0.5 + 0.5 N.L), clamped by the TAM's range
    assert means[2] > 0.4 and means[0] < 0.3


def test_toon_has_at_most_bands_levels(sheet):
    toon = _panel(sheet, "toon")
    inside = ndimage.binary_erosion(_covered(_panel(sheet, "lambert")), iterations=2)
    levels, counts = np.unique(np.round(_lum(toon[inside]) * 255).astype(int), return_counts=True)
    major = levels[counts > 0.01 * inside.sum()]
    print("toon levels", major, counts[counts > 0.01 * inside.sum()] / inside.sum())
    assert 2 <= len(major) <= 3
    assert counts[counts > 0.01 * inside.sum()].sum() > 0.97 * inside.sum()  # only band edges in between


def test_caustics_pattern_shows(sheet):
    """Where the key light falls (the caustics redistribute the sunlit part, as the runtimes do: the shadowed side
    keeps its ambient shade) the caustic network adds pixel-scale detail the smooth Lambert shade lacks."""
    lambert, caustics = _lum(_panel(sheet, "lambert")), _lum(_panel(sheet, "caustics"))
    # lambert = 0.8 (0.15 + 0.85 N.L): N.L > 0.3
    inside = ndimage.binary_erosion(_covered(_panel(sheet, "lambert")), iterations=3) & (lambert > 0.32)

    def detail(image):  # pixel-scale variation: what a smooth shade lacks and a caustic network has
        return np.abs(image - ndimage.uniform_filter(image, 5))[inside].mean()

    print("detail lambert", detail(lambert), "caustics", detail(caustics))
    assert inside.sum() > 500 and detail(caustics) > 4 * detail(lambert)


def test_skin_is_redder_than_lambert_at_the_terminator(sheet):
    lambert, skin = _panel(sheet, "lambert"), _panel(sheet, "skin")
    inside = ndimage.binary_erosion(_covered(lambert), iterations=2)
    terminator = inside & (_lum(lambert) < 0.3)  # N.L < 0.26, the shadowed side included
    red_skin = (skin[..., 0] - skin[..., 2])[terminator].mean()
    red_lambert = (lambert[..., 0] - lambert[..., 2])[terminator].mean()
    print("terminator red - blue: skin", red_skin, "lambert", red_lambert, int(terminator.sum()))
    assert terminator.sum() > 100
    assert red_skin > red_lambert + 0.008  # lambert is grey: exactly 0


def test_outline_ring_and_wireframe_lines(sheet):
    covered = _covered(_panel(sheet, "lambert"))
    ring = ndimage.binary_dilation(covered, iterations=2) & ~covered
    outline = _panel(sheet, "outline")
    dark = outline.max(axis=2) < 0.1  # darker than the background (0.19) and the shading (>= 0.12)
    print("outline: dark fraction of the 2-px ring", dark[ring].mean())
    assert dark[ring].mean() > 0.5
    assert dark[ndimage.binary_dilation(covered, iterations=6) & ~ndimage.binary_dilation(covered, iterations=4)].mean() < 0.02
    inside = ndimage.binary_erosion(covered, iterations=2)
    ink = _lum(_panel(sheet, "wireframe")) < _lum(_panel(sheet, "lambert")) - 0.2
    print("wireframe ink fraction", ink[inside].mean())
    assert 0.05 < ink[inside].mean() < 0.9


def test_fur_shells_stand_out_of_the_surface(sheet):
    covered = _covered(_panel(sheet, "lambert"))
    fur = _covered(_panel(sheet, "fur"))
    print("fur pixels outside the surface", int((fur & ~covered).sum()))
    assert (fur & ~covered).sum() > 100


def test_text_and_hair_panels(tmp_path):
    font = Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
    if not font.exists():
        pytest.skip("no DejaVu font")
    text = tmp_path / "text.glb"
    assert main(["text", "Hi", "--font", str(font), "-o", str(text), "--outline-width", "0.05", "-q"]) == 0
    result = preview(text, size=128)
    assert [n for n, _, _ in result.panels] == ["text"]
    ink = _lum(_panel(result, "text")) > 0.8  # white fill on the dark background
    print("text ink pixels", int(ink.sum()))
    assert ink.sum() > 300

    import trimesh

    ball = tmp_path / "ball.glb"
    trimesh.creation.icosphere(subdivisions=2, radius=0.5).export(str(ball))
    hair = tmp_path / "hair.glb"
    assert main(["hair", str(ball), "-o", str(hair), "--guides", "20", "--children", "10", "--segments", "6",
                 "--length", "0.4", "-q"]) == 0
    result = preview(hair, size=128)
    assert [n for n, _, _ in result.panels] == ["lambert", "hair", "hair-kajiya-kay"]
    emitter = ndimage.binary_dilation(_covered(_panel(result, "lambert")), iterations=2)
    strands = _covered(_panel(result, "hair")) & ~emitter
    print("hair pixels outside the emitter", int(strands.sum()))
    assert strands.sum() > 100


def test_hair_panel_glows_backlit_when_blond(tmp_path):
    """The "hair" panel shades strands with their BAKER_hair_shading (fibre tables + dual scattering, the melanin
    and fibre counts ``baker hair`` writes): lit from behind, blond strands glow around the ball (TT through the
    fibres) and black ones hardly; Kajiya-Kay ("hair-kajiya-kay") has no such glow."""
    import dataclasses

    import trimesh

    from baker import readers
    from baker.preview.core import all_panels, create_context, frame_camera, gather_scene, render_panel

    ball = tmp_path / "ball.glb"
    trimesh.creation.icosphere(subdivisions=2, radius=0.5).export(str(ball))
    glow = {}
    for eumelanin in (0.3, 8.0):
        hair = tmp_path / f"hair{eumelanin}.glb"
        assert main(["hair", str(ball), "-o", str(hair), "--guides", "20", "--children", "10", "--segments", "6",
                     "--length", "0.4", "--hair-eumelanin", str(eumelanin), "-q"]) == 0
        known = {p.name: p for p in all_panels()}
        scene = gather_scene(readers.read(hair, require_triangles=False), list(known.values()))
        camera = frame_camera(scene, 30.0, 15.0)
        ctx = create_context()
        try:
            reference = render_panel(ctx, known["lambert"], scene, camera, 128)
            images = {name: render_panel(ctx, dataclasses.replace(known[name], light="back"), scene, camera, 128)
                      for name in ("hair", "hair-kajiya-kay")}
        finally:
            scene.release()
            ctx.release()
        background = reference[0, 0]
        emitter = ndimage.binary_dilation(np.abs(reference - background).max(axis=2) > 0.02, iterations=2)
        for name, image in images.items():
            # the light the strands add around the ball, summed (thin strands are coverage-blended)
            glow[name, eumelanin] = float(np.clip(_lum(image - background)[~emitter], 0, None).sum())
    print("backlit glow", {k: round(v, 2) for k, v in glow.items()})
    assert glow["hair", 0.3] > 3 * glow["hair", 8.0]
    assert glow["hair", 0.3] > 3 * glow["hair-kajiya-kay", 0.3]


def test_unknown_panel_is_an_error(baked_spot):
    with pytest.raises(baker.errors.BakerError):
        preview(baked_spot, size=32, panels=["nope"])


def test_hair_cards_panel_is_alpha_tested_and_shaded_along_the_flow(tmp_path):
    """The cards panel draws the cards alpha-tested: inside the silhouette of the card quads (the same file with
    alphaMode OPAQUE) and cutting a good part of it; the reference panel honours the material's MASK alike."""
    import json

    from baker.gltf.document import GltfDocument
    from techniques.cards_groom import make_groom, write_groom_usd

    curves, widths = make_groom(strands=600, clumps=24, seed=6)
    groom = write_groom_usd(tmp_path / "groom.usda", curves, widths)
    cards = tmp_path / "cards.glb"
    assert main(["cards", str(groom), "-o", str(cards), "--cards", "24", "--atlas-size", "512", "-q"]) == 0
    result = preview(cards, size=192, azimuth=20, elevation=10)
    assert [n for n, _, _ in result.panels] == ["lambert", "cards", "cards-kajiya-kay"]
    doc = GltfDocument.load(cards)
    (material,) = doc.json["materials"]
    assert material["alphaMode"] == "MASK"
    material["alphaMode"] = "OPAQUE"
    doc.save(tmp_path / "opaque.glb")
    solid = _covered(_panel(preview(tmp_path / "opaque.glb", size=192, azimuth=20, elevation=10), "lambert"))
    cut = _covered(_panel(result, "cards"))
    reference = _covered(_panel(result, "lambert"))
    print("card pixels", int(solid.sum()), "after the alpha test", int(cut.sum()), "reference", int(reference.sum()))
    assert cut.sum() > 300 and (cut & ~ndimage.binary_dilation(solid, iterations=1)).sum() < 0.02 * cut.sum()
    assert cut.sum() < 0.9 * solid.sum()
    # the reference panel cuts at the same alphaCutoff as the cards panel: about as many pixels, mostly the same
    iou = (reference & cut).sum() / (reference | cut).sum()
    print("reference against cards panel: IoU", iou)
    assert reference.sum() < 0.9 * solid.sum() and abs(int(reference.sum()) - int(cut.sum())) < 0.15 * cut.sum()
    assert iou > 0.5  # not the same texels: the cards panel samples the coverage mips, the reference level 0
    # "cards" shades with the material's BAKER_hair_shading, "cards-kajiya-kay" as before: same cut, other colours
    kajiya_kay = _panel(result, "cards-kajiya-kay")
    assert (_covered(kajiya_kay) == cut).mean() > 0.99
    change = np.abs(_panel(result, "cards") - kajiya_kay)[cut].mean()
    print("cards: fibre tables against Kajiya-Kay, mean change", change)
    assert change > 0.02


def test_hair_cards_panel_keeps_coverage_when_small(tmp_path):
    """The cards panel alpha-tests the base colour's coverage-preserving mip chain: rendered at 384, 128 and 64 px
    (the cards 3x and 6x as far; a 1024² atlas minified to about levels 2, 4 and 5) the share of the card quads'
    pixels that pass the test stays near the 384 px frame's, while with the file's chain replaced by the plain box
    chain of the same atlas (what mipmapping the PNG gives) it falls away."""
    from baker.texels.alpha_mips import alpha_mip_chain, read_coverage_mips
    from baker.gltf.document import GltfDocument
    from baker.gltf.ktx2 import encode_ktx2
    from techniques.cards_groom import make_groom, write_groom_usd

    curves, widths = make_groom(strands=600, clumps=24, seed=6)
    groom = write_groom_usd(tmp_path / "groom.usda", curves, widths)
    cards = tmp_path / "cards.glb"
    assert main(["cards", str(groom), "-o", str(cards), "--cards", "24", "--atlas-size", "1024", "-q"]) == 0
    doc = GltfDocument.load(cards)
    (entry,) = doc.json["materials"][0]["extensions"]["BAKER_hair_cards"]["coverageMips"]
    box = alpha_mip_chain(read_coverage_mips(doc, entry)[0], entry["alphaCutoff"], preserve_coverage=False)
    levels = box.levels[entry.get("firstLevel", 0):]  # the file's chain starts where its level 0 is the PNG
    entry["accessor"] = doc.add_accessor(np.frombuffer(encode_ktx2(levels), np.uint8), target=None)
    doc.save(tmp_path / "box.glb")
    (material,) = doc.json["materials"]
    material["alphaMode"] = "OPAQUE"  # the card quads, drawn whole by the reference panel
    doc.save(tmp_path / "opaque.glb")
    kept = {}
    for name, path in (("chain", cards), ("box", tmp_path / "box.glb")):
        for size in (384, 128, 64):
            result = preview(path, size=size, azimuth=20, elevation=10)
            quads = preview(tmp_path / "opaque.glb", size=size, azimuth=20, elevation=10)
            solid, cut = _covered(_panel(quads, "lambert")), _covered(_panel(result, "cards"))
            assert (cut & ~ndimage.binary_dilation(solid, iterations=1)).sum() <= 0.02 * cut.sum() + 1
            kept[name, size] = float(cut.sum() / solid.sum())
    print("share of the card pixels kept by the alpha test", kept)
    near = kept["chain", 384]
    assert 0.1 < near < 0.9
    assert kept["chain", 128] >= 0.8 * near and kept["chain", 64] >= 0.75 * near
    assert kept["box", 64] < 0.4 * near


def test_normal_blur_panel_is_softest_in_red(tmp_path):
    """A bumped sphere baked with normal-blur: the panel shades each channel with its diffuse normal map, so the
    bump's pixel-scale detail is weakest in red and strongest in blue (d'Eon's skin profile)."""
    from tests.techniques.test_normal_blur import bump_sphere

    source = bump_sphere(tmp_path / "sphere.glb", "v", segments=128, rings=64, size=256)
    out = tmp_path / "blurred.glb"
    save(baker.bake(source, bakes=["normal-blur"]), out)
    result = preview(out, size=SIZE, panels=["normal-blur"])
    assert [n for n, _, _ in result.panels] == ["normal-blur"]
    image = _panel(result, "normal-blur")
    inside = ndimage.binary_erosion(_covered(image), iterations=4)

    def detail(channel):  # pixel-scale variation: the bump, not the sphere's smooth shade
        c = image[..., channel]
        return np.abs(c - ndimage.uniform_filter(c, 5))[inside].mean()

    red, green, blue = detail(0), detail(1), detail(2)
    print("detail", red, green, blue)
    assert inside.sum() > 500 and red < 0.7 * green and green <= blue * 1.05


def test_skin_panel_reads_the_diffuse_normals(tmp_path):
    """The same bumped sphere baked with skin alone and with normal-blur + skin. Skin alone blends the normal map's
    normal with the interpolated one per channel (Penner's normal blending; red takes the smooth normal), so its red
    channel shows no bump; with normal-blur it reads the LUT with the per-channel blurred normals: the bump shows in
    red too, softest there."""
    from tests.techniques.test_normal_blur import bump_sphere

    source = bump_sphere(tmp_path / "sphere.glb", "v", segments=128, rings=64, size=256)
    options = {"skin": {"width": 64, "height": 64, "penumbra": False}}
    details = {}
    for label, bakes in (("skin", ["skin"]), ("blurred", ["normal-blur", "skin"])):
        out = tmp_path / f"{label}.glb"
        save(baker.bake(source, bakes=bakes, options=options), out)
        image = _panel(preview(out, size=SIZE, panels=["skin"]), "skin")
        inside = ndimage.binary_erosion(_covered(image), iterations=4)
        details[label] = [np.abs(image[..., c] - ndimage.uniform_filter(image[..., c], 5))[inside].mean()
                          for c in range(3)]
    print("skin panel detail (R, G, B)", details)
    assert details["skin"][0] < 0.5 * details["blurred"][0]
    assert details["blurred"][0] < 0.75 * details["blurred"][2]


# ---------------------------------------------------------------------------------------------------- material, grooms
def _object(result, name):
    """A panel's pixels and the mask of the object in it (pixels away from the background), eroded off the edge."""
    image = _panel(result, name)
    return image, ndimage.binary_erosion(_covered(image), iterations=2)


def test_reference_panel_uses_the_mtl_base_colour(tmp_path):
    """An OBJ whose MTL has a red Kd previews red: the reference panel (and a technique panel) shade with the
    material's base colour, so the sheet's first panel is the asset as it was."""
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=3)
    lines = ["mtllib red.mtl", "usemtl red"] + [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in sphere.vertices] + \
        [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in sphere.faces]
    (tmp_path / "red.obj").write_text("\n".join(lines) + "\n")
    (tmp_path / "red.mtl").write_text("newmtl red\nKd 0.9 0.05 0.05\n")
    out = tmp_path / "red.glb"
    assert main(["bake", str(tmp_path / "red.obj"), "--bakes", "toon", "-o", str(out), "-q"]) == 0
    result = preview(out, size=128)
    for name in ("lambert", "toon"):
        image, inside = _object(result, name)
        r, g, b = (image[..., c][inside].mean() for c in range(3))
        print(name, "mean RGB of the object", r, g, b, int(inside.sum()))
        assert inside.sum() > 1000 and r > 3 * g and r > 3 * b


def _normal_mapped_plane(path, normal_rgb):
    """A unit square facing +Z with UVs (u along +X), its material a constant tangent-space normal map."""
    import trimesh
    from PIL import Image

    plane = trimesh.Trimesh([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], [[0, 1, 2], [0, 2, 3]], process=False)
    material = trimesh.visual.material.PBRMaterial(
        baseColorFactor=[204, 204, 204, 255], metallicFactor=0.0, roughnessFactor=0.5,
        normalTexture=Image.new("RGB", (8, 8), tuple(int(c) for c in normal_rgb)))
    plane.visual = trimesh.visual.TextureVisuals(uv=[[0, 0], [1, 0], [1, 1], [0, 1]], material=material)
    plane.export(str(path))
    return path


def test_reference_panel_uses_the_normal_map(tmp_path):
    """A plane whose normal map tilts every normal 45 degrees towards +u (+X, the key light's side) is brighter
    than the same plane with the flat normal map, and one tilted towards -u darker (tangent frame from the
    derivatives: the plane has no TANGENT)."""
    mean = {}
    for name, rgb in (("flat", (128, 128, 255)), ("right", (218, 128, 218)), ("left", (38, 128, 218))):
        result = preview(_normal_mapped_plane(tmp_path / f"{name}.glb", rgb), size=96, azimuth=0, elevation=0)
        image, inside = _object(result, "lambert")
        assert inside.sum() > 2000
        mean[name] = float(_lum(image)[inside].mean())
    print("plane luminance by normal map", mean)
    assert mean["right"] > mean["flat"] + 0.05 and mean["left"] < mean["flat"] - 0.05


def _lines_gltf(path, mode):
    """A groom of 40 wavy strands of 12 points as one LINES (mode 1) or LINE_STRIP-per-strand primitive set,
    no triangles, no material."""
    import base64
    import json

    rng = np.random.default_rng(0)
    t = np.linspace(0.0, 1.0, 12)[:, None]
    strands = [rng.uniform(-0.5, 0.5, 3) * [1, 0, 1] + t * [0.1 * np.sin(s), 1.0, 0.1 * np.cos(s)]
               + 0.05 * np.sin(6 * t) * [1, 0, 0] for s in range(40)]
    positions = np.concatenate(strands).astype(np.float32)
    if mode == 1:
        indices = [np.stack([np.arange(11), np.arange(1, 12)], 1).reshape(-1) + 12 * s for s in range(40)]
    else:
        indices = [np.arange(12) + 12 * s for s in range(40)]
    blobs = [positions.tobytes()] + [i.astype(np.uint32).tobytes() for i in indices]
    offsets = np.cumsum([0] + [len(b) for b in blobs])
    data = b"".join(blobs)
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
           "buffers": [{"byteLength": len(data),
                        "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
           "bufferViews": [{"buffer": 0, "byteOffset": int(offsets[k]), "byteLength": len(b)}
                           for k, b in enumerate(blobs)],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3",
                          "min": positions.min(0).tolist(), "max": positions.max(0).tolist()}]
           + [{"bufferView": k + 1, "componentType": 5125, "count": len(i), "type": "SCALAR"}
              for k, i in enumerate(indices)],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1 + k, "mode": mode}
                                      for k in range(len(indices))]}]}
    path.write_text(json.dumps(doc))
    return path


@pytest.mark.parametrize("mode", [1, 3])
def test_lines_only_groom_previews_as_strands(tmp_path, mode):
    """A glTF holding only line primitives (a groom) previews: exit 0 and the strands drawn in the reference panel,
    spread over the frame (the 40 strands, not one blob)."""
    source = _lines_gltf(tmp_path / "groom.gltf", mode)
    out = tmp_path / "sheet.png"
    assert main(["preview", str(source), "-o", str(out), "--size", "128", "-q"]) == 0
    sheet = read_image(out).astype(np.float64) / 255.0
    label_h = max(18, 128 // 16)
    strands = _covered(sheet[label_h:, :128, :3])
    columns = strands.any(axis=0)
    print("strand pixels", int(strands.sum()), "columns crossed", int(columns.sum()))
    assert 200 < strands.sum() < 0.4 * strands.size and columns.sum() > 40


# ---------------------------------------------------------------------------------------------------- at the asset's scale
MESHES = Path("/work/shared/assets/meshes")


@pytest.fixture(scope="module", params=["bunny", "spot"])
def toon_caustics_sheet(request, tmp_path_factory):
    """Toon and caustics baked with their defaults (fewer, smaller caustic frames) on the Stanford bunny (0.2 units
    tall) and spot: the caustic tile defaults to half the asset's bounding-box diagonal, the water scaled with it."""
    source = MESHES / "stanford-bunny.obj" if request.param == "bunny" else SPOT
    out = tmp_path_factory.mktemp("scale") / f"{request.param}.glb"
    save(baker.bake(source, bakes=["toon", "caustics"], seed=1, options={"caustics": {"size": 128, "frames": 2}}), out)
    return preview(out, size=SIZE)


def test_toon_shows_every_band(toon_caustics_sheet):
    """Under the grazing key light the ramp's three bands all show: the most common tone covers at most 80% of the
    object, and each band at least 3%."""
    _, inside = _object(toon_caustics_sheet, "lambert")
    toon = _lum(_panel(toon_caustics_sheet, "toon"))[inside]
    levels, counts = np.unique(np.round(toon * 255).astype(int), return_counts=True)
    share = counts / inside.sum()
    print("toon tones", levels[share > 0.01], share[share > 0.01])
    assert share.max() <= 0.8
    assert (share > 0.03).sum() == 3


def test_caustics_detail_at_the_asset_scale(toon_caustics_sheet):
    """The caustic network shows on the object at its scale: the mean luminance gradient inside the object, over
    its mean luminance, is at least 1.5x the reference panel's; the label says at which tile size (the baked
    default, half the asset's diagonal, drawn as baked: the runtimes do not rescale it) and water level."""
    _, inside = _object(toon_caustics_sheet, "lambert")

    def detail(image):
        lum = _lum(image)
        gy, gx = np.gradient(lum)
        return np.hypot(gx, gy)[inside].mean() / lum[inside].mean()

    reference, caustics = detail(_panel(toon_caustics_sheet, "lambert")), detail(_panel(toon_caustics_sheet, "caustics"))
    label = next(label for name, label, _ in toon_caustics_sheet.panels if name == "caustics")
    print("detail reference", reference, "caustics", caustics, label)
    assert caustics >= 1.5 * reference
    tile, extent, _ = (float(v) for v in re.fullmatch(
        r"caustics \(tile ([0-9.e+-]+), asset ([0-9.e+-]+), water at y ([0-9.e+-]+)\)", label).groups())
    assert tile == pytest.approx(0.5 * extent, rel=5e-3)  # 3 significant digits in the label


def test_caustics_project_along_the_refracted_sun_as_the_runtimes_do(tmp_path):
    """The panel projects the frames as runtime-shaders/baker_caustics.glsl does, along projectionDirection from
    the world position (no triplanar read, which no runtime does): on a box's vertical face seen head on, the
    caustic is constant along the projection direction's image and varies across it."""
    import trimesh

    from baker.gltf.document import GltfDocument

    box = tmp_path / "box.glb"
    trimesh.creation.box(extents=[1.0, 1.0, 1.0]).export(str(box))
    out = tmp_path / "caustics.glb"
    save(baker.bake(box, bakes=["caustics"], seed=1, options={"caustics": {"size": 128, "frames": 2}}), out)
    direction = GltfDocument.load(out).json["materials"][0]["extensions"]["BAKER_caustics"]["projectionDirection"]
    sheet = preview(out, size=SIZE, azimuth=0, elevation=0)  # the +Z face, head on: image x = +X, rows = -Y
    (image, inside), reference = _object(sheet, "caustics"), _lum(_panel(sheet, "lambert"))
    change = _lum(image) - reference
    gy, gx = np.gradient(change)
    along = np.array([direction[0], -direction[1]]) / np.hypot(direction[0], direction[1])  # (column, row)
    derivative_along = np.abs(gx * along[0] + gy * along[1])[inside].mean()
    derivative_across = np.abs(-gx * along[1] + gy * along[0])[inside].mean()
    print("caustic change on a vertical face: mean |d/d along|", derivative_along, "|d/d across|", derivative_across)
    assert inside.sum() > 2000 and derivative_across > 0.002 and derivative_along < 0.3 * derivative_across


def test_thickness_on_a_fixed_scale_with_a_legend(tmp_path):
    """A unit cube's thickness (0.46-0.9: a mean over the rays' lengths) maps onto the fixed scale 0-1 m (the
    round length at or above its largest value): the object covers a narrow part of the colour ramp instead of being stretched over all of it; the colour
    bar runs from the ramp's thin end to its thick end and the label gives the scale and the asset's range."""
    import trimesh

    from baker.gltf.document import GltfDocument

    box = tmp_path / "box.glb"
    trimesh.creation.box(extents=[1.0, 1.0, 1.0]).subdivide().subdivide().export(str(box))
    out = tmp_path / "thick.glb"
    save(baker.bake(box, bakes=["thickness"], seed=1, options={"thickness": {"rays": 16, "per_texel": False}}), out)
    doc = GltfDocument.load(out)
    values = np.concatenate([doc.accessor(p["attributes"]["_THICKNESS"]).reshape(len(doc.accessor(
        p["attributes"]["POSITION"])), -1)[:, 0] for m in doc.json["meshes"] for p in m["primitives"]])
    result = preview(out, size=SIZE, panels=["thickness"])
    image, inside = _object(result, "thickness")
    size = image.shape[0]
    t = (image[..., 2] - 0.1) / 0.8  # mix(orange, blue, t): blue 0.1 -> 0.9
    spread = np.percentile(t[inside & (np.arange(size)[:, None] < 0.9 * size)], [5, 95])
    label = result.panels[0][1]
    print("thickness values", values.min(), values.max(), "colour t 5-95%", spread, label)
    assert 0.5 < values.max() <= 1.0 and spread[1] - spread[0] < 0.3
    assert abs(np.median(t[inside]) - np.median(values)) < 0.1  # t = thickness / 1 m
    assert "bar 0-1 m" in label and f"{values.max():.3g}" in label
    bar = image[size - 5, :, :]  # inside the bar along the bottom edge
    assert np.allclose(bar[8], [0.95, 0.35, 0.1], atol=0.03) and np.allclose(bar[-8], [0.1, 0.3, 0.9], atol=0.03)


def _scaled_obj(source: Path, out: Path, extent: float) -> Path:
    """``source`` (an OBJ) centred and scaled so its largest bounding-box side is ``extent`` (metres, as baker takes
    a unitless OBJ); every other line kept."""
    lines = source.read_text().splitlines()
    points = np.array([[float(x) for x in line.split()[1:4]] for line in lines if line.startswith("v ")])
    centre, scale = (points.min(0) + points.max(0)) / 2, extent / (points.max(0) - points.min(0)).max()
    out.write_text("\n".join("v %.9g %.9g %.9g" % tuple((np.array([float(x) for x in line.split()[1:4]]) - centre)
                                                      * scale) if line.startswith("v ") else line
                             for line in lines) + "\n")
    return out


def test_skin_reddens_the_terminator_of_a_15mm_suzanne(tmp_path):
    """Suzanne scaled to 15 mm (median convex radius ~4 mm, where d'Eon's profile matters), curvature + skin with
    their defaults: in the terminator band (reference luminance 0.02-0.25) the skin panel's mean R - G exceeds the
    reference's by at least 0.01 (issue 39). The LUT's axis is fitted to the asset (label: rows in use, the scale
    assumed).

    Measured: +0.034 (the LUT's ring profile integrated across the ring, the curvature along the light from the
    principal curvatures); +0.033 with the mean curvature; +0.005 with Penner's radial ring profile, whose broad red
    lobes weigh 1/sigma."""
    source = _scaled_obj(MESHES / "suzanne.obj", tmp_path / "suzanne15.obj", 0.015)
    out = tmp_path / "suzanne15.glb"
    save(baker.bake(source, bakes=["curvature", "skin"]), out)
    result = preview(out, size=256, panels=["lambert", "skin"])
    reference, inside = _object(result, "lambert")
    skin = _panel(result, "skin")
    band = inside & (_lum(reference) > 0.02) & (_lum(reference) < 0.25)

    def redness(image):
        return (image[..., 0] - image[..., 1])[band].mean()

    label = next(label for name, label, _ in result.panels if name == "skin")
    print("terminator band R - G: skin", redness(skin), "reference", redness(reference), int(band.sum()), label)
    assert band.sum() > 1000
    assert redness(skin) > redness(reference) + 0.01
    assert "1 unit = 1000 mm" in label and "LUT rows 0-" in label and "clamped" not in label


def _projected_fill(triangles, camera, size):
    """Pixels (row 0 at the top, as the panels) whose centres lie inside any of the world triangles (k, 3, 3)."""
    vp = camera.projection @ camera.view
    h = np.concatenate([triangles.reshape(-1, 3), np.ones((triangles.size // 3, 1))], axis=1) @ vp.T
    px = (h[:, :2] / h[:, 3:] * 0.5 + 0.5) * size
    px[:, 1] = size - px[:, 1]
    yy, xx = np.mgrid[0:size, 0:size]
    x, y = xx.ravel() + 0.5, yy.ravel() + 0.5
    inside = np.zeros(len(x), bool)
    for a, b, c in px.reshape(-1, 3, 2):
        sides = [(q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0]) for p, q in ((a, b), (b, c), (c, a))]
        inside |= np.all([d >= 0 for d in sides], axis=0) | np.all([d <= 0 for d in sides], axis=0)
    return inside.reshape(size, size)


def _outline_ink(path, views, size=256):
    """Per view: the camera and the outline panel's ink (i) as baked, (ii) with every material double-sided (the
    mesh's own inside hides the shell: the reference the open single-sided rendering must not exceed)."""
    from baker import readers
    from baker.preview.core import all_panels, create_context, frame_camera, gather_scene, render_panel

    panels = all_panels()
    outline = next(p for p in panels if p.name == "outline")
    scene = gather_scene(readers.read(path), panels)
    ctx = create_context()
    out = []
    try:
        for azimuth, elevation in views:
            camera = frame_camera(scene, azimuth, elevation)
            ink = {}
            for name in ("baked", "double-sided"):
                for item in scene.items:
                    item.material = dict(item.material or {}, doubleSided=name == "double-sided")
                ink[name] = render_panel(ctx, outline, scene, camera, size).max(axis=2) < 0.1
            out.append((camera, ink))
    finally:
        scene.release()
        ctx.release()
    return out


def test_outline_leaves_openings_clear(tmp_path):
    """RTR4 15.2.2: the shell needs a closed mesh; through an opening of a single-sided mesh its inflated back faces
    would fill the hole with ink. The bake pins _OUTLINE_NORMAL to zero on the rims and the panel writes an open
    primitive's back faces to depth first: no ink inside a window cut into a sphere (without that pass: every window
    pixel, see tests/gl/test_edges.py), and inside the teapot's openings (the spout's mouth, the ring between lid and
    body) only what the shell draws when the teapot's inside is there to hide it (double-sided: the lid's own
    contour); the silhouette ring is unchanged."""
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
    centres = sphere.triangles_center
    cut = (centres[:, 2] > 0.3) & (np.abs(centres[:, 0]) < 0.45) & (np.abs(centres[:, 1]) < 0.3)
    source = tmp_path / "holed_sphere.obj"
    trimesh.Trimesh(sphere.vertices, sphere.faces[~cut], process=False).export(source)
    save(baker.bake(source, bakes=("edges",)), tmp_path / "holed_sphere.glb")
    for camera, ink in _outline_ink(tmp_path / "holed_sphere.glb", [(0, 0), (25, 10), (-30, -15)]):
        window = ndimage.binary_erosion(_projected_fill(sphere.vertices[sphere.faces[cut]], camera, 256), iterations=2)
        away = ~ndimage.binary_dilation(window, iterations=12)
        print("holed sphere: window pixels", int(window.sum()), "ink: baked", int(ink["baked"][window].sum()),
              "silhouette", int(ink["baked"][away].sum()))
        assert window.sum() > 4000 and ink["baked"][window].sum() == 0
        assert ink["baked"][away].sum() > 1000 and np.array_equal(ink["baked"][away], ink["double-sided"][away])

    teapot = Path(__file__).resolve().parents[2] / "shared" / "assets" / "meshes" / "teapot.obj"
    mesh = trimesh.load(teapot, process=True)
    rims = mesh.edges_sorted[trimesh.grouping.group_rows(mesh.edges_sorted, require_count=1)]
    # each boundary loop as a fan around its centre: the openings' screen regions (the body's rim minus the lid's)
    labels = trimesh.graph.connected_component_labels(rims, node_count=len(mesh.vertices))[rims[:, 0]]
    fans = []
    for label in np.unique(labels):
        loop = rims[labels == label]
        centre = mesh.vertices[np.unique(loop)].mean(axis=0)
        fans.append((centre, np.concatenate([mesh.vertices[loop], np.repeat(centre[None, None], len(loop), 0)], 1)))
    spout = next(f for c, f in fans if c[0] > 2.9)
    body, lid = sorted((f for c, f in fans if abs(c[1] - 2.4) < 0.05 and abs(c[0]) < 0.05), key=lambda f: -np.ptp(f[..., 0]))
    save(baker.bake(teapot, bakes=("edges",)), tmp_path / "teapot.glb")
    for camera, ink in _outline_ink(tmp_path / "teapot.glb", [(60, 55), (90, 30)], size=512):
        openings = _projected_fill(spout, camera, 512) | (_projected_fill(body, camera, 512) &
                                                          ~ndimage.binary_dilation(_projected_fill(lid, camera, 512)))
        openings = ndimage.binary_erosion(openings, iterations=1)
        counts = {name: int(image[openings].sum()) for name, image in ink.items()}
        print("teapot: opening pixels", int(openings.sum()), "ink in them", counts)
        # the ring between lid and body is narrow: most of it is the lid's own contour, drawn either way
        assert openings.sum() > 500
        assert counts["baked"] <= counts["double-sided"] + 0.01 * openings.sum()


def _alpha_plane(path, alpha_mode, alpha_left, alpha_right, cutoff=0.5):
    """A square facing +Z whose base colour texture is white with alpha ``alpha_left`` on its left half (u < 0.5)
    and ``alpha_right`` on the right, drawn with glTF alphaMode ``alpha_mode``."""
    import trimesh
    from PIL import Image

    pixels = np.full((8, 8, 4), 255, np.uint8)
    pixels[:, :4, 3], pixels[:, 4:, 3] = alpha_left, alpha_right
    plane = trimesh.Trimesh([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], [[0, 1, 2], [0, 2, 3]], process=False)
    material = trimesh.visual.material.PBRMaterial(
        baseColorTexture=Image.fromarray(pixels, "RGBA"), metallicFactor=0.0, roughnessFactor=0.5,
        alphaMode=alpha_mode, alphaCutoff=cutoff if alpha_mode == "MASK" else None)
    plane.visual = trimesh.visual.TextureVisuals(uv=[[0, 0], [1, 0], [1, 1], [0, 1]], material=material)
    plane.export(str(path))
    return path


def test_reference_panel_honours_alpha_mode(tmp_path):
    """glTF alphaMode as every viewer draws it: OPAQUE ignores alpha; MASK cuts the half whose alpha is below the
    cutoff (and keeps the half at or above it); BLEND mixes the surface with the background by the alpha."""
    def halves(alpha_mode, left, right):
        path = _alpha_plane(tmp_path / f"{alpha_mode}_{left}_{right}.glb", alpha_mode, left, right)
        image = _panel(preview(path, size=128, azimuth=0, elevation=0), "lambert")
        covered = _covered(image)
        xs = np.flatnonzero(covered.any(axis=0))
        middle = (xs.min() + xs.max()) // 2
        return image, covered, middle

    opaque, covered, middle = halves("OPAQUE", 0, 255)
    assert covered.mean() > 0.1 and covered[:, :middle].sum() > 0.4 * covered.sum()
    _, masked, _ = halves("MASK", 64, 192)  # 0.25 and 0.75 against the cutoff 0.5
    print("opaque pixels", int(covered.sum()), "masked", int(masked.sum()))
    assert 0.35 * covered.sum() < masked.sum() < 0.65 * covered.sum()
    # the pixels the test kept lie on one side: the one whose alpha passes (u > 0.5 shows on the screen's right or
    # left depending on the view; either way one side is empty)
    left, right = masked[:, :middle].sum(), masked[:, middle + 1:].sum()
    assert min(left, right) < 0.03 * max(left, right)
    blended, _, _ = halves("BLEND", 128, 128)
    background = np.array(BACKGROUND)
    inside = covered & ndimage.binary_erosion(covered, iterations=2)
    # half alpha: halfway (within rounding and the light) between the opaque surface and the background
    mix = (blended[inside] - background) / np.where(np.abs(opaque[inside] - background) > 0.05,
                                                     opaque[inside] - background, np.nan)
    print("blend fraction", np.nanmedian(mix))
    assert 0.4 < np.nanmedian(mix) < 0.6


# ---------------------------------------------------------------------------------------------------- readable panels
@pytest.fixture(scope="module")
def bunny_sheet(tmp_path_factory):
    """The Stanford bunny (69k triangles) with thickness and edges at the default panel size: dense enough that a
    wireframe of full-strength lines is a black blob."""
    out = tmp_path_factory.mktemp("bunny") / "bunny.glb"
    save(baker.bake(MESHES / "stanford-bunny.obj", bakes=["thickness", "edges"], seed=1,
                    options={"thickness": {"rays": 16, "per_texel": False}}), out)
    return out, preview(out, panels=["lambert", "thickness", "translucency", "wireframe"])


def _thickness_values(path):
    from baker.gltf.document import GltfDocument

    doc = GltfDocument.load(path)
    return np.concatenate([doc.accessor(p["attributes"]["_THICKNESS"]).reshape(len(doc.accessor(
        p["attributes"]["POSITION"])), -1)[:, 0] for m in doc.json["meshes"] for p in m["primitives"]])


def test_no_panel_clips_the_asset(sheet, bunny_sheet):
    """Every panel of spot with every bake (caustics aside) and of the bunny leaves at most 2% of the asset's pixels
    (the reference panel's, and what the panel draws around them) clipped white (a channel at 254 or more) or black
    (every channel at 3 or less)."""
    from conftest import clipped_fractions

    for result in (sheet, bunny_sheet[1]):
        asset = _covered(_panel(result, "lambert"))
        measured = {}
        for name, _, _ in result.panels:
            if name == "caustics":  # the caustics panel is another item's
                continue
            image = _panel(result, name)
            measured[name] = clipped_fractions(image, asset | _covered(image))
        print("clipped (white, black)", {k: (round(w, 4), round(b, 4)) for k, (w, b) in measured.items()})
        assert all(w <= 0.02 and b <= 0.02 for w, b in measured.values()), measured


def test_thickness_bar_has_ticks_and_a_range_that_fits(bunny_sheet):
    """The thickness bar ends at a round length at or above the asset's largest thickness and within 1.25 x it (the
    label says which), with evenly spaced light ticks above it, the first at its left end and the last at its right
    end, 4 to 10 steps apart."""
    path, result = bunny_sheet
    values = _thickness_values(path)
    label = next(label for name, label, _ in result.panels if name == "thickness")
    end = float(re.search(r"bar 0-([0-9.e+-]+) m", label).group(1))
    print("thickness max", values.max(), "bar end", end, label)
    assert values.max() <= end <= 1.25 * values.max()
    image = _panel(result, "thickness")
    size = image.shape[0]
    drawn = np.abs(image - np.array(BACKGROUND)).max(axis=2) > 0.05
    top = np.nonzero(drawn.mean(axis=1) > 0.9)[0].min()  # the bar's first row: the only row drawn across the panel
    row = image[top - 1]
    light = (row.min(axis=1) > 0.7)
    starts = np.nonzero(light & ~np.concatenate([[False], light[:-1]]))[0]
    print("bar top row", top, "tick columns", starts)
    assert 5 <= len(starts) <= 11
    gaps = np.diff(starts)
    assert gaps.max() - gaps.min() <= 2  # evenly spaced
    span = np.nonzero((np.abs(image[top + 1] - np.array(BACKGROUND)).max(axis=1) > 0.05))[0]
    assert abs(starts[0] - span.min()) <= 2 and abs(starts[-1] + (light[starts[-1]:].argmin() - 1) - span.max()) <= 2


def test_wireframe_of_a_dense_mesh_is_not_a_blob(bunny_sheet, sheet):
    """The bunny's 69k triangles at 384 pixels: the wireframe's ink darkens at most 45% of the surface's shade (its
    lines fade where the triangles are small on screen; full-strength lines covered 89%) and still shows (at least
    10%); on spot's sparser mesh at 192 pixels the lines show as well (at least 10%)."""
    from baker.preview.core import INK

    for result, dense in ((bunny_sheet[1], True), (sheet, False)):
        reference, wire = _lum(_panel(result, "lambert")), _lum(_panel(result, "wireframe"))
        inside = ndimage.binary_erosion(_covered(_panel(result, "lambert")), iterations=2)
        ink_lum = float(np.dot(INK, [0.299, 0.587, 0.114]))
        shaded = inside & (reference - ink_lum > 0.05)
        coverage = float(np.clip((reference - wire) / (reference - ink_lum), 0, 1)[shaded].mean())
        print("wireframe ink coverage", "bunny" if dense else "spot", coverage)
        assert 0.1 < coverage < (0.45 if dense else 0.9), coverage


def test_translucency_reads_thin_against_thick(bunny_sheet, baked_spot):
    """Lit from behind, the translucency panel follows the thickness (brightness against the thickness panel's
    colour: correlation below -0.8; the thinnest quarter of the pixels at least 1.6 x as bright as the thickest), its
    exposure uses the display's range (the brightest 1% at 0.7 or more, short of white) and the back light is warm
    (red over blue where it shines through)."""
    spot = preview(baked_spot, size=256, panels=["lambert", "thickness", "translucency"])
    for result in (bunny_sheet[1], spot):
        asset = ndimage.binary_erosion(_covered(_panel(result, "lambert")), iterations=2)
        thickness, translucent = _panel(result, "thickness"), _panel(result, "translucency")
        size = thickness.shape[0]
        asset &= np.arange(size)[:, None] < 0.85 * size  # above the colour bar and its ticks
        t = (thickness[..., 2] - 0.1) / 0.8  # mix(orange, blue, t)
        brightness = translucent.mean(axis=2)
        corr = np.corrcoef(t[asset], brightness[asset])[0, 1]
        low, high = np.percentile(t[asset], [25, 75])
        ratio = brightness[asset & (t < low)].mean() / brightness[asset & (t > high)].mean()
        top = np.percentile(translucent.max(axis=2)[asset], 99)
        warm = (translucent[..., 0] - translucent[..., 2])[asset & (t < low)].mean()
        print("translucency: corr", corr, "thin/thick", ratio, "p99", top, "warm", warm)
        assert corr < -0.8 and ratio > 1.6 and 0.7 <= top < 0.99 and warm > 0.1, (corr, ratio, top, warm)
