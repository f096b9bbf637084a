"""What a corpus case is, and small writers for the files cases are made of (independent of baker's own writers)."""
from __future__ import annotations

import json
import struct
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

# the commands a case is run with; {input} and {output} are substituted, {http} is a local server's base URL
BAKE = ("bake", "{input}", "-o", "{output}", "--bakes", "edges")
INSPECT = ("inspect", "{input}")
VALIDATE = ("validate", "{input}", "--no-khronos")


@dataclass(frozen=True)
class Expect:
    """What one command must do with the case: its exit code and words that must appear in its stderr (exit 2) or in
    its report (validate, exit 1)."""

    exit: int
    words: tuple[str, ...] = ()


@dataclass(frozen=True)
class Case:
    """One hostile or malformed input. ``make(folder, env)`` writes the input (and any side files) into ``folder``
    and returns the path to hand to baker; ``env`` has ``outside`` (a folder beside it holding ``secret.bin``, which
    must never be opened) and ``http`` (the base URL of a local server that counts requests)."""

    name: str
    rule: str  # the input rule it exercises, as the issue/README words it
    make: Callable[[Path, dict], Path]
    expect: dict = field(default_factory=lambda: {"bake": Expect(2), "inspect": Expect(2), "validate": Expect(1)})
    commands: dict = field(default_factory=lambda: {"bake": BAKE, "inspect": INSPECT, "validate": VALIDATE})
    # more files a command writes beside {output}, as suffixes added to it (``glyphs -o NAME`` writes NAME.png and
    # NAME.json): each is pre-created like {output} and must be unchanged after a failed run
    side_outputs: tuple = ()


def triangle_gltf(*, uri: str | None = None, positions=None, extra: dict | None = None) -> tuple[dict, bytes]:
    """A one-triangle glTF (JSON, binary) with POSITION only; ``uri`` names the buffer (None: GLB-style)."""
    positions = np.array(positions if positions is not None else [[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    data = positions.tobytes()
    gltf = {
        "asset": {"version": "2.0"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3",
                       "min": np.nan_to_num(positions.min(0)).tolist(), "max": np.nan_to_num(positions.max(0)).tolist()}],
        "bufferViews": [{"buffer": 0, "byteLength": len(data), "target": 34962}],
        "buffers": [{"byteLength": len(data)}],
    }
    if uri is not None:
        gltf["buffers"][0]["uri"] = uri
    for key, value in (extra or {}).items():
        gltf[key] = value
    return gltf, data


def glb_bytes(gltf: dict, binary: bytes | None) -> bytes:
    text = json.dumps(gltf, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text
    if binary is not None:
        binary += b"\0" * (-len(binary) % 4)
        chunks += struct.pack("<II", len(binary), 0x004E4942) + binary
    return b"glTF" + struct.pack("<II", 2, 12 + len(chunks)) + chunks


def write_glb(path: Path, gltf: dict, binary: bytes | None) -> Path:
    path.write_bytes(glb_bytes(gltf, binary))
    return path


def write_gltf(path: Path, gltf: dict) -> Path:
    path.write_text(json.dumps(gltf))
    return path
