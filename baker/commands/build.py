"""``baker build``: bake every asset a recipe names, incrementally, in parallel or on a Dask cluster.

Recipe (``baker.toml``, or ``[tool.baker]`` in ``pyproject.toml``), paths relative to the recipe's folder::

    [build]
    output = "baked"            # output folder; each input keeps its relative path, with the new suffix
    format = "glb"              # glb | gltf | usda | usdc | usdz
    bakes = ["thickness"]
    seed = 0
    attribute-layout = "blender" # blender | native (custom vertex attributes, as `baker bake --attribute-layout`)
    compress = "none"           # none | meshopt | meshopt-gzip | meshopt-lossless (glb/gltf, as `baker bake --compress`)

    [options.thickness]         # defaults for every asset: the fields of the bake's options dataclass
    rays = 64

    [[assets]]                  # later entries override earlier ones for the inputs they both match
    inputs = ["models/**/*.glb", "models/*.obj"]
    [assets.options.thickness]
    rays = 128

    [[commands]]                # standalone generators: any `baker` command, `{input}`/`{output}` substituted
    command = "preview"
    args = ["{input}", "-o", "{output}", "--size", "128"]
    input = "baked/models/spot.glb"   # optional; its bytes join the cache key
    output = "previews/spot.png"

Every task is keyed by a SHA-256 of (input bytes + the files it references, bakes, resolved options, seed, output
format, baker version). ``baker.lock.json`` beside the recipe records, sorted, each output's key, inputs and output
hashes: a task whose key and outputs are unchanged is skipped. ``--check`` recomputes the keys without baking and
validates the outputs (``baker validate`` rules), listing stale, missing, modified or invalid outputs.

Tasks are self-contained: the input files travel with the task as bytes and the outputs come back as bytes, so a
local process pool (``--jobs``) and a Dask cluster (``--scheduler tcp://host:8786``) run the same function and the
client writes every output atomically; an interrupted build leaves no partial output and resumes from the lock.

With ``--jobs N`` each worker runs its kernels on cores / N threads (``BAKER_THREADS``: the ray threads and Embree's
build threads), takes the largest inputs first, and loads every numba kernel from the on-disk cache, which the
parent fills once when it is cold (a stamp in the cache folder records that it is warm).
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import re
import sys
import tempfile
import time
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from baker.version import __version__
from baker.errors import BakerError
from baker.gltf.atomic import write_bytes_atomic, write_files_atomic
from baker.options import coerce
from baker import registry

LOCK_NAME = "baker.lock.json"
FORMATS = ("glb", "gltf", "usda", "usdc", "usdz")


# ---------------------------------------------------------------------------------------------------- recipe
@dataclass
class Task:
    """One unit of work: bake one input, or run one command."""

    output: str  # recipe-relative path of the main output
    kind: str  # "bake" | "command"
    input: str | None = None
    bakes: list = field(default_factory=list)
    options: dict = field(default_factory=dict)  # bake -> {option: value} (every field, resolved)
    seed: int = 0
    attribute_layout: str = "blender"  # baker.gltf.vertex_attributes: "blender" | "native"
    compress: str = "none"  # baker.gltf.meshopt_encode.COMPRESSIONS
    # baking from another mesh: recipe-relative high mesh and cage, the cage distance (None: automatic)
    source: str | None = None
    cage: str | None = None
    cage_distance: float | None = None
    command: str | None = None
    args: list = field(default_factory=list)
    inputs: list = field(default_factory=list)  # recipe-relative files whose bytes the task needs
    key: str = ""


@dataclass
class Recipe:
    path: Path
    root: Path
    tasks: list


def _line_of(text: str, key: str) -> int | None:
    """The line of the first ``key = ...`` or ``[key]``/``[[key]]``/``[a.key]`` header, or None."""
    if not key:
        return None
    pattern = re.compile(rf"^\s*(?:{re.escape(key)}\s*=|\[\[?(?:[\w.-]+\.)?{re.escape(key)}\]\]?)", re.M)
    match = pattern.search(text)
    return text.count("\n", 0, match.start()) + 1 if match else None


def _fail(path: Path, text: str, key: str, message: str):
    line = _line_of(text, key)
    raise BakerError(path, f"line {line}: {message}" if line else message)


def find_recipe(path: str | None) -> Path:
    if path:
        p = Path(path)
        if not p.is_file():
            raise BakerError(p, "recipe not found")
        return p
    for name in ("baker.toml", "pyproject.toml"):
        p = Path(name)
        if p.is_file() and (name == "baker.toml" or "[tool.baker]" in p.read_text()):
            return p
    raise BakerError(Path("baker.toml"), "no recipe (baker.toml, or [tool.baker] in pyproject.toml) in this folder")


def _resolve_options(path, text, bakes, layers) -> dict:
    """Merge option tables (later layers win) into every field of each bake's options dataclass."""
    resolved = {}
    for name in bakes:
        step = registry.bakes()[name]
        values = {}
        for layer in layers:
            table = layer.get(name, {})
            if not isinstance(table, dict):
                _fail(path, text, name, f"options for '{name}' must be a table")
            for key, value in table.items():
                field_name = key.replace("-", "_")
                try:
                    values[field_name] = coerce(step.options, field_name, value)
                except ValueError as exc:
                    _fail(path, text, key, f"{name}: {exc}")
        opts = step.options(**values)
        resolved[name] = {k: list(v) if isinstance(v, tuple) else v for k, v in dataclasses.asdict(opts).items()}
    for layer in layers:
        for name in layer:
            if name not in bakes and name not in registry.bakes():
                _fail(path, text, name, f"options for unknown bake '{name}' (known: {', '.join(registry.bakes())})")
    return resolved


TOML_FORMS = {"object": "a table", "array": "an array", "string": "a string", "integer": "an integer",
              "number": "a number", "boolean": "true or false"}


def _toml_form(value) -> str:
    if isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
        return "an array of tables ([[...]])"
    kinds = ((dict, "a table"), (list, "an array"), (str, "a string"), (bool, "true or false"), (int, "an integer"),
             (float, "a number"))
    return next((name for kind, name in kinds if isinstance(value, kind)), type(value).__name__)


def check_recipe_shape(path: Path, text: str, data) -> None:
    """Check the parsed recipe against ``schemas/recipe/recipe.schema.json`` before anything is read or baked;
    the first problem is a BakerError naming the line, the JSON pointer and what was expected."""
    from jsonschema import Draft202012Validator
    from jsonschema.exceptions import best_match

    from baker.data import RECIPE_SCHEMA

    validator = Draft202012Validator(json.loads(RECIPE_SCHEMA.read_text("utf-8")))
    error = best_match(validator.iter_errors(data))
    if error is None:
        return
    parts = list(error.absolute_path)
    where = "/" + "/".join(map(str, parts))
    keys = [p for p in parts if isinstance(p, str)]
    if error.validator == "additionalProperties":
        extra = sorted(set(error.instance) - set(error.schema.get("properties", {})))
        known = ", ".join(error.schema.get("properties", {}))
        _fail(path, text, extra[0], f"{where.rstrip('/')}/{extra[0]}: unknown key (known: {known})")
    if error.validator == "type":
        expected = error.validator_value if isinstance(error.validator_value, list) else [error.validator_value]
        wanted = " or ".join(TOML_FORMS.get(t, t) for t in expected)
        hint = f"; write [{keys[-1]}]" if keys and expected == ["object"] and isinstance(error.instance, list) else ""
        _fail(path, text, keys[-1] if keys else "", f"{where}: must be {wanted}, not {_toml_form(error.instance)}{hint}")
    if error.validator == "required":
        _fail(path, text, keys[-1] if keys else "", f"{where}: {error.message}")
    _fail(path, text, keys[-1] if keys else "", f"{where}: {error.message}")


def load_recipe(path) -> Recipe:
    path = Path(path)
    try:
        text = path.read_text("utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise BakerError(path, f"cannot read recipe: {exc}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise BakerError(path, f"broken TOML: {exc}") from None
    if path.name == "pyproject.toml":
        data = data.get("tool", {}).get("baker")
        if data is None:
            raise BakerError(path, "no [tool.baker] table")
    check_recipe_shape(path, text, data)
    for key in data:
        if key not in ("build", "options", "assets", "commands"):
            _fail(path, text, key, f"unknown recipe key '{key}' (known: build, options, assets, commands)")
    root = path.parent
    build = data.get("build", {})
    for key in build:
        if key not in ("output", "format", "bakes", "seed", "attribute-layout", "compress"):
            _fail(path, text, key, f"unknown [build] key '{key}' (known: output, format, bakes, seed, "
                  "attribute-layout, compress)")
    out_dir = build.get("output", "baked")
    fmt = build.get("format", "glb")
    if fmt not in FORMATS:
        _fail(path, text, "format", f"format must be one of {', '.join(FORMATS)}, not {fmt!r}")
    default_bakes = build.get("bakes", ["thickness"])
    seed = build.get("seed", 0)
    layout = build.get("attribute-layout", "blender")
    compress = build.get("compress", "none")
    global_options = data.get("options", {})

    per_input: dict[str, dict] = {}
    for entry in data.get("assets", []):
        for key in entry:
            if key not in ("inputs", "bakes", "options", "seed", "attribute-layout", "compress", "from", "cage",
                           "cage-distance"):
                _fail(path, text, key, f"unknown [[assets]] key '{key}' (known: inputs, bakes, options, seed, "
                      "attribute-layout, compress, from, cage, cage-distance)")
        for key in ("from", "cage"):
            if key in entry and not (root / entry[key]).is_file():
                _fail(path, text, key, f"{key} = {entry[key]!r}: no such file")
            if key in entry and not (root / entry[key]).resolve().is_relative_to(root.resolve()):
                _fail(path, text, key, f"{key} = {entry[key]!r}: outside the recipe's folder (a build ships and "
                      "hashes only the files under it)")
        globs = entry.get("inputs", [])
        if isinstance(globs, str):
            globs = [globs]
        matched = sorted({p.relative_to(root).as_posix() for g in globs for p in root.glob(g) if p.is_file()})
        if not matched:
            _fail(path, text, "inputs", f"inputs {globs} match no file")
        for rel in matched:
            config = per_input.setdefault(rel, {"bakes": default_bakes, "layers": [global_options], "seed": seed,
                                                "attribute-layout": layout, "compress": compress})
            for key in ("bakes", "seed", "attribute-layout", "compress", "from", "cage", "cage-distance"):
                if key in entry:
                    config[key] = entry[key]
            config["layers"] = config["layers"] + [entry.get("options", {})]

    tasks = []
    for rel, config in sorted(per_input.items()):
        unknown = [b for b in config["bakes"] if b not in registry.bakes()]
        if unknown:
            _fail(path, text, "bakes", f"unknown bake(s) {', '.join(unknown)} (known: {', '.join(registry.bakes())})")
        output = (Path(out_dir) / Path(rel).with_suffix("." + fmt)).as_posix()
        options = _resolve_options(path, text, config["bakes"], config["layers"])
        if config["compress"] != "none" and fmt not in ("glb", "gltf"):
            _fail(path, text, "compress", f"compress = {config['compress']!r} writes glb or gltf, not {fmt}")
        transfer_files = [Path(config[k]).as_posix() for k in ("from", "cage") if config.get(k)]
        tasks.append(Task(output=output, kind="bake", input=rel, bakes=list(config["bakes"]), options=options,
                          seed=int(config["seed"]), attribute_layout=config["attribute-layout"],
                          compress=config["compress"], source=config.get("from"), cage=config.get("cage"),
                          cage_distance=config.get("cage-distance"),
                          inputs=[rel] + referenced_files(root, rel)
                          + [f for t in transfer_files for f in [t] + referenced_files(root, t)]))
    for entry in data.get("commands", []):
        for key in entry:
            if key not in ("command", "args", "input", "output"):
                _fail(path, text, key, f"unknown [[commands]] key '{key}' (known: command, args, input, output)")
        if "command" not in entry or "output" not in entry:
            _fail(path, text, "command", "a [[commands]] entry needs 'command' and 'output'")
        rel = entry.get("input")
        inputs = [rel] + referenced_files(root, rel) if rel else []
        tasks.append(Task(output=entry["output"], kind="command", input=rel, command=entry["command"],
                          args=[str(a) for a in entry.get("args", [])], inputs=inputs))
    outputs = [t.output for t in tasks]
    if len(set(outputs)) != len(outputs):
        raise BakerError(path, "two recipe entries write the same output")
    return Recipe(path, root, tasks)


def referenced_files(root: Path, rel: str) -> list[str]:
    """Files an input references that change its result (:func:`baker.readers.references`: a .gltf's external
    buffers and images, an .obj's .mtl files and their textures), relative to the recipe's folder; those outside
    it (files the recipe cannot hash and ship) and those missing are left out."""
    from baker import readers

    refs = []
    base = None
    for path in readers.references(root / rel):
        try:  # as written beside the input when it is, else as resolved (an MTL's files are)
            refs.append(path.relative_to(root).as_posix())
        except ValueError:
            base = base or root.resolve()
            try:
                refs.append(path.resolve().relative_to(base).as_posix())
            except ValueError:
                continue
    return sorted(r for r in set(refs) if (root / r).is_file())


# ---------------------------------------------------------------------------------------------------- hashing
def sha256_file(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def task_key(root: Path, task: Task) -> tuple[str, dict]:
    """The cache key of a task and the hashes of its input files."""
    inputs = {rel: sha256_file(root / rel) for rel in task.inputs if (root / rel).is_file()}
    missing = [rel for rel in task.inputs if rel not in inputs]
    if missing:
        raise BakerError(root / missing[0], "input not found")
    payload = {"baker": __version__, "kind": task.kind, "inputs": inputs, "bakes": task.bakes,
               "options": task.options, "seed": task.seed, "output": Path(task.output).suffix,
               "command": task.command, "args": task.args}
    if task.attribute_layout != "blender":  # the default joins no key: locks written before the option stay current
        payload["attributeLayout"] = task.attribute_layout
    if task.compress != "none":  # likewise
        payload["compress"] = task.compress
    if task.source is not None:  # likewise: the source's and cage's bytes are among the inputs
        payload["transfer"] = {"from": task.source, "cage": task.cage, "cageDistance": task.cage_distance}
    return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest(), inputs


# ---------------------------------------------------------------------------------------------------- running
def run_task(payload: dict) -> dict:
    """Run one task in a scratch folder; input files arrive as bytes and outputs leave as bytes.

    Pure function of its payload: runs the same in-process, in a process pool or on a Dask worker.
    """
    import warnings

    from baker import commands
    from baker.errors import BakeNote
    from baker.pipeline import bake, save

    start = time.perf_counter()
    notes = []
    with tempfile.TemporaryDirectory(prefix="baker-build-") as scratch:
        scratch = Path(scratch)
        for rel, data in payload["files"].items():
            target = scratch / "in" / rel
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(data)
        out_main = scratch / "out" / Path(payload["output"]).name
        out_main.parent.mkdir(parents=True)
        try:
            if payload["kind"] == "bake":
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always", BakeNote)
                    asset = bake(scratch / "in" / payload["input"], bakes=payload["bakes"],
                                 options=payload["options"], seed=payload["seed"],
                                 max_memory=payload.get("max_memory"), attribute_layout=payload["attribute_layout"],
                                 **transfer_arguments(scratch / "in", payload))
                # a note naming an input names it as the recipe does, not inside this scratch folder
                notes = [str(w.message) for w in caught if issubclass(w.category, BakeNote)]
                for inputs in {scratch / "in", (scratch / "in").resolve()}:  # an MTL's path is resolved
                    notes = [note.replace(str(inputs) + os.sep, "") for note in notes]
                save(asset, out_main, compress=payload.get("compress"))
            else:
                subst = {"{output}": str(out_main),
                         "{input}": str(scratch / "in" / payload["input"]) if payload.get("input") else ""}
                args = [subst.get(a, a) for a in payload["args"]]
                try:
                    code = commands.run([payload["command"], *args])
                except SystemExit:  # argparse rejected the recipe's args (it has printed why)
                    raise BakerError(None, f"'{payload['command']}': bad arguments {args}") from None
                if code != 0:
                    raise BakerError(None, f"'{payload['command']}' exited {code}")
        except BakerError as exc:
            return {"output": payload["output"], "error": exc.message, "files": {}}
        except Exception as exc:  # a bug or a library error: one line in the table, the traceback in the report
            import traceback

            return {"output": payload["output"], "error": f"{type(exc).__name__}: {exc}".splitlines()[0], "files": {},
                    "traceback": traceback.format_exc()}
        files = {p.relative_to(out_main.parent).as_posix(): p.read_bytes()
                 for p in sorted(out_main.parent.rglob("*")) if p.is_file()}
    return {"output": payload["output"], "error": None, "files": files, "seconds": time.perf_counter() - start,
            "warnings": notes}


def _payload(root: Path, task: Task, max_memory: int | None = None) -> dict:
    return {"kind": task.kind, "output": task.output, "input": task.input, "bakes": task.bakes,
            "options": task.options, "seed": task.seed, "attribute_layout": task.attribute_layout,
            "compress": task.compress, "command": task.command, "args": task.args, "max_memory": max_memory,
            "source": task.source, "cage": task.cage, "cage_distance": task.cage_distance,
            "files": {rel: (root / rel).read_bytes() for rel in task.inputs}}


def transfer_arguments(folder: Path, payload: dict) -> dict:
    """The ``source``/``cage``/``cage_distance`` arguments of a bake task, its files inside ``folder``."""
    if not payload.get("source"):
        return {}
    return {"source": folder / payload["source"],
            "cage": folder / payload["cage"] if payload.get("cage") else None,
            "cage_distance": payload.get("cage_distance")}


def worker_threads(jobs: int) -> int:
    """Kernel threads per worker process: the cores shared out between the jobs (never oversubscribed)."""
    return max(1, (os.cpu_count() or 1) // max(1, jobs))


def _init_worker(threads: int) -> None:
    # read by the thickness ray threads, Embree's device (its TBB build threads) and numba (not imported yet here)
    os.environ["BAKER_THREADS"] = str(threads)
    os.environ["NUMBA_NUM_THREADS"] = str(threads)


def warm_stamp(bakes) -> Path:
    """A file whose presence says :func:`warm_kernels` ran for ``bakes`` since any baker source last changed.

    numba keys each cached kernel on its source file's path, mtime and size, so the stamp is keyed the same way
    (every ``baker/**/*.py``), plus the versions. It sits in numba's cache folder (``NUMBA_CACHE_DIR``, which
    :mod:`baker` sets to the user cache), so clearing the cache clears the stamp too."""
    import platform
    from importlib.metadata import version  # not `import numba`: the parent would pay numba's import for a string

    package = Path(__file__).resolve().parents[1]
    cache = Path(os.environ.get("NUMBA_CACHE_DIR") or package / "__pycache__")
    digest = hashlib.sha256(json.dumps([__version__, sys.version, version("numba"), platform.machine(), str(package),
                                        sorted(bakes)]).encode())
    for source in sorted(package.rglob("*.py")):
        stat = source.stat()
        digest.update(f"{source.relative_to(package)}:{stat.st_mtime_ns}:{stat.st_size};".encode())
    return cache / f"baker-warm-{digest.hexdigest()[:24]}.stamp"


def warm_kernels_once(bakes) -> None:
    """:func:`warm_kernels`, skipped when a previous run already filled numba's cache for these sources: with a warm
    cache the parent would only spend ~2 s of serial imports and cache loads the workers then repeat anyway."""
    stamp = warm_stamp(bakes)
    if stamp.is_file():
        return
    warm_kernels(bakes)
    try:
        stamp.parent.mkdir(parents=True, exist_ok=True)
        stamp.touch()
    except OSError:  # a read-only install: warm again next time (correct, only slower)
        pass


def warm_kernels(bakes) -> None:
    """Run ``bakes`` once on a small sphere in this process, so numba's on-disk cache holds every compiled kernel
    before worker processes start: each worker then loads them instead of compiling the same code at once."""
    import trimesh

    from baker import readers
    from baker.pipeline import bake

    with tempfile.TemporaryDirectory(prefix="baker-warm-") as scratch:
        path = Path(scratch) / "warm.glb"
        trimesh.creation.icosphere(2).export(path)
        options = {"thickness": {"per_texel": False}} if "thickness" in bakes else {}
        try:
            bake(readers.read(path), bakes=list(bakes), options=options)
        except BakerError:  # a bake that needs more than a plain sphere (e.g. UVs): it compiles in the workers
            pass


def _execute(payloads: list, jobs: int, scheduler: str | None, fail_fast: bool):
    """Yield results as they complete: in-process, in a process pool, or on a Dask cluster."""
    if scheduler:
        from distributed import Client, as_completed

        with Client(scheduler) as client:
            futures = [client.submit(run_task, p, key=f"baker-{p['output']}-{i}", pure=False)
                       for i, p in enumerate(payloads)]
            for future in as_completed(futures):
                result = future.result()
                yield result
                if fail_fast and result["error"]:
                    client.cancel(futures)
                    return
    elif jobs > 1 and len(payloads) > 1:
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor, as_completed

        bakes = sorted({b for p in payloads if p["kind"] == "bake" for b in p["bakes"]})
        if bakes:
            warm_kernels_once(bakes)
        # largest inputs first (LPT scheduling): a big asset started last would leave the other workers idle at the
        # end; results are written by content, so the order changes nothing in the outputs or the lock
        payloads = sorted(payloads, key=lambda p: -sum(len(data) for data in p["files"].values()))
        # spawn: Embree, numba and OpenImageIO hold threads and state that fork would copy half-way
        with ProcessPoolExecutor(jobs, mp_context=multiprocessing.get_context("spawn"),
                                 initializer=_init_worker, initargs=(worker_threads(jobs),)) as pool:
            futures = [pool.submit(run_task, p) for p in payloads]
            for future in as_completed(futures):
                result = future.result()
                yield result
                if fail_fast and result["error"]:
                    for f in futures:
                        f.cancel()
                    return
    else:
        for p in payloads:
            result = run_task(p)
            yield result
            if fail_fast and result["error"]:
                return


# ---------------------------------------------------------------------------------------------------- lock
def read_lock(root: Path) -> dict:
    path = root / LOCK_NAME
    if not path.is_file():
        return {}
    try:
        return {e["output"]: e for e in json.loads(path.read_text()).get("entries", [])}
    except (ValueError, KeyError, TypeError):
        raise BakerError(path, "broken lock file (delete it to rebuild everything)") from None


def write_lock(root: Path, entries: dict) -> None:
    data = {"baker": __version__, "entries": [entries[k] for k in sorted(entries)]}
    write_bytes_atomic(root / LOCK_NAME, (json.dumps(data, indent=2, sort_keys=True) + "\n").encode())


def _outputs_current(root: Path, entry: dict) -> bool:
    return all((root / rel).is_file() and sha256_file(root / rel) == digest for rel, digest in entry["outputs"].items())


# ---------------------------------------------------------------------------------------------------- commands
def build(recipe: Recipe, *, jobs: int = 1, scheduler: str | None = None, fail_fast: bool = False,
          progress=None, max_memory: int | None = None) -> dict:
    """Bake what is stale; returns {'baked': [...], 'skipped': [...], 'failed': [(output, reason)], 'tracebacks':
    {output: traceback of an unexpected failure}, 'warnings': [(output, message)], 'seconds'}. ``max_memory``:
    bytes each bake job may need (a job estimated above it fails with the reason; None: no limit)."""
    start = time.perf_counter()
    root = recipe.root
    lock = read_lock(root)
    report = {"baked": [], "skipped": [], "failed": [], "tracebacks": {}, "warnings": [], "seconds": 0.0}
    bar = _bar(progress, len(recipe.tasks), 0)
    # bakes first, then commands: a command's input may be a baked output, hashed only once it exists
    for phase in ("bake", "command"):
        todo = []
        for task in (t for t in recipe.tasks if t.kind == phase):
            try:
                task.key, task_inputs = task_key(root, task)
            except BakerError as exc:
                report["failed"].append((task.output, exc.message if exc.path is None else f"{exc.path}: {exc.message}"))
                continue
            entry = lock.get(task.output)
            if entry and entry.get("key") == task.key and _outputs_current(root, entry):
                report["skipped"].append(task.output)
                if bar:
                    bar.update(1)
            else:
                todo.append((task, task_inputs))
        by_output = {t.output: (t, i) for t, i in todo}
        for result in _execute([_payload(root, t, max_memory) for t, _ in todo], jobs, scheduler, fail_fast):
            task, task_inputs = by_output[result["output"]]
            report["warnings"] += [(task.output, note) for note in result.get("warnings", [])]
            if result["error"]:
                report["failed"].append((task.output, result["error"]))
                if result.get("traceback"):
                    report["tracebacks"][task.output] = result["traceback"]
            else:
                out_dir = (root / task.output).parent
                written = {}
                # one atomic group, side files first, the main output last (as a single bake writes them)
                main_name = Path(task.output).name
                ordered = sorted(result["files"], key=lambda r: (r == main_name, r))
                write_files_atomic([(out_dir / rel, result["files"][rel]) for rel in ordered])
                for rel in ordered:
                    written[(Path(task.output).parent / rel).as_posix()] = \
                        hashlib.sha256(result["files"][rel]).hexdigest()
                lock[task.output] = {"output": task.output, "key": task.key, "kind": task.kind,
                                     "inputs": task_inputs, "bakes": task.bakes, "options": task.options,
                                     "seed": task.seed, "command": task.command, "args": task.args,
                                     "outputs": written}
                write_lock(root, lock)  # after every task: an interrupted build resumes where it stopped
                report["baked"].append(task.output)
            if bar:
                bar.set_postfix_str(task.output[-40:])
                bar.update(1)
        if fail_fast and report["failed"]:
            break
    if bar:
        bar.close()
    report["seconds"] = time.perf_counter() - start
    return report


def check(recipe: Recipe, khronos: bool = True) -> list[dict]:
    """Problems with the recipe's outputs, without baking: missing, stale, modified or invalid."""
    from baker.validate import validate_file

    root = recipe.root
    lock = read_lock(root)
    problems = []
    for task in recipe.tasks:
        try:
            task.key, _ = task_key(root, task)
        except BakerError as exc:  # e.g. a command whose input is a baked output not built yet
            problems.append({"output": task.output, "problem": "missing", "detail": f"input missing: {exc.path}"})
            continue
        entry = lock.get(task.output)
        if entry is None or not all((root / rel).is_file() for rel in entry["outputs"]):
            problems.append({"output": task.output, "problem": "missing", "detail": "not built"})
            continue
        if entry["key"] != task.key:
            problems.append({"output": task.output, "problem": "stale",
                             "detail": "inputs, options or baker version changed since it was built"})
            continue
        if not _outputs_current(root, entry):
            problems.append({"output": task.output, "problem": "modified", "detail": "output differs from the lock"})
            continue
        if Path(task.output).suffix.lower() in (".glb", ".gltf"):
            report = validate_file(root / task.output, khronos=khronos)
            if report["issues"]["numErrors"]:
                first = next(m for m in report["issues"]["messages"] if m["severity"] == 0)
                problems.append({"output": task.output, "problem": "invalid",
                                 "detail": f"{report['issues']['numErrors']} errors, first: {first['code']} "
                                           f"{first.get('pointer', '')} {first['message']}"})
    return problems


def _bar(progress, total: int, skipped: int):
    if progress is None or not progress.enabled:
        return None
    from tqdm import tqdm

    return tqdm(total=total, initial=skipped, desc="baker build", unit="asset", file=sys.stderr, dynamic_ncols=True)


def _table(report: dict) -> str:
    rows = [(o, "baked", "") for o in report["baked"]] + [(o, "skipped (cached)", "") for o in report["skipped"]]
    rows += [(o, "FAILED", reason) for o, reason in report["failed"]]
    rows.sort()
    width = max([len(r[0]) for r in rows] + [6])
    lines = [f"{'output'.ljust(width)}  status            reason", f"{'-' * width}  ----------------  ------"]
    lines += [f"{o.ljust(width)}  {s.ljust(16)}  {r}".rstrip() for o, s, r in rows]
    lines.append(f"{len(report['baked'])} baked, {len(report['skipped'])} skipped (cached), "
                 f"{len(report['failed'])} failed in {report['seconds']:.1f} s")
    return "\n".join(lines)


def job_memory_limit(text: str | None, jobs: int, scheduler: str | None) -> int | None:
    """Each bake job's limit from ``--max-memory``: as given, or by default 75% of this machine's RAM shared by the
    ``jobs`` running at once; no default on a Dask cluster, whose workers' RAM this machine does not know."""
    from baker.memory import parse_limit

    if text is None and scheduler:
        return None
    limit = parse_limit(text)
    return limit // max(1, jobs) if text is None and limit is not None else limit


def main(args) -> int:
    from baker.progress import Progress

    recipe = load_recipe(find_recipe(args.recipe))
    if args.check:
        problems = check(recipe, khronos=not args.no_khronos)
        if args.format == "json":
            print(json.dumps({"ok": not problems, "problems": problems}, indent=2))
        else:
            for p in problems:
                print(f"{p['output']}: {p['problem']}: {p['detail']}")
            print(f"{len(recipe.tasks) - len(problems)} of {len(recipe.tasks)} outputs current and valid")
        return 1 if problems else 0
    report = build(recipe, jobs=args.jobs, scheduler=args.scheduler, fail_fast=args.fail_fast,
                   progress=Progress(enabled=False if args.quiet else None),
                   max_memory=job_memory_limit(args.max_memory, args.jobs, args.scheduler))
    for output, note in report["warnings"]:
        print(f"baker: warning: {output}: {note}", file=sys.stderr)
    if args.format == "json":
        print(json.dumps({**report, "failed": [{"output": o, "reason": r} for o, r in report["failed"]],
                          "warnings": [{"output": o, "message": m} for o, m in report["warnings"]]}, indent=2))
    elif not args.quiet or report["failed"]:
        print(_table(report))
    return 1 if report["failed"] else 0


def add_parser(sub) -> None:
    p = sub.add_parser("build", help="bake every asset of a recipe (baker.toml) incrementally")
    p.add_argument("--recipe", default=None, help="recipe file (default: ./baker.toml or [tool.baker] in pyproject)")
    p.add_argument("--check", action="store_true", help="bake nothing; exit 1 listing stale, missing or invalid outputs")
    p.add_argument("--jobs", "-j", type=int, default=1, help="parallel processes on this machine (default 1)")
    p.add_argument("--scheduler", default=None, help="a Dask distributed scheduler address, e.g. tcp://host:8786")
    p.add_argument("--fail-fast", action="store_true", help="stop at the first failing asset")
    p.add_argument("--format", choices=("text", "json"), default="text", help="report format")
    p.add_argument("--no-khronos", action="store_true", help="--check: skip Khronos' glTF-Validator")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar; print the table only on failure")
    from baker.memory import add_argument

    add_argument(p, help="refuse a bake job whose estimated working memory is larger: bytes (512M, 2G), a share of "
                 "RAM (50%%) or 'none' (default: 75%% of RAM shared by --jobs; none with --scheduler)")
    p.set_defaults(func=main)
