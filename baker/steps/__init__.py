"""The bake registry: name -> (options dataclass, step). A new technique adds one line here."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from ..bakes.thickness import ThicknessOptions
from ..bakes.tam import TamOptions
from ..bakes.toon import ToonOptions
from . import tam, toon
from . import thickness
from ..bakes.edges import EdgesOptions
from . import edges
from ..bakes.curvature import CurvatureOptions
from ..bakes.skin_lut import SkinOptions
from . import curvature, skin
from ..bakes.fur import FurOptions
from . import fur


@dataclass(frozen=True)
class BakeStep:
    name: str
    options: type
    run: Callable  # (asset, options, seed, progress) -> None
    summary: str


BAKES = {
    "thickness": BakeStep("thickness", ThicknessOptions, thickness.run,
                          "local thickness per vertex and texel (KHR_materials_volume + BAKER_thickness)"),
    "tam": BakeStep("tam", TamOptions, tam.run, "tonal art map for real-time hatching on every material (BAKER_tonal_art_map)"),
    "toon": BakeStep("toon", ToonOptions, toon.run, "toon ramp or X-Toon map on every material (BAKER_toon_ramp)"),
    "edges": BakeStep("edges", EdgesOptions, edges.run, "edge adjacency, classes, outline normals, fins (BAKER_edges + EXT_mesh_primitive_edge_visibility)"),
    "curvature": BakeStep("curvature", CurvatureOptions, curvature.run, "per-vertex mean/principal curvature by quadric fitting (_CURVATURE + BAKER_curvature)"),
    "skin": BakeStep("skin", SkinOptions, skin.run, "Penner's pre-integrated skin LUTs on every material (BAKER_skin_lut)"),
    "fur": BakeStep("fur", FurOptions, fur.run, "fur shell + fin textures and fin primitives on every material (BAKER_fur)"),
}
