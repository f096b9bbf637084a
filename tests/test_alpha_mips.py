"""Coverage-preserving alpha mip chains (Castaño 2010; RTR4 14.7.1): coverage held at every level down to 8 x 8 on
fur shells and a hair-like texture while a box chain loses it, the box filter against a brute-force footprint
integral, the KTX2 read back by ktx-parse (the reader glTF-Transform and three.js use) and by a reader written here
from the KTX 2.0 spec, and the fur bake's chains in the document: validators clean, levels as computed, corruption
caught."""
from __future__ import annotations

import json
import math
import shutil
import struct
import subprocess
from pathlib import Path

import numpy as np
import pytest

import baker
from baker.texels.alpha_mips import (alpha_coverage, alpha_mip_chain, box_resample, check_coverage_mips, level_sizes,
                                   levels_off_coverage, read_coverage_mips)
from baker.gltf.document import GltfDocument
from baker.gltf.ktx2 import encode_ktx2
from baker.pipeline import save
from baker.techniques.fur.kernel import bake_fur_textures
from baker.techniques.fur.options import FurOptions
from baker.validate import validate_file
from conftest import assert_khronos_clean, khronos_validate

REPO = Path(__file__).resolve().parents[1]
SPOT = str(REPO / "examples" / "spot" / "spot.obj")
KTX_PARSE = REPO / "runtime-shaders" / "gltf-transform" / "node_modules" / "ktx-parse" / "dist" / "ktx-parse.cjs"


def hair_texture(size: int = 256, strands: int = 60, seed: int = 3) -> np.ndarray:
    """Antialiased strands of 0.6 to 1.2 texels width along random gentle curves: what a hair card atlas holds."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:size, 0:size] + 0.5
    alpha = np.zeros((size, size))
    rgb = np.zeros((size, size, 3)) + [0.35, 0.22, 0.12]
    for _ in range(strands):
        x0, amp, freq, phase = rng.uniform(0, size), rng.uniform(2, 12), rng.uniform(1, 3), rng.uniform(0, 2 * math.pi)
        width = rng.uniform(0.6, 1.2)
        centre = x0 + amp * np.sin(freq * 2 * math.pi * y / size + phase)
        cover = np.clip(width / 2 - np.abs(x - centre) + 0.5, 0.0, 1.0) * (y < rng.uniform(0.5, 1.0) * size)
        alpha = np.maximum(alpha, cover)
    out = np.empty((size, size, 4), np.uint8)
    out[..., :3] = np.rint(rgb * 255)
    out[..., 3] = np.rint(alpha * 255)
    return out


# ------------------------------------------------------------------------------------------------ coverage
def test_hair_texture_keeps_coverage_where_a_box_chain_loses_it():
    image = hair_texture()
    sizes = level_sizes(256, 256)
    chain = alpha_mip_chain(image, 0.5)
    box = alpha_mip_chain(image, 0.5, preserve_coverage=False)
    print("preserving", np.round(chain.coverage, 3), "\nbox       ", np.round(box.coverage, 3))
    c0 = chain.coverage[0]
    assert 0.1 < c0 < 0.5
    for level, (h, w) in enumerate(sizes):
        if min(h, w) >= 8:
            assert abs(chain.coverage[level] - c0) <= 0.1 * c0, (level, chain.coverage[level], c0)
    # the coverage is measured on the stored levels, independently of the chain's own bookkeeping
    assert [alpha_coverage(lv[..., 3], 0.5) for lv in chain.levels] == list(chain.coverage)
    # a plain box filter: strands narrower than a texel drop under the cutoff and vanish
    assert box.coverage[3] < 0.5 * c0  # 32 x 32
    assert levels_off_coverage(box.coverage, sizes) and not levels_off_coverage(chain.coverage, sizes)
    # level 0 is the input untouched; alpha only grows (scale >= 1 here: filtering thins, never thickens strands)
    assert np.array_equal(chain.levels[0], image) and (chain.scales >= 1).all()


def test_fur_shells_keep_coverage_at_every_level_down_to_8x8():
    textures = bake_fur_textures(FurOptions(), seed=0)  # the defaults: 16 shells of 128 x 128
    sizes = level_sizes(128, 128)
    lost = 0
    for i, shell in enumerate(textures.shells):
        chain = alpha_mip_chain(shell, 0.5, transfer="gamma2.2")
        box = alpha_mip_chain(shell, 0.5, transfer="gamma2.2", preserve_coverage=False)
        c0 = chain.coverage[0]
        for level, (h, w) in enumerate(sizes):
            if min(h, w) < 8:
                break
            # within 10%; where 10% of the target is less than one texel of the level (the sparse outer shells:
            # a dozen hair tips), within that texel, the finest step a level of h x w texels can hold
            assert abs(chain.coverage[level] - c0) <= max(0.1 * c0, 1 / (h * w)), (i, level, chain.coverage, c0)
            if c0 * h * w >= 20:  # at least 20 texels to keep: the plain 10% bound alone
                assert abs(chain.coverage[level] - c0) <= 0.1 * c0
        lost += bool(levels_off_coverage(box.coverage, sizes))
        assert box.coverage[3] < 0.9 * c0, (i, box.coverage, c0)  # 16 x 16: the box chain has thinned every shell
    assert lost == len(textures.shells)
    fin = alpha_mip_chain(textures.fin, 0.5, transfer="gamma2.2")
    assert not levels_off_coverage(fin.coverage, level_sizes(*textures.fin.shape[:2]))


def test_box_filter_is_the_footprint_integral():
    rng = np.random.default_rng(0)
    image = rng.random((13, 10, 2))
    for h, w in ((6, 5), (3, 2), (1, 1), (13, 10), (4, 7)):
        got = box_resample(image, h, w)
        # brute force: overlap area of each input texel [j, j+1) with the output footprint, per axis
        def weights(n_in, n_out):
            m = np.zeros((n_out, n_in))
            for o in range(n_out):
                a, b = o * n_in / n_out, (o + 1) * n_in / n_out
                for j in range(n_in):
                    m[o, j] = max(0.0, min(b, j + 1) - max(a, j))
            return m / m.sum(axis=1, keepdims=True)
        expected = np.einsum("yi,xj,ijc->yxc", weights(13, h), weights(10, w), image)
        np.testing.assert_allclose(got, expected, atol=1e-12)


def test_colour_is_filtered_premultiplied():
    # an opaque green strand beside transparent red texels: the strand's colour survives, the red does not bleed in
    image = np.zeros((8, 8, 4), np.uint8)
    image[..., 0] = 255
    image[:, 0, :] = (0, 255, 0, 255)
    chain = alpha_mip_chain(image, 0.5, transfer="linear")
    assert tuple(chain.levels[1][0, 0, :3]) == (0, 255, 0)
    assert tuple(chain.levels[1][0, 3, :3]) == (255, 0, 0)  # nothing covers it: its plain average is kept
    # level 0 covers 1/8; 4 x 4 can hold 0 or 1/4, equally far: the strand is kept (its half-covered texels pass)
    assert chain.levels[1][0, 0, 3] >= 128 and alpha_coverage(chain.levels[1][..., 3], 0.5) == 0.25


def test_non_power_of_two_and_determinism():
    image = hair_texture(size=100)[:60]  # 100 x 60
    a = alpha_mip_chain(image, 0.4)
    b = alpha_mip_chain(image.copy(), 0.4)
    assert [lv.shape[:2] for lv in a.levels] == [(60, 100), (30, 50), (15, 25), (7, 12), (3, 6), (1, 3), (1, 1)]
    assert encode_ktx2(a.levels) == encode_ktx2(b.levels)
    with pytest.raises(ValueError):
        alpha_mip_chain(image[..., :3], 0.5)
    with pytest.raises(ValueError):
        alpha_mip_chain(image, 1.5)


# ------------------------------------------------------------------------------------------------ KTX2 readers
def read_ktx2_per_spec(blob: bytes) -> dict:
    """A KTX 2.0 reader written from the spec (https://registry.khronos.org/KTX/specs/2.0/ktxspec.v2.html), for
    uncompressed formats only; independent of baker.gltf.ktx2."""
    assert blob[:12] == bytes([0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A])
    fields = struct.unpack_from("<9I", blob, 12)
    names = ("vkFormat", "typeSize", "pixelWidth", "pixelHeight", "pixelDepth", "layerCount", "faceCount",
             "levelCount", "supercompressionScheme")
    header = dict(zip(names, fields))
    dfd_offset, dfd_length, kvd_offset, kvd_length, sgd_offset, sgd_length = struct.unpack_from("<IIIIQQ", blob, 48)
    levels = []
    for i in range(header["levelCount"]):
        offset, length, uncompressed = struct.unpack_from("<QQQ", blob, 80 + 24 * i)
        levels.append((offset, length, uncompressed))
    # DFD: dfdTotalSize, then the basic descriptor block
    total, word1, word2, word3, word4 = struct.unpack_from("<5I", blob, dfd_offset)
    model, primaries, transfer = word3 & 0xFF, (word3 >> 8) & 0xFF, (word3 >> 16) & 0xFF
    bytes_plane0 = struct.unpack_from("<I", blob, dfd_offset + 4 + 16)[0] & 0xFF
    kvd, pos = {}, kvd_offset
    while pos < kvd_offset + kvd_length:
        n = struct.unpack_from("<I", blob, pos)[0]
        key, value = blob[pos + 4: pos + 4 + n].split(b"\0", 1)
        kvd[key.decode()] = value.rstrip(b"\0").decode()
        pos += 4 + n + (-n % 4)
    return {**header, "dfdTotalSize": total, "dfdByteLength": dfd_length, "colorModel": model,
            "colorPrimaries": primaries, "transferFunction": transfer, "bytesPlane0": bytes_plane0,
            "kvd": kvd, "levels": levels, "sgdByteLength": sgd_length}


def test_ktx2_read_per_spec_and_by_ktx_parse(tmp_path):
    chain = alpha_mip_chain(hair_texture(size=64)[:, :48], 0.5)  # 48 x 64
    blob = encode_ktx2(chain.levels)
    spec = read_ktx2_per_spec(blob)
    assert spec["vkFormat"] == 37 and spec["typeSize"] == 1  # VK_FORMAT_R8G8B8A8_UNORM
    assert (spec["pixelWidth"], spec["pixelHeight"], spec["pixelDepth"]) == (48, 64, 0)
    assert spec["layerCount"] == 0 and spec["faceCount"] == 1 and spec["supercompressionScheme"] == 0
    assert spec["levelCount"] == len(chain.levels) == 7
    assert spec["dfdTotalSize"] == spec["dfdByteLength"] and spec["sgdByteLength"] == 0
    assert (spec["colorModel"], spec["colorPrimaries"], spec["bytesPlane0"]) == (1, 1, 4)  # RGBSDA, BT.709
    assert spec["kvd"]["KTXorientation"] == "rd"
    offsets = [o for o, _, _ in spec["levels"]]
    assert offsets == sorted(offsets, reverse=True)  # smallest level stored first, base last
    for (offset, length, uncompressed), level in zip(spec["levels"], chain.levels):
        assert offset % 4 == 0 and length == uncompressed == level.size
        assert blob[offset: offset + length] == level.tobytes()

    node = shutil.which("node")
    if node is None or not KTX_PARSE.exists():
        pytest.fail("node and ktx-parse are required (scripts/install-node-tools installs glTF-Transform's)")
    path = tmp_path / "chain.ktx2"
    path.write_bytes(blob)
    script = f"""
const {{ read }} = require({json.dumps(str(KTX_PARSE))});
const fs = require('fs');
const c = read(new Uint8Array(fs.readFileSync({json.dumps(str(path))})));
const crypto = require('crypto');
console.log(JSON.stringify({{vkFormat: c.vkFormat, width: c.pixelWidth, height: c.pixelHeight, levels: c.levels.map(
  (l) => ({{bytes: l.levelData.length, sha: crypto.createHash('sha256').update(l.levelData).digest('hex')}})),
  orientation: c.keyValue.KTXorientation, model: c.dataFormatDescriptor[0].colorModel,
  samples: c.dataFormatDescriptor[0].samples.map((s) => s.channelType)}}));
"""
    out = json.loads(subprocess.run([node, "-e", script], capture_output=True, text=True, check=True).stdout)
    import hashlib

    assert out["vkFormat"] == 37 and (out["width"], out["height"]) == (48, 64) and out["model"] == 1
    assert out["samples"] == [0, 1, 2, 15]  # R, G, B, alpha
    assert out["orientation"].startswith("rd")
    assert [lv["bytes"] for lv in out["levels"]] == [lv.size for lv in chain.levels]
    assert [lv["sha"] for lv in out["levels"]] == [hashlib.sha256(lv.tobytes()).hexdigest() for lv in chain.levels]


# ------------------------------------------------------------------------------------------------ in the document
@pytest.fixture(scope="module")
def fur_files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fur_mips")
    asset = baker.bake(SPOT, bakes=["fur"], options={"fur": {"fins": True, "shells": 4, "texture_size": 64, "hairs": 400}}, seed=2)
    paths = [folder / "fur.glb", folder / "fur.gltf"]
    for p in paths:
        save(asset, p)
    plain = baker.bake(SPOT, bakes=["fur"], options={"fur": {"fins": True, "shells": 4, "texture_size": 64, "hairs": 400,
                                                              "coverage_mips": False}}, seed=2)
    save(plain, folder / "plain.glb")
    return paths + [folder / "plain.glb"]


def test_fur_bake_ships_a_chain_per_alpha_tested_texture(fur_files):
    glb, gltf, plain = fur_files
    kernel = bake_fur_textures(FurOptions(shells=4, texture_size=64, hairs=400), seed=2)
    for path in (glb, gltf):
        report = validate_file(path, khronos=False)
        assert report["issues"]["numErrors"] == 0 and report["issues"]["numWarnings"] == 0, report["issues"]
        assert_khronos_clean(path)
        doc = GltfDocument.load(path)
        ext = doc.json["materials"][0]["extensions"]["BAKER_fur"]
        assert ext["alphaCutoff"] == 0.5
        entries = {e["texture"]: e for e in ext["coverageMips"]}
        textures = [t["index"] for t in ext["shellTextures"]] + [ext["finTexture"]["index"]]
        assert sorted(entries) == sorted(textures)
        for texture, pixels in zip(textures, [*kernel.shells, kernel.fin]):
            levels = read_coverage_mips(doc, entries[texture])
            expected = alpha_mip_chain(pixels, 0.5, transfer="gamma2.2")
            assert len(levels) == entries[texture]["levelCount"] == len(expected.levels)
            assert all(np.array_equal(a, b) for a, b in zip(levels, expected.levels))
            assert entries[texture]["coverage"] == expected.coverage[0]
    # the plain viewer's view is unchanged: same PNG images with and without the chains; Khronos adds nothing
    with_mips, without = khronos_validate(glb), khronos_validate(plain)
    codes = lambda r: sorted((m["code"], m["severity"]) for m in r["issues"]["messages"] if m["severity"] <= 1)
    assert codes(with_mips) == codes(without) == []
    a, b = GltfDocument.load(glb), GltfDocument.load(plain)
    assert [a.image_bytes(i) for i in range(len(a.json["images"]))] == \
        [b.image_bytes(i) for i in range(len(b.json["images"]))]
    assert "coverageMips" not in b.json["materials"][0]["extensions"]["BAKER_fur"]


class Issues:
    def __init__(self):
        self.items = []

    def error(self, code, message, ptr):
        self.items.append(("error", code, ptr))

    def warning(self, code, message, ptr):
        self.items.append(("warning", code, ptr))


def test_check_catches_broken_chains(fur_files):
    doc = GltfDocument.load(fur_files[0])
    ext = doc.json["materials"][0]["extensions"]["BAKER_fur"]
    entries = ext["coverageMips"]
    issues = Issues()
    check_coverage_mips(doc, entries, "/x", issues)
    assert issues.items == []
    texture = entries[0]["texture"]
    image = doc.json["textures"][texture]["source"]
    from baker.gltf.images import decode_image

    pixels = decode_image(doc.image_bytes(image), ".png")
    cases = {
        "box chain": ("warning", "BAKER_COVERAGE_MIPS_COVERAGE",
                      encode_ktx2(alpha_mip_chain(pixels, 0.5, preserve_coverage=False).levels)),
        "other base": ("error", "BAKER_COVERAGE_MIPS_BASE",
                       encode_ktx2(alpha_mip_chain(255 - pixels, 0.5).levels)),
        "short chain": ("error", "BAKER_COVERAGE_MIPS_LEVELS", encode_ktx2(alpha_mip_chain(pixels, 0.5).levels[:3])),
        "truncated": ("error", "BAKER_COVERAGE_MIPS_KTX2", encode_ktx2(alpha_mip_chain(pixels, 0.5).levels)[:300]),
    }
    for name, (severity, code, blob) in cases.items():
        broken = GltfDocument.load(fur_files[0])
        entry = {**entries[0], "firstLevel": 0}  # these KTX2s hold every level
        entry["accessor"] = broken.add_accessor(np.frombuffer(blob, np.uint8), target=None)
        issues = Issues()
        check_coverage_mips(broken, [entry], "/x", issues)
        assert issues.items == [(severity, code, issues.items[0][2])], (name, issues.items)
    # baker's chains start at level 1 (level 0 is the PNG): a KTX2 whose first level is not the image's half is refused
    assert entries[0]["firstLevel"] == 1 and len(read_coverage_mips(doc, entries[0])) == entries[0]["levelCount"]
    broken = GltfDocument.load(fur_files[0])
    entry = {**entries[0], "accessor": broken.add_accessor(
        np.frombuffer(encode_ktx2(alpha_mip_chain(pixels, 0.5).levels[2:]), np.uint8), target=None)}
    issues = Issues()
    check_coverage_mips(broken, [entry], "/x", issues)
    assert [i[1] for i in issues.items] == ["BAKER_COVERAGE_MIPS_KTX2"]
    issues = Issues()
    check_coverage_mips(doc, [{**entries[0], "accessor": 10 ** 6}, {**entries[0], "alphaCutoff": 2}], "/x", issues)
    assert [i[1] for i in issues.items] == ["BAKER_COVERAGE_MIPS_KTX2", "BAKER_COVERAGE_MIPS_CUTOFF"]


def test_corrupt_chain_is_one_line_exit_2(fur_files, tmp_path, capsys):
    from baker.cli import main

    doc = GltfDocument.load(fur_files[0])
    ext = doc.json["materials"][0]["extensions"]["BAKER_fur"]
    ext["coverageMips"][0]["accessor"] = doc.add_accessor(np.zeros(200, np.uint8), target=None)
    out = tmp_path / "broken.glb"
    doc.save(out)
    code = main(["validate", str(out)])
    err = capsys.readouterr()
    assert code != 0 and "BAKER_COVERAGE_MIPS_KTX2" in err.out + err.err
    assert "Traceback" not in err.out + err.err


def test_inspect_lists_the_chains(fur_files, capsys):
    from baker.cli import main

    assert main(["inspect", str(fur_files[0]), "--format", "json"]) == 0
    info = json.loads(capsys.readouterr().out)
    rows = info["coverageMips"]
    assert len(rows) == 5 and {r["place"] for r in rows} == {"/materials/0/extensions/BAKER_fur"}
    for row in rows:
        sizes = level_sizes(row["size"][1], row["size"][0])
        assert row["levels"] == len(sizes) and row["alphaCutoff"] == 0.5
        assert not levels_off_coverage(np.array(row["coverage"]), sizes)


def test_usd_references_each_chain(fur_files, tmp_path):
    from pxr import Usd

    from baker.gltf.usd import write_usd

    doc = GltfDocument.load(fur_files[0])
    ext = doc.json["materials"][0]["extensions"]["BAKER_fur"]
    stage_path = tmp_path / "fur.usda"
    write_usd(doc, stage_path)
    stage = Usd.Stage.Open(str(stage_path))
    (material,) = [p for p in stage.Traverse() if p.GetTypeName() == "Material"]
    for i, entry in enumerate(ext["coverageMips"]):
        at = f"baker:fur:coverageMips:_{i}"
        ktx2 = Path(material.GetAttribute(f"{at}:file").Get().resolvedPath)
        png = Path(material.GetAttribute(f"{at}:image").Get().resolvedPath)
        assert ktx2.suffix == ".ktx2" and png.suffix == ".png"
        assert material.GetAttribute(f"{at}:alphaCutoff").Get() == 0.5
        spec = read_ktx2_per_spec(ktx2.read_bytes())
        blob = ktx2.read_bytes()
        expected = read_coverage_mips(doc, entry)
        first = material.GetAttribute(f"{at}:firstLevel").Get()
        assert first == entry["firstLevel"] == 1  # the KTX2 starts at level 1, level 0 is the PNG beside it
        assert spec["levelCount"] + first == material.GetAttribute(f"{at}:levelCount").Get() == len(expected)
        for (offset, length, _), level in zip(spec["levels"], expected[first:]):
            assert blob[offset: offset + length] == level.tobytes()
        texture = doc.json["textures"][entry["texture"]]
        assert png.read_bytes() == doc.image_bytes(texture["source"])


# ------------------------------------------------------------------------------------------------ baker preview
QUAD_OBJ = ("v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
            "f 1/1/1 2/2/1 3/3/1 4/4/1\n")
QUAD_FUR = {"shells": 2, "texture_size": 64, "hairs": 800, "root_radius": 0.012, "tip_radius": 0.006, "tiling": 4.0,
            "fins": False}


def _replace_chains(source, target, make_levels):
    """Copy of the furred file with every chain's KTX2 replaced by make_levels(level 0, cutoff)."""
    doc = GltfDocument.load(source)
    for entry in doc.json["materials"][0]["extensions"]["BAKER_fur"]["coverageMips"]:
        base = read_coverage_mips(doc, entry)[0]
        levels = make_levels(base, entry["alphaCutoff"])
        entry["accessor"] = doc.add_accessor(np.frombuffer(encode_ktx2(levels), np.uint8), target=None)
        entry["firstLevel"] = 0  # the whole chain in the KTX2 (the form before issue 48, which readers still take)
    doc.save(target)
    return target


def test_preview_fur_keeps_coverage_when_small(tmp_path):
    """`baker preview`'s fur panel draws the shells alpha-tested from the chains: rendered at 384, 128 and 64 px (the
    quad 3x and 6x as far) the fur keeps at least half its near coverage (texel coverage is what the chain holds;
    bilinear sampling of level 0's sharp hairs passes less often, see tests/test_alpha_mips_hosts.py), while with
    the box chain it is gone."""
    from baker.preview.core import BACKGROUND, preview

    (tmp_path / "quad.obj").write_text(QUAD_OBJ)
    fur = tmp_path / "fur.glb"
    save(baker.bake(tmp_path / "quad.obj", bakes=["fur"], options={"fur": QUAD_FUR}, seed=1), fur)
    box = _replace_chains(fur, tmp_path / "box.glb", lambda base, cut: alpha_mip_chain(
        base, cut, transfer="gamma2.2", preserve_coverage=False).levels)
    bare = _replace_chains(fur, tmp_path / "bare.glb", lambda base, cut: [
        np.concatenate([lv[..., :3], np.zeros_like(lv[..., 3:])], axis=2)
        for lv in alpha_mip_chain(base, cut, transfer="gamma2.2").levels])  # every texel fails: the skin alone

    def coverage(path, size):
        result = preview(path, size=size, azimuth=20, elevation=10, panels=["fur"])
        (_, _, (y, x, s)), = [p for p in result.panels if p[0] == "fur"]
        return result.sheet[y: y + s, x: x + s].astype(np.float64) / 255.0

    measured = {}
    for name, path in (("chain", fur), ("box", box)):
        for size in (384, 128, 64):
            on, off = coverage(path, size), coverage(bare, size)
            quad = np.abs(off - np.array(BACKGROUND)).max(axis=2) > 0.02
            changed = np.abs(on - off).max(axis=2) > 0.02  # the shells over the reference-shaded surface
            measured[name, size] = float((changed & quad).sum() / quad.sum())
    print(measured)
    near = measured["chain", 384]
    assert 0.05 < near < 0.9
    assert measured["chain", 128] >= 0.5 * near and measured["chain", 64] >= 0.5 * near
    assert measured["box", 128] < 0.1 * near and measured["box", 64] < 0.1 * near
