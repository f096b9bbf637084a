"""Each technique's ``extension.read``: bake (or write with the technique's writer), save, load, read back, and
compare the typed object with what was written."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import baker
from baker.cli import main
from baker.gltf.document import GltfDocument
from baker.pipeline import save

SPOT = Path(__file__).parents[1] / "examples" / "spot" / "spot.obj"
FONT = Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
BAKES = ["thickness", "curvature", "skin", "edges", "tam", "toon", "fur", "caustics"]
OPTIONS = {"thickness": {"rays": 8, "per_texel": True, "texture_size": 32},
           "curvature": {"per_texel": True, "texture_size": 32},
           "skin": {"width": 32, "height": 32, "samples": 16, "penumbra": True},
           "edges": {"fins": True, "edge_list": True},
           "tam": {"size": 32, "levels": 2, "candidates": 2},
           "toon": {"bands": 3, "xtoon": "depth", "depth_range": (2.0, 20.0)},
           "fur": {"fins": True, "shells": 4, "texture_size": 32, "hairs": 50},
           "caustics": {"size": 16, "frames": 3, "waves": 8, "tile_size": 3.0, "water_level": 2.0}}


@pytest.fixture(scope="module")
def baked(tmp_path_factory):
    out = tmp_path_factory.mktemp("read") / "spot.glb"
    save(baker.bake(SPOT, bakes=BAKES, seed=1, options=OPTIONS), out)
    return GltfDocument.load(out)


def _ext(doc, name, material=0):
    return doc.json["materials"][material]["extensions"][name]


def test_thickness(baked):
    from baker.techniques.thickness.extension import KHR_VOLUME, NAME, read

    ext, volume = _ext(baked, NAME), _ext(baked, KHR_VOLUME)
    got = read(baked, 0)
    assert got.attenuation_distance == ext["attenuationDistance"] and got.power == ext["power"]
    assert (got.distortion, got.scale, got.ambient) == (ext["distortion"], ext["scale"], ext["ambient"])
    assert got.subsurface_color == tuple(ext["subsurfaceColor"])
    assert (got.rays, got.distribution, got.attribute) == (8, ext["distribution"], "_THICKNESS")
    assert got.spread_angle == ext["spreadAngle"] and got.mean_thickness == ext["meanThickness"]
    assert got.has_texture and got.thickness_texture == ext["thicknessTexture"]["index"]
    assert got.thickness_factor == ext["thicknessFactor"]
    # a single-sided material: KHR_materials_volume mirrors the same texture
    assert volume["thicknessTexture"] == ext["thicknessTexture"] and volume["thicknessFactor"] == ext["thicknessFactor"]


def test_curvature(baked):
    from baker.techniques.curvature.extension import NAME, read

    ext, got = _ext(baked, NAME), read(baked, 0)
    assert got.method == ext["method"] and got.range == tuple(ext["range"]) and got.attribute == "_CURVATURE"
    assert got.mean_curvature == ext["meanCurvature"] and got.smoothing_passes == ext["smoothingPasses"]
    assert got.curvature_texture == ext["curvatureTexture"]["index"]
    assert got.texture_range == tuple(ext["textureRange"])


def test_skin(baked):
    from baker.techniques.skin.extension import NAME, read

    ext, got = _ext(baked, NAME), read(baked, 0)
    assert got.lut_texture == ext["lutTexture"]["index"] and got.encoding == ext["encoding"]
    assert got.curvature_range == tuple(ext["curvatureRange"]) and got.curvature_scale == ext["curvatureScale"]
    assert got.penumbra_texture == ext["penumbraTexture"]["index"]
    assert got.penumbra_width_range == tuple(ext["penumbraWidthRange"])
    assert got.normal_blend == tuple(ext["normalBlend"]) and got.scatter_color == tuple(ext["scatterColor"])
    assert (got.wrap, got.scatter_width, got.samples) == (ext["wrap"], ext["scatterWidth"], 16)
    assert got.curvature_attribute == "_CURVATURE"  # curvature baked first (requires), whatever the --bakes order
    assert got.profile["name"] == ext["profile"]["name"]


def test_toon(baked):
    from baker.techniques.toon.extension import NAME, read

    ext, got = _ext(baked, NAME), read(baked, 0)
    assert got.ramp_texture == ext["rampTexture"]["index"]
    assert (got.xtoon, got.bands, got.depth_range) == ("depth", 3, (2.0, 20.0))
    assert got.softness == ext["softness"] and got.shadow == ext["shadow"] and got.min_contrast == ext["minContrast"]
    assert read(baked, 0).orientation_power == 1.0  # absent: the default


def test_tam(baked):
    from baker.techniques.tam.extension import NAME, read

    ext, got = _ext(baked, NAME), read(baked, 0)
    assert got.layout == "packed" and got.tones == tuple(ext["tones"]) and got.scale == ext["scale"]
    assert [lv.size for lv in got.levels] == [lv["size"] for lv in ext["levels"]] and len(got.levels) == 2
    assert [lv.textures for lv in got.levels] == [tuple(t["index"] for t in lv["textures"]) for lv in ext["levels"]]
    assert got.texcoord == ext["texCoord"] == 1  # the stroke set, after the mesh's own TEXCOORD_0
    assert got.style == ext["style"] and got.parameters["seed"] == ext["seed"] and "strokes" not in got.parameters
    assert got.strokes == ext["strokes"] and "directionAttribute" not in got.strokes  # --tam-direction false


def test_fur(baked):
    from baker.techniques.fur.extension import NAME, read, read_fin_source

    ext, got = _ext(baked, NAME), read(baked, 0)
    assert got.shell_count == 4 and got.shell_textures == tuple(t["index"] for t in ext["shellTextures"])
    assert got.shell_spacing == ext["shellSpacing"] and got.tiling == ext["tiling"] and got.length == ext["length"]
    assert got.fin_texture == ext["finTexture"]["index"] and got.shell_coverage == tuple(ext["shellCoverage"])
    assert got.fins == tuple((f["mesh"], f["primitive"]) for f in ext["fins"]) and got.fins
    mesh, fin = got.fins[0]
    assert read_fin_source(baked, mesh, fin) == 0 and read_fin_source(baked, mesh, 0) is None


def test_edges(baked):
    from baker.techniques.edges.extension import FIN_ATTRIBUTES, NAME, read

    prims = baked.json["meshes"][0]["primitives"]
    ext = prims[0]["extensions"][NAME]
    got = read(baked, 0, 0)
    assert got.fins_of is None and got.crease_angle == ext["creaseAngle"] and got.counts == ext["counts"]
    assert got.outline_normal == "_OUTLINE_NORMAL" and got.fins == ext["fins"]
    np.testing.assert_array_equal(got.wireframe_mask, baked.accessor(ext["wireframeMask"]))
    np.testing.assert_array_equal(got.edges, baked.accessor(ext["edges"]))
    assert len(got.flags) == len(got.edges) == ext["counts"]["edges"]
    assert got.dihedral_angles is None and got.opposite_vertices is None  # derivable: only on request
    fins = read(baked, 0, got.fins)
    assert fins.fins_of == 0 and sorted(fins.fin_attributes) == sorted(FIN_ATTRIBUTES)
    assert fins.fin_indices.shape == (2 * ext["counts"]["edges"], 3)
    np.testing.assert_array_equal(fins.fin_attributes["_FIN_V0"],
                                  baked.accessor(prims[got.fins]["attributes"]["_FIN_V0"]))
    plain = baker.bake(SPOT, bakes=["thickness"], options={"thickness": {"rays": 4, "per_texel": False}})
    assert read(plain.doc, 0, 0) is None


def test_caustics(baked):
    from baker.techniques.caustics.extension import NAME, read

    got, ext = read(baked, 0), _ext(baked, NAME)
    assert len(got.frame_textures) == 3 and got.frame_textures == tuple(i["index"] for i in ext["frameTextures"])
    assert (got.tile_size, got.water_level, got.period) == (3.0, 2.0, 4.0)
    assert got.intensity_scale == ext["intensityScale"] and got.projection_direction[1] < 0


def test_no_extension_reads_none(baked):
    from baker.techniques.caustics import extension as caustics
    from baker.techniques.curvature import extension as curvature
    from baker.techniques.fur import extension as fur
    from baker.techniques.skin import extension as skin
    from baker.techniques.tam import extension as tam
    from baker.techniques.thickness import extension as thickness
    from baker.techniques.toon import extension as toon

    plain = baker.bake(SPOT, bakes=["curvature"], options={}).doc
    for module in (caustics, fur, skin, tam, thickness, toon):
        assert module.read(plain, 0) is None
    assert curvature.read(plain, 0) is not None


def test_text_and_atlas(tmp_path):
    from baker.techniques.glyphs.extension import ATLAS_NAME, TEXT_NAME, read_atlas, read_text

    if not FONT.exists():
        pytest.skip("no DejaVu font")
    out = tmp_path / "text.glb"
    assert main(["text", "Hi", "--font", str(FONT), "-o", str(out), "--outline-width", "0.05", "-q"]) == 0
    doc = GltfDocument.load(out)
    written = doc.json["extensions"][ATLAS_NAME]["fonts"]
    fonts = read_atlas(doc)
    assert len(fonts) == len(written) == 1
    font, raw = fonts[0], written[0]
    assert (font.texture, font.type, font.distance_range, font.size) == (raw["texture"], raw["type"],
                                                                       raw["distanceRange"], raw["size"])
    assert (font.width, font.height, font.metrics) == (raw["width"], raw["height"], raw["metrics"])
    assert len(font.glyphs["unicode"]) == raw["glyphs"]["count"]
    assert {chr(int(c)) for c in font.glyphs["unicode"]} >= {"H", "i"}
    node = next(i for i, n in enumerate(doc.json["nodes"]) if TEXT_NAME in n.get("extensions", {}))
    ext = doc.json["nodes"][node]["extensions"][TEXT_NAME]
    label = read_text(doc, node)
    assert (label.text, label.font_index, label.em_size, label.align) == ("Hi", 0, ext["emSize"], ext["align"])
    assert label.color == tuple(ext["color"]) and label.outline_width == 0.05
    assert label.font.texture == font.texture and label.font.name == font.name
    assert label.outline_color == tuple(ext["outline"]["color"])


def test_hair(tmp_path):
    import trimesh

    from baker.techniques.hair.extension import NAME, read, read_strands

    ball = tmp_path / "ball.glb"
    trimesh.creation.icosphere(subdivisions=2, radius=0.5).export(str(ball))
    out = tmp_path / "hair.glb"
    assert main(["hair", str(ball), "-o", str(out), "--guides", "12", "--children", "4", "--segments", "5",
                 "--length", "0.3", "-q"]) == 0
    doc = GltfDocument.load(out)
    mesh = next(m for m, mj in enumerate(doc.json["meshes"]) if any(NAME in p.get("extensions", {})
                                                                    for p in mj["primitives"]))
    prims = doc.json["meshes"][mesh]["primitives"]
    assert len(prims) == 2  # guides, then children
    guides, children = read(doc, mesh, 0), read(doc, mesh, 1)
    assert guides.strand_count == 12 and guides.guides_primitive is None
    assert children.strand_count == 48 and children.guides_primitive == 0
    for p, got in ((0, guides), (1, children)):
        ext, old = prims[p]["extensions"][NAME], read_strands(doc, mesh, p)
        assert got.vertices_per_strand == ext["verticesPerStrand"] == 6
        assert (got.root_width, got.tip_width) == (ext["rootWidth"], ext["tipWidth"])
        np.testing.assert_array_equal(got.positions.reshape(old["positions"].shape), old["positions"])
        np.testing.assert_array_equal(got.tangents.reshape(old["tangents"].shape), old["tangents"])
        np.testing.assert_array_equal(got.param, old["param"].reshape(-1))
        np.testing.assert_array_equal(got.ribbon_indices, old["ribbon"].reshape(-1))
        np.testing.assert_array_equal(got.width_scale, old["width_scale"].reshape(-1))
        assert got.material == prims[p].get("material")
    np.testing.assert_array_equal(children.guide_ids, read_strands(doc, mesh, 1)["guide_ids"])
    assert math.isclose(float(children.guide_weights.reshape(children.strand_count, -1).sum(1).mean()), 1.0,
                        rel_tol=1e-5)
    assert read(doc, 0, 0) is None  # the emitter


def test_hair_cards(tmp_path):
    import json

    from baker.techniques.cards.extension import NAME, read, read_material
    from techniques.cards_groom import make_groom, write_groom_usd

    curves, widths = make_groom(strands=200, clumps=8, seed=1)
    groom = write_groom_usd(tmp_path / "groom.usda", curves, widths)
    out = tmp_path / "cards.gltf"
    assert main(["cards", str(groom), "-o", str(out), "--cards", "8", "--atlas-size", "128", "-q"]) == 0
    doc = GltfDocument.load(out)
    raw = json.loads(out.read_text())
    ext = raw["meshes"][0]["primitives"][0]["extensions"][NAME]
    cards = read(doc, 0, 0)
    assert cards.card_count == ext["cardCount"] == len(cards.regions) == len(cards.card_first_index)
    assert cards.card_first_index[0] == 0 and (np.diff(cards.card_first_index) > 0).all()
    assert cards.groom["strandCount"] == 200 and cards.draw_order == "innerFirst"
    assert cards.clustering_error == ext["clusteringError"]
    material = read_material(doc, 0)
    mext = raw["materials"][0]["extensions"][NAME]
    assert (material.data_texture, material.flow_texture) == (mext["dataTexture"]["index"],
                                                            mext["flowTexture"]["index"])
    assert material.depth_range == mext["depthRange"] > 0 and material.data_channels["g"] == "rootToTip"
    # the base colour's coverage mip chain, keyed by its texture
    base = raw["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"]
    assert material.coverage_mips == {base: mext["coverageMips"][0]} and mext["coverageMips"][0]["levelCount"] == 8
    plain = baker.bake(SPOT, bakes=["curvature"], options={}).doc
    assert read(plain, 0, 0) is None and read_material(plain, 0) is None
