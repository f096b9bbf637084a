"""``baker skin-lut -o OUT``: write Penner's pre-integrated skin LUT (and penumbra LUT) as images plus a JSON sidecar
with the axes, units, profile, Jimenez separable kernel and d'Eon Gaussian blur weights.

OUT's suffix picks the format: ``.exr`` (32-bit float, linear), ``.png`` (``--skin-bits`` 16 or 8, ``--skin-encoding``
linear or srgb). The penumbra LUT goes to ``<stem>_penumbra<suffix>``, the sidecar to ``<stem>.json``.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from baker.techniques.skin.options import SkinOptions
from baker.techniques.skin.kernel import quantize, skin_tables
from baker.errors import BakerError
from baker.gltf.atomic import write_files_atomic
from baker.gltf.images import encode_image
from baker.options import from_args

SUFFIXES = (".exr", ".png")




def _pixels(values: np.ndarray, suffix: str, options: SkinOptions) -> np.ndarray:
    if suffix == ".exr":
        return np.ascontiguousarray(values, np.float32)
    return quantize(values, options.bits, options.encoding)


def sidecar(tables, options: SkinOptions, lut_file: str, penumbra_file: str | None, fmt: str) -> dict:
    axes = tables.axes
    doc = {
        "generator": "baker skin-lut",
        "technique": "Penner & Borshukov 2011, pre-integrated skin shading (RTR4 14.6.3)",
        "lut": {
            "file": lut_file,
            "width": axes.width,
            "height": axes.height,
            "format": fmt,
            "encoding": "linear" if fmt == "exr-float32" else options.encoding,
            "channels": ["red", "green", "blue"],
            "u": {"quantity": "N.L", "range": [-1.0, 1.0], "mapping": "u = N.L * 0.5 + 0.5"},
            "v": {"quantity": "curvature", "unit": "1/mm", "range": [float(c) for c in axes.curvature_range],
                  "radiusRange": [1.0 / axes.curvature_range[1], 1.0 / axes.curvature_range[0]], "radiusUnit": "mm",
                  "mapping": "v = (curvature - range[0]) / (range[1] - range[0]), linear in 1/r"},
            "texels": "endpoint-aligned: column 0 is N.L = -1, the last column N.L = +1; row 0 (top) is range[0]; "
                      "sample at (t * (size - 1) + 0.5) / size",
            "samples": int(options.samples),
            "ringProfile": options.ring_profile,
        },
        "profile": tables.profile.as_json(),
        "curvatureScale": 1.0 / options.unit_scale,
        "unitScale": {"mmPerMeshUnit": options.unit_scale},
        "normalBlend": [float(x) for x in tables.normal_blend],
        "wrap": {"wrap": options.wrap, "scatterWidth": options.scatter_width,
                 "scatterColor": [float(c) for c in options.scatter_color]},
        "jimenezKernel": {
            "technique": "Jimenez et al. 2015, Separable Subsurface Scattering",
            "taps": int(options.jimenez_taps),
            "strength": [float(x) for x in options.jimenez_strength],
            "falloff": [float(x) for x in options.jimenez_falloff],
            "layout": "rows of [red, green, blue, offset], centre tap first; offsets in units of the kernel width",
            "kernel": [[float(x) for x in row] for row in tables.jimenez],
        },
        "deonGaussians": {
            "technique": "d'Eon & Luebke 2007, texture-space diffusion by successive Gaussian blurs (GPU Gems 3 ch. 14)",
            "unit": "mm^2 (variances), mm (sigma)",
            "gaussians": tables.gaussians,
        },
    }
    if tables.penumbra is not None:
        doc["penumbra"] = {
            "file": penumbra_file,
            "width": int(tables.penumbra.shape[1]),
            "height": int(tables.penumbra.shape[0]),
            "u": {"quantity": "shadow", "range": [0.0, 1.0], "mapping": "u = filtered shadow value (0 shadowed)"},
            "v": {"quantity": "1 / penumbra width", "unit": "1/mm", "range": [float(x) for x in tables.penumbra_range],
                  "widthRange": [float(options.penumbra_min_width), float(options.penumbra_max_width)]},
            "sharpening": float(options.sharpening),
        }
    return doc


def run(args) -> int:
    out = Path(args.output)
    suffix = out.suffix.lower()
    if suffix not in SUFFIXES:
        raise BakerError(out, f"unsupported LUT image type (use one of {', '.join(SUFFIXES)})")
    try:
        options = from_args(SkinOptions, "skin", args)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    tables = skin_tables(options)
    penumbra_path = out.with_name(f"{out.stem}_penumbra{out.suffix}") if tables.penumbra is not None else None
    json_path = out.with_suffix(".json")
    fmt = "exr-float32" if suffix == ".exr" else f"png-{options.bits}bit"
    files = [(out, encode_image(_pixels(tables.lut, suffix, options), suffix))]
    if penumbra_path is not None:
        files.append((penumbra_path, encode_image(_pixels(tables.penumbra, suffix, options), suffix)))
    doc = sidecar(tables, options, out.name, penumbra_path.name if penumbra_path else None, fmt)
    files.append((json_path, (json.dumps(doc, indent=2) + "\n").encode("utf-8")))
    write_files_atomic(files)  # one atomic group, the sidecar last: all new files or all earlier ones
    if not args.quiet:
        extra = f", {penumbra_path}" if penumbra_path else ""
        print(f"skin LUT {tables.axes.width}x{tables.axes.height} -> {out}{extra}, {json_path}", file=sys.stderr)
    return 0
