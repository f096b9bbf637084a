"""Plumbing of the WGSL tests: a call of one runtime-module function per sample, evaluated in a WebGPU compute (or
fragment) pass in headless Chromium by ``tests/gl/wgsl_harness.mjs``.

A :class:`Case` names the function's arguments and their WGSL types; :func:`kernel` writes the entry point that
reads them for sample ``i`` from a storage buffer of float32 (interleaved, one row per sample), calls the function
and writes its result to the output buffer. The inputs go in and the outputs come back as raw float32 bytes, so the
comparison with the numpy twins sees exactly what the GPU computed.
"""
from __future__ import annotations

import base64
import json
import subprocess
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from .glsl import REPO

HARNESS = Path(__file__).with_name("wgsl_harness.mjs")
FRAGMENT_WIDTH = 64  # fragments per row of a fragment job's target

# float32 components of each argument and result type (matrices column by column, as WGSL stores them)
WIDTHS = {"f32": 1, "i32": 1, "u32": 1, "bool": 1, "vec2f": 2, "vec3f": 3, "vec4f": 4, "mat3x3f": 9}


@dataclass
class Texture:
    """An rgba32float texture (levels finest first, each (H, W, 4), or (layers, H, W, 4) for "2d-array") and its
    sampler's address mode; filtering is LINEAR for magnification, minification and between mip levels."""
    name: str
    levels: list
    address: str = "clamp-to-edge"
    dimension: str = "2d"

    def wgsl_type(self) -> str:
        return "texture_2d_array<f32>" if self.dimension == "2d-array" else "texture_2d<f32>"

    def spec(self) -> dict:
        base = np.asarray(self.levels[0], np.float32)
        layers = base.shape[0] if self.dimension == "2d-array" else 1
        height, width = base.shape[-3:-1]
        return {"dimension": self.dimension, "width": width, "height": height, "layers": layers,
                "address": self.address, "levels": [_encode(np.asarray(level, np.float32)) for level in self.levels]}


@dataclass
class Case:
    """One function evaluated on ``inputs`` (name -> (n, width) or (n,) array, in ``args`` order). ``call`` is the
    WGSL expression of the result (the argument names are in scope; the textures as ``<name>`` and
    ``<name>Sampler``), or ``body`` statements that set ``var result: <result>``. ``reference`` gives the expected
    (n, width) from the same inputs (the numpy twin); ``tolerance`` (absolute, relative) bounds |WGSL - twin|, and
    ``why`` says why a case needs more than a few ulp. ``stage`` "fragment" for textureSample (implicit derivatives),
    "compute" otherwise."""
    module: str
    function: str
    args: list
    result: str
    inputs: dict
    reference: Callable
    call: str = ""
    body: str = ""
    textures: list = field(default_factory=list)
    stage: str = "compute"
    label: str = ""
    tolerance: tuple = (1e-6, 4e-6)  # (absolute, relative): a few float32 ulp
    why: str = ""  # the reason for a looser tolerance

    @property
    def name(self) -> str:
        return f"{self.module}:{self.function}{'[' + self.label + ']' if self.label else ''}"

    @property
    def count(self) -> int:
        return len(next(iter(self.inputs.values())))


def _encode(array: np.ndarray) -> str:
    return base64.b64encode(np.ascontiguousarray(array, np.float32).tobytes()).decode()


def _load(kind: str, offset: int) -> str:
    parts = [f"inputs[sample_row + {offset + k}u]" for k in range(WIDTHS[kind])]
    if kind == "f32":
        return parts[0]
    if kind in ("i32", "u32"):
        return f"{kind}({parts[0]})"
    if kind == "bool":
        return f"({parts[0]} > 0.5)"
    return f"{kind}({', '.join(parts)})"


def _store(kind: str) -> list:
    if kind in ("f32",):
        return ["result"]
    if kind in ("i32", "u32"):
        return ["f32(result)"]
    if kind == "bool":
        return ["select(0.0, 1.0, result)"]
    if kind == "mat3x3f":
        return [f"result[{c}][{r}]" for c in range(3) for r in range(3)]
    return [f"result[{k}]" for k in range(WIDTHS[kind])]


def stride_in(case: Case) -> int:
    return sum(WIDTHS[kind] for _, kind in case.args)


def kernel(case: Case, module_text: str) -> str:
    """The module, the bindings and an entry point that evaluates ``case`` for one sample."""
    lines = [module_text, "", "// ---- test kernel (tests/gl/wgsl.py) ----",
             "@group(0) @binding(0) var<storage, read> inputs: array<f32>;",
             "@group(0) @binding(1) var<storage, read_write> outputs: array<f32>;"]
    for k, texture in enumerate(case.textures):
        lines.append(f"@group(0) @binding({2 + 2 * k}) var {texture.name}: {texture.wgsl_type()};")
        lines.append(f"@group(0) @binding({3 + 2 * k}) var {texture.name}Sampler: sampler;")
    # `_ = &inputs` keeps binding 0 in the automatic layout when the function takes no argument
    body = ["    _ = &inputs;", f"    let sample_row = i * {max(stride_in(case), 1)}u;"]
    offset = 0
    for name, kind in case.args:
        body.append(f"    let {name} = {_load(kind, offset)};")
        offset += WIDTHS[kind]
    if case.body:
        body.append(case.body)
    else:
        body.append(f"    let result: {case.result} = {case.call};")
    width = WIDTHS[case.result]
    for k, value in enumerate(_store(case.result)):
        body.append(f"    outputs[i * {width}u + {k}u] = {value};")
    if case.stage == "compute":
        lines += ["@compute @workgroup_size(64)", "fn main(@builtin(global_invocation_id) id: vec3u) {",
                  "    let i = id.x;", f"    if (i >= {case.count}u) {{ return; }}", *body, "}"]
    else:
        # every fragment is a sample (count is a multiple of the row width): no early return, so textureSample
        # stays in uniform control flow
        lines += ["@vertex", "fn vertex_main(@builtin(vertex_index) v: u32) -> @builtin(position) vec4f {",
                  "    let corner = vec2f(f32((v << 1u) & 2u), f32(v & 2u));",
                  "    return vec4f(corner * 2.0 - 1.0, 0.0, 1.0);", "}",
                  "@fragment", "fn fragment_main(@builtin(position) position: vec4f) -> @location(0) vec4f {",
                  f"    let i = u32(position.y) * {FRAGMENT_WIDTH}u + u32(position.x);", *body,
                  "    return vec4f(0.0);", "}"]
    return "\n".join(lines) + "\n"


def read_wgsl(name: str) -> str:
    return (REPO / "runtime-shaders" / name).read_text()


def job(case: Case) -> dict:
    module_text = read_wgsl(f"baker_{case.module}.wgsl")
    rows = [np.asarray(case.inputs[name], np.float32).reshape(case.count, -1) for name, _ in case.args]
    for (name, kind), row in zip(case.args, rows):
        assert row.shape[1] == WIDTHS[kind], (case.name, name, row.shape)
    inputs = np.concatenate(rows, axis=1) if rows else np.zeros((case.count, 1), np.float32)
    if case.stage == "fragment":
        assert case.count % FRAGMENT_WIDTH == 0, case.name
    return {"name": case.name, "code": kernel(case, module_text), "stage": case.stage, "count": case.count,
            "stride": WIDTHS[case.result], "inputs": _encode(inputs), "width": FRAGMENT_WIDTH,
            "textures": [texture.spec() for texture in case.textures]}


def run_jobs(jobs: list, spec: Path) -> dict:
    """Run the harness on ``jobs`` (written to ``spec``): name -> {messages, outputs (float32 array), error}."""
    spec.write_text(json.dumps(jobs))
    done = subprocess.run(["node", str(HARNESS), str(spec)], capture_output=True, text=True, timeout=900, cwd=REPO)
    assert done.returncode == 0, done.stderr[-4000:]
    results = {}
    for line in done.stdout.splitlines():
        if line.startswith("{"):
            result = json.loads(line)
            if "outputs" in result:
                result["outputs"] = np.frombuffer(base64.b64decode(result["outputs"]), np.float32)
            results[result["name"]] = result
    assert sorted(results) == sorted(j["name"] for j in jobs), done.stdout[-2000:]
    return results
