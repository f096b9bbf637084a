"""Baking from a high mesh (``--from``): a displaced sphere with an analytic surface onto a 2k-triangle UV sphere.

The output is read back by an independent reader (GLB chunks, accessors and PNG pixels read here with numpy and
OpenImageIO, texel centres rasterized here): the baked normals, decoded in object space or through the file's own
NORMAL and TANGENT as glTF defines (``normalize(x T + y B + z N)``, ``B = cross(N, T) w``), must lie within 2 degrees
RMS of the analytic normal where each texel's ray meets the displaced sphere; the thickness moved from the high
mesh must match the high's own per-vertex thickness there; the bake must be byte-identical run to run, and bad
input must exit 2 with one line and leave nothing behind.
"""
from __future__ import annotations

import json
import struct
import subprocess
import sys
from pathlib import Path

import numpy as np
import OpenImageIO as oiio
import pytest

sys.path.insert(0, str(Path(__file__).parent))
import displaced_sphere as ds  # noqa: E402
from conftest import assert_khronos_clean  # noqa: E402

SIZE = 256
COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}
DTYPES = {5126: np.float32, 5123: np.uint16, 5125: np.uint32, 5121: np.uint8}


@pytest.fixture(scope="module")
def pair(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sculpt")
    high, low = folder / "high.obj", folder / "low.obj"
    ds.write_obj(high, *ds.high_mesh(45))
    positions, uvs, faces = ds.uv_sphere(32, 32)
    ds.write_obj(low, positions, faces, uvs)
    return folder, high, low


def baker(*args, check=True):
    done = subprocess.run([sys.executable, "-m", "baker", *map(str, args)], capture_output=True, text=True)
    if check:
        assert done.returncode == 0, done.stderr
    return done


def read_glb(path: Path):
    data = path.read_bytes()
    length = struct.unpack_from("<I", data, 12)[0]
    gltf = json.loads(data[20: 20 + length])
    start = 20 + length
    bin_length = struct.unpack_from("<I", data, start)[0]
    binary = data[start + 8: start + 8 + bin_length]

    def view_bytes(view):
        v = gltf["bufferViews"][view]
        return binary[v.get("byteOffset", 0): v.get("byteOffset", 0) + v["byteLength"]]

    def accessor(index):
        a = gltf["accessors"][index]
        width = COMPONENTS[a["type"]]
        raw = view_bytes(a["bufferView"])
        array = np.frombuffer(raw, DTYPES[a["componentType"]], count=a["count"] * width,
                              offset=a.get("byteOffset", 0))
        if a["componentType"] != 5126:  # indices
            return array.astype(np.int64)
        return array.reshape(a["count"], width).astype(np.float64) if width > 1 else array.astype(np.float64)

    def image(texture):
        source = gltf["textures"][texture]["source"]
        png = view_bytes(gltf["images"][source]["bufferView"])
        folder = path.parent / f"{path.stem}_png"
        folder.mkdir(exist_ok=True)
        file = folder / f"{texture}.png"
        file.write_bytes(png)
        inp = oiio.ImageInput.open(str(file))
        pixels = inp.read_image(format=inp.spec().format)
        inp.close()
        return pixels

    return gltf, accessor, image


def texel_samples(uv: np.ndarray, faces: np.ndarray, size: int):
    """(rows, cols, triangle, barycentrics) of the texel centres inside triangles, rasterized here."""
    rows, cols, tris, barys = [], [], [], []
    px = uv[faces] * size
    for t, (a, b, c) in enumerate(px):
        lo, hi = np.floor(np.minimum(np.minimum(a, b), c)).astype(int), np.ceil(np.maximum(np.maximum(a, b), c)).astype(int)
        xs, ys = np.meshgrid(np.arange(max(lo[0], 0), min(hi[0], size)), np.arange(max(lo[1], 0), min(hi[1], size)))
        p = np.stack([xs.ravel() + 0.5, ys.ravel() + 0.5], axis=1)
        m = np.array([[b[0] - a[0], c[0] - a[0]], [b[1] - a[1], c[1] - a[1]]])
        if abs(np.linalg.det(m)) < 1e-12:
            continue
        w = np.linalg.solve(m, (p - a).T).T
        bary = np.stack([1 - w[:, 0] - w[:, 1], w[:, 0], w[:, 1]], axis=1)
        inside = (bary > 1e-6).all(axis=1)  # strictly inside: a texel on a shared edge is either triangle's
        rows.append(ys.ravel()[inside])
        cols.append(xs.ravel()[inside])
        tris.append(np.full(inside.sum(), t))
        barys.append(bary[inside])
    return np.concatenate(rows), np.concatenate(cols), np.concatenate(tris), np.concatenate(barys)


def angles_degrees(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    a = a / np.linalg.norm(a, axis=1, keepdims=True)
    b = b / np.linalg.norm(b, axis=1, keepdims=True)
    return np.degrees(np.arccos(np.clip(np.sum(a * b, axis=1), -1.0, 1.0)))


def baked_normals(out: Path, space: str, size: int = SIZE):
    """(analytic normals at the texels' hits, decoded normals, the document, radial directions) over the texel centres strictly inside triangles."""
    gltf, accessor, image = read_glb(out)
    prim = gltf["meshes"][0]["primitives"][0]
    material = gltf["materials"][prim["material"]]
    if space == "tangent":
        info = material["normalTexture"]
    else:
        info = material["extras"]["baker"]["objectSpaceNormalTexture"]
    attributes = prim["attributes"]
    positions = accessor(attributes["POSITION"])
    faces = accessor(prim["indices"]).reshape(-1, 3)
    uv = accessor(attributes[f"TEXCOORD_{info.get('texCoord', 0)}"])
    pixels = image(info["index"])
    assert pixels.shape == (size, size, 3)
    rows, cols, tri, bary = texel_samples(uv, faces, size)
    decoded = pixels[rows, cols].astype(np.float64) / np.iinfo(pixels.dtype).max * 2.0 - 1.0

    def at_texels(values):
        return np.einsum("kj,kjd->kd", bary, values[faces[tri]])

    point = at_texels(positions)
    if space == "tangent":
        normal, tangent = accessor(attributes["NORMAL"]), accessor(attributes["TANGENT"])
        bitangent = np.cross(normal, tangent[:, :3]) * tangent[:, 3:4]
        frame = [at_texels(v) for v in (tangent[:, :3], bitangent, normal)]
        frame = [v / np.linalg.norm(v, axis=1, keepdims=True) for v in frame]
        decoded = decoded[:, :1] * frame[0] + decoded[:, 1:2] * frame[1] + decoded[:, 2:3] * frame[2]
    # the UV sphere's vertices lie on the unit sphere and its smoothed normals are radial: each texel's ray runs
    # radially through its surface point, and meets the displaced sphere at r = 1 + a f(u)
    u = point / np.linalg.norm(point, axis=1, keepdims=True)
    return ds.analytic_normal(ds.surface_point(u)), decoded, gltf, u


def test_bits_follow_banding():
    """8 bits where the map changes fast between texels (or not at all), 16 where 8 bits would band (a slow ramp)."""
    from baker.techniques.normal.kernel import bits_needed

    mask = np.ones((32, 40), bool)
    for steps_per_texel, bits in ((2.0, 8), (0.1, 16), (0.0, 8)):
        x = -0.5 + np.arange(40) * steps_per_texel / 127.5  # the red channel's 8-bit steps per texel
        image = np.zeros((32, 40, 3))
        image[..., 0] = x
        image[..., 2] = np.sqrt(1.0 - x ** 2)
        assert bits_needed(image, mask) == bits, steps_per_texel


@pytest.mark.parametrize("space", ["object", "tangent"])
def test_baked_normals_match_the_analytic_surface(pair, space):
    folder, high, low = pair
    out = folder / f"normal_{space}.glb"
    baker("bake", low, "--from", high, "--bakes", "normal", "--normal-space", space, "--normal-texture-size", SIZE,
          "-o", out, "-q")
    truth, decoded, gltf, radial = baked_normals(out, space)
    error = angles_degrees(truth, decoded)
    rms = float(np.sqrt(np.mean(error ** 2)))
    assert len(error) > 0.5 * SIZE * SIZE * 0.6
    assert rms < 2.0, (rms, np.percentile(error, [50, 90, 99]))
    print(f"{space}: {rms:.3f} degrees RMS, p99 {np.percentile(error, 99):.3f}, over {len(error)} texels")
    # the map carries the sculpt's detail: the low's own (radial) normals are far off
    assert np.sqrt(np.mean(angles_degrees(truth, radial) ** 2)) > 5.0 * rms
    transfer = gltf["asset"]["extras"]["baker"]["transfer"]
    assert transfer["source"] == "high.obj" and transfer["bakes"]["normal"]["texels"]["misses"] == 0
    # both validators clean: baker's checks and Khronos glTF-Validator (no new warnings: the map is core glTF)
    from baker import validate

    assert validate.validate_file(out, khronos=False)["issues"]["numErrors"] == 0
    report = assert_khronos_clean(out)
    assert report["issues"]["numWarnings"] == 0, report["issues"]["messages"]


def radial_hits(positions: np.ndarray, faces: np.ndarray, directions: np.ndarray):
    """(triangle, barycentrics) where rays from the origin along ``directions`` cross the star-shaped mesh
    (Moller-Trumbore over the triangles nearest each direction)."""
    from scipy.spatial import cKDTree

    centres = positions[faces].mean(axis=1)
    centres /= np.linalg.norm(centres, axis=1, keepdims=True)
    _, near = cKDTree(centres).query(directions, k=12)
    best_t, best_b = np.full(len(directions), -1), np.zeros((len(directions), 3))
    for k in range(near.shape[1]):
        tri = near[:, k]
        a, b, c = (positions[faces[tri, i]] for i in range(3))
        e1, e2 = b - a, c - a
        p = np.cross(directions, e2)
        det = np.sum(e1 * p, axis=1)
        s = -a
        u = np.sum(s * p, axis=1) / det
        q = np.cross(s, e1)
        v = np.sum(directions * q, axis=1) / det
        inside = (u >= -1e-9) & (v >= -1e-9) & (u + v <= 1 + 1e-9) & (best_t < 0)
        best_t[inside] = tri[inside]
        best_b[inside] = np.stack([1 - u - v, u, v], axis=1)[inside]
    assert (best_t >= 0).all()
    return best_t, best_b


def test_thickness_from_the_high_mesh_is_the_high_meshs_own(pair):
    folder, high, low = pair
    own = folder / "high_thickness.glb"
    baker("bake", high, "--bakes", "thickness", "--thickness-per-texel", "false", "--thickness-rays", 16, "-o", own, "-q")
    gltf, accessor, _ = read_glb(own)
    prim = gltf["meshes"][0]["primitives"][0]
    high_positions = accessor(prim["attributes"]["POSITION"])
    high_faces = accessor(prim["indices"]).reshape(-1, 3)
    high_thickness = accessor(prim["attributes"]["_THICKNESS"])
    high_thickness = high_thickness[:, 0] if high_thickness.ndim == 2 else high_thickness

    out = folder / "thickness_from_high.glb"
    baker("bake", low, "--from", high, "--bakes", "thickness", "--thickness-rays", 16, "--thickness-texture-size", SIZE,
          "-o", out, "-q")
    gltf, accessor, image = read_glb(out)
    prim = gltf["meshes"][0]["primitives"][0]
    material = gltf["materials"][prim["material"]]
    ext = material["extensions"]["BAKER_thickness"]
    info = ext["thicknessTexture"]
    attributes = prim["attributes"]
    positions, faces = accessor(attributes["POSITION"]), accessor(prim["indices"]).reshape(-1, 3)
    uv = accessor(attributes[f"TEXCOORD_{info.get('texCoord', 0)}"])
    pixels = image(info["index"])
    rows, cols, tri, bary = texel_samples(uv, faces, SIZE)
    baked = pixels[rows, cols, 0].astype(np.float64) / np.iinfo(pixels.dtype).max * ext["thicknessFactor"]
    point = np.einsum("kj,kjd->kd", bary, positions[faces[tri]])
    u = point / np.linalg.norm(point, axis=1, keepdims=True)
    hit_tri, hit_bary = radial_hits(high_positions, high_faces, u)
    truth = np.einsum("kj,kj->k", hit_bary, high_thickness[high_faces[hit_tri]])
    relative = np.abs(baked - truth) / truth
    rms = float(np.sqrt(np.mean(relative ** 2)))
    print(f"thickness texels: {rms:.4f} relative RMS, p99 {np.percentile(relative, 99):.4f}")
    assert rms < 0.03 and np.percentile(relative, 99) < 0.06

    # the low's vertices: each takes the high's thickness where its ray meets the high
    vertex = accessor(attributes["_THICKNESS"])
    vertex = vertex[:, 0] if vertex.ndim == 2 else vertex
    hit_tri, hit_bary = radial_hits(high_positions, high_faces, positions / np.linalg.norm(positions, axis=1)[:, None])
    truth = np.einsum("kj,kj->k", hit_bary, high_thickness[high_faces[hit_tri]])
    moved = float(np.sqrt(np.mean(((vertex - truth) / truth) ** 2)))
    # the low mesh's own thickness (a sphere's) is not the sculpt's
    own_low = folder / "thickness_low.glb"
    baker("bake", low, "--bakes", "thickness", "--thickness-per-texel", "false", "--thickness-rays", 16, "-o", own_low, "-q")
    gltf, accessor, _ = read_glb(own_low)
    low_values = accessor(gltf["meshes"][0]["primitives"][0]["attributes"]["_THICKNESS"])
    low_values = low_values[:, 0] if low_values.ndim == 2 else low_values
    own = float(np.sqrt(np.mean(((low_values - truth) / truth) ** 2)))
    print(f"thickness vertices: moved {moved:.4f}, the low's own {own:.4f} relative RMS")
    assert moved < 0.03 and own > 3 * moved


def test_the_bake_is_byte_identical_run_to_run(pair):
    folder, high, low = pair
    outs = [folder / f"again_{k}.glb" for k in range(2)]
    for out in outs:
        baker("bake", low, "--from", high, "--bakes", "normal", "--normal-texture-size", 64, "-o", out, "-q")
    assert outs[0].read_bytes() == outs[1].read_bytes()


def test_a_low_mesh_without_uvs_is_unwrapped_with_a_note(pair):
    folder, high, _ = pair
    positions, _, faces = ds.uv_sphere(16, 16)
    low = folder / "low_no_uv.obj"
    ds.write_obj(low, positions, faces)
    out = folder / "no_uv.glb"
    done = baker("bake", low, "--from", high, "--bakes", "normal", "--normal-texture-size", 64, "-o", out)
    assert "unwrapped into TEXCOORD_0" in done.stderr
    gltf, _, _ = read_glb(out)
    assert "TEXCOORD_0" in gltf["meshes"][0]["primitives"][0]["attributes"]


def test_bad_input_exits_2_with_one_line_and_writes_nothing(pair):
    folder, high, low = pair
    far = folder / "far.obj"
    positions, faces = ds.high_mesh(6)
    ds.write_obj(far, positions + np.array([10.0, 0.0, 0.0]), faces)
    cases = {
        "missing": (["--from", folder / "nope.obj"], "no such file"),
        "no overlap": (["--from", far], "does not overlap"),
        "cage topology": (["--from", high, "--cage", far], "topology differs"),
        "cage without source": (["--cage-distance", "0.1"], "need --from"),
        "bake that cannot transfer": (["--from", high, "--bakes", "edges"], "cannot bake from another mesh"),
    }
    for label, (extra, message) in cases.items():
        out = folder / "refused.glb"
        args = ["bake", low, "-o", out, *extra]
        if "--bakes" not in extra:
            args += ["--bakes", "normal"]
        done = baker(*args, check=False)
        lines = done.stderr.strip().splitlines()
        assert done.returncode == 2, (label, done.stderr)
        assert len(lines) == 1 and message in lines[0], (label, lines)
        assert not out.exists(), label
        assert not list(folder.glob("refused*")), label


def test_a_recipe_bakes_from_the_high_mesh_and_rebuilds_when_it_changes(pair, tmp_path):
    _, high, low = pair
    (tmp_path / "sculpt").mkdir()
    (tmp_path / "sculpt" / "high.obj").write_bytes(high.read_bytes())
    (tmp_path / "low.obj").write_bytes(low.read_bytes())
    (tmp_path / "baker.toml").write_text('[build]\noutput = "out"\n\n[[assets]]\ninputs = ["low.obj"]\n'
                                         'from = "sculpt/high.obj"\nbakes = ["normal"]\n\n'
                                         '[options.normal]\ntexture-size = 32\n')
    done = subprocess.run([sys.executable, "-m", "baker", "build", "-q"], cwd=tmp_path, capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stderr
    gltf, _, _ = read_glb(tmp_path / "out" / "low.glb")
    assert "normalTexture" in gltf["materials"][0]
    assert gltf["asset"]["extras"]["baker"]["transfer"]["source"] == "high.obj"
    check = subprocess.run([sys.executable, "-m", "baker", "build", "--check"], cwd=tmp_path, capture_output=True,
                           text=True)
    assert check.returncode == 0, check.stdout + check.stderr
    # the sculpt changed: the game mesh's bake is stale
    with open(tmp_path / "sculpt" / "high.obj", "a") as f:
        f.write("# edited\n")
    check = subprocess.run([sys.executable, "-m", "baker", "build", "--check"], cwd=tmp_path, capture_output=True,
                           text=True)
    assert check.returncode == 1, check.stdout + check.stderr


def test_a_cage_mesh_with_the_low_topology(pair):
    folder, high, low = pair
    positions, uvs, faces = ds.uv_sphere(32, 32)
    cage = folder / "cage.obj"
    ds.write_obj(cage, positions * 1.1, faces, uvs)
    out = folder / "caged.glb"
    baker("bake", low, "--from", high, "--cage", cage, "--bakes", "normal", "--normal-space", "object",
          "--normal-texture-size", 64, "-o", out, "-q")
    truth, decoded, gltf, _ = baked_normals(out, "object", size=64)
    assert np.sqrt(np.mean(angles_degrees(truth, decoded) ** 2)) < 2.0
    assert gltf["asset"]["extras"]["baker"]["transfer"]["cage"] == "cage.obj"


def test_the_map_follows_the_low_meshs_own_tangent_frame(pair):
    """A low mesh that brings its own TANGENT (here turned 40 degrees about the normal, mirrored on half the
    vertices) keeps it, and the map decodes through it."""
    from baker.gltf.document import GltfDocument

    folder, high, low = pair
    plain = folder / "plain_for_tangents.glb"
    baker("bake", low, "--from", high, "--bakes", "normal", "--normal-texture-size", 32, "-o", plain, "-q")
    doc = GltfDocument.load(plain)
    prim = doc.json["meshes"][0]["primitives"][0]
    normal = doc.accessor(prim["attributes"]["NORMAL"]).astype(np.float64)
    tangent = doc.accessor(prim["attributes"]["TANGENT"]).astype(np.float64)
    bitangent = np.cross(normal, tangent[:, :3])
    turned = np.cos(np.radians(40)) * tangent[:, :3] + np.sin(np.radians(40)) * bitangent
    sign = np.where(np.arange(len(turned)) % 2 == 0, 1.0, -1.0)
    prim["attributes"]["TANGENT"] = doc.add_accessor(np.concatenate([turned, sign[:, None]], axis=1)
                                                     .astype(np.float32))
    del doc.json["materials"][prim["material"]]["normalTexture"]
    own = folder / "own_tangents.glb"
    doc.save(own)
    out = folder / "own_tangents_baked.glb"
    baker("bake", own, "--from", high, "--bakes", "normal", "--normal-texture-size", 64, "-o", out, "-q")
    truth, decoded, gltf, _ = baked_normals(out, "tangent", size=64)
    assert np.sqrt(np.mean(angles_degrees(truth, decoded) ** 2)) < 2.0
    _, accessor, _ = read_glb(out)
    kept = accessor(gltf["meshes"][0]["primitives"][0]["attributes"]["TANGENT"])
    assert np.allclose(kept[:, 3], sign) and np.allclose(kept[:, :3], turned, atol=1e-6)


def test_misses_are_filled_from_neighbours_and_counted(pair):
    """A sculpt with its top cap cut away: the texels there find no surface, take their nearest hit texel's and
    are counted in the note and in asset.extras.baker."""
    folder, _, low = pair
    positions, faces = ds.high_mesh(30)
    centres = positions[faces].mean(axis=1)
    open_top = folder / "open_top.obj"
    ds.write_obj(open_top, positions, faces[centres[:, 1] < 0.8])
    out = folder / "open_top.glb"
    done = baker("bake", low, "--from", open_top, "--bakes", "normal", "--normal-space", "object",
                 "--normal-texture-size", 64, "-o", out)
    gltf, accessor, image = read_glb(out)
    counts = gltf["asset"]["extras"]["baker"]["transfer"]["bakes"]["normal"]["texels"]
    assert 0 < counts["misses"] < 0.2 * counts["samples"]
    assert f"{counts['misses']} of {counts['samples']} texels found no source surface" in done.stderr
    info = gltf["materials"][0]["extras"]["baker"]["objectSpaceNormalTexture"]
    pixels = image(info["index"])
    pixels = pixels.astype(np.float64) / np.iinfo(pixels.dtype).max * 2.0 - 1.0
    length = np.linalg.norm(pixels, axis=2)
    assert np.all(np.abs(length - 1.0) < 1e-2)  # every texel (filled, dilated) holds a unit normal
    # the filled texels near the pole copy hits at the cut's rim: normals pointing up, not the low's own
    prim = gltf["meshes"][0]["primitives"][0]
    uv = accessor(prim["attributes"]["TEXCOORD_0"])
    top_row = int(np.floor(uv[:, 1].min() * 64)) + 1
    assert pixels[top_row, :, 1].mean() > 0.5


def named_parts(path: Path, parts) -> Path:
    """A GLB of the named meshes, each with a material of its own (OBJ names its meshes after the file: the parts are
    told apart by their radius, each a sphere of its own radius here)."""
    from baker import readers

    ds.write_obj_parts(path, parts)
    doc = readers.read(path).doc
    radii = {name: float(np.linalg.norm(positions, axis=1).mean()) for name, positions, _, _ in parts}
    for mesh in doc.json["meshes"]:
        radius = float(np.linalg.norm(doc.accessor(mesh["primitives"][0]["attributes"]["POSITION"]), axis=1).mean())
        mesh["name"] = min(radii, key=lambda name: abs(radii[name] - radius))
        # a material of its own: each part's map in its own texture, on its own UVs
        doc.json.setdefault("materials", []).append({"name": mesh["name"]})
        mesh["primitives"][0]["material"] = len(doc.json["materials"]) - 1
    assert sorted(m["name"] for m in doc.json["meshes"]) == sorted(radii)
    out = path.with_suffix(".glb")
    doc.save(out)
    return out


def test_parts_bake_from_the_high_part_of_the_same_name(pair):
    """Two parts in one place: the displaced sphere ``rock_high`` and a plain sphere ``shell_high`` just outside
    it. ``rock_low`` takes only ``rock_high``'s surface (the shell would be the first surface along its rays)."""
    folder, _, _ = pair
    rock_positions, rock_faces = ds.high_mesh(30)
    shell_positions, shell_faces = ds.geodesic_sphere(12)
    high = named_parts(folder / "parts_high.obj", [("rock_high", rock_positions, rock_faces, None),
                                                   ("shell_high", shell_positions * 1.06, shell_faces, None)])
    positions, uvs, faces = ds.uv_sphere(32, 32)
    low = named_parts(folder / "parts_low.obj", [("rock_low", positions, faces, uvs),
                                                 ("shell_low", positions * 1.06, faces, uvs)])
    out = folder / "parts.glb"
    baker("bake", low, "--from", high, "--cage-distance", 0.1, "--bakes", "normal", "--normal-space", "object",
          "--normal-texture-size", 64, "-o", out, "-q")
    gltf, accessor, image = read_glb(out)
    rock = next(m for m in gltf["meshes"] if m["name"] == "rock_low")["primitives"][0]
    info = gltf["materials"][rock["material"]]["extras"]["baker"]["objectSpaceNormalTexture"]
    pixels = image(info["index"])
    rows, cols, tri, bary = texel_samples(accessor(rock["attributes"]["TEXCOORD_0"]),
                                          accessor(rock["indices"]).reshape(-1, 3), 64)
    point = np.einsum("kj,kjd->kd", bary, accessor(rock["attributes"]["POSITION"])[accessor(rock["indices"])
                                                                                  .reshape(-1, 3)[tri]])
    u = point / np.linalg.norm(point, axis=1, keepdims=True)
    decoded = pixels[rows, cols].astype(np.float64) / np.iinfo(pixels.dtype).max * 2.0 - 1.0
    error = angles_degrees(ds.analytic_normal(ds.surface_point(u)), decoded)
    assert np.sqrt(np.mean(error ** 2)) < 2.0
    assert gltf["asset"]["extras"]["baker"]["transfer"]["parts"] == ["rock", "shell"]


def test_curvature_from_the_high_mesh_is_the_high_meshs_own(pair):
    """Each low vertex takes the high's own mean and principal curvatures at its hit, and the high's principal
    direction turned into its tangent plane."""
    folder, high, low = pair
    own = folder / "high_curvature.glb"
    baker("bake", high, "--bakes", "curvature", "-o", own, "-q")
    gltf, accessor, _ = read_glb(own)
    attributes = gltf["meshes"][0]["primitives"][0]["attributes"]
    high_positions = accessor(attributes["POSITION"])
    high_faces = accessor(gltf["meshes"][0]["primitives"][0]["indices"]).reshape(-1, 3)

    def scalar(values):
        return values[:, 0] if values.ndim == 2 else values

    high_mean = scalar(accessor(attributes["_CURVATURE"]))
    out = folder / "curvature_from_high.glb"
    baker("bake", low, "--from", high, "--bakes", "curvature", "-o", out, "-q")
    gltf, accessor, _ = read_glb(out)
    attributes = gltf["meshes"][0]["primitives"][0]["attributes"]
    positions = accessor(attributes["POSITION"])
    moved = scalar(accessor(attributes["_CURVATURE"]))
    hit_tri, hit_bary = radial_hits(high_positions, high_faces,
                                    positions / np.linalg.norm(positions, axis=1, keepdims=True))
    truth = np.einsum("kj,kj->k", hit_bary, high_mean[high_faces[hit_tri]])
    assert np.sqrt(np.mean((moved - truth) ** 2)) < 0.03 * np.sqrt(np.mean(truth ** 2))
    # the sculpt's bumps: its curvature is not the unit sphere's (H = 1 everywhere)
    assert np.sqrt(np.mean((truth - 1.0) ** 2)) > 0.1
    direction = accessor(attributes["_PRINCIPAL_DIRECTION"])[:, :3]
    normal = accessor(attributes["NORMAL"])
    assert np.allclose(np.linalg.norm(direction, axis=1), 1.0, atol=1e-5)
    assert np.abs(np.sum(direction * normal, axis=1)).max() < 0.02
