"""The files of ``baker skin-lut -o OUT`` (:func:`baker.techniques.skin.step.run_skin_lut`): Penner's pre-integrated
skin LUT (and penumbra LUT) as images, and a JSON sidecar with the axes, units, profile, Jimenez separable kernel and
d'Eon Gaussian blur weights.

OUT's suffix picks the format: ``.exr`` (32-bit float, linear), ``.png`` (``--skin-bits`` 16 or 8, ``--skin-encoding``
linear or srgb). The penumbra LUT goes to ``<stem>_penumbra<suffix>``, the sidecar to ``<stem>.json``.
"""
from __future__ import annotations

import numpy as np

from baker.techniques.skin.kernel import quantize
from baker.techniques.skin.options import SkinOptions

SUFFIXES = (".exr", ".png")


def lut_pixels(values: np.ndarray, suffix: str, options: SkinOptions) -> np.ndarray:
    """A LUT's values as the image type of ``suffix`` stores them (EXR float32, or PNG integers)."""
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
