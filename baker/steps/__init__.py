"""The bake registry: name -> (options dataclass, step). A new technique adds one line here."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from ..bakes.thickness import ThicknessOptions
from . import thickness


@dataclass(frozen=True)
class BakeStep:
    name: str
    options: type
    run: Callable  # (asset, options, seed, progress) -> None
    summary: str


BAKES = {
    "thickness": BakeStep("thickness", ThicknessOptions, thickness.run,
                          "local thickness per vertex and texel (KHR_materials_volume + BAKER_thickness)"),
}
