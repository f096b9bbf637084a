"""One module per glTF extension: result arrays -> glTF JSON/accessors/images, plus its ``check`` for validation.

``EXTENSIONS`` maps each extension name to its module; ``baker validate`` runs each module's ``check``.
"""
from __future__ import annotations

from . import thickness

EXTENSIONS = {
    thickness.NAME: thickness,
}
