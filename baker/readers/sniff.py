"""What a path given as input is, before any reader opens it: a directory, a named pipe, a dangling link, an empty
file, or a file of another format under the suffix (a PNG renamed ``.obj``) is refused in one line naming the file
and what it is (``adir.obj: a directory, not an OBJ mesh``), never a traceback, and a named pipe is never opened
(opening one blocks until a writer comes).

Content is recognised by its first bytes (the signatures each format's specification fixes: PNG's 8-byte signature,
GLB's ``glTF`` magic, USD crate's ``PXR-USDC``, the sfnt version of a font, ...). Only a file recognised as *another*
format, an empty file, or binary data where a text format is expected (OBJ, glTF JSON, USDA) is refused here;
anything else is the format reader's to check, with the place in the file.
"""
from __future__ import annotations

import os
import stat
from pathlib import Path

from baker.errors import BakerError

HEAD = 4096  # bytes read to recognise a file (and to tell text from binary data)

# (kind, what it is, test on the first bytes), in the order tried: specific signatures before loose ones
SIGNATURES = (
    ("png", "a PNG image", lambda h: h.startswith(b"\x89PNG\r\n\x1a\n")),
    ("jpeg", "a JPEG image", lambda h: h.startswith(b"\xff\xd8\xff")),
    ("gif", "a GIF image", lambda h: h.startswith((b"GIF87a", b"GIF89a"))),
    ("webp", "a WebP image", lambda h: h[:4] == b"RIFF" and h[8:12] == b"WEBP"),
    ("ktx2", "a KTX2 texture", lambda h: h.startswith(b"\xabKTX 20\xbb\r\n\x1a\n")),
    ("exr", "an OpenEXR image", lambda h: h.startswith(b"\x76\x2f\x31\x01")),
    ("glb", "a GLB (binary glTF) file", lambda h: h.startswith(b"glTF")),
    ("usdc", "a USD crate (.usdc) file", lambda h: h.startswith(b"PXR-USDC")),
    ("usda", "a USDA text file", lambda h: h.startswith(b"#usda")),
    ("zip", "a ZIP archive", lambda h: h.startswith(b"PK\x03\x04")),
    ("ply", "a PLY mesh", lambda h: h.startswith(b"ply") and h[3:4] in (b"\n", b"\r", b" ", b"\t")),
    ("font", "a TrueType/OpenType font", lambda h: h[:4] in (b"\x00\x01\x00\x00", b"OTTO", b"true", b"typ1", b"ttcf")),
    ("woff", "a WOFF web font", lambda h: h[:4] in (b"wOFF", b"wOF2")),
    ("pdf", "a PDF document", lambda h: h.startswith(b"%PDF")),
    ("gzip", "gzip-compressed data", lambda h: h.startswith(b"\x1f\x8b")),
    ("elf", "an executable (ELF)", lambda h: h.startswith(b"\x7fELF")),
    ("json", "JSON text", lambda h: h.lstrip(b"\xef\xbb\xbf \t\r\n").startswith((b"{", b"["))),
)
DESCRIPTIONS = {kind: what for kind, what, _ in SIGNATURES}

# what each input is called in a refusal, and the kinds of content it may hold (None: text, or anything the
# reader checks itself; "binary": data no signature names)
EXPECTED = {
    ".obj": ("an OBJ mesh", {"text"}),
    ".ply": ("a PLY mesh", {"ply"}),
    ".stl": ("an STL mesh", {"text", "binary"}),
    ".glb": ("a GLB file", {"glb"}),
    ".gltf": ("a glTF (JSON) file", {"json", "glb"}),  # a .gltf holding a GLB is read as one (gltf.structure)
    ".usda": ("a USD stage", {"usda"}),
    ".usdc": ("a USD stage", {"usdc"}),
    ".usd": ("a USD stage", {"usda", "usdc"}),
    ".usdz": ("a USDZ package", {"zip"}),
    ".tfx": ("a TressFX (.tfx) file", {"binary"}),
    "font": ("a TrueType/OpenType font", {"font", "woff"}),
}


def identify(head: bytes) -> str:
    """The kind of content ``head`` (a file's first bytes) starts: a key of :data:`DESCRIPTIONS`, ``"empty"``,
    ``"text"`` or ``"binary"``."""
    if not head:
        return "empty"
    for kind, _, test in SIGNATURES:
        if test(head):
            return kind
    return "text" if is_text(head) else "binary"


def is_text(head: bytes) -> bool:
    """Whether ``head`` reads as text: no NUL byte and (almost) no other control character. Random bytes hold a
    control character in ~1 of 9; a text file holds none but tab, newline, carriage return and form feed."""
    if b"\x00" in head:
        return False
    controls = sum(head.count(bytes([c])) for c in range(32) if c not in (9, 10, 12, 13)) + head.count(b"\x7f")
    return controls <= len(head) // 100


def describe(kind: str) -> str:
    return {"empty": "an empty file", "text": "a text file", "binary": "binary data"}.get(kind) or DESCRIPTIONS[kind]


def check_path(path, missing: str = "file not found") -> os.stat_result:
    """Refuse a path that names no readable regular file, saying what it names (``missing``: the words for nothing
    there); the file's status otherwise. Nothing is opened (a named pipe would block)."""
    path = Path(path)
    try:
        status = os.stat(path)
    except FileNotFoundError:
        if path.is_symlink():
            raise BakerError(path, f"a symbolic link to a missing file ({os.readlink(path)})") from None
        raise BakerError(path, missing) from None
    except NotADirectoryError:
        parent = next((p for p in reversed(path.parents) if p.is_file()), None)
        raise BakerError(path, f"{missing} ({parent} is a file, not a folder)" if parent else
                         f"{missing} (a part of the path is not a folder)") from None
    except PermissionError:
        raise BakerError(path, "cannot be read: permission denied (on a folder of the path)") from None
    except OSError as exc:
        raise BakerError(path, f"cannot be read: {exc.strerror or exc}") from None
    mode = status.st_mode
    if stat.S_ISDIR(mode):
        return status  # the caller says what it wanted instead
    if stat.S_ISREG(mode):
        return status
    what = ("a named pipe (FIFO)" if stat.S_ISFIFO(mode) else "a socket" if stat.S_ISSOCK(mode) else
            "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) else "not a regular file")
    raise BakerError(path, f"{what}, not a file baker can read")


def read_head(path, size: int = HEAD) -> bytes:
    """The first ``size`` bytes of a regular file (:func:`check_path` first), or a one-line refusal."""
    try:
        with open(path, "rb") as f:
            return f.read(size)
    except PermissionError:
        raise BakerError(path, "cannot be read: permission denied") from None
    except OSError as exc:
        raise BakerError(path, f"cannot be read: {exc.strerror or exc}") from None


def check_input(path, expected: str | None, label: str | None = None, missing: str | None = None) -> bytes:
    """Refuse ``path`` unless it is a readable regular file that may hold ``expected`` (a key of :data:`EXPECTED`: a
    suffix such as ``".obj"``, or ``"font"``); its first bytes otherwise. With ``expected`` None (a suffix no reader
    takes) it is checked only for being a readable, non-empty file; ``label`` names what was wanted instead.
    ``missing``: the words for nothing at ``path`` (default ``file not found``)."""
    path = Path(path)
    wanted, allowed = EXPECTED.get(expected, (label or "a file baker reads", None))
    status = check_path(path, missing or ("font file not found" if expected == "font" else "file not found"))
    if stat.S_ISDIR(status.st_mode):
        raise BakerError(path, f"a directory, not {wanted}")
    head = read_head(path)
    kind = identify(head)
    if kind == "empty":
        raise BakerError(path, f"an empty file, not {wanted}")
    if allowed is None or kind in allowed:
        return head
    if expected == ".stl" and status.st_size >= 84 and (status.st_size - 84) % 50 == 0 and \
            84 + 50 * int.from_bytes(head[80:84], "little") == status.st_size:
        return head  # a binary STL: its 80-byte header may start with anything
    if kind == "binary" and allowed == {"text"}:
        raise BakerError(path, f"binary data, not {wanted} (a text format)")
    if kind in ("text", "binary") and allowed & {"text", "binary"}:
        return head  # no signature: the format's reader says what is wrong, and where
    raise BakerError(path, f"{describe(kind)}, not {wanted}")
