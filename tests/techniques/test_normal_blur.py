"""normal-blur against analytic truth: a sphere (glTF metres) carrying a closed-form plane-wave bump; the gain each
diffuse map applies to the bump must be the recorded Gaussians' exp(-k^2 v / 2) summed with their weights, in every
region; a UV-space blur of the same kernels fails it; the stretch map is the sphere's |dP/du|, |dP/dv|."""
from __future__ import annotations

import math

import numpy as np
import pytest

import baker
from baker import validate
from baker.gltf.document import GltfDocument, TARGET_ELEMENT_ARRAY_BUFFER
from baker.gltf.images import decode_image, encode_image
from baker.pipeline import save
from baker.techniques.normal_blur.extension import NAME, read
from tests.conftest import assert_khronos_clean

RADIUS = 0.03  # m: a 6 cm ball, the curvature of a nose or a cheek
CYCLES = 47  # u-waves: whole waves around every latitude (continuous across the seam); 4 mm at the equator
WAVELENGTH = 0.004  # v-waves: metres along the meridians
AMPLITUDE = 0.15  # slope of the bump
SIZE = 512


def bump_sphere(path, wave: str = "u", tangents: bool = True, radius: float = RADIUS, segments: int = 256,
                rings: int = 256, size: int = SIZE, scale: float = 1.0):
    """A UV sphere (u = longitude, v = colatitude over the whole square, one seam) with exact normals, TANGENT along
    dP/du, and a 16-bit normal map whose tangent-space slope is AMPLITUDE sin(phase): phase = CYCLES * 2 pi u
    ("u": waves along u) or 2 pi R pi v / WAVELENGTH ("v": along the meridians)."""
    i, j = np.meshgrid(np.arange(rings + 1), np.arange(segments + 1), indexing="ij")
    theta, phi = np.pi * i / rings, 2 * np.pi * j / segments
    n = np.stack([np.sin(theta) * np.cos(phi), np.cos(theta), -np.sin(theta) * np.sin(phi)], -1).reshape(-1, 3)
    t = np.stack([-np.sin(phi), np.zeros_like(phi), -np.cos(phi)], -1).reshape(-1, 3)
    uv = np.stack([j / segments, i / rings], -1).reshape(-1, 2)
    idx = np.arange((rings + 1) * (segments + 1)).reshape(rings + 1, segments + 1)
    a, b, c, d = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
    faces = np.concatenate([np.stack([a, b, d], -1)[1:].reshape(-1, 3),
                            np.stack([b, c, d], -1)[:-1].reshape(-1, 3)])
    doc = GltfDocument()
    attrs = {"POSITION": doc.add_accessor((radius * n).astype(np.float32), min_max=True),
             "NORMAL": doc.add_accessor(n.astype(np.float32)),
             "TEXCOORD_0": doc.add_accessor(uv.astype(np.float32))}
    if tangents:
        attrs["TANGENT"] = doc.add_accessor(np.concatenate([t, np.ones((len(t), 1))], 1).astype(np.float32))
    ind = doc.add_accessor(faces.reshape(-1).astype(np.uint32), target=TARGET_ELEMENT_ARRAY_BUFFER)
    local, _ = bump_field(size, wave, radius)
    local[..., :2] /= scale
    local /= np.linalg.norm(local, axis=-1, keepdims=True)
    png = encode_image(np.rint((local + 1) / 2 * 65535).astype(np.uint16), ".png")
    texture = doc.add_texture(doc.add_image(png, "image/png", "bump"), sampler={"magFilter": 9729, "minFilter": 9987})
    normal_texture = {"index": texture} if scale == 1.0 else {"index": texture, "scale": scale}
    doc.json.update({"scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
                     "meshes": [{"primitives": [{"attributes": attrs, "indices": ind, "material": 0}]}],
                     "materials": [{"name": "skin", "normalTexture": normal_texture,
                                    "pbrMetallicRoughness": {"metallicFactor": 0.0}}]})
    doc.save(path)
    return path


def bump_field(size: int, wave: str, radius: float = RADIUS):
    """(unit tangent-space normals (size, size, 3), slope (size, size)) at the texel centres, and per texel the
    wavenumber on the surface (1/m)."""
    centres = (np.arange(size) + 0.5) / size
    u, v = np.meshgrid(centres, centres)
    theta = np.pi * v
    if wave == "u":
        slope = AMPLITUDE * np.sin(CYCLES * 2 * np.pi * u)
        local = np.stack([-slope, np.zeros_like(slope), np.ones_like(slope)], -1)
        k = CYCLES / (radius * np.maximum(np.sin(theta), 1e-9))  # the latitude circle holds CYCLES waves
    else:
        slope = AMPLITUDE * np.sin(2 * np.pi / WAVELENGTH * radius * theta)
        local = np.stack([np.zeros_like(slope), -slope, np.ones_like(slope)], -1)
        k = np.full(slope.shape, 2 * np.pi / WAVELENGTH)
    return local / np.linalg.norm(local, axis=-1, keepdims=True), (slope, k)


def regions(size: int = SIZE) -> dict:
    """Texel masks: equator band, a high-latitude band (colatitude 30-40 degrees), texels beside the u seam."""
    centres = (np.arange(size) + 0.5) / size
    u, v = np.meshgrid(centres, centres)
    colatitude = np.degrees(np.pi * v)
    seam = (u < 0.015) | (u > 0.985)
    return {"equator": (np.abs(colatitude - 90) < 10) & ~seam, "high latitude": (np.abs(colatitude - 35) < 5) & ~seam,
            "seam": (np.abs(colatitude - 90) < 20) & seam}


def predicted_gain(kernel, k: np.ndarray) -> np.ndarray:
    return sum(w * np.exp(-k * k * v / 2) for v, w in kernel)


def measured_gains(maps: list, wave: str, kernels) -> dict:
    """{(channel, region): (measured, predicted)}: least-squares gain of the output slope on the input slope, and
    the prediction weighted the same way (slope^2)."""
    _, (slope, k) = bump_field(maps[0].shape[0], wave)
    axis = 0 if wave == "u" else 1
    out = {}
    for c, image in enumerate(maps):
        out_slope = -image[..., axis] / image[..., 2]
        prediction = predicted_gain(kernels[c], k)
        for name, mask in regions(image.shape[0]).items():
            s, o, p = slope[mask], out_slope[mask], prediction[mask]
            out[("rgb"[c], name)] = (float((s * o).sum() / (s * s).sum()), float((s * s * p).sum() / (s * s).sum()))
    return out


def decode_normals(doc, texture: int) -> np.ndarray:
    pixels = decode_image(doc.image_bytes(doc.json["textures"][texture]["source"]), ".png")
    n = pixels[..., :3].astype(np.float64) / np.iinfo(pixels.dtype).max * 2 - 1
    return n


@pytest.fixture(scope="module", params=["u", "v"])
def baked(request, tmp_path_factory):
    folder = tmp_path_factory.mktemp(f"blur_{request.param}")
    source = bump_sphere(folder / "sphere.glb", request.param)
    asset = baker.bake(source, bakes=["normal-blur"])
    out = folder / "blurred.glb"
    save(asset, out)
    return request.param, out


def test_gain_matches_the_gaussians_on_the_surface_in_every_region(baked):
    wave, path = baked
    doc = GltfDocument.load(path)  # the written file, read back
    blur = read(doc, 0)
    maps = [decode_normals(doc, t) for t in blur.diffuse_textures]
    gains = measured_gains(maps, wave, blur.kernels)
    for (channel, region), (measured, predicted) in gains.items():
        assert abs(measured - predicted) < 0.03, (wave, channel, region, measured, predicted)
    # the bump really is attenuated, red most
    assert gains[("r", "equator")][0] < gains[("g", "equator")][0] < 0.99


def test_uv_space_blur_fails_the_same_check(baked):
    """The naive floor: scipy's Gaussian filter of the same kernels on the input map in UV space, sigma in texels
    from the sphere's mean stretch (|dP/du| at the equator and |dP/dv| averaged), wrapping in u."""
    from scipy.ndimage import gaussian_filter

    wave, path = baked
    doc = GltfDocument.load(path)
    blur = read(doc, 0)
    local, _ = bump_field(SIZE, wave)
    texel = math.sqrt(2 * math.pi * RADIUS * math.pi * RADIUS) / SIZE  # metres per texel, geometric mean
    worst = 0.0
    maps = []
    for kernel in blur.kernels:
        blurred = sum(w * gaussian_filter(local, sigma=(math.sqrt(v) / texel, math.sqrt(v) / texel, 0),
                                          mode=("nearest", "wrap", "nearest")) for v, w in kernel)
        maps.append(blurred / np.linalg.norm(blurred, axis=-1, keepdims=True))
    for measured, predicted in measured_gains(maps, wave, blur.kernels).values():
        worst = max(worst, abs(measured - predicted))
    assert worst > 0.03


def test_stretch_map_is_the_spheres_jacobian(baked):
    _, path = baked
    doc = GltfDocument.load(path)
    blur = read(doc, 0)
    pixels = decode_image(doc.image_bytes(doc.json["textures"][blur.stretch_texture]["source"]), ".png")
    stretch = pixels[..., :2].astype(np.float64) / 65535 * blur.stretch_scale
    centres = (np.arange(SIZE) + 0.5) / SIZE
    _, v = np.meshgrid(centres, centres)
    theta = np.pi * v
    band = np.abs(np.degrees(theta) - 90) < 60
    du = 2 * np.pi * RADIUS * np.sin(theta)
    dv = np.full_like(du, np.pi * RADIUS)
    assert np.abs(stretch[..., 0][band] / du[band] - 1).max() < 0.03
    assert np.abs(stretch[..., 1][band] / dv[band] - 1).max() < 0.03


def test_files_validate_and_say_what_was_done(baked):
    _, path = baked
    khronos = assert_khronos_clean(path)
    assert khronos["issues"]["numWarnings"] == 0, khronos["issues"]["messages"]
    report = validate.validate_file(path)
    assert report["issues"]["numErrors"] == 0, [m for m in report["issues"]["messages"] if m["severity"] == 0]
    doc = GltfDocument.load(path)
    ext = doc.json["materials"][0]["extensions"][NAME]
    assert len(ext["diffuseNormalTextures"]) == 3
    for kernel in ext["kernels"]:
        assert abs(sum(g["weight"] for g in kernel) - 1) < 1e-9
        assert all(g["variance"] > 0 for g in kernel)
    assert ext["kernels"][0][-1]["variance"] == pytest.approx(7.41e-6)  # d'Eon's widest, mm^2 -> m^2
    assert NAME in doc.json["extensionsUsed"] and NAME not in doc.json.get("extensionsRequired", [])
    assert "generatedTangents" not in ext
    blend = ext["channelBlend"]
    smoothed = "rgb".index(ext["smoothedChannel"][0])
    assert blend[smoothed] < 0.05 and blend[0] > blend[1] > 0  # red farthest from the smoothed map
    assert all(0 <= e < 0.1 for e in ext["channelBlendError"])


def test_same_input_same_bytes(tmp_path):
    source = bump_sphere(tmp_path / "s.glb", "v", segments=64, rings=64, size=128)
    outs = []
    for k in range(2):
        save(baker.bake(source, bakes=["normal-blur"]), tmp_path / f"o{k}.glb")
        outs.append((tmp_path / f"o{k}.glb").read_bytes())
    assert outs[0] == outs[1]


def test_generated_tangents_are_written_and_match_the_analytic_frame(tmp_path):
    source = bump_sphere(tmp_path / "s.glb", "u", tangents=False, segments=64, rings=64, size=128)
    asset = baker.bake(source, bakes=["normal-blur"])
    out = tmp_path / "o.glb"
    save(asset, out)
    assert_khronos_clean(out)
    doc = GltfDocument.load(out)
    prim = doc.json["meshes"][0]["primitives"][0]
    assert "TANGENT" in prim["attributes"]
    assert doc.json["materials"][0]["extensions"][NAME]["generatedTangents"] == ["/meshes/0/primitives/0"]
    tangent = doc.accessor(prim["attributes"]["TANGENT"])
    positions = doc.accessor(prim["attributes"]["POSITION"])
    phi = np.arctan2(-positions[:, 2], positions[:, 0])
    expected = np.stack([-np.sin(phi), np.zeros_like(phi), -np.cos(phi)], 1)
    ring = np.abs(positions[:, 1]) < 0.9 * RADIUS  # away from the poles, where dP/du vanishes
    assert np.all(np.einsum("ij,ij->i", tangent[ring, :3], expected[ring]) > 0.99)
    assert np.all(tangent[:, 3] == 1.0)


def test_normal_texture_scale_is_applied(tmp_path):
    """A map stored with half the slope and scale 2 reads as the same bump: same diffuse maps as scale 1."""
    one = baker.bake(bump_sphere(tmp_path / "a.glb", "v", segments=64, rings=64, size=128), bakes=["normal-blur"])
    two = baker.bake(bump_sphere(tmp_path / "b.glb", "v", segments=64, rings=64, size=128, scale=2.0),
                     bakes=["normal-blur"])
    a = decode_normals(one.doc, read(one.doc, 0).diffuse_textures[1])
    b = decode_normals(two.doc, read(two.doc, 0).diffuse_textures[1])
    assert np.abs(a - b).max() <= 2.5 / 127.5


def test_material_without_normal_map_is_left_alone(tmp_path):
    source = bump_sphere(tmp_path / "s.glb", "u", segments=32, rings=16, size=64)
    doc = GltfDocument.load(source)
    del doc.json["materials"][0]["normalTexture"]
    doc.save(tmp_path / "plain.glb")
    asset = baker.bake(tmp_path / "plain.glb", bakes=["normal-blur"])
    assert NAME not in (asset.doc.json["materials"][0].get("extensions") or {})
    assert any("normal-blur" in note for note in asset.notes)


def test_read_returns_what_was_written(baked):
    _, path = baked
    doc = GltfDocument.load(path)
    ext = doc.json["materials"][0]["extensions"][NAME]
    got = read(doc, 0)
    assert got.diffuse_textures == tuple(t["index"] for t in ext["diffuseNormalTextures"]) and got.texcoord == 0
    assert got.kernels == tuple(tuple((g["variance"], g["weight"]) for g in k) for k in ext["kernels"])
    assert got.smoothed_texture == ext["smoothedNormalTexture"]["index"]
    assert got.smoothed_channel == ext["smoothedChannel"]
    assert got.channel_blend == tuple(ext["channelBlend"]) and got.stretch_scale == ext["stretchScale"]
    assert got.stretch_texture == ext["stretchTexture"]["index"]
    assert got.texture_space_diffusion == ext["textureSpaceDiffusion"]
    assert read(doc, 0).meters_per_unit == 1.0
    # the 12-tap kernel keeps the profile's mass per channel and d'Eon's blurs add up to each variance
    for c in range(3):
        assert sum(t["weights"][c] for t in ext["textureSpaceDiffusion"]["twelveTap"]["taps"]) == pytest.approx(1, abs=1e-3)
    gaussians = ext["textureSpaceDiffusion"]["gaussians"]
    assert np.allclose(np.cumsum([g["incrementalVariance"] for g in gaussians]), [g["variance"] for g in gaussians])


def test_usd_carries_the_textures_and_parameters(baked, tmp_path):
    from pxr import Usd, UsdShade

    _, path = baked
    asset = baker.bake(path, bakes=[])  # the baked file as it is
    written = save(asset, tmp_path / "blurred.usda")
    stage = Usd.Stage.Open(str(written[-1]))
    materials = [UsdShade.Material(p) for p in stage.Traverse() if p.IsA(UsdShade.Material)]
    assert len(materials) == 1
    outputs = {o.GetBaseName() for o in materials[0].GetOutputs()}
    for name in ("normal_blur:diffuseNormalTextures:_0", "normal_blur:diffuseNormalTextures:_2",
                 "normal_blur:stretchTexture", "normal_blur:smoothedNormalTexture"):
        assert f"baker:{name}" in outputs or name in outputs, outputs
    prim = materials[0].GetPrim()
    assert prim.GetAttribute("baker:normal_blur:stretchScale").Get() == pytest.approx(
        GltfDocument.load(path).json["materials"][0]["extensions"][NAME]["stretchScale"])


def test_cli_bake_inspect_and_bad_normal_map(tmp_path, capsys):
    from baker.cli import main

    source = bump_sphere(tmp_path / "s.glb", "u", segments=32, rings=16, size=64)
    out = tmp_path / "o.glb"
    assert main(["bake", str(source), "--bakes", "normal-blur", "--normal-blur-meters-per-unit", "0.5", "-o",
                 str(out), "--quiet"]) in (0, None)
    ext = GltfDocument.load(out).json["materials"][0]["extensions"][NAME]
    assert ext["metersPerUnit"] == 0.5 and ext["kernels"][0][-1]["variance"] == pytest.approx(7.41e-6 / 0.25)
    capsys.readouterr()
    assert main(["inspect", str(out)]) == 0
    text = capsys.readouterr().out
    assert "BAKER_normal_blur.diffuseNormalTextures[2]" in text and "BAKER_normal_blur.stretchTexture" in text
    # a normal texture whose image is not an image: exit 2, one line naming the file and the place
    doc = GltfDocument.load(source)  # a grey (one-channel) image is no normal map
    doc.json["textures"][0]["source"] = doc.add_image(encode_image(np.zeros((8, 8), np.uint8)), "image/png", "grey")
    doc.save(tmp_path / "broken.glb")
    capsys.readouterr()
    assert main(["bake", str(tmp_path / "broken.glb"), "--bakes", "normal-blur", "-o", str(tmp_path / "x.glb"),
                 "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "/materials/0/normalTexture" in err[0] and "Traceback" not in err[0], err


def test_vertex_tangents_follow_du_and_the_layouts_handedness():
    """A square in the xy plane facing +z: u along +x and v down the image (glTF) along -y gives T = +x, w = +1
    (cross(N, T) = +y = -dP/dv); the mirrored layout (u along -x) gives T = -x and w = -1."""
    from baker.texels.tangents import uv_jacobians, vertex_tangents

    positions = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    normals = np.tile([0.0, 0.0, 1.0], (4, 1))
    uv = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], float)  # v = 1 - y
    tangents = vertex_tangents(positions, faces, normals, uv)
    np.testing.assert_allclose(tangents, np.tile([1.0, 0.0, 0.0, 1.0], (4, 1)), atol=1e-12)
    dpdu, dpdv = uv_jacobians(positions, faces, uv)
    np.testing.assert_allclose(dpdu, [[1, 0, 0]] * 2, atol=1e-12)
    np.testing.assert_allclose(dpdv, [[0, -1, 0]] * 2, atol=1e-12)
    mirrored = uv * [-1.0, 1.0] + [1.0, 0.0]
    np.testing.assert_allclose(vertex_tangents(positions, faces, normals, mirrored),
                               np.tile([-1.0, 0.0, 0.0, -1.0], (4, 1)), atol=1e-12)


def test_mirrored_layout_is_baked_and_said(tmp_path):
    """A sphere whose second half mirrors the first in u (as heads are often laid out): the bake runs, writes valid
    maps, and says the layout overlaps."""
    source = bump_sphere(tmp_path / "s.glb", "v", segments=32, rings=16, size=64)
    doc = GltfDocument.load(source)
    prim = doc.json["meshes"][0]["primitives"][0]
    uv = doc.accessor(prim["attributes"]["TEXCOORD_0"]).copy()
    uv[:, 0] = 1.0 - np.abs(2.0 * uv[:, 0] - 1.0)  # u: 0 -> 1 -> 0 around the sphere
    prim["attributes"]["TEXCOORD_0"] = doc.add_accessor(uv.astype(np.float32))
    doc.save(tmp_path / "mirrored.glb")
    asset = baker.bake(tmp_path / "mirrored.glb", bakes=["normal-blur"])
    assert any("overlaps itself" in note for note in asset.notes), asset.notes
    save(asset, tmp_path / "out.glb")
    report = validate.validate_file(tmp_path / "out.glb")
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
