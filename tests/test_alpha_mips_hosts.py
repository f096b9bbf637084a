"""Fur that does not thin out with distance, in the web runtimes (headless Chromium, examples/viewer): a furred quad
(`--bakes fur`, alpha-tested shells drawn from their coverage-preserving KTX2 mip chains, Castaño 2010; RTR4
14.7.1) framed at 1, 3 and 6 times the framing distance (?distance=) by @baker/three and by @baker/babylon.

What is measured: the fur's coverage of the quad, i.e. the fraction of the quad's pixels the fur changes (frame with
fur on against the frame with fur off, same page, same camera). From near to far the texture goes from about level
0.3 to about level 3 (8 x 8 texels per tile). The chains hold the fraction of *texels* passing the test (the issue's
criterion, within 10% down to 8 x 8, tests/test_alpha_mips.py); a GPU samples bilinearly and blends two levels, and
on level 0's sharp, antialiased hairs a bilinear sample passes less often than on the blurrier lower levels' blobs:
measured here (SwiftShader), coverage near / 3x / 6x = 0.153 / 0.125 / 0.108 (three.js), 0.169 / 0.107 / 0.093
(Babylon.js, 4x anisotropic by default). So the test asks the far frames to keep at least KEEP of the near coverage,
and the same asset with each chain replaced by the plain box-filtered chain (what mipmapping the PNG gives; written
here with the alpha scale off) to lose it (below LOST of near at 3x and 6x; measured 0): the control that shows the
test can fail. (Matching Castaño's bilinear-sampled coverage instead would hold the frames closer but move the texel
fraction 10-40% or more off level 0's on these shells; see benchmarks/RESULTS.md.)

The hair cards (`baker cards`, a 1024² atlas, so that the far frames sample its levels 4 to 6) likewise: the
plugins swap the base colour for its chain and the loaders' own alpha test cuts it; the hair's drawn pixels x
distance² hold within 20% of the near frame's, and with the box chain instead they fall below CARDS_LOST of it at 6x
(measured: chain 7223 / 7362 / 6948 (three.js), 6878 / 7470 / 6912 (Babylon.js); box 5627 / 3402 / 936 and
5967 / 4635 / 2088).
"""
from __future__ import annotations

import numpy as np
import pytest

import baker
from baker.texels.alpha_mips import alpha_mip_chain, read_coverage_mips
from baker.gltf.document import GltfDocument
from baker.gltf.images import read_image, write_image
from baker.gltf.ktx2 import encode_ktx2
from baker.pipeline import save
from baker.cli import main as baker_main
from browser import BACKGROUND_RGB, ROOT, build_viewer, require_tools, serve, shoot
from conftest import assert_khronos_clean

ARTIFACTS = ROOT / ".cache" / "test-artifacts" / "test_alpha_mips_hosts"
W, H = 480, 360
DISTANCES = (1, 3, 6)
KEEP = 0.5  # the chain: coverage at 3x and 6x at least this fraction of the near frame's
LOST = 0.1  # the box chain: coverage at 3x and 6x below this fraction of the chain's near coverage
CHANGED = 0.08  # a pixel the fur changes by more than this (max over RGB, 0..1)
CARDS_LOST = 0.5  # the cards' box chain: drawn pixels x distance² at 6x below this fraction of the near frame's
# a 2 x 2 quad facing +z, UVs 0..1; 4 tiles of 64 texels across it: 256 texels over ~200 px near, ~35 px far
QUAD_OBJ = ("v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
            "f 1/1/1 2/2/1 3/3/1 4/4/1\n")
# hairs sparse enough that a box-filtered texel falls under the cutoff (dense shells, whose mean alpha exceeds it,
# would thicken instead of thinning: the chain holds coverage both ways, the control shows only the usual way)
FUR = {"shells": 2, "texture_size": 64, "hairs": 800, "root_radius": 0.012, "tip_radius": 0.006, "tiling": 4.0,
       "fins": False}


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    require_tools("alpha mips", ("playwright-core", "three", "@babylonjs/core", "@babylonjs/loaders"))
    root = tmp_path_factory.mktemp("alpha-mips-site")
    build_viewer(root, ("viewer.js", "babylon.js"))
    (root / "quad.obj").write_text(QUAD_OBJ)
    asset = baker.bake(root / "quad.obj", bakes=("fur",), options={"fur": FUR}, seed=1)
    save(asset, root / "fur.glb")
    assert_khronos_clean(root / "fur.glb")
    # the control: every chain replaced by the plain box chain of the same PNG (alpha not scaled)
    doc = GltfDocument.load(root / "fur.glb")
    ext = doc.json["materials"][0]["extensions"]["BAKER_fur"]
    for entry in ext["coverageMips"]:
        base = read_coverage_mips(doc, entry)[0]
        box = alpha_mip_chain(base, entry["alphaCutoff"], transfer="gamma2.2", preserve_coverage=False)
        # from level 1, as baker writes it (firstLevel 1: level 0 is the PNG)
        entry["accessor"] = doc.add_accessor(np.frombuffer(encode_ktx2(box.levels[entry["firstLevel"]:]), np.uint8),
                                             target=None)
    doc.save(root / "fur_box.glb")
    # hair cards of an independent groom, and the same with the atlas's chain replaced by its box chain
    from techniques.cards_groom import make_groom, write_groom_usd

    curves, widths = make_groom(strands=600, clumps=24, seed=6)
    groom = write_groom_usd(root / "groom.usda", curves, widths)
    assert baker_main(["cards", str(groom), "-o", str(root / "cards.glb"), "--cards", "24", "--atlas-size", "1024",
                       "-q"]) == 0
    assert_khronos_clean(root / "cards.glb")
    doc = GltfDocument.load(root / "cards.glb")
    (entry,) = doc.json["materials"][0]["extensions"]["BAKER_hair_cards"]["coverageMips"]
    box = alpha_mip_chain(read_coverage_mips(doc, entry)[0], entry["alphaCutoff"], preserve_coverage=False)
    entry["accessor"] = doc.add_accessor(np.frombuffer(encode_ktx2(box.levels[entry["firstLevel"]:]), np.uint8),
                                         target=None)
    doc.save(root / "cards_box.glb")
    server, url = serve(root)
    yield {"url": url, "root": root}
    server.shutdown()


def _frames(site, tmp_path, engine: str, name: str):
    """{distance: (fur on, fur off)} frames (H, W, 3 in 0..1) of `name` in `engine`'s page."""
    jobs = []
    for d in DISTANCES:
        query = f"{site['url']}/index.html?hud=0&src={name}&distance={d}" + ("&engine=babylon" if engine == "babylon" else "")
        jobs.append({"url": query, "out": str(tmp_path / f"{engine}-{name}-{d}-on.png"), "width": W, "height": H,
                     "shots": [{"on": [], "off": ["fur"], "out": str(tmp_path / f"{engine}-{name}-{d}-off.png")}]})
    infos = shoot(jobs, tmp_path / f"{engine}-{name}.json")
    for info in infos:
        assert info["ready"] and not info["errors"] and not info["warnings"], info
        assert "fur" in info["techniques"], info
    load = lambda p: read_image(p)[..., :3].astype(np.float32) / 255.0  # noqa: E731
    return {d: (load(job["out"]), load(job["shots"][0]["out"])) for d, job in zip(DISTANCES, jobs)}


def fur_coverage(on, off):
    """(fraction of the quad's pixels the fur changes, the quad's pixel count)."""
    background = np.array(BACKGROUND_RGB) / 255.0
    quad = np.abs(off - background).max(axis=2) > 0.03
    changed = np.abs(on - off).max(axis=2) > CHANGED
    return float((changed & quad).sum() / max(quad.sum(), 1)), int(quad.sum())


def _keep(name, frames):
    folder = ARTIFACTS / name
    folder.mkdir(parents=True, exist_ok=True)
    for d, (on, off) in frames.items():
        write_image(folder / f"{d}-on.png", (on * 255 + 0.5).astype(np.uint8))
        write_image(folder / f"{d}-off.png", (off * 255 + 0.5).astype(np.uint8))
    return folder


@pytest.mark.parametrize("engine", ["three", "babylon"])
def test_fur_keeps_its_coverage_at_three_distances(site, tmp_path, engine):
    chain = _frames(site, tmp_path, engine, "fur.glb")
    box = _frames(site, tmp_path, engine, "fur_box.glb")
    kept = {d: fur_coverage(*chain[d]) for d in DISTANCES}
    lost = {d: fur_coverage(*box[d]) for d in DISTANCES}
    print(engine, "coverage-preserving chain", kept, "\n", engine, "box chain", lost)
    near = kept[1][0]
    assert kept[DISTANCES[-1]][1] > 500  # the far quad still has pixels to measure on
    assert 0.05 < near < 0.9, kept
    # near, both chains draw mostly level 0 (the same PNG texels): alike
    assert abs(lost[1][0] - near) < 0.35 * near, (kept, lost)
    far_ok = all(kept[d][0] >= KEEP * near for d in DISTANCES[1:])
    box_thins = all(lost[d][0] < LOST * near for d in DISTANCES[1:])
    if not (far_ok and box_thins):
        _keep(f"{engine}-chain", chain)
        _keep(f"{engine}-box", box)
    assert far_ok, kept
    assert box_thins, lost


@pytest.mark.parametrize("engine", ["three", "babylon"])
def test_hair_cards_keep_their_coverage_at_three_distances(site, tmp_path, engine):
    def drawn(name):
        jobs = [{"url": f"{site['url']}/index.html?hud=0&src={name}&distance={d}"
                        + ("&engine=babylon" if engine == "babylon" else ""),
                 "out": str(tmp_path / f"{engine}-{name}-{d}.png"), "width": W, "height": H} for d in DISTANCES]
        infos = shoot(jobs, tmp_path / f"{engine}-{name}.json")
        for info in infos:
            assert info["ready"] and not info["errors"] and not info["warnings"], info
            assert info["techniques"] == ["cards"], info
        background = np.array(BACKGROUND_RGB) / 255.0
        frames = [read_image(job["out"])[..., :3].astype(np.float32) / 255.0 for job in jobs]
        return {d: int((np.abs(f - background).max(axis=2) > 0.03).sum()) * d * d for d, f in zip(DISTANCES, frames)}

    chain, box = drawn("cards.glb"), drawn("cards_box.glb")
    print(engine, "cards drawn pixels x distance², chain", chain, "box", box)
    near = chain[1]
    assert near > 2000, chain
    assert all(0.8 < chain[d] / near < 1.25 for d in DISTANCES[1:]), chain
    assert box[DISTANCES[-1]] < CARDS_LOST * near, box
