"""``BAKER_hair_shading`` (the hair material of strands, ribbons and cards, its tables embedded once per glTF file:
:mod:`baker.techniques.hair_shading.material`) and the files of the hair fibre tables, written by ``baker hair-lut`` and read back into
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

LONGITUDINAL_FILE = "hair_longitudinal.exr"
AZIMUTHAL_FILE = "hair_azimuthal.exr"
DUAL_FILE = "hair_dual_scattering.exr"
SIDECAR_FILE = "hair_lut.json"


def sidecar(tables, options, dual=None) -> dict:
    from baker.techniques.hair_shading.kernel import azimuthal_scale, longitudinal_variances, sigma_a_from_melanin

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


def lut_files(tables, options, dual=None) -> list[tuple[str, bytes]]:
    """(file name, bytes) of the tables (and Zinke's, if given) and the sidecar, the sidecar last."""
    from baker.gltf.images import encode_image

    files = [(LONGITUDINAL_FILE, encode_image(tables.longitudinal.astype(np.float16), ".exr")),
             (AZIMUTHAL_FILE, encode_image(tables.azimuthal.astype(np.float16), ".exr"))]
    if dual is not None:
        files.append((DUAL_FILE, encode_image(dual.table.astype(np.float16), ".exr")))
    return files + [(SIDECAR_FILE, (json.dumps(sidecar(tables, options, dual), indent=2) + "\n").encode("utf-8"))]


def read_lut(folder):
    """The tables (:class:`~baker.techniques.hair_shading.tables.HairTables`) a ``baker hair-lut`` folder holds, as
    a shader samples them (half float, widened)."""
    from baker.gltf.images import read_image
    from baker.techniques.hair_shading.tables import HairTables

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


# ------------------------------------------------------------------------------------------------ BAKER_hair_shading
NAME = "BAKER_hair_shading"
OCCLUSION = "_HAIR_OCCLUSION"
MELANIN = "_HAIR_MELANIN"
FIBRES_POSITIVE = "_HAIR_FIBRES_POS"
FIBRES_NEGATIVE = "_HAIR_FIBRES_NEG"
VERTEX_ATTRIBUTES = {OCCLUSION: 1, MELANIN: 2, FIBRES_POSITIVE: 3, FIBRES_NEGATIVE: 3}
TABLE_CHANNELS = 4  # RGBA everywhere: WebGPU has no three-channel half-float format
TABLE_KEYS = ("longitudinal", "azimuthal", "dualScattering")
# what a table's rows and columns are (the schema and README say the same; hair_lut.json too)
TABLE_AXES = {
    "longitudinal": "rows theta_o' (row 0 = -pi/2), columns theta_i (column 0 = -pi/2); RGBA = M_R, M_TT, M_TRT, 0",
    "azimuthal": "slices x thetaSize rows (row = slice * thetaSize + |theta_o| index, 0 .. pi/2), columns |phi| "
                 "(0 .. pi); RGBA = A_R N_R, A_TT N_TT, A_TRT N_TRT, A_residual / (2 pi)",
    "dualScattering": "rows = absorption slice (as the azimuthal table's), columns |theta| (0 .. pi/2); RGBA = a_f, "
                      "a_b, alpha_b, beta_b",
}


def table_texels(table: np.ndarray) -> np.ndarray:
    """An (H, W, C <= 4) float table as the extension stores it: (H W, 4) uint16, the bits of RGBA half floats,
    row 0 first (written little-endian as a VEC4 UNSIGNED_SHORT accessor)."""
    table = np.asarray(table, np.float32)
    out = np.zeros(table.shape[:2] + (TABLE_CHANNELS,), np.float16)
    out[..., :table.shape[2]] = table
    return out.reshape(-1, TABLE_CHANNELS).view(np.uint16)


def add_tables(doc, tables, dual, alpha: float) -> int:
    """The index in the root ``BAKER_hair_shading.tables`` of the table set for (beta_m, beta_n, eta, alpha),
    appended (three accessors) unless the document already holds it: each set once per file."""
    root = doc.json.setdefault("extensions", {}).setdefault(NAME, {"tables": []})
    sets = root["tables"]
    key = {"betaM": float(tables.beta_m), "betaN": float(tables.beta_n), "eta": float(tables.eta),
           "alpha": float(alpha)}
    for i, entry in enumerate(sets):
        if all(entry.get(k) == v for k, v in key.items()):
            return i
    entry = table_entry(doc, key, tables.longitudinal, tables.azimuthal, dual.table, tables.slices, tables.n_theta,
                        dual.alpha_f, dual.beta_f)
    sets.append(entry)
    doc.use_extension(NAME)
    return len(sets) - 1


def table_entry(doc, key: dict, m, n, d, slices: int, theta_size: int, alpha_f: float, beta_f: float) -> dict:
    """A root table set: ``key`` (betaM, betaN, eta, alpha) and the three tables as accessors of ``doc``."""
    d = np.asarray(d).reshape(np.shape(d)[0], np.shape(d)[1], -1)
    entry = dict(key)

    def texels(table) -> int:
        return doc.add_accessor(table_texels(table), target=None)

    entry["longitudinal"] = {"accessor": texels(m), "width": int(m.shape[1]), "height": int(m.shape[0])}
    entry["azimuthal"] = {"accessor": texels(n), "width": int(n.shape[1]), "height": int(n.shape[0]),
                          "slices": int(slices), "thetaSize": int(theta_size)}
    entry["dualScattering"] = {"accessor": texels(d), "width": int(d.shape[1]), "height": int(d.shape[0]),
                               "alphaF": float(alpha_f), "betaF": float(beta_f)}
    return entry


_TABLE_CACHE: dict = {}  # (beta_m, beta_n, eta, alpha) -> (HairTables, DualScatteringTable): one bake per setting


def baked_tables(beta_m: float, beta_n: float, eta: float, alpha: float):
    """(HairTables, DualScatteringTable) at ``baker hair-lut``'s default sizes, baked once per process."""
    from baker.techniques.hair_shading.tables import bake_tables, dual_scattering_table

    key = (float(beta_m), float(beta_n), float(eta), float(alpha))
    if key not in _TABLE_CACHE:
        _TABLE_CACHE[key] = (bake_tables(*key[:3]), dual_scattering_table(*key))
    return _TABLE_CACHE[key]


def material_extension(doc, options, *, melanin: bool = False, occlusion: dict | None = None,
                       fibre_count: dict | None = None) -> dict:
    """The ``BAKER_hair_shading`` object of a hair material (``options``: a
    :class:`~baker.techniques.hair_shading.options.HairMaterialOptions`), its tables added to ``doc`` once.
    ``melanin``: the primitives carry ``_HAIR_MELANIN``; ``occlusion``/``fibre_count``: what the strands' rest-pose
    precompute recorded (:func:`baker.techniques.hair_shading.occlusion.strand_occlusion`)."""
    from baker.techniques.hair_shading.kernel import sigma_a_from_color, sigma_a_from_melanin

    beta_m, beta_n = (float(x) for x in options.roughness)
    tables, dual = baked_tables(beta_m, beta_n, options.eta, options.tilt)
    ext = {"tables": add_tables(doc, tables, dual, options.tilt)}
    if options.rgb is not None:
        ext["color"] = [float(c) for c in options.rgb]
        sigma = sigma_a_from_color(options.rgb, beta_n)
    else:
        ext["eumelanin"] = float(options.eumelanin)
        ext["pheomelanin"] = float(options.pheomelanin)
        sigma = sigma_a_from_melanin(options.eumelanin, options.pheomelanin)
    ext.update({"sigmaA": [float(x) for x in sigma], "betaM": beta_m, "betaN": beta_n, "alpha": float(options.tilt),
                "eta": float(options.eta)})
    if melanin:
        ext["melaninAttribute"] = MELANIN
    if occlusion is not None:
        ext["occlusion"] = dict(occlusion)
    if fibre_count is not None:
        ext["fibreCount"] = dict(fibre_count)
    return ext


def add_hair_material(doc, options, name: str = "baker_hair", **kwargs) -> int:
    """A hair material (base colour: the fibres' multiply scattered colour, for viewers without the extension)
    carrying ``BAKER_hair_shading``; returns its index."""
    ext = material_extension(doc, options, **kwargs)
    materials = doc.json.setdefault("materials", [])
    materials.append({"name": name, "pbrMetallicRoughness": {
        "baseColorFactor": [float(c) for c in fibre_color(ext["sigmaA"], ext["betaN"])] + [1.0],
        "metallicFactor": 0.0, "roughnessFactor": 0.6}, "extensions": {NAME: ext}})
    doc.use_extension(NAME)
    return len(materials) - 1


def fibre_color(sigma_a, beta_n: float) -> np.ndarray:
    """The linear colour whose Chiang et al. 2016 inversion is ``sigma_a`` (the forward map, in [0, 1])."""
    b = beta_n
    denom = 5.969 - 0.215 * b + 2.532 * b ** 2 - 10.73 * b ** 3 + 5.574 * b ** 4 + 0.245 * b ** 5
    return np.clip(np.exp(-np.sqrt(np.maximum(np.asarray(sigma_a, float), 0.0)) * denom), 0.0, 1.0)


def read_table(doc, entry: dict, key: str) -> np.ndarray:
    """One table of a root table set as float32 (H, W, 4): its accessor's uint16 values as half floats."""
    spec = entry[key]
    bits = np.ascontiguousarray(doc.accessor(spec["accessor"]), np.uint16)
    return bits.view(np.float16).astype(np.float32).reshape(spec["height"], spec["width"], TABLE_CHANNELS)


def read_tables(doc, index: int):
    """(HairTables, DualScatteringTable) of root table set ``index`` as stored (half float, widened)."""
    from baker.techniques.hair_shading.tables import DualScatteringTable, HairTables

    entry = doc.json["extensions"][NAME]["tables"][index]
    m = read_table(doc, entry, "longitudinal")[..., :3]
    n = read_table(doc, entry, "azimuthal")
    d = read_table(doc, entry, "dualScattering")
    return (HairTables(np.ascontiguousarray(m), n, float(entry["betaM"]), float(entry["betaN"]), float(entry["eta"]),
                       int(entry["azimuthal"]["slices"])),
            DualScatteringTable(d, float(entry["dualScattering"]["alphaF"]), float(entry["dualScattering"]["betaF"])))


# ---------------------------------------------------------------------------------------------------------- validate
PARAMETER_RANGES = {"eumelanin": (0.0, 50.0), "pheomelanin": (0.0, 50.0), "betaM": (0.05, 1.0),
                    "betaN": (0.05, 1.0), "alpha": (-10.0, 10.0), "eta": (1.01, 3.0)}


def check(doc, places: list, issues) -> None:
    """Semantic rules of BAKER_hair_shading (``baker validate``): on the root, every table's accessor holds
    exactly width x height UNSIGNED_SHORT VEC4 (half-float bits), the azimuthal table is slices x thetaSize rows and the dual-scattering
    table one row per slice, every texel finite, the lobes and fractions >= 0; on a material, the table set exists,
    the parameters are in range, colour or melanin (not both), and the attributes it names are on the primitives
    drawn with it, finite, occlusion in [0, 1], melanin and fibre counts >= 0."""
    from baker.checks import is_index, is_number, pointer

    table_sets = []
    for parts, ext in places:
        if parts == () and isinstance(ext, dict) and isinstance(ext.get("tables"), list):
            table_sets = ext["tables"]
            for i, entry in enumerate(table_sets):
                if isinstance(entry, dict):
                    check_table_set(doc, entry, pointer("extensions", NAME, "tables", i), issues)
    for parts, ext in places:
        if not (len(parts) == 2 and parts[0] == "materials" and isinstance(ext, dict)):
            continue
        material = parts[1]
        ptr = pointer("materials", material, "extensions", NAME)
        if not is_index(ext.get("tables"), table_sets):
            issues.error("BAKER_HAIR_SHADING_TABLES", f"tables {ext.get('tables')!r} is not an entry of the root "
                         f"{NAME}.tables ({len(table_sets)} sets)", ptr + "/tables")
        else:
            entry = table_sets[ext["tables"]]
            for key in ("betaM", "betaN", "eta", "alpha"):
                if is_number(ext.get(key)) and is_number(entry.get(key)) and abs(ext[key] - entry[key]) > 1e-6:
                    issues.error("BAKER_HAIR_SHADING_TABLES", f"{key} {ext[key]} differs from the tables' "
                                 f"{entry[key]} (they are baked for it)", ptr + "/" + key)
        for key, (lo, hi) in PARAMETER_RANGES.items():
            value = ext.get(key)
            if value is not None and not (is_number(value) and lo <= value <= hi):
                issues.error("BAKER_HAIR_SHADING_RANGE", f"{key} must be a number in [{lo}, {hi}], got {value!r}",
                             ptr + "/" + key)
        if "color" in ext and ("eumelanin" in ext or "pheomelanin" in ext):
            issues.error("BAKER_HAIR_SHADING_ABSORPTION", "give color or melanin, not both", ptr)
        sigma = ext.get("sigmaA")
        if isinstance(sigma, list) and not all(is_number(x) and x >= 0 for x in sigma):
            issues.error("BAKER_HAIR_SHADING_RANGE", "sigmaA must be three finite numbers >= 0", ptr + "/sigmaA")
        attributes = {}
        if isinstance(ext.get("melaninAttribute"), str):
            attributes[ext["melaninAttribute"]] = (2, 0.0, None)
        if isinstance(ext.get("occlusion"), dict) and isinstance(ext["occlusion"].get("attribute"), str):
            attributes[ext["occlusion"]["attribute"]] = (1, 0.0, 1.0)
        fibres = ext.get("fibreCount")
        if isinstance(fibres, dict):
            for name in (fibres.get("positive"), fibres.get("negative")):
                if isinstance(name, str):
                    attributes[name] = (3, 0.0, None)
        check_material_attributes(doc, material, attributes, issues)


def check_table_set(doc, entry: dict, ptr: str, issues) -> None:
    from baker.checks import is_count, is_index

    accessors = doc.json.get("accessors") or []
    sizes = {}
    for key in TABLE_KEYS:
        spec = entry.get(key)
        if not isinstance(spec, dict):
            continue  # the schema pass reports it
        w, h, a = spec.get("width"), spec.get("height"), spec.get("accessor")
        if not (is_count(w, 2) and is_count(h, 2)):
            continue
        sizes[key] = (w, h)
        if not is_index(a, accessors):
            issues.error("UNRESOLVED_REFERENCE", f"accessor {a!r} does not exist", f"{ptr}/{key}/accessor")
            continue
        acc = accessors[a]
        if acc.get("componentType") != 5123 or acc.get("type") != "VEC4" or acc.get("normalized") \
                or acc.get("count") != w * h:
            issues.error("BAKER_HAIR_SHADING_TABLE_SIZE", f"accessor {a} is {acc.get('count')} "
                         f"{acc.get('componentType')} {acc.get('type')}, the {key} table of {w} x {h} texels needs "
                         f"{w * h} UNSIGNED_SHORT (5123) VEC4 (half-float bits)", f"{ptr}/{key}")
            continue
        try:
            texels = read_table(doc, entry, key)
        except (ValueError, IndexError, TypeError):
            issues.error("BAKER_HAIR_SHADING_TABLE_SIZE", f"the {key} table cannot be read from accessor {a}",
                         f"{ptr}/{key}")
            continue
        if not np.isfinite(texels).all():
            issues.error("BAKER_HAIR_SHADING_TABLE_NOT_FINITE", f"{int((~np.isfinite(texels)).sum())} texels of the "
                         f"{key} table are NaN or infinite", f"{ptr}/{key}")
            continue
        signed = [2] if key == "dualScattering" else []  # alpha_b, a longitudinal shift, may be negative
        unsigned = [c for c in range(TABLE_CHANNELS) if c not in signed]
        if (texels[..., unsigned] < 0).any():
            issues.error("BAKER_HAIR_SHADING_TABLE_NEGATIVE", f"the {key} table holds negative lobes or fractions",
                         f"{ptr}/{key}")
    azimuthal = entry.get("azimuthal") if isinstance(entry.get("azimuthal"), dict) else {}
    slices, theta = azimuthal.get("slices"), azimuthal.get("thetaSize")
    if "azimuthal" in sizes and is_count(slices, 2) and is_count(theta, 2) and sizes["azimuthal"][1] != slices * theta:
        issues.error("BAKER_HAIR_SHADING_TABLE_SIZE", f"the azimuthal table has {sizes['azimuthal'][1]} rows, not "
                     f"slices x thetaSize = {slices * theta}", f"{ptr}/azimuthal/height")
    if "dualScattering" in sizes and is_count(slices, 2) and sizes["dualScattering"][1] != slices:
        issues.error("BAKER_HAIR_SHADING_TABLE_SIZE", f"the dual-scattering table has {sizes['dualScattering'][1]} "
                     f"rows, not one per absorption slice ({slices})", f"{ptr}/dualScattering/height")
    if "longitudinal" in sizes and sizes["longitudinal"][0] != sizes["longitudinal"][1]:
        issues.error("BAKER_HAIR_SHADING_TABLE_SIZE", "the longitudinal table must be square (theta_i and theta_o' "
                     "share the axis)", f"{ptr}/longitudinal")


def check_material_attributes(doc, material: int, attributes: dict, issues) -> None:
    """Each named attribute on every primitive drawn with ``material``: present, finite, in its range."""
    from baker.checks import check_vertex_attribute, pointer

    if not attributes:
        return
    for m, mesh in enumerate(doc.json.get("meshes") or []):
        for p, prim in enumerate(mesh.get("primitives") or []):
            if prim.get("material") != material:
                continue
            for name, (width, lo, hi) in attributes.items():
                values = check_vertex_attribute(doc, m, p, name, issues, code="BAKER_HAIR_SHADING", width=width)
                if values is None or not np.isfinite(values).all():
                    continue
                if (values < lo - 1e-6).any() or (hi is not None and (values > hi + 1e-6).any()):
                    issues.error("BAKER_HAIR_SHADING_RANGE", f"'{name}' must be in [{lo}, {hi if hi is not None else 'inf'}"
                                 f"{']' if hi is not None else ')'}", pointer("meshes", m, "primitives", p,
                                                                              "attributes", name))


# --------------------------------------------------------------------------------------------------------------- USD
def usd_table_data(doc, index: int) -> dict:
    """What a stage carries of root table set ``index`` (``baker:hair_shading:tableData:*``): the set's numbers and
    each table's texels (RGBA, row 0 first) with its size."""
    entry = doc.json["extensions"][NAME]["tables"][index]
    out = {k: entry[k] for k in ("betaM", "betaN", "eta", "alpha")}
    for key in TABLE_KEYS:
        spec = {k: v for k, v in entry[key].items() if k != "accessor"}
        spec["texels"] = read_table(doc, entry, key)
        out[key] = spec
    return out


def write_usd_table_data(prim, data: dict) -> None:
    """``data`` (:func:`usd_table_data`) as custom attributes of a material prim: ``half[]`` texels, the rest
    typed as every other extension field."""
    from pxr import Sdf, Vt

    from baker.gltf.usd import custom_attributes

    ns = "baker:hair_shading:tableData"
    custom_attributes(prim, ns, {k: v for k, v in data.items() if k not in TABLE_KEYS})
    for key in TABLE_KEYS:
        spec = dict(data[key])
        texels = np.asarray(spec.pop("texels"), np.float16).reshape(-1)
        prim.CreateAttribute(f"{ns}:{key}:texels", Sdf.ValueTypeNames.HalfArray, custom=True).Set(
            Vt.HalfArray.FromNumpy(texels))
        custom_attributes(prim, f"{ns}:{key}", spec)


def from_usd(doc, material: int, params: dict) -> None:
    """A stage read back (:mod:`baker.readers.usd_baked`): the material's ``tableData`` becomes a root table set
    (accessors, once per file) and ``tables`` its index."""
    data = params.pop("tableData", None)
    if not isinstance(data, dict):
        return
    key = {k: float(data[k]) for k in ("betaM", "betaN", "eta", "alpha")}
    root = doc.json.setdefault("extensions", {}).setdefault(NAME, {"tables": []})
    for i, entry in enumerate(root["tables"]):
        if all(entry.get(k) == v for k, v in key.items()):
            params["tables"] = i
            return
    arrays = {}
    for name in TABLE_KEYS:
        spec = data[name]
        arrays[name] = np.asarray(spec["texels"], np.float32).reshape(int(spec["height"]), int(spec["width"]),
                                                                      TABLE_CHANNELS)
    azimuthal, dual = data["azimuthal"], data["dualScattering"]
    root["tables"].append(table_entry(doc, key, arrays["longitudinal"], arrays["azimuthal"],
                                      arrays["dualScattering"], int(azimuthal["slices"]),
                                      int(azimuthal["thetaSize"]), float(dual["alphaF"]), float(dual["betaF"])))
    doc.use_extension(NAME)
    params["tables"] = len(root["tables"]) - 1
