"""Blender (``bpy`` 4.5 from PyPI, in its own venv made by ``scripts/install-bpy``) opens every baked asset.

Stock Blender first, no add-on: every bake of examples/spot alone, all together, ``baker hair`` and ``baker text``
import without error, and each baked custom attribute arrives as a Blender mesh attribute whose values equal the
glTF accessor's (vertices matched by position). That is what the one-width layout of
:mod:`baker.gltf.vertex_attributes` exists for: with mixed widths Blender's importer fails (``do_primitives``
``ValueError``). Blender runs as a subprocess on the helper scripts in ``tests/blender/``.
"""
from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

from baker.cli import main as baker_main
from baker.gltf.document import GltfDocument
from conftest import assert_khronos_clean

ROOT = Path(__file__).resolve().parents[1]
SPOT = ROOT / "examples" / "spot" / "spot.obj"
FANDISK = ROOT.parent / "shared" / "assets" / "meshes" / "fandisk.obj"
HELPERS = Path(__file__).parent / "blender"
FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
BAKES = ("thickness", "curvature", "edges", "fur", "skin", "tam", "toon")
# smaller than the defaults where a bake's cost is in its own resolution (the layouts written are the same)
CHEAP = {"thickness": ("--thickness-rays", "32", "--thickness-texture-size", "128"),
         "fur": ("--fur-fins", "true", "--fur-shells", "4", "--fur-texture-size", "64"), "tam": ("--tam-size", "64"),
         "skin": ("--skin-width", "64", "--skin-height", "64")}


@pytest.fixture(scope="session")
def blender_python() -> str:
    """The bpy venv's python: $BAKER_BPY_PYTHON (scripts/test sets it) or whatever scripts/install-bpy makes."""
    python = os.environ.get("BAKER_BPY_PYTHON")
    if not python:
        done = subprocess.run([str(ROOT / "scripts" / "install-bpy")], capture_output=True, text=True)
        assert done.returncode == 0, f"scripts/install-bpy failed:\n{done.stderr[-2000:]}"
        python = done.stdout.strip().splitlines()[-1]
    assert Path(python).is_file(), python
    return python


def run_blender(python: str, script: str, *args, timeout: int = 600, hash_seed: int | None = None) \
        -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "PYTHONHASHSEED")}
    if hash_seed is not None:  # Blender's importer orders custom attributes by string hashing
        env["PYTHONHASHSEED"] = str(hash_seed)
    done = subprocess.run([python, str(HELPERS / script), *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, env=env)
    assert done.returncode == 0, f"{script} failed ({done.returncode}):\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}"
    return done


def bake(*argv) -> None:
    assert baker_main([*map(str, argv), "--quiet"]) in (0, None), argv


@pytest.fixture(scope="session")
def baked(tmp_path_factory) -> dict:
    """{label: .glb} for every bake of spot alone, all bakes together (with edge fins), fandisk's edges, hair and
    text."""
    out = tmp_path_factory.mktemp("blender_baked")
    files = {}
    for name in BAKES:
        files[name] = out / f"spot_{name}.glb"
        bake("bake", SPOT, "--bakes", name, *CHEAP.get(name, ()), "-o", files[name])
    files["edges_fins"] = out / "spot_edges_fins.glb"
    bake("bake", SPOT, "--bakes", "edges", "--edges-fins", "true", "-o", files["edges_fins"])
    files["all"] = out / "spot_all.glb"
    bake("bake", SPOT, "--bakes", ",".join(BAKES), "--edges-fins", "true", "--edges-opposite-vertices", "true",
         *sum(CHEAP.values(), ()), "-o", files["all"])
    files["fandisk"] = out / "fandisk_edges.glb"
    bake("bake", FANDISK, "--bakes", "edges", "-o", files["fandisk"])
    files["hair"] = out / "spot_hair.glb"
    bake("hair", SPOT, "--guides", "40", "--children", "3", "-o", files["hair"])
    files["text"] = out / "text.glb"
    bake("text", "Baker AV", "--font", FONT, "-o", files["text"])
    return files


@pytest.fixture(scope="session")
def stock_report(blender_python, baked, tmp_path_factory) -> dict:
    report = tmp_path_factory.mktemp("blender_stock") / "report.json"
    run_blender(blender_python, "import_report.py", "--out", report, "--", *baked.values())
    return json.loads(report.read_text())


def custom_attributes(path) -> dict:
    """{mesh name: {attribute: [(positions (n, 3), values (n, k)) per primitive]}} of the baked file itself; a
    primitive of the mesh without the attribute gets zeros, as Blender's importer fills them."""
    doc = GltfDocument.load(path)
    found = {}
    for mesh in doc.json.get("meshes", []):
        prims = [(doc.accessor(prim["attributes"]["POSITION"]).astype(np.float32), prim["attributes"])
                 for prim in mesh["primitives"]]
        names = {n for _, attrs in prims for n in attrs if n.startswith("_")}
        per = found.setdefault(mesh.get("name", ""), {})
        for name in sorted(names):
            width = next(doc.accessor(attrs[name]).reshape(len(pos), -1).shape[1] for pos, attrs in prims
                         if name in attrs)
            per[name] = [(pos, doc.accessor(attrs[name]).reshape(len(pos), -1) if name in attrs
                          else np.zeros((len(pos), width), np.float32)) for pos, attrs in prims]
    return found


def assert_values_follow_positions(name, blender_positions, blender_values, gltf_parts) -> None:
    """Every Blender vertex carries the value of a glTF vertex at its position (Blender may merge, split or reorder
    vertices; it moves neither positions nor custom attribute values off their float32 values, so compare exactly)."""
    width = gltf_parts[0][1].shape[1]
    blender_values = np.asarray(blender_values, np.float32)
    assert blender_values.shape[1] == width, f"{name}: width {blender_values.shape[1]}, glTF {width}"
    pairs = lambda pos, val: {a + b for a, b in zip(map(bytes, np.ascontiguousarray(pos, np.float32)),
                                                      map(bytes, np.ascontiguousarray(val, np.float32)))}
    table = set().union(*(pairs(pos, val) for pos, val in gltf_parts))
    got = pairs(np.asarray(blender_positions, np.float32), blender_values)
    missing = got - table
    assert not missing, f"{name}: {len(missing)} Blender (position, value) pairs match no glTF vertex"


@pytest.mark.parametrize("label", [*BAKES, "edges_fins", "all", "hair", "text"])
def test_stock_blender_imports_every_bake(label, baked, stock_report):
    entry = stock_report[str(baked[label])]
    assert entry["error"] is None, f"stock Blender failed to import {label}: {entry['error']}"
    meshes = [o for o in entry["objects"] if o["type"] == "MESH"]
    assert meshes, f"{label}: no mesh object imported"
    expected = custom_attributes(baked[label])
    for obj in meshes:
        mesh_name = next((m for m in expected if m and obj["mesh"].startswith(m)), None)
        if mesh_name is None and len(expected) == 1:
            mesh_name = next(iter(expected))
        attrs = expected.get(mesh_name, {})
        for name, parts in attrs.items():
            assert name in obj["attributes"], f"{label}: {obj['name']} lacks {name} in Blender"
            got = obj["attributes"][name]
            # one width per mesh: VEC3 once a bake writes a vector, SCALAR when only scalars are baked (thickness)
            data_type = {1: "FLOAT", 2: "FLOAT2", 3: "FLOAT_VECTOR"}[parts[0][1].shape[1]]
            assert got["domain"] == "POINT" and got["data_type"] == data_type, (name, got["data_type"])
            assert_values_follow_positions(f"{label}/{name}", obj["positions"], got["values"], parts)
    baked_names = {n for attrs in expected.values() for n in attrs}
    imported = {n for o in meshes for n in o["attributes"] if n.startswith("_")}
    assert baked_names <= imported, f"{label}: Blender dropped {sorted(baked_names - imported)}"


# ---------------------------------------------------------------------------------------------------- the add-on
ADDON = ROOT / "runtime-shaders" / "blender"
# accessor-valued properties of each extension (from the schemas), and those holding vertex indices
ACCESSOR_KEYS = {"BAKER_edges": ("edges", "oppositeVertices", "flags", "dihedralAngles", "wireframeMask"),
                 "EXT_mesh_primitive_edge_visibility": ("visibility", "silhouetteMates"),
                 "BAKER_hair": ("widthScale", "ribbonIndices")}
VERTEX_INDEX_KEYS = {"edges", "oppositeVertices"}
ROUND_TRIP = ("all", "hair", "text", "edges", "fandisk")


@pytest.fixture(scope="session")
def round_trips(blender_python, baked, tmp_path_factory) -> dict:
    """{label: (exported .glb, report of what the add-on made)} for a few inputs that cover every extension."""
    out = tmp_path_factory.mktemp("blender_round_trip")
    done = {}
    for label in ROUND_TRIP:
        target, report = out / f"{label}_blender.glb", out / f"{label}.json"
        run_blender(blender_python, "round_trip.py", ADDON, baked[label], target, report)
        done[label] = (target, json.loads(report.read_text()))
    return done


def digest(data: bytes) -> str:
    import hashlib
    return hashlib.sha256(data).hexdigest()


def image_digest(doc, texture: int) -> str:
    """A texture as what it shows: the image bytes and the sampler settings (indices differ after export)."""
    tex = doc.json["textures"][texture]
    sampler = doc.json["samplers"][tex["sampler"]] if "sampler" in tex else {}
    return digest(doc.image_bytes(tex["source"])) + json.dumps(sampler, sort_keys=True)


def resolve_textures(doc, obj):
    """A copy of an extension object with every texture index replaced by what the texture holds."""
    if isinstance(obj, dict):
        out = {}
        for key, value in obj.items():
            textured = "texture" in key.lower()
            if textured and isinstance(value, int) and not isinstance(value, bool):
                out[key] = image_digest(doc, value)
            elif isinstance(value, dict) and textured and isinstance(value.get("index"), int):
                out[key] = dict(value, index=image_digest(doc, value["index"]))
            else:
                out[key] = resolve_textures(doc, value) if not (textured and isinstance(value, list)) else [
                    dict(v, index=image_digest(doc, v["index"])) if isinstance(v, dict) and "index" in v
                    else resolve_textures(doc, v) for v in value]
        return out
    if isinstance(obj, list):
        return [resolve_textures(doc, v) for v in obj]
    return obj


def primitive_digest(doc, prim) -> str:
    """A primitive named by the set of its vertex positions (its index and vertex copies may change)."""
    positions = np.ascontiguousarray(doc.accessor(prim["attributes"]["POSITION"]), np.float32)
    return digest(b"".join(sorted(set(map(bytes, positions)))))


def triangle_edges(doc, prim):
    """[(triangle key, edge key)] of every triangle edge k = (corner k, corner k+1), in bitfield order; keys are the
    sorted float32 corner positions, so they survive reordering of vertices and of corners."""
    positions = np.ascontiguousarray(doc.accessor(prim["attributes"]["POSITION"]), np.float32)
    triangles = doc.accessor(prim["indices"]).astype(np.int64).reshape(-1, 3)
    out = []
    for tri in triangles:
        corners = [bytes(positions[v]) for v in tri]
        tri_key = b"".join(sorted(corners))
        out.extend((tri_key, b"".join(sorted((corners[k], corners[(k + 1) % 3])))) for k in range(3))
    return out, positions


def canonical_extensions(path) -> dict:
    """Every BAKER_* / edge-visibility extension of a file, with its references replaced by what they point at."""
    doc = GltfDocument.load(path)
    gltf = doc.json
    found = {"root": resolve_textures(doc, {k: v for k, v in (gltf.get("extensions") or {}).items()})}
    for font in (found["root"].get("BAKER_glyph_atlas") or {}).get("fonts", []):
        for part in ("glyphs", "kerning"):
            for key, value in list((font.get(part) or {}).items()):
                if key != "count":
                    font[part][key] = doc.accessor(value).tolist()
    for table_set in (found["root"].get("BAKER_hair_shading") or {}).get("tables", []):
        for table in table_set.values():
            if isinstance(table, dict) and "accessor" in table:  # the fibre tables: compared by their texels
                table["accessor"] = doc.accessor(table["accessor"]).tobytes().hex()
    found["nodes"] = sorted(json.dumps(n["extensions"], sort_keys=True) for n in gltf.get("nodes", [])
                            if "extensions" in n)
    prims = []
    for mesh in gltf.get("meshes", []):
        for prim in mesh["primitives"]:
            exts = prim.get("extensions") or {}
            row = {"attributes": {}, "extensions": {}}
            if "material" in prim:
                material = (gltf["materials"][prim["material"]].get("extensions") or {})
                row["material"] = resolve_textures(doc, {k: v for k, v in material.items() if k.startswith("BAKER_")})
                for fin in (row["material"].get("BAKER_fur") or {}).get("fins", []):
                    fin["primitive"] = primitive_digest(doc, gltf["meshes"][fin.pop("mesh")]["primitives"][fin["primitive"]])
                for chain in (row["material"].get("BAKER_fur") or {}).get("coverageMips", []):
                    chain["accessor"] = digest(doc.accessor(chain["accessor"]).tobytes())  # the KTX2's bytes
            positions = np.ascontiguousarray(doc.accessor(prim["attributes"]["POSITION"]), np.float32)
            for name, acc in prim["attributes"].items():
                if name.startswith("_"):
                    values = np.ascontiguousarray(doc.accessor(acc), np.float32).reshape(len(positions), -1)
                    row["attributes"][name] = {bytes(p) + bytes(v) for p, v in zip(positions, values)}
            for name, ext in exts.items():
                ext = dict(ext)
                for key in ("finsOf", "fins"):
                    if isinstance(ext.get(key), int):
                        ext[key] = primitive_digest(doc, mesh["primitives"][ext[key]])
                if isinstance(ext.get("guides"), dict) and "primitive" in ext["guides"]:
                    ext["guides"] = dict(ext["guides"], primitive=primitive_digest(
                        doc, mesh["primitives"][ext["guides"]["primitive"]]))
                    for key in ("ids", "weights"):  # guide ids and weights: compared by their values
                        if isinstance(ext["guides"].get(key), int):
                            ext["guides"][key] = doc.accessor(ext["guides"][key]).tolist()
                for key in ACCESSOR_KEYS.get(name, ()):
                    if key not in ext:
                        continue
                    values = doc.accessor(ext[key])
                    if key in VERTEX_INDEX_KEYS:
                        ext[key] = [bytes(positions[i]) for i in values.astype(np.int64).reshape(-1)]
                    elif key in ("visibility", "wireframeMask", "silhouetteMates"):
                        ext[key] = None  # compared per triangle edge below
                    else:
                        ext[key] = values.tolist()
                row["extensions"][name] = ext
            if "EXT_mesh_primitive_edge_visibility" in exts or "wireframeMask" in exts.get("BAKER_edges", {}):
                edges, positions = triangle_edges(doc, prim)
                vis = exts.get("EXT_mesh_primitive_edge_visibility")
                if vis:
                    bits = np.unpackbits(doc.accessor(vis["visibility"]).astype(np.uint8), bitorder="little")
                    codes = bits[0:2 * len(edges):2] | (bits[1:2 * len(edges):2] << 1)
                    mates = iter(doc.accessor(vis["silhouetteMates"]).astype(np.int64)) if "silhouetteMates" in vis else iter(())
                    row["visibility"] = sorted((t + e, int(c), bytes(positions[next(mates)]) if c == 1 else b"")
                                               for (t, e), c in zip(edges, codes))
                mask_acc = exts.get("BAKER_edges", {}).get("wireframeMask")
                if mask_acc is not None:
                    mask = doc.accessor(mask_acc).astype(np.int64)
                    row["wireframe"] = sorted((t + e, int((mask[i // 3] >> (i % 3)) & 1))
                                              for i, (t, e) in enumerate(edges))
            prims.append(row)
    found["primitives"] = sorted(prims, key=lambda r: json.dumps(sorted(r["extensions"])) + str(sorted(r["attributes"])))
    return found


@pytest.mark.parametrize("label", ROUND_TRIP)
def test_blender_round_trip_keeps_every_extension(label, baked, round_trips):
    exported, _ = round_trips[label]
    assert baker_main(["validate", str(exported)]) == 0  # baker's checks and Khronos' validator
    assert_khronos_clean(exported)
    before, after = canonical_extensions(baked[label]), canonical_extensions(exported)
    assert after["root"] == before["root"]
    assert after["nodes"] == before["nodes"]
    assert len(after["primitives"]) == len(before["primitives"])
    for old, new in zip(before["primitives"], after["primitives"]):
        assert sorted(new["extensions"]) == sorted(old["extensions"])
        for name in old["extensions"]:
            assert new["extensions"][name] == old["extensions"][name], f"{label}: {name} changed"
        assert new.get("material") == old.get("material"), f"{label}: material extensions changed"
        assert sorted(new["attributes"]) == sorted(old["attributes"])
        for name in old["attributes"]:
            assert new["attributes"][name] == old["attributes"][name], f"{label}: {name} values changed"
        assert new.get("visibility") == old.get("visibility"), f"{label}: edge visibility changed"
        assert new.get("wireframe") == old.get("wireframe"), f"{label}: wireframe mask changed"


def test_addon_shows_the_baked_data(baked, round_trips):
    """What an artist sees after importing with the add-on: attributes, node groups mixed in at factor 0, hard and
    crease edges marked for Freestyle (hard ones sharp too), strands as curves, text quads with their atlas material."""
    _, report = round_trips["all"]
    spot = report["objects"]["spot.obj"]
    doc = GltfDocument.load(baked["all"])
    surface = doc.json["meshes"][0]["primitives"][0]
    for name in ("_THICKNESS", "_CURVATURE", "_PRINCIPAL_CURVATURES", "_PRINCIPAL_DIRECTION", "_OUTLINE_NORMAL"):
        assert spot["attributes"].get(name) == "FLOAT_VECTOR", name
    assert not [n for n in spot["attributes"] if n.startswith(("_FIN", "_FUR"))], "fin data leaked onto the surface"
    assert "baker_gltf" in spot["mesh_properties"]
    # by position, the Freestyle-marked Blender edges are exactly BAKER_edges' hard (normal seam) and crease edges,
    # the sharp ones exactly its hard edges (sharp creases would re-split the imported normals: the look would change)
    edges_ext = surface["extensions"]["BAKER_edges"]
    positions = doc.accessor(surface["attributes"]["POSITION"]).astype(np.float32)
    pairs = doc.accessor(edges_ext["edges"]).astype(np.int64).reshape(-1, 2)
    flags = doc.accessor(edges_ext["flags"]).astype(np.int64)
    crease, hard = 1 << 2, 1 << 7
    for name, bits in (("freestyle_edge", crease | hard), ("sharp_edge", hard)):
        wanted = {tuple(sorted((bytes(positions[a]), bytes(positions[b])))) for a, b in pairs[(flags & bits) != 0]}
        # spot's computed normals are welded across its UV seams, so it has no hard (normal-seam) edges: Blender
        # must then mark no sharp edge either; its creases are still Freestyle edges
        assert wanted or name == "sharp_edge", name
        marked = {tuple(sorted(bytes(np.asarray(p, np.float32)) for p in pair)) for pair in spot[name + "_positions"]}
        assert marked == wanted, f"{name}: {len(marked ^ wanted)} edges differ from BAKER_edges' flagged edges"
    assert spot["freestyle_edge_attribute"] == 0, "Blender 4.5 reads use_freestyle_mark, not a generic attribute"
    material = next(m for m in report["materials"].values() if m["payload"])
    assert {"BAKER Translucency", "BAKER LUT Coordinates"} <= set(material["groups"])
    mixes = {name: fac for name, fac in material["mixes"].items() if name.startswith("BAKER mix")}
    assert mixes == {"BAKER mix translucency": 0.0, "BAKER mix skin lut": 0.0, "BAKER mix toon ramp": 0.0,
                     "BAKER mix fur": 0.0, "BAKER mix hatching": 0.0}
    # the hatching images read the stroke parameterization's UV map by name (TEXCOORD_1 beside spot's own)
    tam = doc.json["materials"][surface["material"]]["extensions"]["BAKER_tonal_art_map"]
    # the stroke u axis is not stored by default (--tam-direction): the stroke set's u gradient gives it
    assert tam["texCoord"] == 1 and "_HATCHING_DIRECTION" not in spot["attributes"]
    assert material["uv_maps"]["BAKER Hatching UV"] == spot["uv_layers"][1]
    # hair: one curve per strand, every strand vertex a curve point, the guide data as attributes
    _, report = round_trips["hair"]
    doc = GltfDocument.load(baked["hair"])
    strands = [p["extensions"]["BAKER_hair"] for m in doc.json["meshes"] for p in m["primitives"]
               if "BAKER_hair" in (p.get("extensions") or {})]
    curves = [o for o in report["objects"].values() if o["type"] == "CURVES"]
    assert sorted(c["curves"] for c in curves) == sorted(s["strandCount"] for s in strands)
    assert sorted(c["points"] for c in curves) == sorted(s["strandCount"] * s["verticesPerStrand"] for s in strands)
    assert all({"_STRAND_TANGENT", "_STRAND_PARAM"} <= set(c["attributes"]) for c in curves)
    # text: the label is a visible mesh of quads with the atlas material, BAKER_text kept on its object
    _, report = round_trips["text"]
    text = [o for o in report["objects"].values() if o["type"] == "MESH"]
    assert text and not text[0]["hidden"] and "baker_gltf_node" in text[0]["properties"]


def test_fandisk_creases_are_marks_freestyle_reads(baked, round_trips):
    """Blender 4.5's Freestyle and Line Art read MeshEdge.use_freestyle_mark (5.0 moved the marks to the
    ``freestyle_edge`` attribute): after the add-on's import, the marked edges are exactly fandisk's crease and hard
    edges as BAKER_edges flags them, matched by end positions."""
    _, report = round_trips["fandisk"]
    (fandisk,) = [o for o in report["objects"].values() if o["type"] == "MESH"]
    doc = GltfDocument.load(baked["fandisk"])
    wanted = set()
    for prim in doc.json["meshes"][0]["primitives"]:
        ext = prim["extensions"]["BAKER_edges"]
        positions = doc.accessor(prim["attributes"]["POSITION"]).astype(np.float32)
        pairs = doc.accessor(ext["edges"]).astype(np.int64).reshape(-1, 2)
        flags = doc.accessor(ext["flags"]).astype(np.int64)
        wanted |= {tuple(sorted((bytes(positions[a]), bytes(positions[b])))) for a, b in pairs[(flags & (4 | 128)) != 0]}
    marked = {tuple(sorted(bytes(np.asarray(p, np.float32)) for p in pair)) for pair in fandisk["freestyle_edge_positions"]}
    print("fandisk: BAKER_edges crease/hard edges", len(wanted), "Freestyle-marked Blender edges", fandisk["freestyle_edge"])
    assert len(wanted) > 100
    assert fandisk["freestyle_edge"] == len(wanted) and marked == wanted


def test_freestyle_draws_the_fandisk_marks(blender_python, baked, tmp_path):
    """Freestyle itself (Cycles, a 128 px render, edge marks the only line selection) draws lines from the add-on's
    marks, and none once they are cleared: the marks are where Blender 4.5's Freestyle looks."""
    report = tmp_path / "freestyle.json"
    run_blender(blender_python, "render_freestyle.py", ADDON, baked["fandisk"], report)
    lines = json.loads(report.read_text())
    print("fandisk Freestyle:", lines)
    assert lines["marked"] > 100
    assert lines["with_marks"] > 500 and lines["without_marks"] == 0


def test_translucency_group_renders_thin_parts_brighter(blender_python, baked, tmp_path):
    """Cycles CPU, 64 x 64: spot lit from behind through the BAKER Translucency group. Thin pixels are brighter than
    thick ones, and per pixel lit / control (same render with thickness 0) follows exp(-thickness / d)."""
    out = tmp_path / "render.npz"
    run_blender(blender_python, "render_translucency.py", ADDON, baked["thickness"], out)
    data = np.load(out)
    lit = data["lit"][..., :3].mean(axis=-1)
    control = data["control"][..., :3].mean(axis=-1)
    thickness, inside = data["thickness"], (data["alpha"] > 0.99) & (control > 0.05)
    assert inside.sum() > 200, "the object covers too few pixels"
    thin_edge, thick_edge = np.quantile(thickness[inside], [0.25, 0.75])
    thin, thick = lit[inside & (thickness <= thin_edge)].mean(), lit[inside & (thickness >= thick_edge)].mean()
    assert thin > 1.3 * thick, (thin, thick)
    expected = np.exp(-thickness[inside] / float(data["attenuation"]))
    assert np.corrcoef(lit[inside] / control[inside], expected)[0, 1] > 0.8


def test_addon_leaves_the_untouched_look_unchanged(blender_python, baked, tmp_path):
    """The same Cycles frame (fixed seed) of every bake together, imported by stock Blender and with the add-on:
    node groups mixed in at factor 0 and the edge marks change no pixel."""
    stock, addon = tmp_path / "stock.npy", tmp_path / "addon.npy"
    run_blender(blender_python, "render_look.py", "-", baked["all"], stock)
    run_blender(blender_python, "render_look.py", ADDON, baked["all"], addon)
    stock, addon = np.load(stock), np.load(addon)
    assert stock[..., 3].sum() > 100 and stock[..., :3].max() > 0.05, "the render shows nothing"
    np.testing.assert_allclose(addon, stock, atol=1e-6)


def test_addon_accessor_table_matches_the_schemas():
    """The add-on renumbers every accessor an extension references; a path missing from its table would leave a
    dangling index after export. Its table must name exactly the accessor references that tools/references.mjs
    derives from the schemas (runtime-shaders/gltf-transform/src/references.js, itself checked against them)."""
    import importlib.util
    import re

    refs_path = ROOT / "runtime-shaders" / "blender" / "baker_blender" / "refs.py"
    spec = importlib.util.spec_from_file_location("baker_blender_refs", refs_path)
    refs = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(refs)  # refs.py is plain Python: no bpy needed
    generated = (ROOT / "runtime-shaders" / "gltf-transform" / "src" / "references.js").read_text()
    from_schemas: dict[str, set[str]] = {}
    extension = None
    for line in generated.splitlines():
        head = re.match(r'^\t"([A-Za-z0-9_]+)": \{$', line)
        if head:
            extension = head.group(1)
        entry = re.match(r'^\t\t\t\["([^"]+)", "accessor"', line)
        if entry:
            path = entry.group(1).replace("/*/", "[].").replace("/", ".")
            from_schemas.setdefault(extension, set()).add(path)
    assert from_schemas, "no accessor reference parsed from references.js"
    table = {name: set(paths) for name, paths in refs.ACCESSORS.items()}
    assert table == from_schemas


# ---------------------------------------------------------------------------------------------------- widths
HASH_SEEDS = range(5)
FIN_ATTRIBUTES = ("_FIN_V0", "_FIN_V1", "_FIN_V2", "_FIN_V3", "_FIN_CORNER", "_FIN_FLAGS")


@pytest.fixture(scope="session")
def width_cases(tmp_path_factory) -> dict:
    """A mesh with a SCALAR custom attribute of the user's own (``_PRESSURE``, as a Blender export writes a float
    attribute) before and after baking in the blender layout, and spot baked in the native layout."""
    import trimesh

    out = tmp_path_factory.mktemp("blender_widths")
    sphere = trimesh.creation.icosphere(2, radius=1.0)
    pressure = np.linspace(0.0, 1.0, len(sphere.vertices), dtype=np.float32)
    files = {"pressure": out / "pressure.glb", "pressure_baked": out / "pressure_baked.glb",
             "native": out / "spot_native.glb"}
    GltfDocument.from_triangles(files["pressure"], "pressured", {"POSITION": sphere.vertices.astype(np.float32),
                                "_PRESSURE": pressure}, sphere.faces.reshape(-1), "test").save(files["pressure"])
    bake("bake", files["pressure"], "--bakes", "thickness,curvature", "--curvature-directions", "false",
         *CHEAP["thickness"], "-o", files["pressure_baked"])
    bake("bake", SPOT, "--bakes", "thickness,curvature,edges", "--edges-fins", "true", *CHEAP["thickness"],
         "--attribute-layout", "native", "-o", files["native"])
    for path in files.values():
        assert_khronos_clean(path)
    return files


@pytest.fixture(scope="session")
def width_reports(blender_python, width_cases, tmp_path_factory) -> dict:
    """{(hash seed, "stock" | "addon"): import report} over several string-hashing seeds."""
    folder = tmp_path_factory.mktemp("blender_width_reports")
    reports = {}
    for seed in HASH_SEEDS:
        for kind, extra in (("stock", ()), ("addon", ("--addon", ADDON))):
            report = folder / f"{kind}_{seed}.json"
            run_blender(blender_python, "import_report.py", *extra, "--out", report, "--", *width_cases.values(),
                        hash_seed=seed)
            reports[seed, kind] = json.loads(report.read_text())
    return reports


def assert_imported_values(label, entry, path, width=None, skip=()) -> None:
    """Every custom attribute of ``path`` but ``skip`` arrived in Blender with its values (first components when
    ``width`` pads it)."""
    assert entry["error"] is None, f"{label}: {entry['error']}"
    (obj,) = [o for o in entry["objects"] if o["type"] == "MESH"]
    for name, parts in next(iter(custom_attributes(path).values())).items():
        if name in skip:
            continue
        if width:
            parts = [(pos, np.pad(values, ((0, 0), (0, width - values.shape[1])))) for pos, values in parts]
        assert name in obj["attributes"], f"{label}: Blender lacks {name}"
        assert_values_follow_positions(f"{label}/{name}", obj["positions"], obj["attributes"][name]["values"], parts)


def test_users_scalar_attribute_imports_after_baking_every_time(width_cases, width_reports):
    """Stock Blender 4.5, several hash seeds: the user's SCALAR ``_PRESSURE`` next to baker's attributes (which took
    its width) imports every time, with the user's values untouched."""
    for seed in HASH_SEEDS:
        report = width_reports[seed, "stock"]
        for label in ("pressure", "pressure_baked"):
            entry = report[str(width_cases[label])]
            assert_imported_values(f"{label} (PYTHONHASHSEED={seed})", entry, width_cases[label])
        (obj,) = [o for o in report[str(width_cases["pressure_baked"])]["objects"] if o["type"] == "MESH"]
        assert {obj["attributes"][n]["data_type"] for n in ("_PRESSURE", "_THICKNESS", "_CURVATURE")} == {"FLOAT"}


def test_native_layout_needs_the_addon(width_cases, width_reports):
    """The native layout mixes widths in one mesh: stock Blender 4.5 fails on it depending on the hash seed; with
    the add-on it imports every time, each attribute's values in its first components."""
    stock_errors = [width_reports[seed, "stock"][str(width_cases["native"])]["error"] for seed in HASH_SEEDS]
    assert any(stock_errors), "stock Blender imported mixed widths under every seed: the add-on hook is untested"
    for seed in HASH_SEEDS:
        entry = width_reports[seed, "addon"][str(width_cases["native"])]
        # the add-on keeps the fin primitive's attributes in its payload, not on the Blender mesh
        assert_imported_values(f"native + add-on (PYTHONHASHSEED={seed})", entry, width_cases["native"], width=3,
                               skip=FIN_ATTRIBUTES)


def test_addon_shows_caustics_on_a_floor(blender_python, tmp_path):
    """A floor 1.8 m under the water, baked for 1.5 m (the projection along the refracted sun and the depth fade both
    act), imported with the add-on and rendered from above in Cycles: the BAKER Caustics group's irradiance equals
    the GLSL module's numpy twin on the first frame (tests/gl/twins_caustics.py, bilinear on the file's 16-bit
    texels) per pixel, and it is added to the surface as imported: lit minus the control without it follows
    (E - 1) x fade, brighter on the caustic lines and darker in the cells."""
    from browser import CAUSTIC_FLOOR_OBJ
    from gl.twins_caustics import baker_caustics_depth, baker_caustics_fade, baker_caustics_uv
    from gl.twins_hatching import sample_linear

    from baker.gltf.images import decode_image

    obj, glb, out = tmp_path / "floor.obj", tmp_path / "floor.glb", tmp_path / "render.npz"
    obj.write_text(CAUSTIC_FLOOR_OBJ)
    bake("bake", obj, "--bakes", "caustics", "--caustics-size", "64", "--caustics-frames", "2", "--caustics-waves", "16",
         "--caustics-tile-size", "1.0", "--caustics-water-level", "1.8", "--caustics-depth", "1.5",
         "--caustics-fade-distance", "1.0", "-o", glb)
    doc = GltfDocument.load(glb)
    ext = doc.json["materials"][0]["extensions"]["BAKER_caustics"]
    source = doc.json["textures"][ext["frameTextures"][0]["index"]]["source"]
    frame = decode_image(doc.image_bytes(source)).astype(np.float32) / 65535.0
    run_blender(blender_python, "render_caustics.py", ADDON, glb, out)
    data = np.load(out)
    assert bool(data["surface_is_add"])
    # pixel centres, rows bottom-up as Blender stores them; Blender (x, y, 0) is glTF (x, 0, -y)
    n = data["irradiance"].shape[0]
    centres = -2.0 + (np.arange(n) + 0.5) * 4.0 / n
    by, bx = np.meshgrid(centres, centres, indexing="ij")
    world = np.stack([bx, np.zeros_like(bx), -by], -1)
    uv = baker_caustics_uv(world, ext["projectionDirection"], ext["waterLevel"], ext["depth"], ext["tileSize"])
    texels = frame if frame.ndim == 3 else frame[..., None]
    expected = sample_linear(texels, uv)[..., 0] * ext["intensityScale"]
    fade = baker_caustics_fade(baker_caustics_depth(world, ext["waterLevel"]), ext["depth"], ext["fadeDistance"])
    assert np.allclose(fade, 0.7, atol=1e-5)  # 0.3 m from the baked depth, fade distance 1 m
    irradiance = data["irradiance"][..., 0]
    assert expected.std() > 0.3  # a caustic network, not a flat field
    error = np.abs(irradiance - expected)
    print("irradiance error: median", np.median(error), "99%", np.percentile(error, 99), "E std", expected.std())
    assert np.median(error) < 1e-3 and np.percentile(error, 99) < 1e-2, (np.median(error), error.max())
    added = data["lit"][..., :3].mean(-1) - data["control"][..., :3].mean(-1)
    assert (added > 0.02).mean() > 0.05 and (added < -0.02).mean() > 0.05
    assert np.corrcoef(added.ravel(), ((expected - 1) * fade).ravel())[0, 1] > 0.95


def test_blender_imports_hair_cards_alpha_clipped(blender_python, tmp_path):
    """`baker cards` output in stock Blender: one mesh with every vertex, the base colour's alpha clipping the
    material, and a Cycles render (orthographic along glTF -Z, pixel centres, transparent film) covering the pixels a
    numpy rasteriser of the same triangles and atlas covers (tests/techniques/test_cards.py). With the add-on the flow
    texture drives the Principled BSDF's tangent and the data and flow images come in."""
    import ast

    from techniques.cards_groom import make_groom, write_groom_usd
    from techniques.cards_views import card_silhouette
    from techniques.test_cards import cards_from_glb

    curves, widths = make_groom(strands=800, clumps=24, seed=3)
    groom = write_groom_usd(tmp_path / "groom.usda", curves, widths)
    glb = tmp_path / "cards.glb"
    bake("cards", groom, "-o", glb, "--cards", "24", "--atlas-size", "512")
    cards = cards_from_glb(glb)
    lo, hi = cards["positions"].min(0), cards["positions"].max(0)
    centre = (lo + hi) / 2
    half = float((hi - lo)[:2].max()) / 2 * 1.05
    size = 128
    runs = {}
    for kind, addon in (("stock", "-"), ("addon", ADDON)):
        out = tmp_path / f"{kind}.npz"
        run_blender(blender_python, "render_cards.py", addon, glb, out, centre[0], centre[1], half, size)
        data = np.load(out)
        runs[kind] = (data["pixels"], ast.literal_eval(str(data["report"])))
    pixels, report = runs["stock"]
    assert report["meshes"] == 1 and report["vertices"] == len(cards["positions"]), report
    assert report["polygons"] == len(cards["triangles"]) and report["alpha_linked"], report
    basis = (np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]))
    expected = card_silhouette(cards, basis, (centre[:2] - half, 2 * half), size, cards["material"]["alphaCutoff"])
    drawn = pixels[..., 3] > 0.5
    iou = (drawn & expected).sum() / (drawn | expected).sum()
    print("cards coverage IoU Cycles/numpy", iou, int(drawn.sum()), int(expected.sum()))
    assert iou > 0.8 and drawn.sum() > 300, iou
    addon_pixels, addon_report = runs["addon"]
    assert addon_report["tangent_linked"] and addon_report["alpha_linked"], addon_report
    assert sum("baker texture" in name for name in addon_report["images"]) >= 2, addon_report
    addon_drawn = addon_pixels[..., 3] > 0.5
    assert (addon_drawn & drawn).sum() / (addon_drawn | drawn).sum() > 0.95  # the add-on keeps the clip


def test_blender_round_trip_keeps_the_cards_coverage_mips(blender_python, tmp_path):
    """`baker cards` output imported with the add-on and exported again: BAKER_hair_cards keeps its coverage mip
    chain (the accessor renumbered, the same KTX2 bytes, still naming the material's base colour texture) and the
    exported file passes baker's checks (level 0 equal to the exported PNG, coverage held) and Khronos'."""
    from techniques.cards_groom import make_groom, write_groom_usd

    curves, widths = make_groom(strands=300, clumps=8, seed=3)
    groom = write_groom_usd(tmp_path / "groom.usda", curves, widths)
    glb = tmp_path / "cards.glb"
    bake("cards", groom, "-o", glb, "--cards", "8", "--atlas-size", "256")
    exported = tmp_path / "cards_blender.glb"
    run_blender(blender_python, "round_trip.py", ADDON, glb, exported, tmp_path / "report.json")
    from baker.validate import validate_file

    messages = validate_file(exported, khronos=False)["issues"]["messages"]
    assert not [m for m in messages if m["severity"] <= 1], messages  # no error, no warning
    assert_khronos_clean(exported)

    def chains(path):
        doc = GltfDocument.load(path)
        (material,) = [m for m in doc.json["materials"] if "BAKER_hair_cards" in (m.get("extensions") or {})]
        ext = material["extensions"]["BAKER_hair_cards"]
        base = material["pbrMetallicRoughness"]["baseColorTexture"]["index"]
        return [(digest(doc.accessor(e["accessor"]).tobytes()), e["texture"] == base, e["alphaCutoff"],
                 e["levelCount"]) for e in ext["coverageMips"]]

    before, after = chains(glb), chains(exported)
    assert len(before) == 1 and before[0][1] and after == before


@pytest.fixture(scope="session")
def blurred_head(blender_python, tmp_path_factory):
    """(Blender's export, its bake with normal-blur,curvature,skin): tests/blender/normal_mapped_head.py."""
    folder = tmp_path_factory.mktemp("blender_head")
    head = folder / "head.glb"
    run_blender(blender_python, "normal_mapped_head.py", head, 256)
    out = folder / "head_baked.glb"
    bake("bake", head, "--bakes", "normal-blur,curvature,skin", "--skin-width", "64", "--skin-height", "64",
         "-o", out)
    return head, out


def test_blender_exported_head_bakes_normal_blur_curvature_and_skin(blender_python, blurred_head, tmp_path):
    """A real normal-mapped asset: a subdivided Suzanne with a ridged normal map, exported by Blender's own glTF
    exporter with TANGENT (tests/blender/normal_mapped_head.py). normal-blur, curvature and skin bake together; both
    validators are clean (no Khronos warning the export lacked); stock Blender imports the result; the diffuse maps
    are softer than the input, red softest, and the input normal map (the specular term's) is untouched."""
    from baker.techniques.normal_blur.extension import NAME, read

    head, out = blurred_head
    source = GltfDocument.load(head)
    assert "TANGENT" in source.json["meshes"][0]["primitives"][0]["attributes"]
    before = assert_khronos_clean(head)["issues"]
    after = assert_khronos_clean(out)["issues"]
    assert after["numWarnings"] <= before["numWarnings"], after["messages"]
    from baker import validate

    report = validate.validate_file(out)
    assert report["issues"]["numErrors"] == 0, [m for m in report["issues"]["messages"] if m["severity"] == 0]
    doc = GltfDocument.load(out)
    material = doc.json["materials"][0]
    assert {NAME, "BAKER_curvature", "BAKER_skin_lut"} <= set(material["extensions"])
    assert "generatedTangents" not in material["extensions"][NAME]  # Blender's TANGENT was used
    assert material["normalTexture"] == source.json["materials"][0]["normalTexture"]

    def detail(texture):  # mean squared tangent-plane part of the normals: the bump's energy
        from baker.gltf.images import decode_image

        pixels = decode_image(doc.image_bytes(doc.json["textures"][texture]["source"]), ".png")
        n = pixels[..., :3].astype(np.float64) / np.iinfo(pixels.dtype).max * 2 - 1
        return float((n[..., :2] ** 2).sum(-1).mean())

    blur = read(doc, 0)
    energies = [detail(t) for t in blur.diffuse_textures]
    original = detail(material["normalTexture"]["index"])
    assert energies[0] < energies[1] <= energies[2] <= original * 1.01 and energies[0] < 0.8 * original, \
        (energies, original)

    report_path = tmp_path / "report.json"
    run_blender(blender_python, "import_report.py", "--out", report_path, "--", out)
    entry = json.loads(report_path.read_text())[str(out)]
    assert entry["error"] is None, entry["error"]
    assert any(o["type"] == "MESH" for o in entry["objects"])


def test_addon_maps_the_diffuse_normals_and_keeps_them_on_export(blender_python, blurred_head, tmp_path):
    """The add-on imports BAKER_normal_blur as a BAKER Diffuse Normals group (the three maps through tangent-space
    Normal Map nodes, one Diffuse BSDF per channel) mixed in at factor 0, and exports the extension unchanged (its
    textures compared by what they hold)."""
    _, baked_head = blurred_head
    exported, report_path = tmp_path / "head_blender.glb", tmp_path / "report.json"
    run_blender(blender_python, "round_trip.py", ADDON, baked_head, exported, report_path)
    report = json.loads(report_path.read_text())
    material = next(m for m in report["materials"].values() if m["payload"])
    assert "BAKER Diffuse Normals" in material["groups"]
    assert material["mixes"].get("BAKER mix diffuse normals") == 0.0
    assert baker_main(["validate", str(exported)]) == 0
    before, after = canonical_extensions(baked_head), canonical_extensions(exported)
    old = next(p for p in before["primitives"] if "BAKER_normal_blur" in json.dumps(p.get("material")))
    new = next(p for p in after["primitives"] if "BAKER_normal_blur" in json.dumps(p.get("material")))
    assert new["material"] == old["material"]


def test_diffuse_normals_group_renders_softer_red(blender_python, blurred_head, tmp_path):
    """Cycles CPU, 128 x 128: the head through BAKER Diffuse Normals, with the baked maps and (control) with the
    material's own sharp normal map in every channel. The ridges' pixel-scale detail drops in red far more than in
    blue, as the profile says (d'Eon's red is the widest)."""
    from scipy import ndimage

    _, baked_head = blurred_head
    out = tmp_path / "render.npz"
    run_blender(blender_python, "render_diffuse_normals.py", ADDON, baked_head, out)
    data = np.load(out)
    blurred, sharp = data["blurred"], data["sharp"]
    inside = ndimage.binary_erosion((sharp[..., 3] > 0.99) & (sharp[..., :3].max(-1) > 0.02), iterations=2)
    assert inside.sum() > 500, "the head covers too few pixels"

    def detail(image, channel):
        c = image[..., channel]
        return float(np.abs(c - ndimage.uniform_filter(c, 3))[inside].mean())

    ratios = [detail(blurred, c) / detail(sharp, c) for c in range(3)]
    print("detail blurred / sharp per channel", ratios)
    # the frame's detail also holds the head's own shape and the path-tracing noise, which both renders share
    assert ratios[0] < 0.9 and ratios[0] < min(ratios[1:]) - 0.08
