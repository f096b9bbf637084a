"""Input files into an :class:`baker.geometry.asset.Asset`: one module per format, each checking its file's
structure once (header counts against the file size, byte ranges, URIs kept inside the asset's folder) before any
data is read, and returning a glTF document, so every bake and writer deals with one representation.

Formats are registered by suffix as ``"module:function"`` references and imported only when a file of that kind
is read (as :class:`baker.technique.Technique` imports a technique's parts), so reading a GLB imports neither
trimesh nor usd-core. Adding a format: a module with ``read(path, allow_outside, max_memory) -> GltfDocument``
(and ``references(path, allow_outside)`` when its result depends on other files) and a line in each table below;
a groom format: ``read_groom(path) -> Groom`` and a line in ``GROOM_READERS``.
"""
from __future__ import annotations

from pathlib import Path

from baker.errors import BakerError
from baker.geometry.asset import Asset
from baker.readers.groom import Groom
from baker.readers.sniff import DESCRIPTIONS, check_input, identify
from baker.technique import load

READERS = {
    ".glb": "baker.readers.gltf:read",
    ".gltf": "baker.readers.gltf:read",
    ".obj": "baker.readers.obj:read",
    ".ply": "baker.readers.ply:read",
    ".stl": "baker.readers.stl:read",
    ".usd": "baker.readers.usd:read",
    ".usda": "baker.readers.usd:read",
    ".usdc": "baker.readers.usd:read",
    ".usdz": "baker.readers.usd:read",
}
# formats whose result depends on files beside them (what ``baker build`` hashes with the input)
REFERENCES = {
    ".gltf": "baker.readers.gltf:references",
    ".obj": "baker.readers.obj:references",
}
INPUT_SUFFIXES = set(READERS)
# grooms (dense hair curves for ``baker guides`` and ``baker cards``): ``read_groom(path) -> Groom``
GROOM_READERS = {
    ".usd": "baker.readers.usd:read_groom",
    ".usda": "baker.readers.usd:read_groom",
    ".usdc": "baker.readers.usd:read_groom",
    ".usdz": "baker.readers.usd:read_groom",
    ".gltf": "baker.readers.gltf:read_groom",
    ".glb": "baker.readers.gltf:read_groom",
    ".tfx": "baker.readers.tfx:read_groom",
}
GROOM_SUFFIXES = tuple(GROOM_READERS)


def read(path, allow_outside=None, max_memory: int | None = None, require_triangles: bool = True) -> Asset:
    """Read any input into an :class:`Asset`. ``allow_outside``: folders (beside the file's own) its URIs, MTL
    files and textures may point into. ``max_memory``: bytes reading it may need, checked from the file's size and
    header before it is parsed (:func:`baker.memory.check_file`; None: no limit). ``require_triangles=False`` also
    takes a glTF of lines or points only (a groom), which ``baker inspect`` lists but no bake can use."""
    path = Path(path)
    suffix = path.suffix.lower()
    # a directory, a named pipe, an empty file, a PNG renamed .obj: one line saying what it is (sniff)
    head = check_input(path, suffix if suffix in READERS else None, "an input baker reads")
    if suffix not in READERS:
        raise BakerError(path, f"unsupported input type '{suffix}' ({content_note(head)}use one of "
                               f"{', '.join(sorted(INPUT_SUFFIXES))})")
    asset = Asset(doc=load(READERS[suffix])(path, allow_outside, max_memory), source=path)
    if require_triangles:
        asset.check_has_triangles()
    return asset


def read_groom(path) -> Groom:
    """Any groom file's curves as a :class:`baker.readers.groom.Groom` in world space (unchecked curves:
    :func:`baker.readers.groom.clean_groom` drops or refuses the bad ones)."""
    path = Path(path)
    suffix = path.suffix.lower()
    head = check_input(path, suffix if suffix in GROOM_READERS else None, "a groom")
    reader = GROOM_READERS.get(suffix)
    if reader is None:
        raise BakerError(path, f"unsupported groom type ({content_note(head)}use one of {' '.join(GROOM_SUFFIXES)})")
    return load(reader)(path)


def content_note(head: bytes) -> str:
    """``"a PNG image; "`` when the first bytes of a file of an unsupported suffix say what it is, else ``""``."""
    kind = identify(head)
    return f"{DESCRIPTIONS[kind]}; " if kind in DESCRIPTIONS else ""


def references(path, allow_outside=None) -> list[Path]:
    """Files ``path`` names that change what :func:`read` makes of it (a .gltf's external buffers and images, an
    .obj's .mtl files and their textures), as each format resolves them; whether they exist is the caller's to
    check. ``baker build`` hashes them with the input."""
    path = Path(path)
    reference = REFERENCES.get(path.suffix.lower())
    if reference is None or not path.is_file():
        return []
    return load(reference)(path, allow_outside)
