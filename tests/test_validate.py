"""``baker validate``: baker's own output passes (baker's checks and Khronos'), corrupt copies are rejected."""
from __future__ import annotations

import json
import re
import shutil
import struct

import numpy as np
import pytest
import trimesh
from jsonschema import Draft202012Validator

import baker
import baker.pipeline
from baker import validate
from baker.data import SCHEMA_ROOT
from baker.cli import main as cli
from baker.gltf.document import GltfDocument
from conftest import assert_khronos_clean, khronos_validate

EXT = "/materials/0/extensions/BAKER_thickness"


@pytest.fixture(scope="module")
def baked(tmp_path_factory):
    """A thickness-baked icosphere written as .glb and as .gltf (+ .bin + png)."""
    d = tmp_path_factory.mktemp("baked")
    src = d / "ico.glb"
    trimesh.creation.icosphere(3).export(src)
    out = {}
    for suffix in (".glb", ".gltf"):
        asset = baker.bake(src, options={"thickness": {"rays": 16, "texture_size": 64}})
        out[suffix] = d / f"ico_out{suffix}"
        baker.pipeline.save(asset, out[suffix])
    return out


class Copy:
    """An editable copy of the baked .gltf: its JSON and its .bin, written back by ``save()``."""

    def __init__(self, baked, tmp_path):
        src = baked[".gltf"]
        for f in src.parent.glob("ico_out*"):
            if f.suffix != ".glb":
                shutil.copy(f, tmp_path / f.name)
        self.path = tmp_path / src.name
        self.json = json.loads(self.path.read_text())
        self.bin_path = tmp_path / self.json["buffers"][0]["uri"]
        self.bin = bytearray(self.bin_path.read_bytes())

    @property
    def primitive(self):
        return self.json["meshes"][0]["primitives"][0]

    def accessor_offset(self, index):
        acc = self.json["accessors"][index]
        return self.json["bufferViews"][acc["bufferView"]].get("byteOffset", 0) + acc.get("byteOffset", 0)

    def save(self):
        self.path.write_text(json.dumps(self.json))
        self.bin_path.write_bytes(bytes(self.bin))
        return self.path


@pytest.fixture
def copy(baked, tmp_path):
    return Copy(baked, tmp_path)


def codes(report, severity=None):
    return {m["code"] for m in report["issues"]["messages"] if severity is None or m["severity"] == severity}


def find(report, code):
    return [m for m in report["issues"]["messages"] if m["code"] == code]


# ---------------------------------------------------------------------------------------------------- clean output
@pytest.mark.parametrize("suffix", [".glb", ".gltf"])
def test_baked_output_passes_baker_checks(baked, suffix):
    report = validate.validate_file(baked[suffix], khronos=False)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert report["issues"]["numWarnings"] == 0, report["issues"]["messages"]
    assert report["mimeType"] == ("model/gltf-binary" if suffix == ".glb" else "model/gltf+json")
    assert cli(["validate", "--no-khronos", str(baked[suffix])]) == 0


@pytest.mark.parametrize("suffix", [".glb", ".gltf"])
def test_baked_output_passes_khronos(baked, suffix):
    report = assert_khronos_clean(baked[suffix])
    if report is None:
        pytest.skip("Khronos glTF-Validator not installed (scripts/install-node-tools)")
    assert report["validatorVersion"].startswith("2.0.0")
    # merged through baker: Khronos' messages keep their source, and it no longer calls BAKER_thickness unsupported
    merged = validate.validate_file(baked[suffix], khronos=True)
    assert merged["khronos"]["ran"]
    assert merged["issues"]["numErrors"] == 0
    assert not [m for m in merged["issues"]["messages"]
                if m["code"] == "UNSUPPORTED_EXTENSION" and "BAKER_thickness" in m["message"]]
    assert all(m["source"] in ("baker", "khronos") for m in merged["issues"]["messages"])


def test_text_and_json_formats(baked, capsys):
    assert cli(["validate", "--no-khronos", str(baked[".glb"]), str(baked[".gltf"])]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0] == f"{baked['.glb']}: OK" and out[1] == f"{baked['.gltf']}: OK"

    assert cli(["validate", "--format", "json", str(baked[".glb"])]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["issues"]["numErrors"] == 0
    assert set(report["issues"]) >= {"numErrors", "numWarnings", "numInfos", "numHints", "messages", "truncated"}
    assert report["uri"] == baked[".glb"].name and report["validatorVersion"].startswith("baker ")


# ---------------------------------------------------------------------------------------------------- corruptions
def test_wrong_type_in_extension(copy, capsys):
    copy.json["materials"][0]["extensions"]["BAKER_thickness"]["rays"] = "many"
    path = copy.save()
    report = validate.validate_file(path, khronos=False)
    [msg] = find(report, "BAKER_SCHEMA")
    assert msg["pointer"] == EXT + "/rays" and msg["severity"] == 0
    assert cli(["validate", str(path)]) == 1
    assert "BAKER_SCHEMA" in capsys.readouterr().out


@pytest.mark.parametrize("edit, pointer", [
    (lambda e: e.pop("maxDistance"), EXT),                           # required
    (lambda e: e.update(distribution="gaussian"), EXT + "/distribution"),
    (lambda e: e.update(spreadAngle=4.0), EXT + "/spreadAngle"),     # > pi
    (lambda e: e.update(subsurfaceColor=[1, 1]), EXT + "/subsurfaceColor"),
    (lambda e: e.update(colour=[1, 0, 0]), EXT),                     # unknown key
])
def test_schema_rules(copy, edit, pointer):
    edit(copy.json["materials"][0]["extensions"]["BAKER_thickness"])
    report = validate.validate_file(copy.save(), khronos=False)
    assert [m["pointer"] for m in find(report, "BAKER_SCHEMA")] == [pointer]


def test_extension_extras_and_extensions_allowed(copy):
    copy.json["materials"][0]["extensions"]["BAKER_thickness"]["extras"] = {"note": 1}
    copy.json["materials"][0]["extensions"]["BAKER_thickness"]["extensions"] = {}
    assert validate.validate_file(copy.save(), khronos=False)["issues"]["numErrors"] == 0


def test_thickness_accessor_count_mismatch(copy):
    copy.json["accessors"][copy.primitive["attributes"]["_THICKNESS"]]["count"] -= 1
    path = copy.save()
    report = validate.validate_file(path, khronos=False)
    assert "BAKER_THICKNESS_ACCESSOR_COUNT" in codes(report, 0)
    assert cli(["validate", str(path)]) == 1


def test_thickness_accessor_format(copy):
    # the index accessor: integers, not FLOAT (either attribute layout's width would do: SCALAR, VEC2 ... VEC4)
    copy.primitive["attributes"]["_THICKNESS"] = copy.primitive["indices"]
    report = validate.validate_file(copy.save(), khronos=False)
    assert "BAKER_THICKNESS_ACCESSOR_FORMAT" in codes(report, 0)


def test_negative_thickness(copy):
    a = copy.primitive["attributes"]["_THICKNESS"]
    struct.pack_into("<f", copy.bin, copy.accessor_offset(a), -1.0)
    path = copy.save()
    report = validate.validate_file(path, khronos=False)
    [msg] = find(report, "BAKER_THICKNESS_VALUE_NEGATIVE")
    assert msg["pointer"] == f"/accessors/{a}"
    assert cli(["validate", str(path)]) == 1


def test_non_finite_and_too_large_thickness(copy):
    a = copy.primitive["attributes"]["_THICKNESS"]
    # _THICKNESS is FLOAT SCALAR (a thickness-only bake): vertex 0 gets NaN, vertex 1 a value far above maxDistance
    assert copy.json["accessors"][a]["type"] == "SCALAR"
    struct.pack_into("<ff", copy.bin, copy.accessor_offset(a), float("nan"), 1e6)
    report = validate.validate_file(copy.save(), khronos=False)
    assert "BAKER_THICKNESS_VALUE_NOT_FINITE" in codes(report, 0)
    assert "BAKER_THICKNESS_VALUE_ABOVE_MAX" in codes(report, 1)


def test_missing_attribute(copy):
    del copy.primitive["attributes"]["_THICKNESS"]
    report = validate.validate_file(copy.save(), khronos=False)
    [msg] = find(report, "BAKER_THICKNESS_ATTRIBUTE_MISSING")
    assert msg["pointer"] == "/meshes/0/primitives/0/attributes"


def test_texture_without_factor(copy):
    del copy.json["materials"][0]["extensions"]["BAKER_thickness"]["thicknessFactor"]
    report = validate.validate_file(copy.save(), khronos=False)
    assert [m for m in report["issues"]["messages"] if m["severity"] == 0
            and m.get("pointer", "").startswith("/materials/0/extensions/BAKER_thickness")], report


def test_texture_texcoord_missing(copy):
    copy.json["materials"][0]["extensions"]["BAKER_thickness"]["thicknessTexture"]["texCoord"] = 1
    report = validate.validate_file(copy.save(), khronos=False)
    assert "BAKER_THICKNESS_TEXCOORD_MISSING" in codes(report, 0)


def test_texture_index_unresolved(copy):
    copy.json["materials"][0]["extensions"]["BAKER_thickness"]["thicknessTexture"]["index"] = 7
    report = validate.validate_file(copy.save(), khronos=False)
    [msg] = find(report, "UNRESOLVED_REFERENCE")
    assert msg["pointer"] == "/materials/0/extensions/BAKER_thickness/thicknessTexture/index"


def test_extension_missing_from_extensions_used(copy):
    copy.json["extensionsUsed"].remove("BAKER_thickness")
    path = copy.save()
    report = validate.validate_file(path, khronos=False)
    [msg] = find(report, "BAKER_EXTENSION_NOT_DECLARED")
    assert msg["severity"] == 1 and report["issues"]["numErrors"] == 0
    assert cli(["validate", "--no-khronos", str(path)]) == 0  # a warning, not an error


def test_extension_required_is_a_warning(copy):
    copy.json["extensionsRequired"] = ["BAKER_thickness"]
    report = validate.validate_file(copy.save(), khronos=False)
    assert find(report, "BAKER_EXTENSION_REQUIRED")[0]["pointer"] == "/extensionsRequired/0"


def test_misplaced_and_unknown_extensions(copy):
    copy.json["nodes"][0].setdefault("extensions", {})["BAKER_thickness"] = {"rays": 1}
    copy.json["nodes"][0]["extensions"]["BAKER_nonsense"] = {}
    copy.json["extensionsUsed"] += ["BAKER_nonsense"]
    report = validate.validate_file(copy.save(), khronos=False)
    unexpected = find(report, "BAKER_EXTENSION_UNEXPECTED_OBJECT")[0]
    assert unexpected["pointer"] == "/nodes/0/extensions/BAKER_thickness"
    assert "is defined on material, not on node" in unexpected["message"]
    [unknown] = find(report, "BAKER_UNKNOWN_EXTENSION")
    assert unknown["pointer"] == "/nodes/0/extensions/BAKER_nonsense"
    assert unknown["severity"] == 0  # an extension baker cannot check fails the gate


def test_accessor_out_of_bounds(copy):
    a = copy.primitive["attributes"]["_THICKNESS"]
    acc = copy.json["accessors"][a]
    acc["byteOffset"] = copy.json["bufferViews"][acc["bufferView"]]["byteLength"] - 4
    path = copy.save()
    report = validate.validate_file(path, khronos=False)
    [msg] = find(report, "ACCESSOR_OUT_OF_BOUNDS")
    assert msg["pointer"] == f"/accessors/{a}"
    assert "BAKER_DATA_NOT_CHECKED" in codes(report)  # baker does not read past it
    assert cli(["validate", str(path)]) == 1


def test_buffer_view_out_of_bounds(copy):
    copy.json["bufferViews"][0]["byteLength"] = len(copy.bin) + 1
    report = validate.validate_file(copy.save(), khronos=False)
    assert "BUFFER_VIEW_TOO_LONG" in codes(report, 0)


def test_truncated_buffer(copy):
    del copy.bin[-16:]
    report = validate.validate_file(copy.save(), khronos=False)
    assert "BUFFER_BYTE_LENGTH_MISMATCH" in codes(report, 0)


def test_index_out_of_range(copy):
    prim = copy.primitive
    indices = copy.json["accessors"][prim["indices"]]
    vertex_count = copy.json["accessors"][prim["attributes"]["POSITION"]]["count"]
    fmt = {5121: "<B", 5123: "<H", 5125: "<I"}[indices["componentType"]]
    struct.pack_into(fmt, copy.bin, copy.accessor_offset(prim["indices"]), vertex_count + 5)
    path = copy.save()
    report = validate.validate_file(path, khronos=False)
    [msg] = find(report, "ACCESSOR_INDEX_OOB")
    assert msg["pointer"] == "/meshes/0/primitives/0/indices"
    assert cli(["validate", str(path)]) == 1


@pytest.mark.parametrize("edit, code", [
    (lambda j: j["meshes"][0]["primitives"][0].update(material=5), "UNRESOLVED_REFERENCE"),
    (lambda j: j["nodes"][0].update(mesh=3), "UNRESOLVED_REFERENCE"),
    (lambda j: j["accessors"][0].update(componentType=5130), "VALUE_NOT_IN_LIST"),
    # an unknown type is a warning on the accessor (as in Khronos' validator), an error where a mesh reads it
    (lambda j: j["accessors"][j["meshes"][0]["primitives"][0]["attributes"]["POSITION"]].update(type="VEC5"),
     "MESH_PRIMITIVE_ATTRIBUTES_ACCESSOR_INVALID_FORMAT"),
    (lambda j: j["accessors"][j["meshes"][0]["primitives"][0]["indices"]].update(type="VEC5"),
     "MESH_PRIMITIVE_INDICES_ACCESSOR_INVALID_FORMAT"),
])
def test_structure_rules(copy, edit, code):
    edit(copy.json)
    report = validate.validate_file(copy.save(), khronos=False)
    assert code in codes(report, 0)


def test_unparseable_and_missing_files(tmp_path, baked, capsys):
    """A file validate cannot parse (broken or truncated JSON, a GLB cut short, a .usda cut short) or that is not
    there is refused: exit 2 and one line naming the file, the place and the problem, nothing on stdout (it is not a
    report on a document: those are exit 1)."""
    baker.pipeline.save(baker.bake(baked[".glb"], bakes=()), tmp_path / "ico.usda")
    usda = (tmp_path / "ico.usda").read_bytes()
    # the problem and its place: the JSON's line and column, the GLB's sizes, the stage's line:column
    cases = {"broken.gltf": (b"{ not json", r"broken JSON at line 1 column 3 \(char 2\)"),
             "truncated.gltf": (baked[".gltf"].read_bytes()[:700], r"truncated JSON: the file ends at line \d+ column"),
             "truncated.glb": (baked[".glb"].read_bytes()[:1000],
                               r"truncated GLB: header says \d+ bytes, file has 1000"),
             "truncated.usda": (usda[:len(usda) // 2],
                                r"cannot open USD stage: \S*truncated.usda:\d+:\d+: parse error")}
    lines = []
    for name, (data, problem) in cases.items():
        (tmp_path / name).write_bytes(data)
        assert cli(["validate", "--no-khronos", str(tmp_path / name)]) == 2, name
        out, err = capsys.readouterr()
        lines.append(err.strip())
        assert out == "" and len(err.strip().splitlines()) == 1 and err.startswith(f"baker: error: {tmp_path / name}: ")
        assert re.search(problem, err) and "Traceback" not in err and "pxrInternal" not in err, err
    print("\n".join(lines))

    assert cli(["validate", str(tmp_path / "nope.glb")]) == 2


def test_corrupt_file_fails_khronos_too(copy):
    """Khronos' messages are merged: an out-of-range index is an error there as well."""
    prim = copy.primitive
    indices = copy.json["accessors"][prim["indices"]]
    fmt = {5121: "<B", 5123: "<H", 5125: "<I"}[indices["componentType"]]
    struct.pack_into(fmt, copy.bin, copy.accessor_offset(prim["indices"]), 60000)
    path = copy.save()
    report = khronos_validate(path)
    if report is None:
        pytest.skip("Khronos glTF-Validator not installed")
    assert report["issues"]["numErrors"] > 0
    merged = validate.validate_file(path)
    assert {m["source"] for m in merged["issues"]["messages"] if m["severity"] == 0} == {"baker", "khronos"}


# ---------------------------------------------------------------------------------------------------- schemas
def test_schema_registry_and_files():
    registry = validate.schema_registry()
    assert ("BAKER_thickness", "material") in registry
    for (ext, kind), path in registry.items():
        schema = json.loads(path.read_text())
        Draft202012Validator.check_schema(schema)
        assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
        assert schema["$id"] == path.name and schema.get("title") and schema.get("description")
        for name, prop in schema.get("properties", {}).items():
            assert prop.get("description"), f"{path.name}: property {name} has no description"
        assert (path.parents[1] / "README.md").is_file(), f"{ext} has no README.md"


def test_schema_roots_are_the_repo_then_each_techniques_own(tmp_path):
    """Built-in techniques use the top-level schemas/; another root adds its extensions and may not redefine ours
    (tests/test_add_technique.py shows a technique bringing its root through the CLI)."""
    assert validate.schema_roots()[0] == SCHEMA_ROOT
    assert all(path.is_relative_to(SCHEMA_ROOT) for path in validate.schema_registry().values())
    (tmp_path / "BAKER_extra" / "schema").mkdir(parents=True)
    (tmp_path / "BAKER_extra" / "schema" / "node.BAKER_extra.schema.json").write_text("{}")
    both = validate.schema_registry((SCHEMA_ROOT, tmp_path))
    assert both[("BAKER_extra", "node")].parent == tmp_path / "BAKER_extra" / "schema"
    assert len(both) == len(validate.schema_registry()) + 1
    clash = tmp_path / "clash"
    (clash / "BAKER_thickness" / "schema").mkdir(parents=True)
    (clash / "BAKER_thickness" / "schema" / "material.BAKER_thickness.schema.json").write_text("{}")
    with pytest.raises(RuntimeError, match="two schemas for BAKER_thickness on material"):
        validate.schema_registry((SCHEMA_ROOT, clash))


def test_schema_matches_the_writer():
    """Everything the writer puts in BAKER_thickness is declared in the schema, and the README example is valid."""
    schema = json.loads(validate.schema_registry()[("BAKER_thickness", "material")].read_text())
    readme = (SCHEMA_ROOT / "BAKER_thickness" / "README.md").read_text()
    example = json.loads(readme.split("```json")[1].split("```")[0])
    ext = example["materials"][0]["extensions"]["BAKER_thickness"]
    assert not list(Draft202012Validator(schema).iter_errors(ext))
    assert set(ext) <= set(schema["properties"])
    assert set(schema["required"]) == {"rays", "distribution", "maxDistance", "attenuationDistance", "power"}


def test_thickness_values_are_read_as_written(baked):
    """The validator reads the accessor baker wrote (sanity check on the fixture itself)."""
    doc = GltfDocument.load(baked[".glb"])
    prim = doc.json["meshes"][0]["primitives"][0]
    values = doc.accessor(prim["attributes"]["_THICKNESS"])
    ext = doc.json["materials"][0]["extensions"]["BAKER_thickness"]
    assert np.all(values >= 0) and values.max() <= ext["maxDistance"]


# ---------------------------------------------------------------------------------------------------- one reader
def _gltf_corpus(tmp_path):
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).parent))
    from corpus import cases_gltf

    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "secret.bin").write_bytes(b"secret" * 16)
    env = {"outside": outside, "http": "http://127.0.0.1:9/"}
    for case in cases_gltf.CASES:
        folder = tmp_path / "cases" / case.name
        folder.mkdir(parents=True)
        yield case, case.make(folder, env)


def test_load_and_validate_report_the_same_first_problem(tmp_path):
    """``GltfDocument.load`` (bake, inspect, preview, build) and ``baker validate`` share one structural check: the
    one line a bake fails with is validate's first error, pointer and message."""
    from baker.errors import BakerError

    checked = refused = 0
    for case, path in _gltf_corpus(tmp_path):
        if case.expect["validate"].exit == 2:  # a container neither can parse: both refuse it with the same line
            with pytest.raises(BakerError) as raised_by_validate:
                validate.validate_file(path, khronos=False)
            with pytest.raises(BakerError) as raised:
                GltfDocument.load(path)
            assert raised.value.message == raised_by_validate.value.message, case.name
            refused += 1
            continue
        report = validate.validate_file(path, khronos=False)
        errors = [m for m in report["issues"]["messages"] if m["severity"] == 0]
        if case.expect["validate"].exit == 0:
            assert not errors, (case.name, errors)
            GltfDocument.load(path)
            continue
        with pytest.raises(BakerError) as raised:
            GltfDocument.load(path)
        first = f"{errors[0]['pointer']}: {errors[0]['message']}" if errors[0].get("pointer") else errors[0]["message"]
        assert raised.value.message == first, case.name
        checked += 1
    assert checked > 40 and refused >= 2


@pytest.mark.parametrize("edit, code, ptr", [
    (lambda j: j["meshes"][0]["primitives"][0]["attributes"].update(POSITION="0"), "TYPE_MISMATCH",
     "/meshes/0/primitives/0/attributes/POSITION"),
    (lambda j: j["nodes"].append({"children": [len(j["nodes"])]}), "NODE_LOOP", None),
    (lambda j: j["buffers"][0].pop("uri"), "BUFFER_DATA_MISSING", "/buffers/0"),
    (lambda j: j["buffers"][0].update(uri="../elsewhere.bin"), "URI_REFUSED", "/buffers/0/uri"),
    (lambda j: j["buffers"][0].update(uri="https://example.com/x.bin"), "URI_REFUSED", "/buffers/0/uri"),
    (lambda j: j["images"][0].update(uri="/etc/passwd"), "URI_REFUSED", "/images/0/uri"),
    (lambda j: j["accessors"][j["meshes"][0]["primitives"][0]["attributes"]["POSITION"]].update(type="VEC2"),
     "MESH_PRIMITIVE_ATTRIBUTES_ACCESSOR_INVALID_FORMAT", "/meshes/0/primitives/0/attributes/POSITION"),
])
def test_input_policy_errors(copy, edit, code, ptr):
    edit(copy.json)
    report = validate.validate_file(copy.save(), khronos=False)
    found = find(report, code)
    assert found and found[0]["severity"] == 0, report["issues"]["messages"]
    if ptr:
        assert found[0]["pointer"] == ptr


def test_nan_position_is_an_error_naming_the_accessor(copy):
    a = copy.primitive["attributes"]["POSITION"]
    struct.pack_into("<f", copy.bin, copy.accessor_offset(a) + 4, float("nan"))
    report = validate.validate_file(copy.save(), khronos=False)
    [msg] = find(report, "ACCESSOR_INVALID_FLOAT")
    assert msg["pointer"] == f"/accessors/{a}" and msg["severity"] == 0
