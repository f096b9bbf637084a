"""``baker cards``: hair cards from a dense groom (RTR4 14.7.1), checked against independent truth.

The groom is written by pxr directly (``cards_groom.py``: thousands of strands in clumps, some curly), never by
baker's grower. The written GLB is parsed here (JSON + BIN chunks), the atlas PNG decoded by Pillow, and every
geometric check measures the input curves against the card triangles with numpy written here: exact point-triangle
distances, texel lookups at the projected points, and silhouettes of strands and cards rasterised the same way.
"""
from __future__ import annotations

import contextlib
import io
import json
import struct
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from scipy.spatial import cKDTree

from baker.cli import main as cli_main
from baker.validate import validate_file
from conftest import assert_khronos_clean
from techniques.cards_groom import make_groom, write_groom_usd
from techniques.curly_groom import make_curly_groom
from techniques.cards_views import alpha_at, card_silhouette, coverage_image, strand_silhouette, view_basis

CARDS = 96
MESHES = Path("/work/shared/assets/meshes")  # as tests/browser.py
ATLAS = 1024


# ----------------------------------------------------------------------------------------------------- readers
def read_glb(path: Path):
    """(glTF JSON, accessor reader, image decoder) from the GLB chunks, without baker."""
    data = path.read_bytes()
    magic, version, total = struct.unpack_from("<4sII", data, 0)
    assert magic == b"glTF" and version == 2 and total == len(data)
    json_len, _ = struct.unpack_from("<I4s", data, 12)
    gltf = json.loads(data[20:20 + json_len])
    bin_len, bin_type = struct.unpack_from("<I4s", data, 20 + json_len)
    assert bin_type == b"BIN\x00"
    blob = data[28 + json_len:28 + json_len + bin_len]
    dtypes = {5126: "<f4", 5125: "<u4", 5123: "<u2", 5121: "u1"}
    sizes = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}

    def accessor(i):
        a = gltf["accessors"][i]
        view = gltf["bufferViews"][a["bufferView"]]
        n = sizes[a["type"]]
        arr = np.frombuffer(blob, dtypes[a["componentType"]], a["count"] * n,
                            view.get("byteOffset", 0) + a.get("byteOffset", 0))
        return arr.reshape(a["count"], n) if n > 1 else arr

    def image(texture):
        view = gltf["bufferViews"][gltf["images"][gltf["textures"][texture]["source"]]["bufferView"]]
        start = view.get("byteOffset", 0)
        return np.asarray(Image.open(io.BytesIO(blob[start:start + view["byteLength"]])))

    return gltf, accessor, image


def cards_from_glb(path: Path) -> dict:
    gltf, acc, image = read_glb(path)
    mesh = next(m for m in gltf["meshes"] if m.get("name") == "hair_cards")
    prim = mesh["primitives"][0]
    material = gltf["materials"][prim["material"]]
    ext = prim["extensions"]["BAKER_hair_cards"]
    return {"gltf": gltf, "positions": acc(prim["attributes"]["POSITION"]).astype(np.float64),
            "uv": acc(prim["attributes"]["TEXCOORD_0"]).astype(np.float64),
            "normals": acc(prim["attributes"]["NORMAL"]).astype(np.float64),
            "triangles": acc(prim["indices"]).astype(np.int64).reshape(-1, 3),
            "first": acc(ext["cardFirstIndex"]).astype(np.int64), "ext": ext, "material": material,
            "color": image(material["pbrMetallicRoughness"]["baseColorTexture"]["index"]),
            "data": image(material["extensions"]["BAKER_hair_cards"]["dataTexture"]["index"]),
            "flow": image(material["extensions"]["BAKER_hair_cards"]["flowTexture"]["index"])}


def ktx2_levels(blob: bytes) -> list:
    """The levels of an uncompressed RGBA8 KTX 2.0 file, level 0 first, read from the spec's header and level index
    (https://registry.khronos.org/KTX/specs/2.0/ktxspec.v2.html), without baker."""
    assert blob[:12] == bytes([0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A])
    vk_format, type_size, width, height, depth, layers, faces, count, scheme = struct.unpack_from("<9I", blob, 12)
    assert (vk_format, type_size, depth, layers, faces, scheme) == (37, 1, 0, 0, 1, 0)  # R8G8B8A8_UNORM, 2D
    levels = []
    for i in range(count):
        offset, length, _ = struct.unpack_from("<3Q", blob, 80 + 24 * i)
        h, w = max(1, height >> i), max(1, width >> i)
        assert length == w * h * 4
        levels.append(np.frombuffer(blob, np.uint8, length, offset).reshape(h, w, 4))
    return levels


def coverage(alpha, cutoff):
    """Fraction of texels passing the alpha test (8-bit alpha / 255 >= cutoff, compared in float32 as a GPU does)."""
    return float(np.mean(alpha.astype(np.float32) / np.float32(255) >= np.float32(cutoff)))


# -------------------------------------------------------------------------------------------- geometry, here
def closest_on_triangles(p, a, b, c):
    """Closest points of triangles (a, b, c) to points p (all (n, 3)): (distance, barycentrics (n, 3))."""
    ab, ac = b - a, c - a
    n = np.cross(ab, ac)
    nn = np.maximum((n * n).sum(1), 1e-300)
    # inside: the plane projection's barycentrics are all >= 0
    w = p - a
    v_ = (np.cross(w, ac) * n).sum(1) / nn
    w_ = (np.cross(ab, w) * n).sum(1) / nn
    bary = np.stack([1 - v_ - w_, v_, w_], 1)
    best = np.abs((w * n).sum(1)) / np.sqrt(nn)
    inside = (bary >= 0).all(1)
    best = np.where(inside, best, np.inf)
    out = np.where(inside[:, None], bary, 0.0)
    for (i, j) in ((0, 1), (1, 2), (0, 2)):
        q0, q1 = (a, b, c)[i], (a, b, c)[j]
        e = q1 - q0
        t = np.clip(((p - q0) * e).sum(1) / np.maximum((e * e).sum(1), 1e-300), 0, 1)
        d = np.linalg.norm(p - (q0 + t[:, None] * e), axis=1)
        better = d < best
        best = np.where(better, d, best)
        edge = np.zeros_like(bary)
        edge[:, i], edge[:, j] = 1 - t, t
        out = np.where(better[:, None], edge, out)
    return best, out


def nearest_card_points(points, cards, candidates=24):
    """For each point, the closest point over the card triangles: (distance, triangle, barycentrics). Candidate
    triangles: those owning the nearest samples of a dense barycentric grid on every triangle."""
    pos, tri = cards["positions"], cards["triangles"]
    grid = np.array([(i / 8, j / 8) for i in range(9) for j in range(9 - i)])
    bary = np.column_stack([1 - grid.sum(1), grid])
    samples = np.einsum("gk,tkd->tgd", bary, pos[tri]).reshape(-1, 3)
    owner = np.repeat(np.arange(len(tri)), len(grid))
    _, near = cKDTree(samples).query(points, k=candidates)
    best = np.full(len(points), np.inf)
    best_tri = np.zeros(len(points), np.int64)
    best_bary = np.zeros((len(points), 3))
    for k in range(candidates):
        t = owner[near[:, k]]
        d, b = closest_on_triangles(points, pos[tri[t, 0]], pos[tri[t, 1]], pos[tri[t, 2]])
        better = d < best
        best, best_tri = np.where(better, d, best), np.where(better, t, best_tri)
        best_bary = np.where(better[:, None], b, best_bary)
    return best, best_tri, best_bary


# ----------------------------------------------------------------------------------------------------- fixtures
@pytest.fixture(scope="module")
def groom(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cards")
    curves, widths = make_groom(strands=4000, clumps=120, seed=11)
    path = write_groom_usd(folder / "groom.usda", curves, widths)
    return {"path": path, "folder": folder, "curves": curves, "points": np.concatenate(curves),
            "mean_length": float(np.mean([np.linalg.norm(np.diff(c, axis=0), axis=1).sum() for c in curves]))}


@pytest.fixture(scope="module")
def baked(groom):
    out = {}
    for suffix in (".glb", ".usda"):
        path = groom["folder"] / f"cards{suffix}"
        with contextlib.redirect_stdout(io.StringIO()) as buffer:
            assert cli_main(["cards", str(groom["path"]), "-o", str(path), "--cards", str(CARDS),
                             "--atlas-size", str(ATLAS), "--format", "json"]) == 0
        out[suffix] = path
        out["summary" + suffix] = json.loads(buffer.getvalue())
    out["cards"] = cards_from_glb(out[".glb"])
    return out


@pytest.fixture(scope="module")
def projected(groom, baked):
    return nearest_card_points(groom["points"], baked["cards"])


# -------------------------------------------------------------------------------------------------------- tests
def test_strand_points_lie_near_a_card(groom, baked, projected):
    distance, _, _ = projected
    near = distance <= 0.05 * groom["mean_length"]
    assert near.mean() >= 0.90, near.mean()
    assert baked["cards"]["ext"]["cardCount"] == CARDS
    assert len(groom["curves"]) == baked["cards"]["ext"]["groom"]["strandCount"] == 4000


def test_projected_points_land_on_opaque_texels(baked, projected):
    cards = baked["cards"]
    _, tri, bary = projected
    uv = np.einsum("pk,pkd->pd", bary, cards["uv"][cards["triangles"][tri]])
    cutoff = cards["material"]["alphaCutoff"]
    assert cards["material"]["alphaMode"] == "MASK" and 0 < cutoff < 1
    passes = alpha_at(cards, uv) >= round(cutoff * 255)
    assert passes.mean() >= 0.80, passes.mean()
    # and the atlas is not simply opaque: most texels are cut
    assert (cards["color"][..., 3] >= round(cutoff * 255)).mean() < 0.6


@pytest.mark.parametrize("view", [(0, 0), (90, 10), (200, 35)])
def test_silhouettes_of_strands_and_cards_agree(groom, baked, view):
    basis = view_basis(*view)
    points = groom["points"]
    xy = np.stack([points @ basis[0], points @ basis[1]], 1)
    lo = xy.min(0) - 0.01
    span = float((xy.max(0) + 0.01 - lo).max())
    size, supersample = 160, 4
    strands = coverage_image(strand_silhouette(groom["curves"], basis, (lo, span), size * supersample), size)
    cards = coverage_image(card_silhouette(baked["cards"], basis, (lo, span), size * supersample,
                                           baked["cards"]["material"]["alphaCutoff"]), size)
    iou = (strands & cards).sum() / (strands | cards).sum()
    assert iou >= 0.8, iou


def test_inner_cards_are_drawn_first(groom, baked):
    cards = baked["cards"]
    roots = cKDTree(np.stack([c[0] for c in groom["curves"]]))
    first = list(cards["first"]) + [3 * len(cards["triangles"])]
    depth = []
    for a, b in zip(first[:-1], first[1:]):
        vertices = np.unique(cards["triangles"][a // 3: b // 3])
        centre = 0.5 * (cards["positions"][vertices[0::2]] + cards["positions"][vertices[1::2]])
        depth.append(roots.query(centre)[0].mean())
    assert np.all(np.diff(depth) >= -1e-6), "cards are not ordered inner first"
    assert cards["ext"]["drawOrder"] == "innerFirst"


def test_card_faces_and_flow_agree_with_the_strands(groom, baked, projected):
    """The flow texture, decoded in the card's tangent frame, points along the strand at its projected texel."""
    cards = baked["cards"]
    gltf, acc, _ = read_glb(baked[".glb"])
    tangents = acc(gltf["meshes"][0]["primitives"][0]["attributes"]["TANGENT"]).astype(np.float64)
    assert np.allclose(tangents[:, 3], -1.0)
    _, tri, bary = projected
    corners = cards["triangles"][tri]
    n = np.einsum("pk,pkd->pd", bary, cards["normals"][corners])
    t = np.einsum("pk,pkd->pd", bary, tangents[corners, :3])
    b = np.cross(n, t) * -1.0
    uv = np.einsum("pk,pkd->pd", bary, cards["uv"][corners])
    size = cards["flow"].shape[0]
    texel = np.clip(np.floor(uv * size).astype(np.int64), 0, size - 1)
    code = cards["flow"][texel[:, 1], texel[:, 0]].astype(np.float64) / 255.0 * 2.0 - 1.0
    flow = code[:, :1] * t + code[:, 1:2] * b + code[:, 2:3] * n
    direction = np.concatenate([np.gradient(c, axis=0) for c in groom["curves"]])
    cos = np.abs((flow * direction).sum(1)) / np.maximum(np.linalg.norm(flow, axis=1) *
                                                        np.linalg.norm(direction, axis=1), 1e-300)
    opaque = alpha_at(cards, uv) >= 128
    assert np.median(cos[opaque]) > 0.85, np.median(cos[opaque])
    # the root-to-tip channel rises from root to tip along the strands
    g = cards["data"][texel[:, 1], texel[:, 0], 1].astype(np.float64) / 255.0
    param = np.concatenate([np.linspace(0, 1, len(c)) for c in groom["curves"]])
    assert np.corrcoef(g[opaque], param[opaque])[0, 1] > 0.8


def test_glb_validates_and_inspect_lists_cards(baked, capsys):
    report = validate_file(baked[".glb"], khronos=False)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert report["issues"]["numWarnings"] == 0, report["issues"]["messages"]
    assert_khronos_clean(baked[".glb"])
    capsys.readouterr()
    assert cli_main(["inspect", str(baked[".glb"]), "--format", "json"]) == 0
    text = capsys.readouterr().out
    assert "BAKER_hair_cards" in text and f'"cards": {CARDS}' in text
    (row,) = json.loads(text)["coverageMips"]
    assert row["place"].endswith("/extensions/BAKER_hair_cards") and row["size"] == [ATLAS, ATLAS]
    assert len(row["coverage"]) == row["levels"] == int(np.log2(ATLAS)) + 1
    assert row["coverage"][0] == pytest.approx(coverage(baked["cards"]["color"][..., 3], row["alphaCutoff"]))


def test_usd_output_read_by_pxr(baked):
    from pxr import Usd, UsdGeom, UsdShade

    stage = Usd.Stage.Open(str(baked[".usda"]))
    meshes = [p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)]
    assert len(meshes) == 1
    mesh = UsdGeom.Mesh(meshes[0])
    assert len(mesh.GetPointsAttr().Get()) == len(baked["cards"]["positions"])
    material, _ = UsdShade.MaterialBindingAPI(meshes[0]).ComputeBoundMaterial()
    surface = material.ComputeSurfaceSource()[0]
    assert surface.GetInput("opacityThreshold").Get() == pytest.approx(baked["cards"]["material"]["alphaCutoff"])
    opacity = surface.GetInput("opacity").GetConnectedSources()[0][0]
    texture = UsdShade.Shader(opacity.source.GetPrim())
    file = Path(baked[".usda"]).parent / texture.GetInput("file").Get().path
    assert np.array_equal(np.asarray(Image.open(file))[..., 3], baked["cards"]["color"][..., 3])
    scope = next(p for p in stage.Traverse() if p.HasAttribute("baker:hair_cards:cardCount"))
    assert scope.GetAttribute("baker:hair_cards:cardCount").Get() == CARDS
    regions = np.asarray(scope.GetAttribute("baker:hair_cards:regions").Get())
    gltf, acc, _ = read_glb(baked[".glb"])
    assert np.allclose(regions, acc(baked["cards"]["ext"]["regions"]))
    outputs = [o.GetBaseName() for o in material.GetOutputs()]
    assert any("dataTexture" in o for o in outputs) and any("flowTexture" in o for o in outputs)
    # the base colour's coverage mip chain: a KTX2 file beside the PNGs, byte-equal to the GLB's
    prim = material.GetPrim()
    ktx2 = Path(prim.GetAttribute("baker:hair_cards:coverageMips:_0:file").Get().resolvedPath)
    png = Path(prim.GetAttribute("baker:hair_cards:coverageMips:_0:image").Get().resolvedPath)
    assert ktx2.suffix == ".ktx2" and ktx2.parent == png.parent and png == file.resolve()
    (entry,) = baked["cards"]["material"]["extensions"]["BAKER_hair_cards"]["coverageMips"]
    assert ktx2.read_bytes() == acc(entry["accessor"]).tobytes()
    assert prim.GetAttribute("baker:hair_cards:coverageMips:_0:levelCount").Get() == entry["levelCount"]
    # no glTF index in the stage; base colour (sRGB) and the data and flow textures (raw) reachable with the GLB's
    # pixels; pxr's validators find no error
    from baker.gltf.document import GltfDocument
    from usd_checks import assert_usd_matches_gltf, validation_errors

    assert assert_usd_matches_gltf(baked[".usda"], GltfDocument.load(baked[".glb"])) == {"core": 1, "baker": 2}
    assert validation_errors(baked[".usda"]) == []


# ------------------------------------------------------------------------------------ coverage-preserving mips
def box_chain(rgba):
    """The plain mip chain of a square power-of-two RGBA8 image: each level the 2 x 2 mean of the one above
    (alpha and colour averaged as stored, rounded): what mipmapping the PNG gives."""
    levels, level = [rgba], rgba.astype(np.float64)
    while level.shape[0] > 1:
        h, w = level.shape[0] // 2, level.shape[1] // 2
        level = level.reshape(h, 2, w, 2, 4).mean(axis=(1, 3))
        levels.append(np.rint(level).astype(np.uint8))
    return levels


def test_atlas_chain_keeps_alpha_test_coverage_down_to_8x8(baked):
    """The base colour's chain, read from the GLB and decoded here: level 0 is the PNG atlas, the full chain down to
    1 x 1, and every level down to 8 x 8 passes the alpha test on level 0's fraction of texels within 10% (or one
    texel); the box chain of the same atlas, built here, loses it."""
    cards = baked["cards"]
    gltf, acc, _ = read_glb(baked[".glb"])
    material = cards["material"]
    (entry,) = material["extensions"]["BAKER_hair_cards"]["coverageMips"]
    assert entry["texture"] == material["pbrMetallicRoughness"]["baseColorTexture"]["index"]
    assert entry["mimeType"] == "image/ktx2" and entry["alphaCutoff"] == material["alphaCutoff"]
    accessor = gltf["accessors"][entry["accessor"]]
    assert accessor["componentType"] == 5121 and accessor["type"] == "SCALAR"
    # the KTX2 starts at level 1 (firstLevel): level 0 is the PNG atlas, not stored twice
    stored = ktx2_levels(acc(entry["accessor"]).tobytes())
    assert entry["firstLevel"] == 1 and stored[0].shape == (ATLAS // 2, ATLAS // 2, 4)
    levels = [cards["color"], *stored]
    assert len(levels) == entry["levelCount"] == int(np.log2(ATLAS)) + 1 and levels[-1].shape == (1, 1, 4)
    cutoff = material["alphaCutoff"]

    def off(chain):
        """(level, coverage) of the levels of at least 8 x 8 more than 10% (or one texel) from level 0's."""
        target = coverage(chain[0][..., 3], cutoff)
        return [(i, coverage(lv[..., 3], cutoff)) for i, lv in enumerate(chain) if lv.shape[0] >= 8 and
                abs(coverage(lv[..., 3], cutoff) - target) > max(0.1 * target, 1 / lv[..., 3].size)]

    target = coverage(levels[0][..., 3], cutoff)
    assert 0.02 < target < 0.6 and entry["coverage"] == pytest.approx(target)
    print("chain coverage per level", [round(coverage(lv[..., 3], cutoff), 4) for lv in levels])
    assert off(levels) == []
    box = off(box_chain(cards["color"]))
    print("box chain: levels off", box)
    assert len(box) >= 3 and box[-1][1] < 0.5 * target
    # colour: where the chain passes the test, it shows the strands' colour (premultiplied filtering), not the
    # dark or empty texels between them: the mean colour of passing texels stays near level 0's
    def passing_mean(level):
        keep = level[..., 3].astype(np.float32) / 255 >= cutoff
        return level[..., :3][keep].astype(np.float64).mean(0)
    assert np.abs(passing_mean(levels[4]) - passing_mean(levels[0])).max() < 20


def test_coverage_mips_read_back_and_checked(baked, tmp_path):
    """read_material() returns the chain entry; the semantic check catches a chain whose level 0 is not the atlas,
    a box chain that loses coverage (warning), and a chain made for another cutoff (warning)."""
    from baker.texels.alpha_mips import read_coverage_mips
    from baker.gltf.document import GltfDocument
    from baker.gltf.ktx2 import encode_ktx2
    from baker.techniques.cards.extension import read_material

    doc = GltfDocument.load(baked[".glb"])
    index = baked["cards"]["gltf"]["meshes"][0]["primitives"][0]["material"]
    read = read_material(doc, index)
    (entry,) = doc.json["materials"][index]["extensions"]["BAKER_hair_cards"]["coverageMips"]
    assert read.coverage_mips == {entry["texture"]: entry}
    levels = read_coverage_mips(doc, entry)
    _, acc, _ = read_glb(baked[".glb"])
    stored = ktx2_levels(acc(entry["accessor"]).tobytes())
    assert len(levels) == len(stored) + 1 and all(np.array_equal(a, b) for a, b in zip(levels[1:], stored))

    def codes_of(levels, **changes):
        broken = GltfDocument.load(baked[".glb"])
        (e,) = broken.json["materials"][index]["extensions"]["BAKER_hair_cards"]["coverageMips"]
        e["accessor"] = broken.add_accessor(np.frombuffer(encode_ktx2(levels), np.uint8), target=None)
        e["firstLevel"] = 0  # every level in the KTX2, level 0 included
        e.update(changes)
        out = tmp_path / f"broken{len(list(tmp_path.iterdir()))}.glb"
        broken.save(out)
        return {m["code"] for m in validate_file(out, khronos=False)["issues"]["messages"]}

    shifted = [np.roll(levels[0], 1, axis=1)] + levels[1:]
    assert "BAKER_COVERAGE_MIPS_BASE" in codes_of(shifted)
    assert "BAKER_COVERAGE_MIPS_COVERAGE" in codes_of(box_chain(levels[0]))
    assert "BAKER_HAIR_CARDS_COVERAGE_MIPS" in codes_of(levels, alphaCutoff=0.25)
    assert "BAKER_HAIR_CARDS_COVERAGE_MIPS" in codes_of(levels, texture=entry["texture"] + 1)


# ------------------------------------------------------------------------------------------- kernel, analytic
def test_flat_clump_card_lies_in_its_plane_and_straight_clump_has_one_quad():
    from baker.techniques.cards.ribbon import build_card

    v = 32
    curve = np.stack([np.zeros(v), -np.linspace(0, 1, v), np.zeros(v)], 1)  # straight down
    spread = np.linspace(-0.05, 0.05, 9)
    members = curve[None] + spread[:, None, None] * np.array([1.0, 0.0, 0.0])
    card = build_card(curve, members, np.array([0.0, 0.0, 1.0]), coverage=1.0, min_half_width=1e-4,
                      tolerance=0.005, max_segments=24)
    assert np.allclose(np.abs(card.width_axis[:, 0]), 1.0)  # spread along x: the card's width
    assert np.allclose(card.normal, [0.0, 0.0, 1.0])  # faces out of the scalp (+z)
    assert np.allclose(card.half_width, 0.05)
    assert list(card.kept) == [0, v - 1]


def test_segments_follow_curvature():
    from baker.techniques.cards.ribbon import build_card

    v = 64
    t = np.linspace(0, 1, v)
    curl = np.stack([0.05 * np.cos(12 * t), -t, 0.05 * np.sin(12 * t)], 1)
    gentle = np.stack([0.05 * t ** 2, -t, np.zeros(v)], 1)
    kw = dict(coverage=1.0, min_half_width=1e-3, tolerance=0.005, max_segments=40)
    n_curl = len(build_card(curl, curl[None], np.array([0.0, 0.0, 1.0]), **kw).kept) - 1
    n_gentle = len(build_card(gentle, gentle[None], np.array([0.0, 0.0, 1.0]), **kw).kept) - 1
    assert n_gentle <= 4 < 16 <= n_curl


def test_fit_splits_two_sheets_one_card_cannot_cover():
    """Two parallel sheets of straight strands, 0.2 x their length apart along z, roots interleaved in x: the first
    clusters mix the sheets, and the fit splits them (by depth along the card normal) until every point lies on
    its card."""
    from baker.techniques.cards.fit import fit_clumps

    v, per_sheet = 16, 150
    x = np.linspace(-0.3, 0.3, per_sheet)
    down = -np.linspace(0.0, 1.0, v)
    sheets = [np.stack([np.broadcast_to(x[:, None], (per_sheet, v)), np.broadcast_to(down, (per_sheet, v)),
                        np.full((per_sheet, v), z)], axis=2) for z in (0.0, 0.2)]
    strands = np.concatenate(sheets)
    lengths = np.ones(len(strands))
    fit = fit_clumps(strands, lengths, target=1.0, locality=1.0, seed=0,
                     card_options=dict(coverage=1.0, min_half_width=1e-3, tolerance=0.005, max_segments=8))
    assert fit.rounds >= 1 and fit.near == 1.0
    assert fit.clumps.count <= 2 * fit.first_count  # a split per mixed clump, nothing more
    # the split itself: members at two depths (with noise) part exactly; members of one depth profile do not
    from baker.techniques.cards.clumps import split_by_depth

    rng = np.random.default_rng(4)
    group = rng.random(40) < 0.3
    depth = np.where(group[:, None], 0.1, -0.05) * np.linspace(1.0, 0.5, v) + rng.normal(0, 0.01, (40, v))
    side = split_by_depth(depth)
    assert np.array_equal(side, group) or np.array_equal(~side, group)
    assert split_by_depth(np.zeros((5, v))) is None and split_by_depth(depth[:1]) is None


@pytest.fixture(scope="module")
def curly(tmp_path_factory):
    """The held-out groom: 3000 strands in 30 wide, curly clumps (curly_groom.py), not the groom of the tests above."""
    folder = tmp_path_factory.mktemp("curly")
    curves, widths = make_curly_groom(strands=3000, clumps=30, seed=5)
    path = write_groom_usd(folder / "curly.usda", curves, widths)
    out = folder / "cards.glb"
    with contextlib.redirect_stdout(io.StringIO()) as buffer:
        assert cli_main(["cards", str(path), "-o", str(out), "--format", "json"]) == 0
    return {"curves": curves, "points": np.concatenate(curves), "path": path, "cards": cards_from_glb(out),
            "summary": json.loads(buffer.getvalue()),
            "mean_length": float(np.mean([np.linalg.norm(np.diff(c, axis=0), axis=1).sum() for c in curves]))}


def test_default_count_holds_a_curly_wide_clump_groom(curly):
    """No --cards: the count comes from the groom, and the cards hold 90 % of the strand points within 5 % of the
    mean strand length (distances measured here, to any card) and match the strands' silhouettes."""
    distance, _, _ = nearest_card_points(curly["points"], curly["cards"])
    near = (distance <= 0.05 * curly["mean_length"]).mean()
    assert near >= 0.90, near
    summary = curly["summary"]
    assert summary["cardCountFrom"]["source"] == "groom" and summary["cardCountFrom"]["splitRounds"] >= 1
    assert summary["cards"] == curly["cards"]["ext"]["cardCount"] <= 3000 // 8
    for view in [(0, 0), (90, 10), (200, 35)]:
        basis = view_basis(*view)
        xy = np.stack([curly["points"] @ basis[0], curly["points"] @ basis[1]], 1)
        lo = xy.min(0) - 0.01
        box = (lo, float((xy.max(0) + 0.01 - lo).max()))
        strands = coverage_image(strand_silhouette(curly["curves"], basis, box, 640), 160)
        cards = coverage_image(card_silhouette(curly["cards"], basis, box, 640,
                                               curly["cards"]["material"]["alphaCutoff"]), 160)
        iou = (strands & cards).sum() / (strands | cards).sum()
        assert iou >= 0.8, (view, iou)


def test_fitted_cards_beat_one_clustering_of_the_same_count(curly):
    """Splitting where a card cannot cover the cross-section holds more points than the k-medoids alone at the
    same card count, and so do the refinement rounds at a fixed count (strands moved to the card holding them
    best); an explicit --cards is used exactly as given."""
    from baker.techniques.cards.kernel import make_cards
    from baker.techniques.cards.options import CardsOptions
    from baker.readers import read_groom
    from baker.readers.groom import clean_groom
    from baker.techniques.hair.guide_solver import resample_strands

    groom = clean_groom(read_groom(curly["path"]), curly["path"])
    strands, lengths, widths = resample_strands(groom.points, groom.counts, 32, groom.widths)
    fitted = make_cards(strands, lengths, widths, CardsOptions(atlas_size=256))
    count = fitted.card_count
    assert count == curly["summary"]["cards"]  # the atlas size does not change the count
    alone = make_cards(strands, lengths, widths, CardsOptions(cards=count, atlas_size=256, refine=0))
    fixed = make_cards(strands, lengths, widths, CardsOptions(cards=count, atlas_size=256))
    assert fixed.card_count == alone.card_count == count and fixed.stats["cardCountFrom"] == {"source": "option"}
    near = {name: r.stats["cardDistance"]["within5Percent"] for name, r in
            (("fitted", fitted), ("alone", alone), ("refined", fixed))}
    print(f"{count} cards: share of points within 5 %", near)
    assert near["fitted"] > near["alone"] and near["refined"] > near["alone"] + 0.01


def test_fixed_budget_holds_the_held_out_groom(curly, tmp_path):
    """A fixed budget: --cards 60 for the 3000 strands (50 strands a card, as 120 cards for 6,000) holds 90 % of
    the strand points within 5 % of the mean strand length, measured here to the nearest card surface; the summary
    states the share against --fit (met), and the JSON's share is the one to the strand's own card (never more
    than to the nearest card)."""
    out = tmp_path / "budget.glb"
    with contextlib.redirect_stdout(io.StringIO()) as buffer:
        assert cli_main(["cards", str(curly["path"]), "-o", str(out), "--cards", "60", "--format", "json"]) == 0
    summary = json.loads(buffer.getvalue())
    cards = cards_from_glb(out)
    assert cards["ext"]["cardCount"] == summary["cards"] == 60
    distance, _, _ = nearest_card_points(curly["points"], cards)
    near = (distance <= 0.05 * curly["mean_length"]).mean()
    print("60 cards: share within 5 % of the nearest card", near, "of its own card", summary["fit"])
    assert near >= 0.90, near
    assert summary["fit"]["met"] and summary["fit"]["within5Percent"] >= 0.90
    assert summary["fit"]["within5Percent"] <= near + 0.002  # own card (resampled points) vs nearest (input points)


def grown_strands(path: Path) -> list:
    """The child strands of a ``baker hair`` GLB (the groom ``baker cards`` reads), parsed here: the ``hair`` mesh's
    second primitive, ``verticesPerStrand`` points a strand (BAKER_hair)."""
    gltf, acc, _ = read_glb(path)
    children = next(m for m in gltf["meshes"] if m["name"] == "hair")["primitives"][1]
    v = children["extensions"]["BAKER_hair"]["verticesPerStrand"]
    return list(acc(children["attributes"]["POSITION"]).astype(np.float64).reshape(-1, v, 3))


def test_fixed_budget_on_a_grown_groom(tmp_path):
    """A groom grown by ``baker hair`` (round guide bundles: clumped, curly children) on the top of suzanne's head,
    3000 strands at --cards 60 (50 strands a card, as 120 cards for 6,000). Measured here: every input point's
    distance to the nearest card surface against 5 % of its OWN strand's length (the issue's wording) and of the
    mean length (the same here: the grower gives every strand one length). The cards do not reach the 90 % target
    on this groom (a flat card cannot hold a round guide bundle thicker than the tolerance: README, hair cards);
    this checks the share they do reach and that the summary says the target is missed."""
    import trimesh

    head = trimesh.load(MESHES / "suzanne.obj", force="mesh")
    lo, hi = head.bounds
    top = (head.face_normals[:, 1] > 0.2) & (head.triangles_center[:, 1] > lo[1] + 0.55 * (hi[1] - lo[1]))
    head.submesh([np.flatnonzero(top)], append=True).export(tmp_path / "top.obj")
    grown = tmp_path / "grown.glb"
    assert cli_main(["hair", str(tmp_path / "top.obj"), "-o", str(grown), "--guides", "150", "--children", "20",
                     "--seed", "5", "--curl-amplitude", "0.03", "--curl-frequency", "2", "--clump", "0.5",
                     "--segments", "24", "-q"]) == 0
    curves = grown_strands(grown)
    assert len(curves) == 3000
    out = tmp_path / "cards.glb"
    with contextlib.redirect_stdout(io.StringIO()) as buffer:
        assert cli_main(["cards", str(grown), "-o", str(out), "--cards", "60", "--atlas-size", "256",
                         "--format", "json"]) == 0
    summary = json.loads(buffer.getvalue())
    cards = cards_from_glb(out)
    assert cards["ext"]["cardCount"] == 60
    lengths = np.array([np.linalg.norm(np.diff(c, axis=0), axis=1).sum() for c in curves])
    distance, _, _ = nearest_card_points(np.concatenate(curves), cards)
    own = (distance <= 0.05 * np.repeat(lengths, [len(c) for c in curves])).mean()
    mean = (distance <= 0.05 * lengths.mean()).mean()
    print("grown groom, 60 cards: within 5 % of the own strand length", own, "of the mean length", mean,
          "summary", summary["fit"])
    # 0.675 (own card 0.574) before the cards followed their members' sheet and roots; 0.696 (0.601) now
    assert own >= 0.69 and mean >= 0.69, (own, mean)
    assert not summary["fit"]["met"] and summary["fit"]["within5Percent"] <= mean + 0.002


# -------------------------------------------------------------------------------------- formats, bytes, errors
def test_every_groom_format_and_same_seed_same_bytes(tmp_path):
    curves, widths = make_groom(strands=400, clumps=16, seed=5)
    src = write_groom_usd(tmp_path / "small.usda", curves, widths)
    args = ["--cards", "12", "--atlas-size", "256", "--seed", "3", "-q"]
    outs = []
    for k in range(2):
        out = tmp_path / f"o{k}.glb"
        assert cli_main(["cards", str(src), "-o", str(out), *args]) == 0
        outs.append(out.read_bytes())
    assert outs[0] == outs[1]
    usd = []
    for k in range(2):
        (tmp_path / f"u{k}").mkdir()
        out = tmp_path / f"u{k}" / "cards.usda"
        assert cli_main(["cards", str(src), "-o", str(out), *args]) == 0
        usd.append({p.relative_to(out.parent).as_posix(): p.read_bytes() for p in sorted(out.parent.rglob("*"))
                    if p.is_file()})
    assert usd[0] == usd[1] and len(usd[0]) == 5  # the stage, its three textures and the base colour's KTX2
    # --coverage-mips false: no chain, nothing else changes
    plain = tmp_path / "plain.glb"
    assert cli_main(["cards", str(src), "-o", str(plain), *args, "--coverage-mips", "false"]) == 0
    gltf, _, _ = read_glb(plain)
    assert "coverageMips" not in gltf["materials"][0]["extensions"]["BAKER_hair_cards"]
    assert len(gltf["accessors"]) == len(read_glb(tmp_path / "o0.glb")[0]["accessors"]) - 1
    # the same groom as glTF BAKER_hair and TressFX (through baker guides), and a .gltf output
    for suffix in (".glb", ".tfx"):
        converted = tmp_path / f"groom{suffix}"
        assert cli_main(["guides", str(src), "-o", str(converted), "--guides", "20", "-q"]) == 0
        out = tmp_path / f"from{suffix[1:]}.gltf"
        assert cli_main(["cards", str(converted if suffix == ".glb" else tmp_path / "groom.children.tfx"),
                         "-o", str(out), *args]) == 0
        doc = json.loads(out.read_text())
        assert doc["meshes"][0]["primitives"][0]["extensions"]["BAKER_hair_cards"]["groom"]["strandCount"] == 400
        assert validate_file(out, khronos=False)["issues"]["numErrors"] == 0


@pytest.mark.parametrize("case", ["missing", "suffix", "atlas", "counts", "too_many"])
def test_bad_input_one_line_exit_2(tmp_path, capsys, case):
    curves, widths = make_groom(strands=60, clumps=4, seed=2)
    src = write_groom_usd(tmp_path / "g.usda", curves, widths)
    out = tmp_path / "o.glb"
    args = ["cards", str(src), "-o", str(out)]
    if case == "missing":
        args[1] = str(tmp_path / "nothing.usda")
    elif case == "suffix":
        out = tmp_path / "o.obj"
        args[3] = str(out)
    elif case == "atlas":
        args += ["--atlas-size", "1000"]
    elif case == "counts":
        src.write_text('#usda 1.0\ndef BasisCurves "c" {\n    int[] curveVertexCounts = [3, 5]\n'
                       '    point3f[] points = [(0, 0, 0), (0, 1, 0), (0, 2, 0)]\n}\n')
    elif case == "too_many":
        args += ["--cards", "60", "--atlas-size", "64", "--padding", "8"]
    capsys.readouterr()
    assert cli_main(args) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert not out.exists()


def test_validate_reports_broken_card_layouts(tmp_path):
    """The semantic check catches what the schema cannot: a region outside [0, 1] or upside down, first indices
    that do not ascend, a non-MASK material."""
    curves, widths = make_groom(strands=120, clumps=6, seed=4)
    src = write_groom_usd(tmp_path / "g.usda", curves, widths)
    out = tmp_path / "c.gltf"
    assert cli_main(["cards", str(src), "-o", str(out), "--cards", "6", "--atlas-size", "128", "-q"]) == 0
    assert validate_file(out, khronos=False)["issues"]["numErrors"] == 0
    gltf = json.loads(out.read_text())
    ext = gltf["meshes"][0]["primitives"][0]["extensions"]["BAKER_hair_cards"]
    bin_path = out.parent / gltf["buffers"][0]["uri"]
    blob = bytearray(bin_path.read_bytes())

    def offset(accessor):
        a = gltf["accessors"][accessor]
        return gltf["bufferViews"][a["bufferView"]].get("byteOffset", 0) + a.get("byteOffset", 0)

    struct.pack_into("<4f", blob, offset(ext["regions"]), 0.5, 0.5, 0.25, 1.5)  # u1 < u0 and v1 > 1
    struct.pack_into("<2I", blob, offset(ext["cardFirstIndex"]), 0, 0)  # not ascending
    bin_path.write_bytes(bytes(blob))
    gltf["materials"][0]["alphaMode"] = "BLEND"
    out.write_text(json.dumps(gltf))
    codes = {m["code"] for m in validate_file(out, khronos=False)["issues"]["messages"]}
    assert {"BAKER_HAIR_CARDS_REGIONS", "BAKER_HAIR_CARDS_FIRST_INDEX", "BAKER_HAIR_CARDS_ALPHA_MODE"} <= codes, codes
