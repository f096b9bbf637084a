"""How baker writes its custom vertex attributes (``_NAME``): the one place that chooses their accessor width.

Two layouts (``--attribute-layout``, recipe key ``attribute-layout``, ``baker.bake(attribute_layout=...)``):

- ``blender`` (the default while Blender 4.5 LTS is supported): every custom attribute of a mesh gets one width: the
  widest data the run's bakes write (:attr:`AttributeLayout.width`: SCALAR when only scalars are baked, e.g.
  ``--bakes thickness``; VEC3 as soon as one bake writes a vector), unless the mesh already carries custom attributes
  of its own that all share another width W that the data fits in (then W). Scalar data sits in x and pairs in x, y;
  the other components are zero.
- ``native``: each attribute at its data's width (SCALAR, VEC2, VEC3): a third of the bytes for a scalar.

Why ``blender``: Blender's glTF importer (io_scene_gltf2 4.5, ``blender/imp/mesh.py`` ``do_primitives``) keeps a
mesh's custom attributes in a Python ``set`` but makes their (initially empty) per-attribute arrays in first-seen
order; it then fills and names them in the set's order, which string hashing makes arbitrary. When two custom
attributes of one glTF mesh (all its primitives together) differ in component count, the arrays it concatenates
disagree in width and the import fails with ``ValueError`` depending on ``PYTHONHASHSEED`` (fixed in glTF-Blender-IO
#2658, Blender 5.2). Attributes of equal width import correctly in any order, so the only layout that composes is one
width per mesh. That is also why a mesh's own custom attributes set the width: a user's SCALAR ``_PRESSURE`` next to
baker's ``_THICKNESS`` imports when ``_THICKNESS`` is SCALAR too, and the user's data is never changed. Data wider
than the mesh's width cannot join it: the bake then warns once, naming the attributes and the option that leaves the
wide ones out (a separate primitive would not help: the importer gathers the attributes of all of a mesh's
primitives). A shader binds either layout the same way: GL reads x of a wider buffer into a ``float`` attribute and
fills the missing components of a narrower one.

Readers accept both: a FLOAT accessor of at least the data's width, the meaningful components first
(:func:`accepted_types`, :func:`unpadded`).
"""
from __future__ import annotations

import enum
import warnings
from dataclasses import dataclass, field

import numpy as np

from baker.errors import BakeNote

WIDTH_TYPES = {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4"}
TYPE_WIDTHS = {kind: width for width, kind in WIDTH_TYPES.items()}
FLOAT = 5126
BLENDER_WIDTH = 3  # the widest data any bake writes (normals, positions, directions)
TYPE = WIDTH_TYPES[BLENDER_WIDTH]


class Layout(str, enum.Enum):
    BLENDER = "blender"
    NATIVE = "native"


LAYOUTS = tuple(layout.value for layout in Layout)
DEFAULT = Layout.BLENDER


class BlenderWidthWarning(BakeNote):
    """A mesh's custom attributes mix widths, which Blender 4.5's glTF importer fails on at random."""

    label = "warning"


@dataclass
class AttributeLayout:
    """The layout one bake writes with (held by the document, so every extension writer sees it), and the width
    conflicts met on the way (reported once by :meth:`warn`)."""

    layout: Layout = DEFAULT
    # blender layout: the width of baker's attributes on a mesh without custom attributes of its own, the widest data
    # of the bakes in the run (pipeline.bake sets it from each extension's VERTEX_ATTRIBUTES; compact when narrow)
    width: int = BLENDER_WIDTH
    # (mesh index, mesh name, attribute written, its data width, {other attribute: width}, option that leaves it out)
    conflicts: list = field(default_factory=list)
    written: set = field(default_factory=set)  # names this bake wrote (not the mesh's own)

    def __post_init__(self):
        self.layout = parse(self.layout)

    def warn(self, source=None) -> None:
        """One :class:`BlenderWidthWarning` summing up every conflict, then forget them."""
        if not self.conflicts:
            return
        mesh, mesh_name, _, _, others, _ = self.conflicts[0]
        wide = sorted({c[2] for c in self.conflicts if c[0] == mesh})
        options = sorted({c[5] for c in self.conflicts if c[5]})
        own = ", ".join(f"'{name}' ({width})" for name, width in sorted(others.items())
                        if name not in wide and name not in self.written)
        more = len({c[0] for c in self.conflicts}) - 1
        where = f"{source}: " if source else ""
        text = (f"{where}mesh {mesh}{f' ({mesh_name!r})' if mesh_name else ''} has custom attributes {own} that "
                f"{', '.join(map(repr, wide))} cannot share the width of"
                f"{f' (and {more} more meshes)' if more > 0 else ''}: Blender 4.5's glTF importer fails on mixed "
                "widths at random (--attribute-layout native mixes them too); "
                + (f"leave them out ({', '.join(options)})" if options else "leave them out")
                + " or give the mesh's own attributes 3 components")
        self.conflicts = []
        warnings.warn(BlenderWidthWarning(text), stacklevel=2)


def parse(value) -> Layout:
    """A :class:`Layout` from its name (``blender``, ``native``) or itself; ValueError names the choices."""
    try:
        return Layout(value)
    except ValueError:
        raise ValueError(f"attribute layout must be one of {', '.join(LAYOUTS)}, got {value!r}") from None


def data_width(values: np.ndarray) -> int:
    values = np.asarray(values)
    return 1 if values.ndim == 1 else values.shape[1]


def padded(values: np.ndarray, width: int = BLENDER_WIDTH) -> np.ndarray:
    """(N,) or (N, k <= width) values -> float32 of ``width`` components ((N,) for 1), zeros in the unused ones."""
    values = np.asarray(values, np.float32)
    if values.ndim == 1:
        values = values[:, None]
    if values.ndim != 2 or values.shape[1] > width:
        raise ValueError(f"a custom vertex attribute of {width} components cannot hold shape {values.shape}")
    if width == 1:
        return np.ascontiguousarray(values[:, 0])
    out = np.zeros((len(values), width), np.float32)
    out[:, :values.shape[1]] = values
    return out


def unpadded(values: np.ndarray, width: int) -> np.ndarray:
    """The ``width`` meaningful components of a custom attribute as read (either layout): (N,) for width 1, else
    (N, width)."""
    values = np.asarray(values)
    if values.ndim == 1:
        return values if width == 1 else values.reshape(len(values), -1)[:, :width]
    return values[:, 0] if width == 1 else values[:, :width]


def accepted_types(width: int) -> tuple:
    """The accessor types a reader accepts for data of ``width`` components: its own type (``native``) and every
    wider one (``blender``: VEC3, or the width of a mesh's own attributes)."""
    return tuple(WIDTH_TYPES[w] for w in range(width, 5))


def used_columns(values: np.ndarray) -> np.ndarray:
    """A custom attribute's values without trailing all-zero columns (the padding of a scalar or pair), for
    summaries such as ``baker inspect`` that do not know the attribute's width; at least one column is kept."""
    values = np.asarray(values)
    if values.ndim != 2:
        return values
    width = values.shape[1]
    while width > 1 and not values[:, width - 1].any():
        width -= 1
    return values[:, 0] if width == 1 else values[:, :width]


def _widths_beside(doc, mesh: int | None, attributes: dict, skip: str) -> dict:
    """{name: component count} of the custom attributes but ``skip`` of every primitive of ``mesh`` and of
    ``attributes`` (the primitive being written, attached or not)."""
    accessors = doc.json.get("accessors") or []
    primitives = doc.json["meshes"][mesh].get("primitives") or [] if mesh is not None else []
    widths = {}
    for attrs in [prim.get("attributes") or {} for prim in primitives] + [attributes]:
        for name, index in attrs.items():
            if name.startswith("_") and name != skip and isinstance(index, int) and 0 <= index < len(accessors):
                widths[name] = TYPE_WIDTHS.get(accessors[index].get("type"), 0)
    return widths


def add_vertex_attribute(doc, mesh: int | None, attributes: dict, name: str, values: np.ndarray, *,
                         min_max: bool = False, leave_out: str | None = None) -> int:
    """Write ``values`` ((N,) or (N, k)) as custom attribute ``name`` into ``attributes`` (a primitive's, of mesh
    ``mesh``; None for a mesh being made) in the document's layout (``doc.attribute_layout``); returns the accessor
    index. ``leave_out``: the option that omits this attribute, for the warning when it cannot share the mesh's
    width."""
    layout = doc.attribute_layout
    width = data_width(values)
    if layout.layout is Layout.BLENDER:
        others = _widths_beside(doc, mesh, attributes, name)
        shared = set(others.values())
        target = shared.pop() if len(shared) == 1 and max(others.values()) >= width else max(layout.width, width)
        if any(w != target for w in others.values()):
            mesh_name = doc.json["meshes"][mesh].get("name") if mesh is not None else None
            layout.conflicts.append((mesh, mesh_name, name, width, others, leave_out))
    else:
        target = width
    attributes[name] = doc.add_accessor(padded(values, target), min_max=min_max)
    layout.written.add(name)
    return attributes[name]
