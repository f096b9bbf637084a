"""``BAKER_curvature``: per-vertex curvature attributes (and an optional texture) -> glTF, and their checks.

Where the data goes (see ``schemas/BAKER_curvature/README.md``):
- primitive attributes (FLOAT SCALAR / VEC2 / VEC3 in the ``native`` layout, all FLOAT VEC3 in the ``blender`` one:
  :mod:`baker.gltf.vertex_attributes`): ``_CURVATURE`` (mean curvature H, x), ``_PRINCIPAL_CURVATURES`` (k1 >= k2,
  x, y) and ``_PRINCIPAL_DIRECTION`` (unit tangent of k1), curvatures in 1 / mesh units, convex positive;
- optionally ``BAKER_curvature.curvatureTexture``: H per texel, remapped from ``textureRange`` to [0, 1];
- ``BAKER_curvature`` on the material: how it was baked and which attributes hold what.
USD gets ``primvars:baker:curvature``, ``primvars:baker:principal_curvatures``, ``primvars:baker:principal_direction``
through the generic custom-attribute path of :mod:`baker.gltf.usd`.
"""
from __future__ import annotations

import math

from dataclasses import dataclass

import numpy as np

from baker.gltf.document import GltfDocument
from baker.gltf.images import encode_image
from baker.gltf.vertex_attributes import add_vertex_attribute

NAME = "BAKER_curvature"
ATTRIBUTE = "_CURVATURE"
PRINCIPAL = "_PRINCIPAL_CURVATURES"
DIRECTION = "_PRINCIPAL_DIRECTION"
VERTEX_ATTRIBUTES = {ATTRIBUTE: 1, PRINCIPAL: 2, DIRECTION: 3}  # name -> the data's width (baker.registry)


def write_vertex_curvature(doc: GltfDocument, mesh: int, primitive: int, mean: np.ndarray,
                           principal: np.ndarray | None = None, direction: np.ndarray | None = None) -> dict:
    """Add the curvature attributes to one primitive; returns {attribute name: accessor index}."""
    attrs = doc.json["meshes"][mesh]["primitives"][primitive]["attributes"]
    written = {ATTRIBUTE: add_vertex_attribute(doc, mesh, attrs, ATTRIBUTE, mean, min_max=True,
                                               leave_out="--curvature-per-vertex false")}
    if principal is not None:
        written[PRINCIPAL] = add_vertex_attribute(doc, mesh, attrs, PRINCIPAL, principal, min_max=True,
                                                  leave_out="--curvature-directions false")
    if direction is not None:
        written[DIRECTION] = add_vertex_attribute(doc, mesh, attrs, DIRECTION, direction,
                                                  leave_out="--curvature-directions false")
    return written


def encode_curvature_texture(curvature: np.ndarray, bits: int) -> tuple[bytes, list]:
    """(H, W) mean curvature -> grayscale PNG remapped so [lo, hi] -> [0, 1]; returns (png, [lo, hi])."""
    lo = float(curvature.min()) if curvature.size else 0.0
    hi = float(curvature.max()) if curvature.size else 0.0
    if hi <= lo:
        hi = lo + 1.0
    scale = (1 << bits) - 1
    q = np.clip(np.rint((curvature - lo) / (hi - lo) * scale), 0, scale)
    return encode_image(q.astype(np.uint16 if bits == 16 else np.uint8), ".png"), [lo, hi]


def add_curvature_texture(doc: GltfDocument, material: int, png: bytes) -> int:
    image = doc.add_image(png, "image/png", f"curvature_m{material}")
    return doc.add_texture(image, sampler={"magFilter": 9729, "minFilter": 9987},
                           name=f"baker curvature (material {material})")


def write_material_parameters(doc: GltfDocument, material: int, *, options, value_range: list,
                              mean_curvature: float, per_vertex: bool, directions: bool,
                              texture: int | None = None, texcoord: int = 0, texture_range: list | None = None) -> dict:
    ext = {
        "method": options.fit,
        "smoothingPasses": int(options.smoothing),
        "range": [float(value_range[0]), float(value_range[1])],
        "meanCurvature": float(mean_curvature),
    }
    if options.radius:
        ext["radius"] = float(options.radius)
    else:
        ext["rings"] = int(options.rings)
    if per_vertex:
        ext["attribute"] = ATTRIBUTE
        if directions:
            ext["principalCurvaturesAttribute"] = PRINCIPAL
            ext["principalDirectionAttribute"] = DIRECTION
    if texture is not None:
        info = {"index": int(texture)}
        if texcoord:
            info["texCoord"] = int(texcoord)
        ext["curvatureTexture"] = info
        ext["textureRange"] = [float(texture_range[0]), float(texture_range[1])]
    return doc.set_material_extension(material, NAME, ext)


def check(doc: GltfDocument, places: list, issues) -> None:
    """Semantic rules of BAKER_curvature: named attributes exist with the right types, agree with each other
    (H = (k1 + k2) / 2, k1 >= k2, unit directions) and with ``range``; the texture's UV set exists."""
    from baker.checks import (check_vertex_attribute, is_index, is_number, material_extensions, pointer,
                              primitives_using, stored_resolution)

    gltf = doc.json
    for material, ext, ext_ptr in material_extensions(places, NAME):
        users = list(primitives_using(gltf, material))
        if not users:
            issues.info("BAKER_CURVATURE_UNUSED", "no triangle primitive uses this material", ext_ptr)
        value_range = ext.get("range")
        ranged = isinstance(value_range, list) and len(value_range) == 2 and all(map(is_number, value_range))
        if ranged and value_range[0] > value_range[1]:
            issues.error("BAKER_CURVATURE_RANGE", f"range {value_range} is reversed", ext_ptr + "/range")
            ranged = False
        for m, p, prim in users:
            mean = principal = None
            name = ext.get("attribute")
            if isinstance(name, str):
                mean = check_vertex_attribute(doc, m, p, name, issues, code="BAKER_CURVATURE")
                if mean is not None and ranged and len(mean):
                    span = max(abs(value_range[0]), abs(value_range[1]), 1e-30)
                    finite = mean[np.isfinite(mean)]
                    if len(finite) and (finite.min() < value_range[0] - 1e-4 * span
                                        or finite.max() > value_range[1] + 1e-4 * span):
                        issues.warning("BAKER_CURVATURE_OUTSIDE_RANGE", f"values span [{finite.min():g}, "
                                       f"{finite.max():g}], outside range {value_range}",
                                       pointer("accessors", prim["attributes"][name]))
            name = ext.get("principalCurvaturesAttribute")
            if isinstance(name, str):
                principal = check_vertex_attribute(doc, m, p, name, issues, code="BAKER_CURVATURE", width=2)
                if principal is not None:
                    acc_ptr = pointer("accessors", prim["attributes"][name])
                    k1, k2 = principal[:, 0], principal[:, 1]
                    scale = max(float(np.nanmax(np.abs(principal))) if principal.size else 0.0, 1e-30)
                    # quantized forms (KHR_mesh_quantization, Draco) move each value by half its stored step
                    step = stored_resolution(doc, m, p, name, principal) + (
                        stored_resolution(doc, m, p, ext["attribute"], mean) if mean is not None else 0.0)
                    bad = int((k1 < k2 - 1e-5 * scale - step).sum())
                    if bad:
                        issues.error("BAKER_CURVATURE_ORDER", f"{bad} vertices have k1 < k2", acc_ptr)
                    if mean is not None and len(mean) == len(k1):
                        off = np.abs(mean - 0.5 * (k1 + k2)) > 1e-4 * scale + step
                        if off.any():
                            issues.error("BAKER_CURVATURE_MEAN_MISMATCH", f"{int(off.sum())} vertices have H != "
                                         "(k1 + k2) / 2", acc_ptr)
            name = ext.get("principalDirectionAttribute")
            if isinstance(name, str):
                direction = check_vertex_attribute(doc, m, p, name, issues, code="BAKER_CURVATURE", width=3)
                if direction is not None:
                    length = np.linalg.norm(direction, axis=1)
                    step = math.sqrt(3.0) * stored_resolution(doc, m, p, name, direction)
                    bad = ~((np.abs(length - 1.0) < 1e-3 + step) | (length < 1e-6 + step))
                    if bad.any():
                        issues.error("BAKER_CURVATURE_DIRECTION_NOT_UNIT", f"{int(bad.sum())} directions are neither "
                                     "unit length nor zero", pointer("accessors", prim["attributes"][name]))
        info = ext.get("curvatureTexture")
        if isinstance(info, dict) and is_index(info.get("index"), gltf.get("textures") or []):
            texcoord = info.get("texCoord", 0)
            for m, p, prim in users:
                if f"TEXCOORD_{texcoord}" not in (prim.get("attributes") or {}):
                    issues.error("BAKER_CURVATURE_TEXCOORD_MISSING", f"the curvature texture reads "
                                 f"TEXCOORD_{texcoord} but this primitive has none",
                                 pointer("meshes", m, "primitives", p, "attributes"))
            texture_range = ext.get("textureRange")
            if not (isinstance(texture_range, list) and len(texture_range) == 2
                    and all(map(is_number, texture_range)) and texture_range[0] < texture_range[1]):
                issues.error("BAKER_CURVATURE_TEXTURE_RANGE", "curvatureTexture needs textureRange [lo, hi] with "
                             "lo < hi", ext_ptr)


# ---------------------------------------------------------------------------------------------------- reading back
@dataclass(frozen=True)
class CurvatureMaterial:
    """``BAKER_curvature`` of one material as read back (signed mean curvature, 1 / mesh units)."""

    method: str | None = None
    smoothing_passes: int = 0
    range: tuple = (0.0, 0.0)  # (min, max) of the baked values
    mean_curvature: float | None = None
    radius: float | None = None  # neighbourhood radius (mesh units), or ``rings`` of neighbours
    rings: int | None = None
    attribute: str | None = None  # ``_CURVATURE`` when baked per vertex
    principal_curvatures_attribute: str | None = None
    principal_direction_attribute: str | None = None
    curvature_texture: int | None = None
    curvature_texcoord: int = 0
    texture_range: tuple | None = None  # values at texel 0 and 1


def read(doc: GltfDocument, material: int) -> CurvatureMaterial | None:
    """What :func:`write_material_parameters` wrote on ``material``, or None without ``BAKER_curvature``."""
    ext = (doc.json.get("materials", [])[material].get("extensions") or {}).get(NAME)
    if ext is None:
        return None
    info = ext.get("curvatureTexture") or {}
    return CurvatureMaterial(
        method=ext.get("method"), smoothing_passes=int(ext.get("smoothingPasses", 0)),
        range=tuple(float(v) for v in ext.get("range", (0.0, 0.0))),
        mean_curvature=float(ext["meanCurvature"]) if "meanCurvature" in ext else None,
        radius=float(ext["radius"]) if "radius" in ext else None, rings=int(ext["rings"]) if "rings" in ext else None,
        attribute=ext.get("attribute"), principal_curvatures_attribute=ext.get("principalCurvaturesAttribute"),
        principal_direction_attribute=ext.get("principalDirectionAttribute"),
        curvature_texture=int(info["index"]) if "index" in info else None,
        curvature_texcoord=int(info.get("texCoord", 0)),
        texture_range=tuple(float(v) for v in ext["textureRange"]) if "textureRange" in ext else None)
