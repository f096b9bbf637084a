"""``baker bake --compress meshopt`` (issue 48, item 4): EXT_meshopt_compression written by baker, the bake intact.

The spot with every surface bake is written plain and compressed. The compressed files must be clean for baker
validate and Khronos glTF-Validator; with ``meshopt-lossless`` every accessor must decode to the plain file's bytes,
with ``meshopt`` and ``meshopt-gzip`` too but for the float vertex attributes of EXPONENTIAL_BITS, which must decode
within their stated bound of the plain values; through baker's reader (baker/gltf/compression.py) and independently
through three.js's GLTFLoader with meshoptimizer's MeshoptDecoder in Node (examples/viewer/test/accessor_digests.mjs,
whose bytes must equal baker's decode); three.js and Babylon.js must draw both files alike in headless Chromium. The mode choice is checked on hand-made index data: the triangle codec is kept only where it decodes to
the stored corner order.
"""
from __future__ import annotations

import gzip
import hashlib
import json
import subprocess
import sys

import meshopt
import numpy as np
import pytest
from scipy import ndimage
from skimage.metrics import structural_similarity

import baker
from baker.gltf.compression import decompress
from baker.gltf.document import GltfDocument
from baker.gltf.images import read_image
from baker.gltf.meshopt_encode import EXPONENTIAL_BITS, EXTENSION, OCTAHEDRAL_BITS, compress_meshopt
from baker.pipeline import save
from baker.validate import validate_file
from browser import BACKGROUND_RGB, SPOT, SPOT_PAGE_OPTIONS, VIEWER, build_viewer, require_tools, serve, shoot
from conftest import assert_khronos_clean

BAKES = ("thickness", "curvature", "skin", "edges", "tam", "toon", "fur")
SIZE = 256


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    root = tmp_path_factory.mktemp("meshopt")
    asset = baker.bake(SPOT, bakes=BAKES, options={k: v for k, v in SPOT_PAGE_OPTIONS.items() if k in BAKES})
    save(asset, root / "plain.glb")
    save(asset, root / "meshopt.glb", compress="meshopt")
    save(asset, root / "meshopt-gzip.glb", compress="meshopt-gzip")
    save(asset, root / "meshopt-lossless.glb", compress="meshopt-lossless")
    return root


def _accessor_bytes(doc: GltfDocument) -> list[bytes]:
    return [np.ascontiguousarray(doc.accessor(i)).tobytes() for i in range(len(doc.json.get("accessors") or []))]


def _gzip(path) -> int:
    return len(gzip.compress(path.read_bytes(), compresslevel=6, mtime=0))


def test_each_target_is_smallest_where_it_aims(files):
    plain, small, gzipped = (files / f"{name}.glb" for name in ("plain", "meshopt", "meshopt-gzip"))
    assert small.stat().st_size < gzipped.stat().st_size < plain.stat().st_size
    assert _gzip(gzipped) < min(_gzip(plain), _gzip(small))


def _filtered_accessors(gltf: dict) -> dict[int, tuple[str, str]]:
    """accessor -> (attribute name, filter), for the accessors whose bufferView is stored with a filter."""
    filtered = {i: v["extensions"][EXTENSION]["filter"] for i, v in enumerate(gltf["bufferViews"])
                if "filter" in v.get("extensions", {}).get(EXTENSION, {})}
    return {a: (name, filtered[gltf["accessors"][a]["bufferView"]]) for mesh in gltf["meshes"]
            for prim in mesh["primitives"] for name, a in prim["attributes"].items()
            if gltf["accessors"][a].get("bufferView") in filtered}


@pytest.mark.parametrize("name", ["meshopt", "meshopt-gzip", "meshopt-lossless"])
def test_compressed_bake_is_clean_and_decodes_to_the_same_bytes(files, name):
    plain, packed = files / "plain.glb", files / f"{name}.glb"
    report = validate_file(packed)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert report["validators"] == ["baker", "khronos"]
    assert_khronos_clean(packed)

    a, b = GltfDocument.load(plain), GltfDocument.load(packed)
    assert decompress(b)[0]["extension"] == EXTENSION  # baker's reader of compressed inputs
    raw = json.loads(packed.read_bytes()[20: 20 + int.from_bytes(packed.read_bytes()[12:16], "little")])
    assert EXTENSION in raw["extensionsRequired"]
    assert raw["buffers"][1] == {"byteLength": raw["buffers"][1]["byteLength"],
                                 "extensions": {EXTENSION: {"fallback": True}}}  # a size, no data
    modes = [v["extensions"][EXTENSION]["mode"] for v in raw["bufferViews"] if EXTENSION in v.get("extensions", {})]
    assert modes.count("ATTRIBUTES") >= 5 and "INDICES" in modes, modes
    filtered = _filtered_accessors(raw)
    if name == "meshopt-lossless":
        assert "filter" not in json.dumps(raw["bufferViews"])  # lossless: no filter
    else:  # every baked float attribute the spot has, and nothing else; unit vectors octahedral
        assert sorted({n for n, _ in filtered.values()}) == sorted(EXPONENTIAL_BITS), filtered
        assert {n for n, f in filtered.values() if f == "OCTAHEDRAL"} == set(OCTAHEDRAL_BITS), filtered
        assert "KHR_mesh_quantization" in raw["extensionsRequired"]  # NORMAL as normalized SHORT
    # the bake intact: every extension and accessor where it was, with the same bytes but for the filtered ones
    for key in ("meshes", "materials", "nodes"):
        assert a.json.get(key) == b.json.get(key), key
    assert [e for e in b.json["extensionsUsed"] if e != "KHR_mesh_quantization"] == a.json["extensionsUsed"]
    plain_bytes, packed_bytes = _accessor_bytes(a), _accessor_bytes(b)
    assert len(plain_bytes) > 30 and any("BAKER_" in name for name in a.json["extensionsUsed"])
    for i, (before, after) in enumerate(zip(a.json["accessors"], b.json["accessors"])):
        if i not in filtered:
            assert before == after and plain_bytes[i] == packed_bytes[i], i
            continue
        # each value within its stated bound of the plain one, the bounds those of the decoded values
        attribute, filter_name = filtered[i]
        kept = ("min", "max", "componentType", "normalized") if filter_name == "OCTAHEDRAL" else ("min", "max")
        assert {k: v for k, v in before.items() if k not in kept} == {k: v for k, v in after.items() if k not in kept}
        original, decoded = np.asarray(a.accessor(i), np.float64), np.asarray(b.accessor(i), np.float64)
        if filter_name == "OCTAHEDRAL":  # normalized SHORT, unit length
            assert after["componentType"] == 5122 and after["normalized"] and b.accessor(i).dtype == np.int16
            unit = decoded / 32767.0
            assert np.abs(unit - original).max() <= 2.0 ** (2 - OCTAHEDRAL_BITS[attribute]), attribute
            assert np.abs(np.linalg.norm(unit, axis=1) - 1.0).max() <= 1e-4, attribute
            continue
        mode, bits = EXPONENTIAL_BITS[attribute]
        scale = np.abs(original) if mode == "Separate" else np.abs(original).max(axis=1, keepdims=True)
        error = np.abs(decoded - original)
        assert (error <= scale * 2.0 ** (1 - bits) + 1e-30).all(), attribute
        assert 0 < error.max() and b.accessor(i).dtype == np.float32, attribute  # filtered: changed, still floats
        if "min" in after:
            assert np.allclose(after["min"], decoded.min(axis=0)) and np.allclose(after["max"], decoded.max(axis=0))

    # independently: three.js's GLTFLoader + MeshoptDecoder reads the compressed file's accessors as those bytes
    require_tools("meshopt", ("three",))
    result = subprocess.run(["node", str(VIEWER / "test" / "accessor_digests.mjs"), str(packed)], capture_output=True,
                            text=True, timeout=120, cwd=VIEWER)
    assert result.returncode == 0, result.stderr
    digests = json.loads(result.stdout.strip().splitlines()[-1])["accessors"]
    assert digests == [hashlib.sha256(data).hexdigest() for data in packed_bytes]


def _luma(image):
    return ndimage.gaussian_filter(image, sigma=(1.0, 1.0, 0)) @ np.array([0.2126, 0.7152, 0.0722], np.float32)


def test_three_and_babylon_draw_it_like_the_plain_file(files, tmp_path):
    require_tools("meshopt", ("playwright-core", "three", "@babylonjs/core", "@babylonjs/loaders"))
    build_viewer(files, ("viewer.js", "babylon.js"))
    server, url = serve(files)
    try:
        jobs = [{"url": f"{url}/index.html?hud=0&src={name}.glb{engine}", "out": str(tmp_path / f"{name}{engine}.png"),
                 "width": SIZE, "height": SIZE}
                for engine in ("", "&engine=babylon") for name in ("plain", "meshopt")]
        infos = shoot(jobs, tmp_path / "jobs.json")
    finally:
        server.shutdown()
    for job, info in zip(jobs, infos):
        assert info["ready"] and not info["errors"], (job["url"], info)
    background = np.array(BACKGROUND_RGB, np.float32) / 255.0
    for plain_job, packed_job in (jobs[0:2], jobs[2:4]):
        plain = read_image(plain_job["out"])[..., :3].astype(np.float32) / 255.0
        packed = read_image(packed_job["out"])[..., :3].astype(np.float32) / 255.0
        assert 0.05 < (np.abs(plain - background).max(axis=2) > 0.03).mean() < 0.9  # the cow is on screen
        ssim = structural_similarity(_luma(plain), _luma(packed), data_range=1.0)
        differing = float((np.abs(plain - packed).max(axis=2) > 2 / 255).mean())
        print(f"{packed_job['url']}: SSIM {ssim:.4f}, pixels differing > 2/255: {differing:.4%}")  # for the record
        assert ssim >= 0.95 and differing < 0.01, (packed_job["url"], ssim, differing)


def _triangle_document(indices: np.ndarray) -> tuple[dict, bytes]:
    positions = np.random.default_rng(0).random((int(indices.max()) + 1, 3)).astype(np.float32)
    doc = GltfDocument.from_triangles("t.glb", "t", {"POSITION": positions}, indices, "test")
    return doc.json, bytes(doc.bin)


def _stored_mode(gltf: dict, accessor: int) -> str | None:
    view = gltf["bufferViews"][gltf["accessors"][accessor]["bufferView"]]
    return view.get("extensions", {}).get(EXTENSION, {}).get("mode")


def _decoded(gltf: dict, data: bytes, accessor: int) -> bytes:
    ext = gltf["bufferViews"][gltf["accessors"][accessor]["bufferView"]]["extensions"][EXTENSION]
    stored = bytes(data[ext["byteOffset"]: ext["byteOffset"] + ext["byteLength"]])
    return meshopt.decode_gltf_buffer(stored, ext["count"], ext["byteStride"], ext["mode"]).tobytes()


def test_triangle_codec_only_where_it_keeps_the_corner_order():
    # a grid's triangles in a vertex-cache order: the triangle codec rotates the corners of some of them
    n = 40
    grid = [(r * n + c, r * n + c + 1, (r + 1) * n + c) for r in range(n - 1) for c in range(n - 1)]
    grid += [(r * n + c + 1, (r + 1) * n + c + 1, (r + 1) * n + c) for r in range(n - 1) for c in range(n - 1)]
    rotated = meshopt.reorder_mesh(np.array(grid, np.uint32).reshape(-1), True, False)[0].astype(np.uint32)
    packed = meshopt.encode_index_buffer(rotated)
    assert not np.array_equal(meshopt.decode_index_buffer(packed, len(rotated), 4), rotated)  # the premise
    gltf, binary = _triangle_document(rotated)
    out, data, summary = compress_meshopt(gltf, binary)
    assert _stored_mode(out, 0) in ("INDICES", "ATTRIBUTES") and summary["TRIANGLES"] == 0  # the smaller of them
    assert _decoded(out, data, 0) == rotated.tobytes()

    # the same triangles in the codec's own corner order (decoded once): kept as TRIANGLES, byte for byte
    canonical = meshopt.decode_index_buffer(packed, len(rotated), 4).astype(np.uint32)
    gltf, binary = _triangle_document(canonical)
    out, data, summary = compress_meshopt(gltf, binary)
    assert _stored_mode(out, 0) == "TRIANGLES" and summary["TRIANGLES"] == 1
    assert _decoded(out, data, 0) == canonical.tobytes()


def test_compress_is_glb_or_gltf_only(tmp_path):
    result = subprocess.run([sys.executable, "-m", "baker.cli", "bake", str(SPOT), "-o", str(tmp_path / "spot.usda"),
                             "--compress", "meshopt"], capture_output=True, text=True)
    assert result.returncode == 2
    assert len(result.stderr.strip().splitlines()) == 1 and "--compress meshopt" in result.stderr, result.stderr
    assert not (tmp_path / "spot.usda").exists()


def test_recipe_compress_key(tmp_path):
    """``compress`` in a recipe's [build] (or [[assets]]) as ``--compress``; refused with USD output."""
    import trimesh

    from baker.commands.build import build, load_recipe
    from baker.errors import BakerError

    (tmp_path / "models").mkdir()
    trimesh.creation.icosphere(subdivisions=2).export(tmp_path / "models" / "ball.obj")
    recipe = ('[build]\noutput = "out"\nbakes = ["thickness", "edges"]\ncompress = "meshopt"\n'
              '[options.thickness]\nrays = 4\nper_texel = false\n[[assets]]\ninputs = ["models/*.obj"]\n')
    (tmp_path / "baker.toml").write_text(recipe)
    report = build(load_recipe(tmp_path / "baker.toml"))
    assert report["baked"] == ["out/models/ball.glb"] and not report["failed"], report
    out = tmp_path / "out" / "models" / "ball.glb"
    gltf = json.loads(out.read_bytes()[20: 20 + int.from_bytes(out.read_bytes()[12:16], "little")])
    assert gltf["extensionsRequired"] == [EXTENSION, "KHR_mesh_quantization"]  # octahedral normals
    assert "BAKER_edges" in gltf["extensionsUsed"]
    assert validate_file(out, khronos=False)["issues"]["numErrors"] == 0
    (tmp_path / "baker.toml").write_text(recipe.replace('compress = "meshopt"', 'compress = "meshopt"\nformat = "usda"'))
    with pytest.raises(BakerError, match="compress"):
        load_recipe(tmp_path / "baker.toml")
    (tmp_path / "baker.toml").write_text(recipe.replace('"meshopt"', '"zip"'))
    with pytest.raises(BakerError, match="compress"):
        load_recipe(tmp_path / "baker.toml")
