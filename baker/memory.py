"""A bake's working memory, estimated up front, against a limit (``baker bake --max-memory``, default 75% of RAM).

A job that would not fit is refused with one line (exit 2) before it starts, instead of being killed by the OS half
way. Two checks:

- :func:`check_file` before the input is read: OBJ/PLY/STL parsing costs a multiple of the file size (trimesh reads
  the text into arrays); a PLY or binary STL header gives the counts directly (read and checked against the file
  size by the format's reader in :mod:`baker.readers`, which calls this).
- :func:`check_bake` after loading, before any bake runs: bytes per triangle per requested bake, plus a fixed cost
  per bake and, for the texture bakes, a cost per texel of the texture asked for.

Both include the process itself (about 270 MiB). The figures are peak resident memory above a process that only loaded
the mesh, measured with ``benchmarks/bake_memory.py`` (Spot subdivided to 5,856 / 93,696 / 374,784 triangles, one
bake per process, default options; slope between the smallest and the largest mesh), rounded up. They are estimates: real use can be lower
(welded meshes are shared between bakes) and the limit errs on the side of running.
"""
from __future__ import annotations

import os
import re
from pathlib import Path

from baker.errors import BakerError

MIB = 1 << 20
# Measured (benchmarks/bake_memory.py, peak RSS above a load-only process, slope between 5,856 and 374,784 triangles):
# thickness 162 B/triangle + 101 MiB (its 1024^2 texture), curvature 244, edges 951 (1,064 between the two larger
# meshes), skin 108, tam 117, toon 3, fur 1,368; loading 134 B/triangle above a 270 MiB process. The figures below are
# those, rounded up by about half again. Edges since issue 18 (no UV/normal corner arrays without those attributes, no
# fin corners unless fins are written, one compiled pass per primitive): 96 B/triangle above the load on Spot (UVs
# and normals), 450 B/triangle for the whole process on the 4.4M-triangle bunny PLY (benchmarks/scale.py), load
# included; 400 covers both.
PER_TRIANGLE = {"thickness": 250, "curvature": 400, "edges": 400, "skin": 160, "tam": 180, "toon": 8, "fur": 2000,
                "normal-blur": 200}
# tam's stroke parameterization (--tam-strokes field, the default) on top of its own figure: 5.5 KB/triangle measured
# between tori of 11,520 and 184,320 triangles (the curvature estimate, the cross field's SuperLU factor, the patch
# graph and the patch solve), rounded up
STROKES_PER_TRIANGLE = 8000
# fixed cost per bake (kernels, tables, default-size textures), bytes
FIXED = {"thickness": 110 * MIB, "curvature": 16 * MIB, "edges": 8 * MIB, "skin": 8 * MIB, "tam": 8 * MIB,
         "toon": 4 * MIB, "fur": 16 * MIB, "normal-blur": 16 * MIB}
# bytes per texel of the bake's texture (option ``texture_size`` squared) beyond the texels counted in FIXED
# normal-blur: 1.2 GB peak for the 1M texels of a 1024^2 normal map on a sphere (about 900 B/texel above the process:
# frames, the per-Gaussian blurred normals, the lattice), rounded up; its maps take the input normal map's size, which
# the estimate does not read: the automatic texture size stands in for it
PER_TEXEL = {"thickness": 100, "curvature": 100, "normal-blur": 1200}
DEFAULT_TEXELS = {"thickness": 1024 * 1024, "curvature": 0,  # curvature measured without its texture (off by default)
                  "normal-blur": 0}
# automatic texture sizes (texel density, baker/texels/texture_space.py): 8 texels along the mean edge puts about
# 28 texels on a triangle's area, over the UV coverage (about half) and rounded to a power of two per side (up to 2x
# the texels): 128 per triangle bounds it; each material's texture stays within [64^2, 2048^2]
AUTO_TEXELS_PER_TRIANGLE = 128
AUTO_SIZE_RANGE = (64, 2048)
PER_TRIANGLE_OTHER = 2000  # a bake not listed above (a plug-in technique): a generous per-triangle figure
FIXED_OTHER = 64 * MIB
PROCESS = 280 * MIB  # the interpreter with numpy, trimesh, numba kernels and Embree loaded (270 MiB measured)
LOAD_PER_TRIANGLE = 200  # the decoded, cached primitive and its weld (float64 positions, int64 faces, inverse)
# reading a mesh file: peak bytes per byte of a text file (trimesh holds the text, the split tokens and the arrays
# at once; 134 B/triangle measured for an OBJ of about 55 B/triangle), and per triangle for the binary formats whose
# header gives the count
FILE_FACTOR = {".obj": 6, ".ply": 6, ".stl": 6}
FILE_PER_TRIANGLE = 400
DEFAULT_FRACTION = 0.75


def physical_memory() -> int | None:
    """Bytes of RAM this process may use: physical memory, or a smaller cgroup (container) limit."""
    total = None
    try:
        total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        try:
            for line in Path("/proc/meminfo").read_text().splitlines():
                if line.startswith("MemTotal:"):
                    total = int(line.split()[1]) * 1024
        except OSError:
            pass
    for limit_file in ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"):
        try:
            text = Path(limit_file).read_text().strip()
        except OSError:
            continue
        if text.isdigit() and (total is None or int(text) < total):
            total = int(text)
    return total


def default_limit() -> int | None:
    total = physical_memory()
    return int(total * DEFAULT_FRACTION) if total else None


_UNITS = {"": 1, "b": 1, "k": 1 << 10, "kb": 1000, "kib": 1 << 10, "m": 1 << 20, "mb": 1000 ** 2, "mib": 1 << 20,
          "g": 1 << 30, "gb": 1000 ** 3, "gib": 1 << 30, "t": 1 << 40, "tb": 1000 ** 4, "tib": 1 << 40}


def parse_limit(text: str | None) -> int | None:
    """``--max-memory``: bytes (``512M``, ``2G``, ``1.5GiB``, ``1000000``), a share of RAM (``50%``), or ``none``
    (no limit). None (the option not given) is the default, 75% of RAM."""
    if text is None:
        return default_limit()
    value = text.strip().lower()
    if value in ("none", "off", "unlimited"):
        return None
    m = re.fullmatch(r"(\d+(?:\.\d*)?)\s*(%|[a-z]*)", value)
    if not m or (m.group(2) != "%" and m.group(2) not in _UNITS):
        raise BakerError(None, f"--max-memory {text!r}: use bytes with an optional unit (512M, 2G, 1.5GiB), a share "
                               "of RAM (50%) or 'none'")
    number = float(m.group(1))
    if m.group(2) == "%":
        total = physical_memory()
        if total is None:
            raise BakerError(None, f"--max-memory {text!r}: the size of RAM is unknown here; give bytes")
        return int(total * number / 100)
    return int(number * _UNITS[m.group(2)])


def human(n: float) -> str:
    for unit, size in (("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)):
        if n >= size:
            return f"{n / size:.1f} {unit}"
    return f"{int(n)} B"


def _refuse(path, what: str, need: int, limit: int) -> None:
    raise BakerError(path, f"{what} needs about {human(need)} of memory, more than the limit of {human(limit)} "
                           "(--max-memory; default 75% of RAM): use a smaller mesh or texture, fewer bakes at once, "
                           "or a larger --max-memory")


def file_estimate(path, counts: dict | None = None) -> int:
    """Peak bytes to read ``path`` (0 for formats read without a large parse: glTF/GLB buffers are read as they are,
    USD by usd-core). ``counts``: ``{"faces": m}`` from a PLY or binary STL header, when the reader has one."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in FILE_FACTOR:
        return 0
    try:
        size = path.stat().st_size
    except OSError:
        return 0
    need = PROCESS + FILE_FACTOR[suffix] * size
    if counts:
        need = max(need, PROCESS + FILE_PER_TRIANGLE * counts.get("faces", 0))
    return need


def check_file(path, limit: int | None, counts: dict | None = None) -> None:
    """Refuse reading a mesh file that would not fit in ``limit`` bytes (None: no limit); ``counts`` as
    :func:`file_estimate` takes them."""
    if limit is None:
        return
    need = file_estimate(path, counts)
    if need > limit:
        _refuse(path, f"reading this {Path(path).suffix.lower().lstrip('.').upper()} file", need, limit)


def texture_texels(triangles: int, materials: int, size: int | None) -> int:
    """Texels of a texture bake over ``materials`` texture sets: ``size`` squared each when forced, else the bound of
    the automatic sizes for ``triangles`` triangles (:data:`AUTO_TEXELS_PER_TRIANGLE`)."""
    if size:
        return materials * size * size
    low, high = (materials * s * s for s in AUTO_SIZE_RANGE)
    return min(high, max(low, AUTO_TEXELS_PER_TRIANGLE * triangles))


def bake_estimate(triangles: int, bakes, options: dict | None = None, materials: int = 1) -> int:
    """Peak bytes of running ``bakes`` (names) on an asset of ``triangles`` triangles and ``materials`` materials
    (texture sets); ``options`` maps a bake name to its options instance (for texture sizes)."""
    options = options or {}
    need = PROCESS + LOAD_PER_TRIANGLE * triangles
    for name in bakes:
        need += PER_TRIANGLE.get(name, PER_TRIANGLE_OTHER) * triangles + FIXED.get(name, FIXED_OTHER)
        chosen = options.get(name)
        if name == "tam" and getattr(chosen, "strokes", "field") == "field":
            need += STROKES_PER_TRIANGLE * triangles
        if name in PER_TEXEL and chosen is not None:
            size = getattr(chosen, "texture_size", None)
            enabled = getattr(chosen, "per_texel", getattr(chosen, "texture", True))
            if enabled is not False:
                texels = texture_texels(triangles, max(1, materials), size)
                need += PER_TEXEL[name] * max(0, texels - DEFAULT_TEXELS[name])
    return need


def asset_triangles(asset) -> int:
    total = 0
    for m in range(len(asset.meshes())):
        for p in asset.triangle_primitives(m):
            prim = asset.meshes()[m]["primitives"][p]
            count = _index_count(asset, prim)
            total += count // 3 if count else 0
    return total


def _index_count(asset, prim) -> int:
    accessors = asset.doc.json.get("accessors", [])
    index = prim.get("indices", prim.get("attributes", {}).get("POSITION"))
    try:
        return int(accessors[index]["count"])
    except (IndexError, KeyError, TypeError, ValueError):
        return 0


def check_bake(asset, bakes, options: dict | None, limit: int | None, what: str | None = None) -> int:
    """Refuse running ``bakes`` on ``asset`` when the estimate exceeds ``limit`` bytes (None: no limit); returns the
    estimate. ``what`` names the job in the refusal (default: the bakes)."""
    materials = len(asset.doc.json.get("materials") or ()) or 1
    need = bake_estimate(asset_triangles(asset), bakes, options, materials)
    if limit is not None and need > limit:
        triangles = asset_triangles(asset)
        doing = f"{what} ({triangles} triangles)" if what else f"baking {', '.join(bakes)} on {triangles} triangles"
        _refuse(asset.source, doing, need, limit)
    return need


MAX_MEMORY_HELP = ("refuse a job whose estimated working memory is larger: bytes (512M, 2G), a share of RAM (50%%) "
                   "or 'none' (default: 75%% of RAM)")


def add_argument(parser, help: str = MAX_MEMORY_HELP) -> None:
    """``--max-memory SIZE`` on a command's parser (read with :func:`parse_limit`)."""
    parser.add_argument("--max-memory", metavar="SIZE", help=help)
