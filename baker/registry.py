"""Finds every technique: each package under ``baker/techniques/`` and each ``baker.techniques`` entry point
(techniques installed by other packages). No list of techniques is kept anywhere else."""
from __future__ import annotations

import importlib
import pkgutil
from functools import lru_cache
from importlib.metadata import entry_points

from baker.data import SCHEMA_ROOT
from baker.errors import BakerError
from baker.technique import USD_READ_HOOKS, Technique

ENTRY_POINT_GROUP = "baker.techniques"


@lru_cache(maxsize=None)
def techniques() -> dict[str, Technique]:
    """Every technique by name, in name order (a stable order for help texts and reports)."""
    import baker.techniques as package

    found = {}
    for info in pkgutil.iter_modules(package.__path__):
        if info.ispkg:
            _add(found, importlib.import_module(f"{package.__name__}.{info.name}").TECHNIQUE)
    for point in entry_points(group=ENTRY_POINT_GROUP):
        _add(found, point.load())
    return {name: found[name] for name in sorted(found)}


def _add(found: dict, technique: Technique) -> None:
    if technique.name in found:
        raise RuntimeError(f"two techniques are named {technique.name!r}")
    found[technique.name] = technique


def bakes() -> dict[str, Technique]:
    """The techniques that bake into an asset (``baker bake --bakes NAME``)."""
    return {name: t for name, t in techniques().items() if t.run is not None}


def bake_order(names) -> list[str]:
    """``names`` with every technique after those it ``requires`` (when both are asked for), and those that split
    vertices (``Technique.splits_vertices``) after those that do not, ties in name order: a deterministic order
    whatever order the user listed them in."""
    known = bakes()
    unknown = [n for n in names if n not in known]
    if unknown:
        raise BakerError(None, f"unknown bake(s) {', '.join(unknown)} (known: {', '.join(known)})")
    wanted = sorted(set(names))
    done, order = set(), []
    while len(order) < len(wanted):
        ready = [n for n in wanted if n not in done and all(r in done or r not in wanted for r in known[n].requires)]
        ready.sort(key=lambda n: known[n].splits_vertices)  # stable: ties stay in name order
        if not ready:
            raise RuntimeError(f"techniques {', '.join(n for n in wanted if n not in done)} require each other")
        order.append(ready[0])
        done.add(ready[0])
    return order


@lru_cache(maxsize=None)
def extensions() -> dict:
    """Every extension object by its glTF name (imports the extension modules)."""
    return {ext.NAME: ext for t in techniques().values() for ext in t.extension_objects()}


def vertex_index_members() -> dict:
    """Primitive extension name -> the members of it that are accessors of vertex indices (each extension
    module's ``VERTEX_INDEX_MEMBERS``, {extension name: members}): what a bake that splits a primitive's vertices
    must renumber."""
    members = {}
    for ext in extensions().values():
        members.update(getattr(ext, "VERTEX_INDEX_MEMBERS", {}))
    return members


def usd_primitive_hooks() -> dict:
    """Extension name -> ``to_usd_primitive`` for the extensions that add USD beside a mesh primitive."""
    return {name: ext.to_usd_primitive for name, ext in extensions().items() if hasattr(ext, "to_usd_primitive")}


def usd_primitive_accessors() -> dict:
    """Primitive extension name -> its members that are accessors, from each extension module's
    ``USD_PRIMITIVE_ACCESSORS``: the USD writer stores them on the mesh prim so the stage reads back."""
    members = {}
    for ext in extensions().values():
        members.update(getattr(ext, "USD_PRIMITIVE_ACCESSORS", {}))
    return members


def usd_material_readers() -> dict:
    """Extension name -> ``from_usd(doc, material, params)``: fills in what a material extension's USD attributes
    cannot carry (lists of objects holding glTF indices) when :mod:`baker.readers.usd_baked` reads a stage back."""
    return {name: ext.from_usd for name, ext in extensions().items() if hasattr(ext, "from_usd")}


def vertex_attribute_widths() -> dict:
    """Custom attribute name -> its data's component count, from each extension's ``VERTEX_ATTRIBUTES``: what a
    padded glTF layout (:mod:`baker.gltf.vertex_attributes`) hides and USD writes at its own width."""
    widths = {}
    for ext in extensions().values():
        widths.update(getattr(ext, "VERTEX_ATTRIBUTES", {}))
    return widths


def vertex_attribute_width(names) -> int:
    """The widest custom attribute data the bakes ``names`` can write (each extension's ``VERTEX_ATTRIBUTES``,
    whatever the options): the width the ``blender`` layout gives every custom attribute of a mesh
    (:mod:`baker.gltf.vertex_attributes`); 1 when they write only scalars or no attributes at all."""
    known = techniques()
    return max([1] + [width for name in names for ext in known[name].extension_objects()
                      for width in getattr(ext, "VERTEX_ATTRIBUTES", {}).values()])


def usd_texture_color_spaces() -> dict:
    """Extension name -> its ``usd_color_space(params, json_path)`` ("sRGB" or "raw") for the extensions whose
    textures are not all data (the USD writer reads every other extension's textures as ``raw``)."""
    return {name: ext.usd_color_space for name, ext in extensions().items() if hasattr(ext, "usd_color_space")}


def semantic_checks() -> dict:
    """Extension name -> its ``check(doc, places, issues)`` for ``baker validate``."""
    return {name: ext.check for name, ext in extensions().items() if hasattr(ext, "check")}


def schema_roots() -> list:
    """Every folder laid out like ``schemas/`` (``<EXT>/schema/<kind>.<EXT>.schema.json``): the repo's own, then each
    technique's ``schemas`` (techniques installed from elsewhere bring theirs), in technique order."""
    roots = [SCHEMA_ROOT]
    for technique in techniques().values():
        root = technique.schema_root()
        if root is not None and root not in roots:
            roots.append(root)
    return roots


def command_modules() -> list:
    """The light modules that add a standalone command each (``add_parser(subparsers)``)."""
    return [importlib.import_module(reference) for t in techniques().values() for reference in t.commands]


def panels() -> list:
    """Every technique's preview panels, in technique order."""
    from baker.technique import load

    return [panel for t in techniques().values() if t.panels for panel in load(t.panels)]


# the USD reader (a shared layer) reaches these through baker.technique, not by importing the registry
def usd_curve_readers() -> dict:
    """Extension name -> ``from_usd_curves(doc, prim, world matrix)``: the primitive a ``BasisCurves`` prim baker
    wrote reads back as (``BAKER_hair``'s strands), for :mod:`baker.readers.usd_baked`."""
    return {name: ext.from_usd_curves for name, ext in extensions().items() if hasattr(ext, "from_usd_curves")}


USD_READ_HOOKS.update(primitive_accessors=usd_primitive_accessors, material_readers=usd_material_readers,
                      curve_readers=usd_curve_readers)
