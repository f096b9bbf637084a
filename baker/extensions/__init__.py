"""One module per glTF extension: result arrays -> glTF JSON/accessors/images, plus its ``check`` for validation.

``EXTENSIONS`` maps each extension name to its module; ``baker validate`` runs each module's ``check``.
"""
from __future__ import annotations

from . import edges, thickness
from . import tam, toon
from . import curvature, skin
from . import hair
from . import fur
from . import glyphs

EXTENSIONS = {
    thickness.NAME: thickness,
    edges.NAME: edges,
    tam.NAME: tam,
    toon.NAME: toon,
    curvature.NAME: curvature,
    skin.NAME: skin,
    hair.NAME: hair,
    fur.NAME: fur,
    glyphs.ATLAS.NAME: glyphs.ATLAS, glyphs.TEXT.NAME: glyphs.TEXT,
}
