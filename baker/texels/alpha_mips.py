"""Coverage-preserving mip chains for alpha-tested textures (Castaño 2010; RTR4 14.7.1), shipped as KTX2.

Mipmapping an alpha-tested texture shrinks what passes the test: averaging thin opaque strands with the transparent
texels around them gives texels below the cutoff, so hair, fur shells and fins thin out and vanish with distance
(RTR4 14.7.1, "Geometry and Alpha"). Castaño ("Computing Alpha Mipmaps", 2010) scales each level's alpha so the
fraction of texels passing the test equals level 0's, the scale found by binary search.

Filter: every level is the exact box (area) average of level 0's texels under its footprint (kept unquantized from
level to level: the 2 x 2 mean of the level above where sides halve exactly, else straight from level 0 through prefix
sums), so non-power-of-two sizes (a 64 x 100 fin texture) get their true footprint and no rounding compounds from
level to level. Colour is filtered *premultiplied* (weighted by alpha) in linear light and
stored straight: texels that pass the test after the alpha scale show the strands' colour, not the colour under the
transparent texels around them; where a footprint holds no alpha at all, its plain average is kept. Alpha is
filtered plainly, then scaled. Level 0 is the input unchanged (the PNG the document keeps).

In a glTF document the chain is an uncompressed RGBA8 KTX2 (:mod:`baker.gltf.ktx2`) whose bytes are an accessor
(``UNSIGNED_BYTE``, ``SCALAR``, one element per byte of the file), named by the technique's extension in a
``coverageMips`` list, one entry per chain::

    {"texture": 3, "accessor": 41, "mimeType": "image/ktx2", "alphaCutoff": 0.5, "levelCount": 8,
     "firstLevel": 1, "coverage": 0.23}

``texture`` is the glTF texture whose image is level 0 (a plain viewer keeps using it), ``coverage`` the fraction of
level 0's texels with alpha >= ``alphaCutoff``. ``firstLevel`` 1: the KTX2 holds levels 1.. (its header's size is
level 1's) and a reader takes level 0 from the texture's image, so the PNG's texels are not stored twice (they were
75% of a chain's bytes); without it (0, files before issue 48, and 1 x 1 images) the KTX2 holds every level.
``levelCount`` counts the whole chain. Not an ``images`` entry: glTF admits ``image/ktx2`` only through
KHR_texture_basisu, for Basis-compressed data, and the Khronos validator warns on an uncompressed one
(VALUE_NOT_IN_LIST, IMAGE_UNRECOGNIZED_FORMAT). An accessor rather than a bare bufferView: glTF tools that rebuild
the buffers (glTF-Transform) carry accessors an extension names through, as they do every other array baker
writes; the validator notes only its UNUSED_OBJECT info.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from baker.gltf.ktx2 import coverage_mips_bytes, decode_ktx2, encode_ktx2
from baker.texels.color import TRANSFERS

MIME_TYPE = "image/ktx2"
SEARCH_STEPS = 24  # binary search on the scale: 2^-24 of the bracket, far below one texel's step in coverage
MAX_SCALE = 64.0  # a level whose strongest texel is under cutoff / 64 keeps that: nothing worth preserving
CHECKED_DOWN_TO = 8  # the check holds each level down to 8 x 8 (smaller levels have too few texels for 10%)
COVERAGE_TOLERANCE = 0.10  # relative to level 0's coverage


@dataclass(frozen=True)
class AlphaMipChain:
    """A mip chain, level 0 first, down to 1 x 1.

    levels : list of (h, w, 4) uint8 straight-alpha RGBA, level i ``max(1, W >> i)`` x ``max(1, H >> i)``
    coverage : (L,) fraction of each level's texels with alpha >= alpha_cutoff (as stored, 8-bit)
    scales : (L,) the alpha scale applied to each level (1 at level 0; all 1 for a plain box chain)
    alpha_cutoff : the alpha-test threshold, 0..1
    """

    levels: list
    coverage: np.ndarray
    scales: np.ndarray
    alpha_cutoff: float


def level_sizes(height: int, width: int) -> list[tuple[int, int]]:
    """(h, w) of every level of the full chain of a ``width`` x ``height`` texture, down to 1 x 1 (KTX2, GL)."""
    count = int(max(height, width)).bit_length()
    return [(max(1, height >> i), max(1, width >> i)) for i in range(count)]


def alpha_coverage(alpha_u8: np.ndarray, alpha_cutoff: float) -> float:
    """Fraction of texels whose 8-bit alpha passes the test ``alpha / 255 >= cutoff`` (compared in float32, as a GPU
    compares the sampled value in the shader)."""
    a = np.asarray(alpha_u8, np.float32) / np.float32(255.0)
    return float(np.mean(a >= np.float32(alpha_cutoff))) if a.size else 0.0


def bilinear_coverage(alpha_u8: np.ndarray, alpha_cutoff: float, samples: int = 4, repeat: bool = True) -> float:
    """Fraction of ``samples`` x ``samples`` bilinear samples per texel that pass the test: what a GPU's LINEAR
    filter sees, Castaño's (2010) own coverage measure (the chains hold :func:`alpha_coverage`, the texel
    fraction; this measures how that survives bilinear sampling). ``repeat``: wrap at the edges, else clamp."""
    a = np.asarray(alpha_u8, np.float64) / 255.0
    offsets = (np.arange(samples) + 0.5) / samples - 0.5  # from the texel centre, in texels
    passed = 0.0
    for axis_y in offsets:
        ay = _lerp_neighbour(a, axis_y, 0, repeat)
        for axis_x in offsets:
            passed += float(np.mean(_lerp_neighbour(ay, axis_x, 1, repeat) >= alpha_cutoff))
    return passed / samples ** 2


def _lerp_neighbour(a: np.ndarray, offset: float, axis: int, repeat: bool) -> np.ndarray:
    """``a`` sampled ``offset`` texels (|offset| < 1) along ``axis`` with linear interpolation."""
    step = 1 if offset > 0 else -1
    if repeat:
        neighbour = np.roll(a, -step, axis=axis)
    else:
        n = a.shape[axis]
        neighbour = np.take(a, np.clip(np.arange(n) + step, 0, n - 1), axis=axis)
    return (1.0 - abs(offset)) * a + abs(offset) * neighbour


def box_resample(values: np.ndarray, height: int, width: int) -> np.ndarray:
    """Area-weighted (box) average of ``values`` (H, W, C) float64 onto ``height`` x ``width``: each output texel is
    the mean of the input over its footprint, fractional texels weighted by the part covered. Exact, any ratio."""
    return _resample_axis(_resample_axis(values, height, 0), width, 1)


def _resample_axis(values: np.ndarray, n_out: int, axis: int) -> np.ndarray:
    n_in = values.shape[axis]
    if n_out == n_in:
        return values
    # prefix sums at integer edges; the sum up to a fractional edge x interpolates linearly (texels are constant)
    prefix = np.concatenate([np.zeros_like(np.take(values, [0], axis=axis)), np.cumsum(values, axis=axis)], axis=axis)
    edges = np.arange(n_out + 1, dtype=np.float64) * (n_in / n_out)
    lower = np.minimum(np.floor(edges).astype(np.int64), n_in - 1)
    frac = edges - lower
    shape = [1] * values.ndim
    shape[axis] = n_out + 1
    at = np.take(prefix, lower, axis=axis) + frac.reshape(shape) * np.take(values, lower, axis=axis)
    upper = np.take(at, np.arange(1, n_out + 1), axis=axis)
    low = np.take(at, np.arange(n_out), axis=axis)
    return (upper - low) * (n_out / n_in)


def alpha_scale_for_coverage(alpha: np.ndarray, alpha_cutoff: float, target: float) -> float:
    """The scale ``s`` whose stored alpha ``round(clip(alpha * s) * 255)`` passes the test on a fraction of texels
    closest to ``target`` (Castaño 2010: binary search on the scale; coverage only grows with ``s``).

    alpha : float64 filtered alpha, 0..1. A stored value ``k`` passes when ``k / 255 >= cutoff`` (float32), i.e.
    ``k >= k_pass``; ``round(x) >= k_pass`` when ``x >= k_pass - 0.5``; so a texel passes at scale ``s`` when
    ``alpha >= (k_pass - 0.5) / (255 s)``, counted by a binary search in the sorted alphas (one sort per level,
    not one pass over the level per step)."""
    if target <= 0.0:
        return 1.0  # nothing passes at level 0: nothing to preserve
    k_pass = int(np.argmax(np.arange(256, dtype=np.float32) / np.float32(255.0) >= np.float32(alpha_cutoff)))
    if k_pass == 0:
        return 1.0  # a cutoff of 0: every texel passes at any scale
    ordered = np.sort(alpha, axis=None)
    n = ordered.size

    def covered(scale: float) -> float:
        if scale <= 0.0:
            return 0.0
        return (n - int(np.searchsorted(ordered, (k_pass - 0.5) / (255.0 * scale), side="left"))) / n

    low, high = 0.0, MAX_SCALE
    if covered(high) <= target:
        return high if covered(high) > covered(1.0) else 1.0
    for _ in range(SEARCH_STEPS):  # invariant: covered(low) <= target < covered(high)
        mid = 0.5 * (low + high)
        if covered(mid) <= target:
            low = mid
        else:
            high = mid
    # the step in coverage lies between low and high: take the side nearer the target, on a tie the covering one
    # (a strand kept a little thicker rather than gone)
    return low if target - covered(low) < covered(high) - target else high


def alpha_mip_chain(rgba: np.ndarray, alpha_cutoff: float, *, preserve_coverage: bool = True,
                    transfer: str = "srgb") -> AlphaMipChain:
    """The mip chain of an RGBA8 image down to 1 x 1, each level's alpha scaled so its alpha-test coverage equals
    level 0's (``preserve_coverage=False``: the plain box chain, for comparison).

    Parameters
    ----------
    rgba : (H, W, 4) uint8, straight alpha, row 0 at the top
    alpha_cutoff : the alpha-test threshold (glTF ``alphaCutoff``), 0..1
    transfer : how colour is encoded: ``"srgb"`` (glTF base colour), ``"gamma2.2"`` (a plain power curve) or
        ``"linear"``; colour is decoded to linear light, filtered, and encoded back the same way
    """
    rgba = np.asarray(rgba)
    if rgba.dtype != np.uint8 or rgba.ndim != 3 or rgba.shape[2] != 4 or min(rgba.shape[:2]) < 1:
        raise ValueError(f"expected an (H, W, 4) uint8 image, got {rgba.shape} {rgba.dtype}")
    if not 0.0 <= alpha_cutoff <= 1.0:
        raise ValueError(f"alphaCutoff {alpha_cutoff} is outside 0..1")
    height, width = rgba.shape[:2]
    alpha0 = rgba[..., 3].astype(np.float64) / 255.0
    color0 = rgba[..., :3].astype(np.float64) / 255.0
    if transfer not in TRANSFERS:
        raise ValueError(f"transfer {transfer!r} is none of {', '.join(TRANSFERS)}")
    decode, encode = TRANSFERS[transfer]
    color0 = decode(color0)
    # one resampling per level of (premultiplied colour, colour, alpha)
    stacked = np.concatenate([color0 * alpha0[..., None], color0, alpha0[..., None]], axis=2)
    target = alpha_coverage(rgba[..., 3], alpha_cutoff)
    levels, coverage, scales = [np.ascontiguousarray(rgba)], [target], [1.0]
    previous = stacked
    for h, w in level_sizes(height, width)[1:]:
        if previous.shape[:2] == (2 * h, 2 * w):  # footprints nest: the 2 x 2 mean of the level above is exact
            filtered = previous.reshape(h, 2, w, 2, -1).mean(axis=(1, 3))
        else:  # an odd side: each texel's exact footprint in level 0
            filtered = box_resample(stacked, h, w)
        previous = filtered
        alpha = np.clip(filtered[..., 6], 0.0, 1.0)
        weighted = alpha > 1e-9
        color = np.where(weighted[..., None], filtered[..., 0:3] / np.maximum(alpha, 1e-9)[..., None],
                         filtered[..., 3:6])
        color = encode(color)
        scale = alpha_scale_for_coverage(alpha, alpha_cutoff, target) if preserve_coverage else 1.0
        level = np.empty((h, w, 4), np.uint8)
        level[..., :3] = np.rint(np.clip(color, 0.0, 1.0) * 255.0)
        level[..., 3] = np.rint(np.clip(alpha * scale, 0.0, 1.0) * 255.0)
        levels.append(level)
        coverage.append(alpha_coverage(level[..., 3], alpha_cutoff))
        scales.append(scale)
    return AlphaMipChain(levels, np.array(coverage), np.array(scales), float(alpha_cutoff))


def coverage_error(coverage: np.ndarray, sizes: list, down_to: int = CHECKED_DOWN_TO) -> float:
    """Largest relative difference from level 0's coverage over the levels whose smaller side is >= ``down_to``
    (0 when level 0 covers nothing and neither does any level)."""
    target = float(coverage[0])
    worst = 0.0
    for c, (h, w) in zip(coverage, sizes):
        if min(h, w) < down_to:
            break
        worst = max(worst, abs(float(c) - target) / target if target > 0 else float(c > 0))
    return worst


def levels_off_coverage(coverage: np.ndarray, sizes: list, tolerance: float = COVERAGE_TOLERANCE,
                        down_to: int = CHECKED_DOWN_TO) -> list[int]:
    """The levels (smaller side >= ``down_to``) whose coverage differs from level 0's by more than ``tolerance``
    of it, or by more than one texel of the level where that is larger: a level of ``n`` texels can only hold
    coverage in steps of ``1 / n``, so a shell with a few dozen covered texels cannot be held to 10% at 16 x 16."""
    target = float(coverage[0])
    out = []
    for i, (c, (h, w)) in enumerate(zip(coverage, sizes)):
        if min(h, w) < down_to:
            break
        if abs(float(c) - target) > max(tolerance * target, 1.0 / (h * w)) + 1e-12:
            out.append(i)
    return out


# ---------------------------------------------------------------------------------------------------- glTF
def write_coverage_mips(doc, texture: int, rgba: np.ndarray, alpha_cutoff: float, transfer: str = "srgb") -> dict:
    """Build the coverage-preserving chain of ``rgba`` (texture ``texture``'s image), store it as an RGBA8 KTX2 in
    a new accessor, and return the ``coverageMips`` entry for the technique's extension to list."""
    chain = alpha_mip_chain(rgba, alpha_cutoff, transfer=transfer)
    # level 0 is the texture's image unchanged: the KTX2 starts at level 1 (firstLevel; issue 48: level 0 was 75% of
    # every chain's bytes, a second copy of the PNG). A 1 x 1 image has no level 1: its chain is level 0 alone.
    first = 1 if len(chain.levels) > 1 else 0
    blob = np.frombuffer(encode_ktx2(chain.levels[first:]), np.uint8)
    accessor = doc.add_accessor(blob, target=None, name=f"coverage mips of texture {int(texture)} (KTX2)")
    entry = {"texture": int(texture), "accessor": int(accessor), "mimeType": MIME_TYPE,
             "alphaCutoff": float(alpha_cutoff), "levelCount": len(chain.levels), "coverage": float(chain.coverage[0])}
    if first:
        entry["firstLevel"] = first
    return entry


def read_coverage_mips(doc, entry: dict) -> list:
    """The levels (uint8 RGBA arrays, level 0 first) of one ``coverageMips`` entry: the KTX2's, after the texture's
    image as level 0 when the KTX2 starts at level 1 (``firstLevel`` 1); ValueError when unreadable."""
    levels = decode_ktx2(coverage_mips_bytes(doc, entry))["levels"]
    first = entry.get("firstLevel", 0)
    if first == 0:
        return levels
    if first != 1:
        raise ValueError(f"firstLevel {first!r} is neither 0 nor 1")
    from baker.gltf.images import decoded_texture

    texture = entry.get("texture")
    base = decoded_texture(doc, texture) if isinstance(texture, int) and not isinstance(texture, bool) \
        and 0 <= texture < len(doc.json.get("textures") or []) else None
    if base is None or base.dtype != np.uint8 or base.ndim != 3 or base.shape[2] != 4:
        raise ValueError(f"level 0 (the image of texture {texture!r}) is not an RGBA8 PNG")
    expected = (max(1, base.shape[0] >> 1), max(1, base.shape[1] >> 1))
    if levels[0].shape[:2] != expected:
        raise ValueError(f"the KTX2's first level is {levels[0].shape[1]} x {levels[0].shape[0]}, level 1 of a "
                         f"{base.shape[1]} x {base.shape[0]} image is {expected[1]} x {expected[0]}")
    return [base, *levels]


def check_coverage_mips(doc, entries, ptr: str, issues) -> None:
    """Rules of a ``coverageMips`` list at JSON pointer ``ptr``: each entry names an existing texture and accessor;
    the accessor holds an RGBA8 KTX2 with the full chain of the texture's image, from level 1 (``firstLevel`` 1:
    level 0 is the image) or level 0 equal to the image; the coverage
    of every level down to 8 x 8 stays within 10% (or one texel) of level 0's (else a warning: the chain is valid,
    it just does not preserve coverage)."""
    from baker.gltf.images import decoded_texture

    if not isinstance(entries, list):
        issues.error("BAKER_COVERAGE_MIPS", "coverageMips must be a list", ptr)
        return
    textures = doc.json.get("textures") or []
    for i, entry in enumerate(entries):
        at = f"{ptr}/{i}"
        if not isinstance(entry, dict):
            issues.error("BAKER_COVERAGE_MIPS", "a coverageMips entry must be an object", at)
            continue
        texture, cutoff = entry.get("texture"), entry.get("alphaCutoff")
        if not isinstance(texture, int) or isinstance(texture, bool) or not 0 <= texture < len(textures):
            issues.error("UNRESOLVED_REFERENCE", f"texture {texture!r} does not exist", at + "/texture")
            continue
        if not isinstance(cutoff, (int, float)) or isinstance(cutoff, bool) or not 0.0 <= cutoff <= 1.0:
            issues.error("BAKER_COVERAGE_MIPS_CUTOFF", f"alphaCutoff {cutoff!r} is not a number in 0..1",
                         at + "/alphaCutoff")
            continue
        try:
            levels = read_coverage_mips(doc, entry)
        except (ValueError, KeyError, TypeError) as exc:
            issues.error("BAKER_COVERAGE_MIPS_KTX2", f"the mip chain cannot be read: {exc}", at + "/accessor")
            continue
        except Exception as exc:  # struct.error and kin from a malformed file: one line, no traceback
            issues.error("BAKER_COVERAGE_MIPS_KTX2", f"the mip chain cannot be read: {type(exc).__name__}: {exc}",
                         at + "/accessor")
            continue
        base = levels[0]
        if base.ndim != 3 or base.shape[2] != 4:
            issues.error("BAKER_COVERAGE_MIPS_KTX2", f"the chain is {base.shape}, not a 2D RGBA8 texture",
                         at + "/accessor")
            continue
        sizes = level_sizes(*base.shape[:2])
        if len(levels) != len(sizes) or entry.get("levelCount") != len(levels):
            issues.error("BAKER_COVERAGE_MIPS_LEVELS", f"{len(levels)} levels (levelCount "
                         f"{entry.get('levelCount')!r}); the full chain of {base.shape[1]} x {base.shape[0]} has "
                         f"{len(sizes)}", at + "/levelCount")
            continue
        image = decoded_texture(doc, texture)
        if image is not None and (image.shape != base.shape or image.dtype != np.uint8
                                  or not np.array_equal(image, base)):
            issues.error("BAKER_COVERAGE_MIPS_BASE", "level 0 of the chain is not the texture's image",
                         at + "/accessor")
            continue
        coverage = np.array([alpha_coverage(level[..., 3], cutoff) for level in levels])
        off = levels_off_coverage(coverage, sizes)
        if off:
            issues.warning("BAKER_COVERAGE_MIPS_COVERAGE", f"alpha-test coverage of level {off[0]} is "
                           f"{coverage[off[0]]:.4f}, level 0's {coverage[0]:.4f}: more than 10% (or one texel) "
                           f"apart", at)
