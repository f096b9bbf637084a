"""The numbers read from a mesh file are numbers: NaN, infinities and values beyond float32 (what glTF stores; they
would become infinities there) are refused, naming where they sit in the file when the format's reader can say."""
from __future__ import annotations

import math

import numpy as np

from baker.errors import BakerError

FLOAT32_MAX = 3.4028234663852886e38


def is_bad(value: float) -> bool:
    """A number glTF cannot store: NaN, infinite, or beyond float32."""
    return not math.isfinite(value) or abs(value) > FLOAT32_MAX


def refuse_non_finite(path, values, label: str, locate) -> None:
    """Refuse ``values`` (an array read from ``path``) holding a NaN, an infinity or a value beyond float32. The
    message names the place ``locate(path)`` finds (the OBJ line, PLY element, STL triangle), else ``label``."""
    with np.errstate(invalid="ignore"):
        bad = not np.isfinite(values).all() or bool((np.abs(values) > FLOAT32_MAX).any())
    if bad:
        where = locate(path) or f"{label}: NaN, infinite or beyond float32"
        raise BakerError(path, f"{where} (NaN and infinite coordinates, normals and UVs are refused)")
