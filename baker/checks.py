"""The validation vocabulary every technique's ``check`` uses: the issue list, JSON pointers, and checks of
indices, numbers and vertex attributes. ``baker validate`` (:mod:`baker.validate`) orchestrates them."""
from __future__ import annotations

from dataclasses import dataclass, field

import math

import numpy as np

from baker.gltf.vertex_attributes import accepted_types, unpadded

ERROR, WARNING, INFO, HINT = 0, 1, 2, 3
TRIANGLE_MODES = (4, 5, 6)


SEVERITY_NAMES = {ERROR: "error", WARNING: "warning", INFO: "info", HINT: "hint"}


# ---------------------------------------------------------------------------------------------------- report
def pointer(*parts) -> str:
    """A JSON pointer (RFC 6901) from path parts."""
    return "".join("/" + str(p).replace("~", "~0").replace("/", "~1") for p in parts)


def material_extensions(places: list, name: str):
    """(material index, extension object, its JSON pointer) for each place of material extension ``name`` that sits on
    a material and is an object; misplaced or malformed ones are the schema pass's to report."""
    for parts, ext in places:
        if len(parts) == 2 and parts[0] == "materials" and isinstance(ext, dict):
            yield parts[1], ext, pointer("materials", parts[1], "extensions", name)


@dataclass
class Issues:
    messages: list = field(default_factory=list)

    def add(self, code: str, message: str, severity: int, ptr: str | None = None, source: str = "baker") -> None:
        msg = {"code": code, "message": message, "severity": severity}
        if ptr is not None:
            msg["pointer"] = ptr
        msg["source"] = source
        self.messages.append(msg)

    def error(self, code, message, ptr=None):
        self.add(code, message, ERROR, ptr)

    def warning(self, code, message, ptr=None):
        self.add(code, message, WARNING, ptr)

    def info(self, code, message, ptr=None):
        self.add(code, message, INFO, ptr)


    def as_dict(self) -> dict:
        counts = [sum(m["severity"] == s for m in self.messages) for s in (ERROR, WARNING, INFO, HINT)]
        return {"numErrors": counts[0], "numWarnings": counts[1], "numInfos": counts[2], "numHints": counts[3],
                "messages": self.messages, "truncated": False}


# ---------------------------------------------------------------------------------------------------- structure
def is_index(value, collection) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and 0 <= value < len(collection)


def is_count(value, minimum=0) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value >= minimum


# ---------------------------------------------------------------------------------------------------- semantics
def is_derived_fins(prim: dict) -> bool:
    """True for fin primitives baker derives from a mesh (BAKER_edges / BAKER_fur ``finsOf``): zero-area quads that
    bakes must not sample."""
    exts = prim.get("extensions") or {}
    return isinstance(exts, dict) and any(isinstance(exts.get(name), dict) and "finsOf" in exts[name]
                                          for name in ("BAKER_edges", "BAKER_fur"))


def primitives_using(gltf: dict, material: int):
    """(mesh, primitive, primitive dict) of every triangle primitive drawn with ``material``, without the fin
    primitives baker derives from a mesh (they carry no baked surface data)."""
    for m, mesh in enumerate(gltf.get("meshes") or []):
        for p, prim in enumerate(mesh.get("primitives") or []):
            if prim.get("material") == material and prim.get("mode", 4) in TRIANGLE_MODES \
                    and not is_derived_fins(prim):
                yield m, p, prim


def is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


# KHR_mesh_quantization's forms of a float attribute: normalized BYTE, UNSIGNED_BYTE, SHORT, UNSIGNED_SHORT
NORMALIZED_COMPONENT_TYPES = (5120, 5121, 5122, 5123)


def normalized_to_float(data: np.ndarray) -> np.ndarray:
    """glTF's decoding of normalized integers (spec 3.11): c / max, signed values clamped at -1."""
    out = data.astype(np.float64) / np.iinfo(data.dtype).max
    return np.maximum(out, -1.0) if data.dtype.kind == "i" else out


def check_vertex_attribute(doc, mesh: int, primitive: int, name: str, issues: Issues, *,
                           code: str, width: int = 1, types: tuple | None = None,
                           component_type: int = 5126) -> np.ndarray | None:
    """Shared rules for a baked per-vertex attribute of ``doc`` (a :class:`~baker.gltf.document.GltfDocument`):
    present, FLOAT (or, for a FLOAT ``component_type``, a normalized integer type as KHR_mesh_quantization stores
    it: glTF-Transform's ``quantize`` and ``meshopt`` write those) of at least ``width`` components (``types``,
    default: either layout of :mod:`baker.gltf.vertex_attributes`, the data's own width or padded), one value per
    vertex, finite. Returns the ``width`` meaningful components as floats
    (float64, (N,) for width 1; non-finite values included and reported) when the accessor can be read, else None
    (errors reported). :func:`stored_resolution` says how finely the stored form holds them.
    """
    gltf = doc.json
    accessors = gltf.get("accessors") or []
    prim = gltf["meshes"][mesh]["primitives"][primitive]
    attrs = prim.get("attributes") or {}
    prim_ptr = pointer("meshes", mesh, "primitives", primitive, "attributes")
    if name not in attrs:
        issues.error(f"{code}_ATTRIBUTE_MISSING", f"the extension names attribute '{name}' but this primitive has none",
                     prim_ptr)
        return None
    a = attrs[name]
    if not is_index(a, accessors):
        return None  # reported as UNRESOLVED_REFERENCE
    acc = accessors[a]
    acc_ptr = pointer("accessors", a)
    types = types or accepted_types(width)
    quantized = component_type == 5126 and acc.get("normalized") is True \
        and acc.get("componentType") in NORMALIZED_COMPONENT_TYPES
    if (acc.get("componentType") != component_type or acc.get("normalized")) and not quantized \
            or acc.get("type") not in types:
        allowed = f"{component_type}" + (" (or normalized 5120, 5121, 5122, 5123)" if component_type == 5126 else "")
        issues.error(f"{code}_ACCESSOR_FORMAT", f"'{name}' must be componentType {allowed} "
                     f"{' or '.join(types)}, not {acc.get('componentType')} {acc.get('type')}"
                     f"{' (not normalized)' if acc.get('componentType') in NORMALIZED_COMPONENT_TYPES else ''}",
                     acc_ptr)
        return None
    positions = attrs.get("POSITION")
    if is_index(positions, accessors) and acc.get("count") != accessors[positions].get("count"):
        issues.error(f"{code}_ACCESSOR_COUNT", f"'{name}' has {acc.get('count')} values but POSITION has "
                     f"{accessors[positions].get('count')} vertices", prim_ptr + "/" + name)
        return None
    data = doc.accessor(a)
    values = unpadded(normalized_to_float(data) if quantized else data.astype(np.float64), width)
    finite = np.isfinite(values)
    if not finite.all():
        issues.error(f"{code}_VALUE_NOT_FINITE", f"{int((~finite).sum())} of {values.size} values are NaN or "
                     "infinite", acc_ptr)
    return values


def stored_resolution(doc, mesh: int, primitive: int, name: str, values: np.ndarray) -> float:
    """How finely attribute ``name`` of the primitive holds ``values`` (as :func:`check_vertex_attribute` returned
    them): a normalized integer's step (1/127, 1/32767, ...); for data decoded from Draco (each component quantized
    to a uniform grid over its range) the smallest spacing between its distinct values, one grid step; 0 for plain
    FLOAT data. Value checks widen their tolerances by it, so quantized forms pass where their precision permits."""
    gltf = doc.json
    prim = gltf["meshes"][mesh]["primitives"][primitive]
    acc = (gltf.get("accessors") or [])[prim["attributes"][name]]
    if acc.get("normalized") and acc.get("componentType") in NORMALIZED_COMPONENT_TYPES:
        bits = {5120: 7, 5121: 8, 5122: 15, 5123: 16}[acc["componentType"]]
        return 1.0 / (2 ** bits - 1)
    extras = (gltf.get("asset") or {}).get("extras")
    record = extras.get("baker") if isinstance(extras, dict) else None
    entries = record.get("decompressed") if isinstance(record, dict) else None
    here = pointer("meshes", mesh, "primitives", primitive)
    if not any(isinstance(entry, dict) and entry.get("extension") == "KHR_draco_mesh_compression"
               and here in (entry.get("primitives") or []) for entry in (entries or [])):
        return 0.0
    step = 0.0
    for column in values.reshape(len(values), -1).T:
        distinct = np.unique(column[np.isfinite(column)])
        if len(distinct) > 1:
            step = max(step, float(np.diff(distinct).min()))
    return step
