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


def check_vertex_attribute(doc, mesh: int, primitive: int, name: str, issues: Issues, *,
                           code: str, width: int = 1, types: tuple | None = None,
                           component_type: int = 5126) -> np.ndarray | None:
    """Shared rules for a baked per-vertex attribute of ``doc`` (a :class:`~baker.gltf.document.GltfDocument`):
    present, FLOAT of at least ``width`` components (``types``, default: either layout of
    :mod:`baker.gltf.vertex_attributes`, the data's own width or padded), one value per vertex, finite. Returns the
    ``width`` meaningful components
    (float64, (N,) for width 1; non-finite values included and reported) when the accessor can be read, else None
    (errors reported).
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
    if acc.get("componentType") != component_type or acc.get("type") not in types or acc.get("normalized"):
        issues.error(f"{code}_ACCESSOR_FORMAT", f"'{name}' must be componentType {component_type} "
                     f"{' or '.join(types)}, not {acc.get('componentType')} {acc.get('type')}", acc_ptr)
        return None
    positions = attrs.get("POSITION")
    if is_index(positions, accessors) and acc.get("count") != accessors[positions].get("count"):
        issues.error(f"{code}_ACCESSOR_COUNT", f"'{name}' has {acc.get('count')} values but POSITION has "
                     f"{accessors[positions].get('count')} vertices", prim_ptr + "/" + name)
        return None
    values = unpadded(doc.accessor(a).astype(np.float64), width)
    finite = np.isfinite(values)
    if not finite.all():
        issues.error(f"{code}_VALUE_NOT_FINITE", f"{int((~finite).sum())} of {values.size} values are NaN or "
                     "infinite", acc_ptr)
    return values
