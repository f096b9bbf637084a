"""The runtime descriptors (runtime-shaders/shared/src/techniques.js) against what is written about the runtimes:
every module named exists, the READMEs' runtime tables (which extension -> which module, switch, property) say what
the descriptors say and are the ones tools/readme_tables.mjs writes from them, and the viewer passes every module
the descriptors name. A technique added to the descriptors and missing from a table, or a table row naming another
extension's switch or module, fails here."""
from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
SHADERS = ROOT / "runtime-shaders"


@pytest.fixture(scope="module")
def runtimes():
    if shutil.which("node") is None:
        pytest.skip("node is not installed (scripts/test installs it)")
    script = ("import { RUNTIMES, TECHNIQUES } from './runtime-shaders/shared/src/index.js';"
              "console.log(JSON.stringify({ RUNTIMES, TECHNIQUES }));")
    result = subprocess.run(["node", "--input-type=module", "-e", script], cwd=ROOT, capture_output=True, text=True,
                            timeout=60)
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)


def _rows(readme: Path, header: str) -> list[list[str]]:
    """The cells of the table under the header row starting with `header` (markdown, `|`-separated)."""
    lines = readme.read_text().splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(header))
    rows = []
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        rows.append([cell.strip() for cell in line.strip("|").split("|")])
    return rows


def _codes(cell: str) -> list[str]:
    return re.findall(r"`([^`]+)`", cell)


def test_every_module_a_descriptor_names_exists(runtimes):
    for r in runtimes["RUNTIMES"]:
        if r["modules"].get("glsl"):
            assert (SHADERS / r["modules"]["glsl"]).is_file(), r["name"]
            # its WGSL twin (runtime-shaders/README.md), named beside it: what a WebGPU host passes (options.wgsl)
            assert r["modules"].get("wgsl") == r["modules"]["glsl"][:-len(".glsl")] + ".wgsl", r["name"]
            assert (SHADERS / r["modules"]["wgsl"]).is_file(), r["name"]


def test_switches_are_the_descriptors_in_order(runtimes):
    switches = [s["name"] for r in runtimes["RUNTIMES"] for s in r["switches"]]
    assert list(runtimes["TECHNIQUES"]) == switches
    assert len(set(switches)) == len(switches)
    for r in runtimes["RUNTIMES"]:
        for s in r["switches"]:
            assert runtimes["TECHNIQUES"][s["name"]]["extension"] == r["extension"]


def test_runtime_shaders_module_table_matches(runtimes):
    rows = _rows(SHADERS / "README.md", "| Module |")
    table = {_codes(row[0])[0]: _codes(row[2]) for row in rows}
    named = {r["modules"]["glsl"]: r["extension"] for r in runtimes["RUNTIMES"] if r["modules"].get("glsl")}
    assert set(table) == set(named), "runtime-shaders/README.md's module table lists other modules than the descriptors"
    for module, extension in named.items():
        assert extension in table[module], f"{module}: the README says {table[module]}, the descriptor {extension}"


@pytest.mark.parametrize("readme,header,switch_column,module_column", [
    ("three/README.md", "| extension | plugin | switch |", 2, None),
    ("babylon/README.md", "| Extension | Technique (switch) |", 1, 3),
])
def test_host_tables_match(runtimes, readme, header, switch_column, module_column):
    by_switch = {s["name"]: (r, s) for r in runtimes["RUNTIMES"] for s in r["switches"]}
    seen = set()
    for row in _rows(SHADERS / readme, header):
        extensions = [c.split(".")[0] for c in _codes(row[0]) if c.startswith("BAKER_")]
        switches = [c for c in _codes(row[switch_column]) if c in by_switch]
        if not switches:
            continue  # a row of an extension with no switch of its own (EXT_mesh_primitive_edge_visibility)
        for name in switches:
            r, s = by_switch[name]
            seen.add(name)
            assert r["extension"] in extensions, f"{readme}: switch {name} is on {extensions}, not {r['extension']}"
            assert ("off by default" in row[switch_column]) == bool(s.get("defaultOff")), f"{readme}: {name}"
            if module_column is not None:
                module = r["modules"].get("glsl")
                assert (_codes(row[module_column]) == [module]) if module else row[module_column] == "—", \
                    f"{readme}: {name} draws with {module}, the table says {row[module_column]}"
    assert seen == set(by_switch), f"{readme}: no row for the switches {sorted(set(by_switch) - seen)}"


def test_gltf_transform_table_places_match(runtimes):
    places = {"material": "material", "primitive": "mesh.primitive", "fin primitive": "mesh.primitive",
              "node": "node", "root": "glTF", "cards primitive": "mesh.primitive"}
    rows = {_codes(row[0])[0]: row[2] for row in _rows(SHADERS / "gltf-transform" / "README.md", "| extension | class |")}
    for r in runtimes["RUNTIMES"]:
        assert r["extension"] in rows, f"gltf-transform/README.md has no row for {r['extension']}"
        said = {places[p] for p in re.findall(r"\(([^)]+)\)", rows[r["extension"]])}
        assert said == set(r["on"]), f"{r['extension']}: the README puts it on {said}, the descriptor on {r['on']}"


def test_viewer_passes_every_module(runtimes, tmp_path):
    # the viewer's shaders.js derives its list from the descriptors: bundled as the viewer builds it and run, it must
    # hold every descriptor's module, as the file's text, under its key
    viewer = ROOT / "examples" / "viewer"
    esbuild = viewer / "node_modules" / ".bin" / "esbuild"
    assert esbuild.is_file(), "examples/viewer has no esbuild (scripts/test installs it)"
    bundle = tmp_path / "shaders.mjs"
    build = subprocess.run([str(esbuild), "src/shaders.js", "--bundle", "--format=esm", "--platform=node",
                            "--loader:.glsl=text", "--alias:@baker/shared=../../runtime-shaders/shared/src/index.js",
                            f"--outfile={bundle}", "--log-level=warning"], cwd=viewer, capture_output=True, text=True,
                           timeout=60)
    assert build.returncode == 0, build.stderr
    script = f"import {{ shaders }} from {json.dumps(bundle.as_uri())}; console.log(JSON.stringify(shaders));"
    result = subprocess.run(["node", "--input-type=module", "-e", script], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    passed = json.loads(result.stdout)
    wanted = {r["modules"]["key"]: r["modules"]["glsl"] for r in runtimes["RUNTIMES"] if r["modules"].get("glsl")}
    wanted["hairShading"] = "baker_hair_shading.glsl"  # BAKER_hair_shading's module: hair includes it, no descriptor
    assert set(passed) == set(wanted)
    for key, module in wanted.items():
        assert passed[key] == (SHADERS / module).read_text(), f"options.shaders.{key} is not {module}"


def test_descriptor_places_are_the_schemas(runtimes):
    for r in runtimes["RUNTIMES"]:
        schemas = sorted((ROOT / "schemas" / r["extension"] / "schema").glob(f"*.{r['extension']}.schema.json"))
        kinds = {path.name[: -len(f".{r['extension']}.schema.json")] for path in schemas}
        assert kinds == set(r["on"]), f"{r['extension']}: schemas for {kinds}, the descriptor says {r['on']}"


def test_stages_module_is_up_to_date(runtimes):
    # shared/src/stages.js carries runtime-shaders/hosts/web/*.glsl to the web hosts: regenerated, it must not change
    result = subprocess.run(["node", str(SHADERS / "shared" / "tools" / "stages.mjs"), "--check"], capture_output=True,
                            text=True, timeout=60)
    assert result.returncode == 0, result.stderr


def test_descriptor_reads_only_properties_the_schemas_define(runtimes):
    # a misspelt or renamed property would silently give the default in every host
    for r in runtimes["RUNTIMES"]:
        properties = set()
        for path in (ROOT / "schemas" / r["extension"] / "schema").glob("*.schema.json"):
            properties |= set(json.loads(path.read_text()).get("properties", {}))
        for entry in r["attributes"] + r["textures"] + r["uniforms"]:
            sources = entry.get("from", [])
            for source in [sources] if isinstance(sources, str) else sources:
                assert source.split(".")[0] in properties, f"{r['extension']}: {entry['name']} reads {source}"


def test_readme_tables_are_the_descriptors(runtimes):
    # the four READMEs' runtime tables are written from the descriptors' `readme` rows: rewritten, none may change
    result = subprocess.run(["node", str(SHADERS / "shared" / "tools" / "readme_tables.mjs"), "--check"],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
