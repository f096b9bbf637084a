"""The hair material on USD hair prims: a ``UsdShade.Material`` (``UsdPreviewSurface`` of the fibres' colour, the
``BAKER_hair_shading`` fields as ``baker:hair_shading:*`` attributes and the tables as ``baker:hair_shading:
tableData:*``) bound to the strands' ``BasisCurves``, and their per-vertex data as ``primvars:baker:hair_*``."""
from __future__ import annotations

import numpy as np

from baker.techniques.hair_shading.extension import fibre_color, material_extension, usd_table_data, \
    write_usd_table_data


def material_prim_path(stage, name: str) -> str:
    stage.DefinePrim("/Root/Materials", "Scope")
    path, k = f"/Root/Materials/{name}", 1
    while stage.GetPrimAtPath(path):
        path, k = f"/Root/Materials/{name}_{k}", k + 1
    return path


def define_hair_material(stage, ext_doc, ext: dict, name: str = "baker_hair"):
    """A Material carrying ``ext`` (a ``BAKER_hair_shading`` object whose tables ``ext_doc`` holds)."""
    from pxr import Gf, Sdf, UsdShade

    from baker.gltf.usd import custom_attributes, usd_parameters

    path = material_prim_path(stage, name)
    material = UsdShade.Material.Define(stage, path)
    surface = UsdShade.Shader.Define(stage, f"{path}/PreviewSurface")
    surface.CreateIdAttr("UsdPreviewSurface")
    surface.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).Set(
        Gf.Vec3f(*map(float, fibre_color(ext["sigmaA"], ext["betaN"]))))
    surface.CreateInput("metallic", Sdf.ValueTypeNames.Float).Set(0.0)
    surface.CreateInput("roughness", Sdf.ValueTypeNames.Float).Set(0.6)
    material.CreateSurfaceOutput().ConnectToSource(surface.ConnectableAPI(), "surface")
    prim = material.GetPrim()
    custom_attributes(prim, "baker:hair_shading", usd_parameters({k: v for k, v in ext.items() if k != "tables"}))
    write_usd_table_data(prim, usd_table_data(ext_doc, ext["tables"]))
    return material


def write_strand_material(stage, curve_paths, options, attributes, kwargs) -> None:
    """Bind the strands' hair material to each ``BasisCurves`` of ``curve_paths`` and write its ``attributes``
    ({name: per-vertex values}, one dict per path) as vertex primvars; ``kwargs``: what
    :func:`~baker.techniques.hair_shading.strands.strand_attributes` returned for the material."""
    from pxr import Sdf, UsdGeom, UsdShade, Vt

    from baker.gltf.document import GltfDocument
    from baker.gltf.usd import primvar_name

    scratch = GltfDocument()
    kwargs = dict(kwargs)
    ext = material_extension(scratch, options, fibre_count=kwargs.pop("fibreCount", None), **kwargs)
    material = define_hair_material(stage, scratch, ext)
    types = {1: (Sdf.ValueTypeNames.FloatArray, Vt.FloatArray), 2: (Sdf.ValueTypeNames.Float2Array, Vt.Vec2fArray),
             3: (Sdf.ValueTypeNames.Float3Array, Vt.Vec3fArray)}
    for path, attrs in zip(curve_paths, attributes):
        prim = stage.GetPrimAtPath(path)
        UsdShade.MaterialBindingAPI.Apply(prim).Bind(material)
        api = UsdGeom.PrimvarsAPI(prim)
        for name, values in attrs.items():
            values = np.asarray(values, np.float32)
            width = 1 if values.ndim == 1 else values.shape[1]
            type_name, array = types[width]
            api.CreatePrimvar(primvar_name(name)[len("primvars:"):], type_name, UsdGeom.Tokens.vertex).Set(
                array.FromNumpy(np.ascontiguousarray(values)))
