"""glTF and GLB files: the container and JSON checked and read by :class:`baker.gltf.document.GltfDocument` (byte
ranges, URIs kept inside the asset's folder), Draco / meshopt geometry decompressed into plain accessors."""
from __future__ import annotations

import json
import urllib.parse
from pathlib import Path

from baker.gltf.compression import decompress
from baker.gltf.document import GltfDocument


def read(path: Path, allow_outside=None, max_memory: int | None = None) -> GltfDocument:
    """The document as it is (buffers are read as they are: no memory estimate before it), decompressed
    (``asset.extras.baker.decompressed`` says what was)."""
    doc = GltfDocument.load(path, allow_outside=allow_outside)
    decompress(doc)
    return doc


def references(path: Path, allow_outside=None) -> list[Path]:
    """The external buffers and images a .gltf names (``data:`` URIs are inside it), as paths beside it; a file
    that does not parse references nothing (the bake reports it)."""
    try:
        gltf = json.loads(path.read_text())
    except (ValueError, UnicodeDecodeError):
        return []
    found = []
    for item in gltf.get("buffers", []) + gltf.get("images", []):
        uri = item.get("uri") if isinstance(item, dict) else None
        if uri and not uri.startswith("data:"):
            found.append(path.parent / urllib.parse.unquote(uri))
    return found
