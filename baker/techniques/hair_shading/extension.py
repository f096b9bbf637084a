"""The files of the hair fibre tables, written by ``baker hair-lut`` and read back into
:class:`~baker.techniques.hair_shading.tables.HairTables` (the layout ``BAKER_hair_shading`` will embed):

- ``hair_longitudinal.exr``: the M table, RGB half float, row 0 (top) is theta_o' = -pi/2, column 0 theta_i = -pi/2;
- ``hair_azimuthal.exr``: the N table, RGBA half float, ``slices`` stacked blocks of ``thetaSize`` rows (row 0 of a
  block is theta_o = 0), column 0 is phi = 0;
- ``hair_dual_scattering.exr``: Zinke et al. 2008's per-fibre averages, RGBA half float (a_f, a_b, alpha_b,
  beta_b), row = absorption slice, column = |theta|;
- ``hair_lut.json``: axes, encodings, the model's parameters and how a shader combines the two.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from baker.errors import BakerError
from baker.techniques.hair_shading.kernel import longitudinal_variances, azimuthal_scale, sigma_a_from_melanin
from baker.techniques.hair_shading.tables import HairTables

LONGITUDINAL_FILE = "hair_longitudinal.exr"
AZIMUTHAL_FILE = "hair_azimuthal.exr"
DUAL_FILE = "hair_dual_scattering.exr"
SIDECAR_FILE = "hair_lut.json"


def sidecar(tables: HairTables, options, dual=None) -> dict:
    m_size = tables.longitudinal.shape[0]
    return {
        "generator": "baker hair-lut",
        "technique": "Chiang et al. 2016 far-field hair fibre scattering as pbrt-v3/v4's HairBxDF (d'Eon et al. 2011 "
                     "M_p, trimmed logistic N_p, p = R, TT, TRT + residual), averaged over the fibre offset h; "
                     "RTR4 14.7.2",
        "frame": "sin theta = dot(w, tangent); phi = angle between light and view projected on the normal plane; "
                 "S(view, light) = sum_p M_p N_p + M_residual N_residual, integral over light directions (d omega, "
                 "no cosine) = the fibre's albedo",
        "parameters": {"betaM": tables.beta_m, "betaN": tables.beta_n, "eta": tables.eta, "alpha": options.alpha,
                       "alphaUnit": "degree", "eumelanin": options.eumelanin, "pheomelanin": options.pheomelanin,
                       "sigmaA": [float(x) for x in sigma_a_from_melanin(options.eumelanin, options.pheomelanin)],
                       "sigmaAUnit": "per fibre radius",
                       "longitudinalVariance": [float(x) for x in longitudinal_variances(tables.beta_m)],
                       "azimuthalScale": float(azimuthal_scale(tables.beta_n)),
                       "eumelaninSigmaA": [0.419, 0.697, 1.37], "pheomelaninSigmaA": [0.187, 0.4, 1.05],
                       "offsets": int(options.offsets)},
        "longitudinal": {
            "file": LONGITUDINAL_FILE, "format": "exr-half", "width": m_size, "height": m_size,
            "channels": ["M_R", "M_TT", "M_TRT"],
            "u": {"quantity": "theta_i", "unit": "rad", "range": [-math.pi / 2, math.pi / 2],
                  "mapping": "u = theta_i / pi + 0.5"},
            "v": {"quantity": "theta_o' (theta_o tilted per lobe)", "unit": "rad", "range": [-math.pi / 2, math.pi / 2],
                  "mapping": "v = asin(sin theta_o') / pi + 0.5; R: sin theta_o' = sin(theta_o - 2 alpha), TT: "
                             "sin(theta_o + alpha), TRT: sin(theta_o + 4 alpha); the residual reads M_TRT at the "
                             "untilted theta_o"},
        },
        "azimuthal": {
            "file": AZIMUTHAL_FILE, "format": "exr-half", "width": int(tables.azimuthal.shape[1]),
            "height": int(tables.azimuthal.shape[0]), "slices": tables.slices, "thetaSize": tables.n_theta,
            "channels": ["A_R N_R", "A_TT N_TT", "A_TRT N_TRT", "A_residual / (2 pi)"],
            "u": {"quantity": "|phi|", "unit": "rad", "range": [0.0, math.pi], "mapping": "u = |phi| / pi"},
            "v": {"quantity": "|theta_o|", "unit": "rad", "range": [0.0, math.pi / 2],
                  "mapping": "row = slice * thetaSize + t * (thetaSize - 1), t = |theta_o| / (pi / 2)"},
            "slice": {"quantity": "sigma_a of the colour channel", "mapping": "x = 1 - exp(-sigma_a / 2); slice = "
                      "x * (slices - 1), linear between the two nearest slices (one lookup per colour channel)"},
        },
        "dualScattering": None if dual is None else {
            "technique": "Zinke et al. 2008, Dual Scattering Approximation for Fast Multiple Scattering in Hair",
            "file": DUAL_FILE, "format": "exr-half", "width": int(dual.table.shape[1]),
            "height": int(dual.table.shape[0]),
            "channels": ["a_f", "a_b", "alpha_b", "beta_b"],
            "meaning": "a_f, a_b: fraction of light one fibre scatters into the forward (|phi| > pi/2) and backward "
                       "half; alpha_b, beta_b (rad): longitudinal shift and width of the backward lobe (R and TRT "
                       "weighted by their backward fractions); forward shift and width are TT's (alphaF, betaF)",
            "alphaF": dual.alpha_f, "betaF": dual.beta_f,
            "u": {"quantity": "|theta|", "unit": "rad", "range": [0.0, math.pi / 2], "mapping": "u = |theta| / (pi / 2)"},
            "v": {"quantity": "sigma_a of the colour channel", "mapping": "row = x * (height - 1), x = 1 - exp(-sigma_a "
                  "/ 2) (the azimuthal table's slices)"},
        },
        "texels": "endpoint-aligned: texel i is at t = i / (size - 1); sample at (t * (size - 1) + 0.5) / size "
                  "with linear filtering",
    }


def lut_files(tables: HairTables, options, dual=None) -> list[tuple[str, bytes]]:
    """(file name, bytes) of the tables (and Zinke's, if given) and the sidecar, the sidecar last."""
    from baker.gltf.images import encode_image

    files = [(LONGITUDINAL_FILE, encode_image(tables.longitudinal.astype(np.float16), ".exr")),
             (AZIMUTHAL_FILE, encode_image(tables.azimuthal.astype(np.float16), ".exr"))]
    if dual is not None:
        files.append((DUAL_FILE, encode_image(dual.table.astype(np.float16), ".exr")))
    return files + [(SIDECAR_FILE, (json.dumps(sidecar(tables, options, dual), indent=2) + "\n").encode("utf-8"))]


def read_lut(folder) -> HairTables:
    """The tables a ``baker hair-lut`` folder holds, as a shader samples them (half float, widened)."""
    from baker.gltf.images import read_image

    folder = Path(folder)
    path = folder / SIDECAR_FILE
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
        params, lon, azi = doc["parameters"], doc["longitudinal"], doc["azimuthal"]
        m = read_image(folder / lon["file"]).astype(np.float32)
        n = read_image(folder / azi["file"]).astype(np.float32)
        slices = int(azi["slices"])
        beta_m, beta_n, eta = float(params["betaM"]), float(params["betaN"]), float(params["eta"])
    except OSError as exc:
        raise BakerError(path, f"cannot read the hair tables: {exc.strerror or exc}") from None
    except (ValueError, KeyError, TypeError) as exc:
        raise BakerError(path, f"not a baker hair-lut sidecar: {type(exc).__name__} {exc}") from None
    if m.shape != (lon["height"], lon["width"], 3) or n.shape != (azi["height"], azi["width"], 4) \
            or slices < 2 or n.shape[0] % slices:
        raise BakerError(path, f"/azimuthal: table sizes {m.shape}, {n.shape} disagree with the sidecar")
    return HairTables(m, n, beta_m, beta_n, eta, slices)
