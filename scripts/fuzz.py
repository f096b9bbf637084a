#!/usr/bin/env python3
"""Fuzz baker's readers: mutate the bytes and the JSON of a few valid assets and run ``bake --bakes edges``,
``inspect`` and ``validate --no-khronos`` on every case; report tracebacks, time-outs and cases per second.

    scripts/fuzz.py [--cases 200] [--seed 0] [--timeout 20] [--subprocess-every 0] [--keep DIR] [--json] [--only K]

Seeds (made once per run in a temporary folder): examples/spot/spot.obj baked with ``edges,toon`` as a GLB and with
``edges,thickness`` as .gltf + .bin + PNG (bakes whose kernels compile quickly on a cold numba cache), and a hand-made indexed quad (normals, UVs, a material with a data: PNG
texture, extras) as .gltf + .bin and as .glb. Case ``k`` of seed ``S`` is a function of ``(S, k)`` alone, so
``--only k`` reproduces it. The mutator is small and seeded: byte flips, truncation, GLB header and chunk-length
edits, spans zeroed, inserted or cut, NaN floats in the binary data; and on the JSON (repacked into a valid GLB
container, so the damage reaches past the container check): numbers to strings, negatives, huge values, floats or
NaN/Infinity, keys deleted, lists and objects swapped, indices out of range, values moved between places.

Commands run in this process through :func:`baker.cli.main` (fast: nothing is imported or compiled twice), under a
SIGALRM time-out; ``--subprocess-every K`` runs every K-th case as ``python -m baker.cli`` instead (the real exit path,
a hard time-out). What counts as a finding:

- ``traceback``: an exception other than BakerError left ``baker.cli.main`` (in process), or a traceback on stderr;
- ``timeout``: a command ran longer than ``--timeout`` seconds;
- ``exit``: an exit code other than 0, 1 (validation errors) or 2 (bad input);
- ``left-behind``: a bake that failed left a file in its output folder.

Python warnings (e.g. numpy's RuntimeWarning on NaN data) are counted and listed, not findings. Exit status: 1 when
there are findings, else 0. ``--keep DIR`` saves each finding's input there; ``--json`` prints the report as JSON.
"""
from __future__ import annotations

import argparse
import base64
import contextlib
import io
import json
import math
import os
import random
import resource
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time
import traceback
import warnings
import zlib
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SPOT = ROOT / "examples" / "spot" / "spot.obj"
COMMANDS = ("bake", "inspect", "validate")
GLB_MAGIC, JSON_CHUNK, BIN_CHUNK = b"glTF", 0x4E4F534A, 0x004E4942


# ---------------------------------------------------------------------------------------------------- seeds
def png_1x1() -> bytes:
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 1, 1, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(b"\x00\xc0\x80\x40")) + chunk(b"IEND", b""))


def quad() -> tuple[dict, bytes]:
    """A hand-made indexed quad: POSITION, NORMAL, TEXCOORD_0, uint16 indices, a textured material, a node with a
    transform and extras. Returns (JSON without buffer URI, binary)."""
    pos = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0)
    nrm = struct.pack("<12f", *([0, 0, 1] * 4))
    uv = struct.pack("<8f", 0, 1, 1, 1, 1, 0, 0, 0)
    idx = struct.pack("<6H", 0, 1, 2, 0, 2, 3) + b"\0\0"
    binary = pos + nrm + uv + idx
    views = []
    offset = 0
    for data, target in ((pos, 34962), (nrm, 34962), (uv, 34962), (idx, 34963)):
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(data) - (2 if target == 34963 else 0),
                      "target": target})
        offset += len(data)
    gltf = {
        "asset": {"version": "2.0", "generator": "baker fuzz seed"},
        "scene": 0, "scenes": [{"nodes": [0], "name": "scene"}],
        "nodes": [{"mesh": 0, "name": "quad", "translation": [0, 0, 1], "extras": {"tag": [1, 2, 3]}}],
        "meshes": [{"name": "quad", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                                    "indices": 3, "material": 0, "mode": 4}]}],
        "materials": [{"name": "m", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                                              "baseColorFactor": [1, 0.5, 0.25, 1]},
                       "doubleSided": True}],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(png_1x1()).decode(), "mimeType": "image/png"}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"},
        ],
        "bufferViews": views,
        "buffers": [{"byteLength": len(binary)}],
    }
    return gltf, binary


def glb_bytes(gltf: dict, binary: bytes | None, allow_nan: bool = False) -> bytes:
    text = json.dumps(gltf, separators=(",", ":"), allow_nan=allow_nan).encode()
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<II", len(text), JSON_CHUNK) + text
    if binary is not None:
        binary += b"\0" * (-len(binary) % 4)
        chunks += struct.pack("<II", len(binary), BIN_CHUNK) + binary
    return GLB_MAGIC + struct.pack("<II", 2, 12 + len(chunks)) + chunks


def split_glb(data: bytes) -> tuple[dict, bytes | None]:
    (json_len,) = struct.unpack_from("<I", data, 12)
    gltf = json.loads(data[20:20 + json_len])
    rest = data[20 + json_len:]
    binary = rest[8:8 + struct.unpack_from("<I", rest, 0)[0]] if len(rest) >= 8 else None
    return gltf, binary


@dataclass
class Seed:
    """A valid asset: ``main`` (a .glb, or a .gltf) and the side files a .gltf names (relative name -> bytes)."""

    name: str
    main: str
    files: dict  # relative name -> bytes, main included


def make_seeds(folder: Path) -> list[Seed]:
    """Bake spot twice (GLB; .gltf + .bin + PNG) and write the quad twice; read every file back as bytes."""
    from baker.cli import main

    folder.mkdir(parents=True, exist_ok=True)
    fast = ["-q", "--thickness-rays", "4", "--thickness-texture-size", "32"]
    spot_glb, spot_gltf = folder / "spot_glb" / "spot.glb", folder / "spot_gltf" / "spot.gltf"
    for out, bakes in ((spot_glb, "edges,toon"), (spot_gltf, "edges,thickness")):
        out.parent.mkdir()
        code = main(["bake", str(SPOT), "-o", str(out), "--bakes", bakes, *fast])
        if code != 0:
            raise SystemExit(f"fuzz: could not bake the seed {out.name} (exit {code})")
    gltf, binary = quad()
    (folder / "quad_gltf").mkdir()
    (folder / "quad_gltf" / "quad.bin").write_bytes(binary)
    (folder / "quad_gltf" / "quad.gltf").write_text(json.dumps({**gltf, "buffers": [
        {"byteLength": len(binary), "uri": "quad.bin"}]}))
    (folder / "quad_glb").mkdir()
    (folder / "quad_glb" / "quad.glb").write_bytes(glb_bytes(gltf, binary))

    seeds = []
    for sub, main_name in (("spot_glb", "spot.glb"), ("spot_gltf", "spot.gltf"), ("quad_gltf", "quad.gltf"),
                           ("quad_glb", "quad.glb")):
        files = {p.name: p.read_bytes() for p in sorted((folder / sub).iterdir()) if p.is_file()}
        seeds.append(Seed(sub, main_name, files))
    return seeds


# ---------------------------------------------------------------------------------------------------- mutator
INTERESTING_INTS = (0, 1, -1, 2, 3, 4, 255, 256, 65535, 65536, 2**31 - 1, 2**31, 2**32 - 1, 2**32, 2**53, 2**63,
                    -(2**31), 10**12)
INTERESTING_VALUES = (None, True, False, "", "0", "NaN", "Infinity", "-1", "../../outside.bin", "data:,",
                      "http://127.0.0.1:9/x.bin", "/etc/passwd", [], {}, [[]], {"": {}}, 0.5, -0.0, 1e308, -1e308,
                      5e-324, 3.0, float("nan"), float("inf"), float("-inf"))


def json_paths(node, parts=()):
    """Every (path, value) in a JSON tree, the root excluded."""
    if isinstance(node, dict):
        for key, value in node.items():
            yield parts + (key,), value
            yield from json_paths(value, parts + (key,))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield parts + (i,), value
            yield from json_paths(value, parts + (i,))


def get_parent(doc, path):
    node = doc
    for part in path[:-1]:
        node = node[part]
    return node


def mutate_number(rng: random.Random, value):
    choice = rng.randrange(9)
    if choice == 0:
        return str(value)
    if choice == 1:
        return -value if value else -1
    if choice == 2:
        return rng.choice(INTERESTING_INTS)
    if choice == 3:
        return float(value) + rng.choice((0.0, 0.5, 1e-9))  # 3.0 is a legal index; 3.5 is not
    if choice == 4:
        return rng.choice((float("nan"), float("inf"), float("-inf"), 1e308, "NaN"))
    if choice == 5:
        return value + rng.choice((1, -1, 4, -4, 1000))
    if choice == 6:
        return [value]
    if choice == 7:
        return bool(value)
    return None


COLLECTIONS = ("accessors", "bufferViews", "buffers", "meshes", "nodes", "materials", "textures", "images",
               "samplers", "scenes", "cameras", "skins", "animations")


def mutate_json(rng: random.Random, doc) -> str:
    """One JSON mutation in place; returns what it did."""
    paths = list(json_paths(doc))
    if not paths:
        return "json: empty document"
    path, value = rng.choice(paths)
    parent = get_parent(doc, path)
    key = path[-1]
    where = "/" + "/".join(str(p) for p in path)
    op = rng.randrange(10)
    if op == 0 and isinstance(value, (int, float)) and not isinstance(value, bool):
        parent[key] = mutate_number(rng, value)
        return f"json: number {where} -> {parent[key]!r}"
    if op == 1:  # an index out of range: the length of some collection, or -1
        name = rng.choice(COLLECTIONS)
        parent[key] = rng.choice((len(doc.get(name) or []) if isinstance(doc, dict) else 0, -1, 2**31, 10**6))
        return f"json: {where} -> index {parent[key]} (len {name})"
    if op == 2:
        if isinstance(parent, dict):
            del parent[key]
        else:
            parent.pop(key)
        return f"json: delete {where}"
    if op == 3 and isinstance(value, list):
        parent[key] = {str(i): v for i, v in enumerate(value)}
        return f"json: list -> object {where}"
    if op == 4 and isinstance(value, dict):
        parent[key] = list(value.values())
        return f"json: object -> list {where}"
    if op == 5:
        parent[key] = rng.choice(INTERESTING_VALUES)
        return f"json: {where} -> {parent[key]!r}"
    if op == 6:  # a value from elsewhere in the document (type confusion)
        other_path, other = rng.choice(paths)
        parent[key] = json.loads(json.dumps(other, allow_nan=True))
        return f"json: {where} -> copy of /{'/'.join(map(str, other_path))}"
    if op == 7 and isinstance(value, list) and value:
        value.append(json.loads(json.dumps(rng.choice(value), allow_nan=True)))
        return f"json: duplicate an item of {where}"
    if op == 8 and isinstance(value, str):
        parent[key] = rng.choice((value[: len(value) // 2], value + "\x00", value.upper(), "%2e%2e/" + value,
                                  value * 50, str(rng.randrange(100))))
        return f"json: string {where} -> {parent[key][:40]!r}"
    if op == 9 and isinstance(parent, dict):  # an unknown or misplaced key
        parent[rng.choice(("extensions", "extras", "byteStride", "sparse", "normalized", "KHR_x"))] = \
            rng.choice(INTERESTING_VALUES)
        return f"json: add a key beside {where}"
    parent[key] = mutate_number(rng, value) if isinstance(value, (int, float)) else rng.choice(INTERESTING_VALUES)
    return f"json: {where} -> {parent[key]!r}"


def mutate_bytes(rng: random.Random, data: bytes, is_glb: bool) -> tuple[bytes, str]:
    """One byte-level mutation; returns (new bytes, what it did)."""
    buf = bytearray(data)
    n = len(buf)
    op = rng.randrange(8 if is_glb else 6)
    if n == 0:
        return bytes(rng.randbytes(rng.randrange(1, 64))), "bytes: random"
    if op == 0:
        spots = [rng.randrange(min(n, 256)) if rng.random() < 0.5 else rng.randrange(n) for _ in
                 range(rng.randint(1, 8))]
        for i in spots:
            buf[i] ^= 1 << rng.randrange(8) if rng.random() < 0.7 else rng.randrange(1, 256)
        return bytes(buf), f"bytes: flip {len(spots)} at {sorted(spots)[:4]}"
    if op == 1:
        cut = rng.choice((0, 1, 11, 12, 19, 20, 21, n // 2, n - 1, rng.randrange(n)))
        return bytes(buf[:cut]), f"bytes: truncate to {cut} of {n}"
    if op == 2:
        i, k = rng.randrange(n), rng.randint(1, 64)
        buf[i:i + k] = bytes(min(k, n - i))
        return bytes(buf), f"bytes: zero {k} at {i}"
    if op == 3:
        i = rng.randrange(n)
        buf[i:i] = rng.randbytes(rng.randint(1, 16))
        return bytes(buf), f"bytes: insert at {i}"
    if op == 4:
        i, k = rng.randrange(n), rng.randint(1, 64)
        del buf[i:i + k]
        return bytes(buf), f"bytes: cut {k} at {i}"
    if op == 5:  # NaN / Inf floats at 4-aligned offsets (accessor data)
        start = 20 + struct.unpack_from("<I", buf, 12)[0] + 8 if is_glb and n > 20 else 0
        start = min(start, n)
        count = rng.randint(1, 4)
        for _ in range(count):
            if n - start >= 4:
                i = start + (rng.randrange(n - start - 3) & ~3)
                struct.pack_into("<f", buf, i, rng.choice((math.nan, math.inf, -math.inf, 3.4e38)))
        return bytes(buf), f"bytes: {count} non-finite floats in data"
    # GLB header and chunk lengths (ops 6, 7)
    fields = {"magic": 0, "version": 4, "length": 8, "json length": 12, "json type": 16}
    if n > 20:
        bin_at = 20 + struct.unpack_from("<I", buf, 12)[0]
        if bin_at + 8 <= n:
            fields.update({"bin length": bin_at, "bin type": bin_at + 4})
    name = rng.choice(sorted(fields))
    at = fields[name]
    if at + 4 > n:
        return bytes(buf[:at]), f"bytes: truncate in {name}"
    old = struct.unpack_from("<I", buf, at)[0]
    new = rng.choice((0, 1, old - 1, old + 1, old - 4, old + 4, old * 2, n, n + 8, 2**31, 2**32 - 1,
                      rng.randrange(2**32))) % 2**32
    struct.pack_into("<I", buf, at, new)
    return bytes(buf), f"bytes: {name} {old} -> {new}"


@dataclass
class Case:
    index: int
    seed: str
    main: str
    files: dict
    steps: list = field(default_factory=list)


def make_case(seeds: list[Seed], run_seed: int, index: int) -> Case:
    """Case ``index`` of run ``run_seed``: a seed, then 1-3 JSON mutations or 1-2 byte mutations of one file."""
    rng = random.Random(f"{run_seed}:{index}")
    seed = seeds[rng.choice((0, 1, 2, 2, 3, 3))]  # the small quad twice as often: it is fast and fully reached
    files = dict(seed.files)
    case = Case(index, seed.name, seed.main, files)
    is_glb = seed.main.endswith(".glb")
    target = seed.main if rng.random() < 0.85 else rng.choice(sorted(files))
    data = files[target]
    if rng.random() < 0.55 and (target.endswith(".gltf") or (is_glb and target == seed.main)):
        gltf, binary = split_glb(data) if target.endswith(".glb") else (json.loads(data), None)
        for _ in range(rng.randint(1, 3)):
            case.steps.append(f"{target} {mutate_json(rng, gltf)}")
        nan_text = rng.random() < 0.5  # JSON with NaN/Infinity literals (not JSON, but Python's json reads them)
        try:
            if target.endswith(".glb"):
                data = glb_bytes(gltf, binary, allow_nan=nan_text)
            else:
                data = json.dumps(gltf, allow_nan=nan_text).encode()
        except ValueError:  # NaN refused: write it as the strict writer would not
            data = json.dumps(gltf, allow_nan=True).encode() if not target.endswith(".glb") else \
                glb_bytes(gltf, binary, allow_nan=True)
    else:
        for _ in range(rng.randint(1, 2)):
            data, what = mutate_bytes(rng, data, target.endswith(".glb"))
            case.steps.append(f"{target} {what}")
    files[target] = data
    return case


# ---------------------------------------------------------------------------------------------------- running
class TimedOut(BaseException):
    """Raised by SIGALRM in the command under test (BaseException: a broad ``except Exception`` cannot eat it)."""


def _alarm(signum, frame):
    raise TimedOut()


@dataclass
class Finding:
    case: int
    command: str
    kind: str  # traceback, timeout, exit, left-behind
    detail: str
    steps: list
    seed: str
    input: str = ""

    def signature(self) -> str:
        return f"{self.command}: {self.kind}: {self.detail.strip().splitlines()[-1] if self.detail.strip() else ''}"


def argv_for(command: str, path: Path, out: Path) -> list[str]:
    return {"bake": ["bake", str(path), "-o", str(out / ("out" + path.suffix)), "--bakes", "edges", "-q"],
            "inspect": ["inspect", str(path)],
            "validate": ["validate", str(path), "--no-khronos"]}[command]


def run_in_process(argv: list[str], timeout: float) -> tuple[int | None, str, str, str | None, list]:
    """(exit code, stdout, stderr, traceback text or None, warnings) of ``baker.cli.main(argv)``."""
    from baker.cli import main

    out, err = io.StringIO(), io.StringIO()
    code, tb = None, None
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, timeout)
    try:
        with warnings.catch_warnings(record=True) as caught, contextlib.redirect_stdout(out), \
                contextlib.redirect_stderr(err):
            warnings.simplefilter("always")
            try:
                code = main(argv)
            except SystemExit as exc:  # argparse
                code = exc.code if isinstance(exc.code, int) else 2
            finally:
                signal.setitimer(signal.ITIMER_REAL, 0)
    except TimedOut:
        tb = "TimedOut"
        caught = []
    except Exception:  # noqa: BLE001 - exactly what the fuzzer looks for
        tb = traceback.format_exc()
        caught = []
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    return code, out.getvalue(), err.getvalue(), tb, [f"{w.category.__name__}: {w.message}" for w in caught]


def run_subprocess(argv: list[str], timeout: float) -> tuple[int | None, str, str, str | None, list]:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH")) if p)}
    try:
        proc = subprocess.run([sys.executable, "-m", "baker.cli", *argv], capture_output=True, text=True,
                              timeout=timeout, env=env, stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        return None, "", "", "TimedOut", []
    return proc.returncode, proc.stdout, proc.stderr, None, []


def run_case(case: Case, work: Path, timeout: float, use_subprocess: bool, stats: dict) -> list[Finding]:
    folder = work / f"case_{case.index}"
    shutil.rmtree(folder, ignore_errors=True)
    (folder / "in").mkdir(parents=True)
    for name, data in case.files.items():
        (folder / "in" / name).write_bytes(data)
    path = folder / "in" / case.main
    findings = []
    for command in COMMANDS:
        out = folder / f"out_{command}"
        out.mkdir()
        argv = argv_for(command, path, out)
        runner = run_subprocess if use_subprocess else run_in_process
        code, stdout, stderr, tb, caught = runner(argv, timeout)
        stats["exits"][f"{command} {code}"] = stats["exits"].get(f"{command} {code}", 0) + 1
        for w in caught:
            stats["warnings"][f"{command}: {w}"] = stats["warnings"].get(f"{command}: {w}", 0) + 1

        def found(kind, detail):
            findings.append(Finding(case.index, command, kind, detail, case.steps, case.seed))

        if tb == "TimedOut":
            found("timeout", f"over {timeout:g} s")
        elif tb is not None:
            found("traceback", tb)
        elif "Traceback (most recent call last)" in stderr:
            found("traceback", stderr[stderr.index("Traceback (most recent call last)"):])
        elif code not in (0, 1, 2):
            found("exit", f"exit {code}: {stderr.strip()[-500:]}")
        if command == "bake" and code != 0 and any(out.iterdir()):
            found("left-behind", f"exit {code} left {sorted(p.name for p in out.iterdir())}")
    shutil.rmtree(folder, ignore_errors=True)
    return findings


def limit_memory(gib: float):
    """Cap this process's address space (a mutated count must not take the machine); returns the old limit."""
    old = resource.getrlimit(resource.RLIMIT_AS)
    if gib > 0:
        want = int(gib * 2**30)
        hard = old[1]
        resource.setrlimit(resource.RLIMIT_AS, (want if hard == resource.RLIM_INFINITY else min(want, hard), hard))
    return old


def fuzz(cases: int = 200, seed: int = 0, timeout: float = 20.0, subprocess_every: int = 0, keep: Path | None = None,
         only: int | None = None, max_memory_gib: float = 16.0, log=None) -> dict:
    """Run the fuzz; return the report (``cases``, ``seconds``, ``casesPerSecond``, ``findings``, ``signatures``,
    ``exits``, ``warnings``)."""
    log = log or (lambda text: None)
    with tempfile.TemporaryDirectory(prefix="baker-fuzz-") as tmp:
        work = Path(tmp)
        t0 = time.perf_counter()
        seeds = make_seeds(work / "seeds")
        seed_seconds = time.perf_counter() - t0
        log(f"seeds: {', '.join(s.name for s in seeds)} in {seed_seconds:.1f} s")
        old_limit = limit_memory(max_memory_gib)
        stats = {"exits": {}, "warnings": {}}
        findings: list[Finding] = []
        indices = [only] if only is not None else range(cases)
        t1 = time.perf_counter()
        try:
            for n, index in enumerate(indices):
                case = make_case(seeds, seed, index)
                use_sub = bool(subprocess_every) and index % subprocess_every == 0
                new = run_case(case, work / "cases", timeout, use_sub, stats)
                for f in new:
                    if keep is not None:
                        dest = Path(keep) / f"case_{index}"
                        dest.mkdir(parents=True, exist_ok=True)
                        for name, data in case.files.items():
                            (dest / name).write_bytes(data)
                        f.input = str(dest / case.main)
                    log(f"case {index} [{case.seed}] {f.command}: {f.kind}: {f.signature()}\n    "
                        + "\n    ".join(case.steps))
                findings.extend(new)
                if (n + 1) % 50 == 0:
                    log(f"{n + 1} cases, {len(findings)} findings, {time.perf_counter() - t1:.1f} s")
        finally:
            resource.setrlimit(resource.RLIMIT_AS, old_limit)
        seconds = time.perf_counter() - t1
    signatures: dict[str, list[int]] = {}
    for f in findings:
        signatures.setdefault(f.signature(), []).append(f.case)
    done = len(indices)
    return {"cases": done, "seed": seed, "seedSeconds": round(seed_seconds, 2), "seconds": round(seconds, 2),
            "casesPerSecond": round(done / seconds, 2) if seconds else None,
            "findings": [f.__dict__ for f in findings], "signatures": signatures,
            "exits": dict(sorted(stats["exits"].items())), "warnings": dict(sorted(stats["warnings"].items()))}


def format_report(report: dict) -> str:
    lines = [f"{report['cases']} cases (seed {report['seed']}) in {report['seconds']} s: "
             f"{report['casesPerSecond']} cases/s (seeds made in {report['seedSeconds']} s); "
             f"{len(report['findings'])} findings, {len(report['signatures'])} distinct"]
    for sig, case_ids in sorted(report["signatures"].items(), key=lambda kv: -len(kv[1])):
        lines.append(f"  {len(case_ids):4d} x {sig}   (cases {', '.join(map(str, case_ids[:8]))}"
                     f"{' ...' if len(case_ids) > 8 else ''})")
    shown = set()
    for f in report["findings"]:
        sig = f"{f['command']}: {f['kind']}"
        key = (f["command"], f["kind"], f["detail"].strip().splitlines()[-1] if f["detail"].strip() else "")
        if key in shown:
            continue
        shown.add(key)
        lines.append(f"\ncase {f['case']} [{f['seed']}] {sig}" + (f", input kept in {f['input']}" if f["input"] else ""))
        lines.extend(f"  mutation: {s}" for s in f["steps"])
        lines.extend("  | " + line for line in f["detail"].rstrip().splitlines()[-12:])
    lines.append("\nexit codes: " + ", ".join(f"{k}: {v}" for k, v in report["exits"].items()))
    if report["warnings"]:
        lines.append("warnings (not findings):")
        lines.extend(f"  {v:4d} x {k[:160]}" for k, v in sorted(report["warnings"].items(), key=lambda kv: -kv[1]))
    return "\n".join(lines)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("--cases", type=int, default=200, help="number of cases (default 200)")
    p.add_argument("--seed", type=int, default=0, help="run seed (default 0)")
    p.add_argument("--only", type=int, default=None, help="run only case K of this seed (reproduce a finding)")
    p.add_argument("--timeout", type=float, default=20.0, help="seconds per command (default 20)")
    p.add_argument("--subprocess-every", type=int, default=0, metavar="K",
                   help="run every K-th case in a subprocess too (default 0: none)")
    p.add_argument("--max-memory", type=float, default=16.0, metavar="GIB",
                   help="address-space cap for this process in GiB (default 16; 0: none)")
    p.add_argument("--keep", type=Path, default=None, metavar="DIR", help="save each finding's input in DIR")
    p.add_argument("--json", action="store_true", help="print the report as JSON")
    args = p.parse_args(argv)
    sys.path.insert(0, str(ROOT))
    report = fuzz(args.cases, args.seed, args.timeout, args.subprocess_every, args.keep, args.only, args.max_memory,
                  log=lambda text: print(text, file=sys.stderr, flush=True))
    print(json.dumps(report, indent=1) if args.json else format_report(report))
    return 1 if report["findings"] else 0


if __name__ == "__main__":
    sys.exit(main())
