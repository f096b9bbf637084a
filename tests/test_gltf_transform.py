"""Baked assets survive glTF-Transform (dedup, flatten, resample, prune, sparse) with our extension classes.

Every BAKER_* extension (and EXT_mesh_primitive_edge_visibility) is baked, the file goes through
runtime-shaders/gltf-transform/test/roundtrip.mjs, and each extension's JSON is compared with the original with its
references resolved to data: accessors by their values, textures by image bytes, sampler and UV set, primitives by
their vertex data (prune and dedup renumber accessors, textures and samplers, so indices are not compared). The
result must pass `baker validate` and Khronos' validator. A control run without our classes shows the loss.
"""
from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import baker
from baker import validate
from baker.cli import main as baker_main
from baker.gltf.document import GltfDocument
from baker.pipeline import save
from conftest import assert_khronos_clean

PACKAGE = Path(__file__).parents[1] / "runtime-shaders" / "gltf-transform"
SPOT = Path(__file__).parents[1] / "examples" / "spot" / "spot.obj"
FONT = Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
EDGE_VISIBILITY = "EXT_mesh_primitive_edge_visibility"

# Where each extension references other glTF objects; '*' = any index. The classes under test do not keep such a
# list: they read runtime-shaders/gltf-transform/src/references.js, generated from the schemas by
# tools/references.mjs. This table is kept by hand on purpose, as the test's independent statement of what the
# schemas mean: test_reference_table_matches_the_schemas checks the generated table against it, so a schema whose
# reference does not follow the convention the generator reads (e.g. an accessor index described without
# "Accessor") fails there instead of silently losing its reference in the classes and in this comparison alike.
REFS = {
    "BAKER_curvature": {"curvatureTexture": "texture"},
    "BAKER_skin_lut": {"lutTexture": "texture", "penumbraTexture": "texture", "curvatureTexture": "texture"},
    "BAKER_tonal_art_map": {"levels/*/textures/*": "texture", "levels/*/texture": "texture"},
    "BAKER_toon_ramp": {"rampTexture": "texture"},
    "BAKER_caustics": {"frameTextures/*": "texture"},
    "BAKER_hair_cards": {"dataTexture": "texture", "flowTexture": "texture", "regions": "accessor",
                         "cardFirstIndex": "accessor", "coverageMips/*/texture": "texture-index",
                         "coverageMips/*/accessor": "accessor"},
    "BAKER_normal_blur": {"diffuseNormalTextures/*": "texture", "smoothedNormalTexture": "texture",
                          "stretchTexture": "texture"},
    "BAKER_edges": {"edges": "accessor", "oppositeVertices": "accessor", "flags": "accessor",
                    "dihedralAngles": "accessor", "wireframeMask": "accessor", "fins": "primitive",
                    "finsOf": "primitive"},
    EDGE_VISIBILITY: {"visibility": "accessor", "silhouetteMates": "accessor", "lineStrings/*/indices": "accessor",
                      "lineStrings/*/material": "material"},  # baker writes no lineStrings
    "BAKER_hair": {"widthScale": "accessor", "ribbonIndices": "accessor", "guides/ids": "accessor",
                   "guides/weights": "accessor", "guides/primitive": "primitive", "rootBinding/primitives": "accessor",
                   "rootBinding/triangles": "accessor", "rootBinding/barycentrics": "accessor"},
    "BAKER_fur": {"shellTextures/*": "texture", "finTexture": "texture", "finsOf": "primitive",
                  "fins/*": "mesh-primitive", "coverageMips/*/texture": "texture-index",
                  "coverageMips/*/accessor": "accessor"},
    "BAKER_glyph_atlas": {"fonts/*/texture": "texture-index", "fonts/*/glyphs/unicode": "accessor",
                          "fonts/*/glyphs/advance": "accessor", "fonts/*/glyphs/planeBounds": "accessor",
                          "fonts/*/glyphs/atlasBounds": "accessor", "fonts/*/glyphs/glyphIndex": "accessor",
                          "fonts/*/glyphs/face": "accessor", "fonts/*/kerning/pairs": "accessor",
                          "fonts/*/kerning/advance": "accessor"},
    "BAKER_text": {"glyphs/glyph": "accessor", "glyphs/position": "accessor"},
    "BAKER_thickness": {"thicknessTexture": "texture"},
    "BAKER_hair_shading": {"tables/*/longitudinal/accessor": "accessor", "tables/*/azimuthal/accessor": "accessor",
                           "tables/*/dualScattering/accessor": "accessor"},
}
SAMPLER_DEFAULTS = {"wrapS": 10497, "wrapT": 10497}


def _require_package():
    missing = shutil.which("node") is None or not (PACKAGE / "node_modules" / "@gltf-transform" / "core").is_dir()
    if missing:
        if os.environ.get("CI", "").lower() in ("1", "true", "yes"):
            pytest.fail("glTF-Transform is required in CI (scripts/install-node-tools installs it)")
        pytest.skip("node or @gltf-transform not installed (run scripts/install-node-tools)")


def _node_tool(*args):
    result = subprocess.run(["node", str(PACKAGE / "tools" / "references.mjs"), *args], capture_output=True, text=True,
                            timeout=60)
    return result


def _transform(src, out, control=False):
    env = dict(os.environ, BAKER_GLTF_TRANSFORM_CONTROL="1" if control else "0")
    result = subprocess.run(["node", str(PACKAGE / "test" / "roundtrip.mjs"), str(src), str(out)], env=env,
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr


# ------------------------------------------------------------------------------------------------ assets
def _write_sphere_obj(path: Path, radius=0.5, rings=10, segments=16):
    """A small UV sphere (poles shared) as OBJ, outward counter-clockwise faces."""
    theta = np.linspace(0, math.pi, rings + 1)[1:-1]
    phi = np.linspace(0, 2 * math.pi, segments, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    ring = np.stack([np.sin(t) * np.cos(p), np.cos(t), -np.sin(t) * np.sin(p)], -1).reshape(-1, 3) * radius
    verts = np.vstack([[0, radius, 0], ring, [0, -radius, 0]])
    idx = lambda r, s: 1 + r * segments + s % segments  # 0-based vertex index of ring r, segment s
    faces = [(0, idx(0, s), idx(0, s + 1)) for s in range(segments)]
    for r in range(rings - 2):
        for s in range(segments):
            a, b, c, d = idx(r, s), idx(r, s + 1), idx(r + 1, s), idx(r + 1, s + 1)
            faces += [(a, c, b), (b, c, d)]
    last = len(verts) - 1
    faces += [(idx(rings - 2, s), last, idx(rings - 2, s + 1)) for s in range(segments)]
    lines = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in verts]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    path.write_text("\n".join(lines) + "\n")


@pytest.fixture(scope="module")
def assets(tmp_path_factory):
    folder = tmp_path_factory.mktemp("gltf_transform")
    # two spots: `baker validate` checks material-level bakes (thickness, curvature, skin, TAM) on every triangle
    # primitive drawn with the material, fin primitives included, so it reports the fins of edges/fur as lacking
    # _THICKNESS etc. even straight out of `baker bake` (see the report); baked separately, each file validates
    spot = folder / "spot.glb"
    save(baker.bake(SPOT, bakes=["thickness", "curvature", "skin", "tam", "toon"], options={
        "thickness": {"rays": 8, "texture_size": 64},
        "curvature": {"rings": 1, "smoothing": 1, "per_texel": True, "texture_size": 64},
        "skin": {"width": 32, "height": 32, "samples": 16, "penumbra_size": 16},
        "tam": {"size": 32, "levels": 2, "candidates": 2},
        "toon": {"width": 16},
    }), spot)
    fins = folder / "spot_fins.glb"
    save(baker.bake(SPOT, bakes=["edges", "fur", "caustics"], options={
        "edges": {"fins": True, "opposite_vertices": True},
        "caustics": {"size": 16, "frames": 2, "waves": 8},
        "fur": {"fins": True, "shells": 3, "texture_size": 16, "hairs": 50},
    }), fins)
    from tests.techniques.test_normal_blur import bump_sphere

    bumped = folder / "sphere_blur.glb"
    save(baker.bake(bump_sphere(folder / "sphere_bump.glb", "v", segments=32, rings=16, size=64),
                    bakes=["normal-blur"]), bumped)
    out = {"spot": spot, "spot_fins": fins, "sphere_blur": bumped}
    if FONT.is_file():
        text = folder / "text.glb"
        assert baker_main(["text", "Hi AV", "--font", str(FONT), "-o", str(text), "-q"]) == 0
        out["text"] = text
    sphere = folder / "sphere.obj"
    _write_sphere_obj(sphere)
    hair = folder / "hair.glb"
    assert baker_main(["hair", str(sphere), "--guides", "12", "--children", "2", "--segments", "4",
                       "--iterations", "2", "-o", str(hair), "-q"]) == 0
    out["hair"] = hair
    from techniques.cards_groom import make_groom, write_groom_usd

    curves, widths = make_groom(strands=150, clumps=6, seed=2)
    groom = write_groom_usd(folder / "groom.usda", curves, widths)
    cards = folder / "cards.glb"
    assert baker_main(["cards", str(groom), "-o", str(cards), "--cards", "6", "--atlas-size", "128", "-q"]) == 0
    out["cards"] = cards
    return out


# ------------------------------------------------------------------------------------------------ comparison
def _walk(value, path=()):
    """Yield (path, value) for every node of a JSON value."""
    yield path, value
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _walk(v, path + (k,))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from _walk(v, path + (i,))


def _kind(extension, path):
    for pattern, kind in REFS[extension].items():
        parts = pattern.split("/")
        if len(parts) == len(path) and all(p == "*" and isinstance(q, int) or p == str(q)
                                           for p, q in zip(parts, path)):
            return kind
    return None


def _texture(doc, index, tex_coord=0):
    tex = doc.json["textures"][index]
    sampler = dict(SAMPLER_DEFAULTS, **(doc.json["samplers"][tex["sampler"]] if "sampler" in tex else {}))
    return doc.image_bytes(tex["source"]), sampler, tex_coord


def _primitive_data(doc, mesh, primitive):
    prim = doc.json["meshes"][mesh]["primitives"][primitive]
    data = {k: doc.accessor(v) for k, v in prim["attributes"].items() if k == "POSITION" or k.startswith("_")}
    data["indices"] = doc.accessor(prim["indices"]) if "indices" in prim else None
    return data


def _resolve(doc, extension, ext, mesh):
    """The extension's JSON with references replaced by the data they point at."""
    def resolve(value, path):
        kind = _kind(extension, path)
        if kind == "accessor":
            return ("accessor", doc.accessor(value).tolist())
        if kind == "texture":
            tex_coord = value.get("texCoord", ext.get("texCoord", 0) if extension == "BAKER_tonal_art_map" else 0)
            rest = {k: v for k, v in value.items() if k not in ("index", "texCoord")}
            return ("texture", _texture(doc, value["index"], tex_coord), rest)
        if kind == "texture-index":
            return ("texture", _texture(doc, value))
        if kind == "primitive":
            return ("primitive", _primitive_data_list(doc, mesh, value))
        if kind == "mesh-primitive":
            return ("primitive", _primitive_data_list(doc, value["mesh"], value["primitive"]))
        if isinstance(value, dict):
            return {k: resolve(v, path + (k,)) for k, v in value.items()
                    if not (extension == "BAKER_tonal_art_map" and path == () and k == "texCoord")}
        if isinstance(value, list):
            return [resolve(v, path + (i,)) for i, v in enumerate(value)]
        return value

    return resolve(ext, ())


def _primitive_data_list(doc, mesh, primitive):
    return {k: (None if v is None else v.tolist()) for k, v in _primitive_data(doc, mesh, primitive).items()}


def _places(doc):
    """{(where, key): (extension name -> JSON, mesh index)} for every extensible place of interest."""
    gltf = doc.json
    out = {("root",): ((gltf.get("extensions") or {}), None)}
    for i, m in enumerate(gltf.get("materials") or []):
        out[("material", i)] = (m.get("extensions") or {}, None)
    for m, mesh in enumerate(gltf.get("meshes") or []):
        for p, prim in enumerate(mesh["primitives"]):
            out[("primitive", m, p)] = (prim.get("extensions") or {}, m)
    for node in gltf.get("nodes") or []:
        out[("node", node.get("name"))] = (node.get("extensions") or {}, None)
    return out


def _ours(name):
    return name.startswith("BAKER_") or name == EDGE_VISIBILITY


def _check_survived(before: GltfDocument, after: GltfDocument) -> list:
    """Assert every BAKER_* extension of ``before`` is in ``after`` with the same data; returns the names seen."""
    seen = []
    places_after = _places(after)
    for where, (exts, mesh) in _places(before).items():
        for name, ext in exts.items():
            if not _ours(name):
                continue
            seen.append(name)
            assert where in places_after, f"{where} is gone"
            exts_after, mesh_after = places_after[where]
            assert name in exts_after, f"{name} lost at {where}"
            assert _resolve(after, name, exts_after[name], mesh_after) == _resolve(before, name, ext, mesh), \
                f"{name} at {where} changed"
            assert name in after.json["extensionsUsed"]
    # the custom vertex attributes the extensions name
    for m, mesh in enumerate(before.json["meshes"]):
        for p, prim in enumerate(mesh["primitives"]):
            attrs_after = after.json["meshes"][m]["primitives"][p]["attributes"]
            for name, acc in prim["attributes"].items():
                if name.startswith("_"):
                    assert np.array_equal(after.accessor(attrs_after[name]), before.accessor(acc)), name
    return seen


def _assert_valid(path):
    report = validate.validate_file(path, khronos=False)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert_khronos_clean(path)


# ------------------------------------------------------------------------------------------------ tests
def test_every_extension_survives_the_pipeline(assets, tmp_path):
    _require_package()
    seen = set()
    for label, src in assets.items():
        out = tmp_path / f"{label}.processed.glb"
        _transform(src, out)
        before, after = GltfDocument.load(src), GltfDocument.load(out)
        seen.update(_check_survived(before, after))
        _assert_valid(out)
        if label == "spot":
            mat_before, mat_after = before.json["materials"][0], after.json["materials"][0]
            vol_before = mat_before["extensions"]["KHR_materials_volume"]
            vol_after = mat_after["extensions"]["KHR_materials_volume"]
            assert vol_after["thicknessFactor"] == pytest.approx(vol_before["thicknessFactor"])
            assert _texture(after, vol_after["thicknessTexture"]["index"]) == \
                _texture(before, vol_before["thicknessTexture"]["index"])
            # the TAM's stroke parameterization (a UV set of its own, issue 38): the same set, per triangle corner
            tam_before = mat_before["extensions"]["BAKER_tonal_art_map"]
            tam_after = mat_after["extensions"]["BAKER_tonal_art_map"]
            assert tam_before["texCoord"] == tam_after["texCoord"] == 1 and tam_after["strokes"] == tam_before["strokes"]
            corners = []
            for doc in (before, after):
                prim = doc.json["meshes"][0]["primitives"][0]
                corners.append(doc.accessor(prim["attributes"]["TEXCOORD_1"])[doc.accessor(prim["indices"])])
            assert np.array_equal(*corners)
    expected = {"BAKER_thickness", "BAKER_curvature", "BAKER_skin_lut", "BAKER_edges", EDGE_VISIBILITY,
                "BAKER_tonal_art_map", "BAKER_toon_ramp", "BAKER_fur", "BAKER_hair", "BAKER_caustics",
                "BAKER_hair_cards", "BAKER_normal_blur"}
    if "text" in assets:
        expected |= {"BAKER_glyph_atlas", "BAKER_text"}
    assert expected <= seen, f"not covered: {expected - seen}"
    assert set(REFS) | {EDGE_VISIBILITY} >= seen


def test_references_follow_renumbering(assets, tmp_path):
    # prune/dedup renumber accessors and textures: the data is the same, the indices generally are not. The
    # comparison above resolves references; this checks that renumbering did happen, so it was exercised.
    _require_package()
    out = tmp_path / "spot.processed.glb"
    _transform(assets["spot_fins"], out)
    before, after = GltfDocument.load(assets["spot_fins"]), GltfDocument.load(out)
    ext_b = before.json["meshes"][0]["primitives"][0]["extensions"]["BAKER_edges"]
    ext_a = after.json["meshes"][0]["primitives"][0]["extensions"]["BAKER_edges"]
    keys = ("edges", "oppositeVertices", "flags", "dihedralAngles", "wireframeMask")
    assert [ext_a[k] for k in keys] != [ext_b[k] for k in keys]
    assert len(after.json["accessors"]) < len(before.json["accessors"])  # dedup merged the two fin primitives'


def test_control_without_our_classes_loses_the_extensions(assets, tmp_path):
    # proves the tests above can fail: glTF-Transform drops extensions it has no class for, and prune then drops
    # the textures only they referenced
    _require_package()
    for label, src in assets.items():
        out = tmp_path / f"{label}.control.glb"
        _transform(src, out, control=True)
        before, after = GltfDocument.load(src), GltfDocument.load(out)
        lost = [name for exts, _ in _places(after).values() for name in exts if _ours(name)]
        assert not lost, lost
        assert not any(_ours(n) for n in after.json.get("extensionsUsed") or [])
        if label in ("spot", "spot_fins"):
            assert len(after.json.get("images") or []) < len(before.json["images"])


def test_reference_table_matches_the_schemas():
    # the classes' reference fields come from src/references.js: it must be what tools/references.mjs derives from
    # schemas/ now, and that derivation must agree with the hand-kept REFS above
    _require_package()
    check = _node_tool("--check")
    assert check.returncode == 0, check.stderr
    derived = _node_tool("--json")
    assert derived.returncode == 0, derived.stderr
    table = json.loads(derived.stdout)
    flat = {name: {pattern: kind for refs in places.values() for pattern, kind, *_ in refs}
            for name, places in table.items()}
    assert flat == REFS
    # extensions with a schema in schemas/ are all in the table (none forgotten)
    schemas = {p.parent.parent.name for p in (PACKAGE.parents[1] / "schemas").glob("*/schema/*.schema.json")}
    assert schemas <= set(table), schemas - set(table)
