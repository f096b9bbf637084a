"""Errors a user can act on: one line, naming the file and the problem."""
from __future__ import annotations


class BakerError(Exception):
    """Bad input or an impossible request. The CLI prints ``baker: error: PATH: MESSAGE`` and exits 2."""

    def __init__(self, path, message: str):
        self.path = str(path) if path is not None else None
        self.message = message
        super().__init__(f"{self.path}: {message}" if self.path else message)


class NothingToBake(Exception):
    """A bake that finds nothing on this asset to cover (every material unlit, no normal map for normal-blur): not
    bad input. A bake raises it, with the reason, before it writes anything; :meth:`baker.technique.Technique.bake`
    turns it into one note, ``<bake>: nothing baked: <reason>``, and the run's other bakes go on."""


class BakeNote(UserWarning):
    """Something the user should know about a bake's result, though nothing failed (a Khronos field left out,
    materials skipped, attribute widths Blender cannot import). Issued as a Python warning, so API callers see it
    too; every command prints each once as ``baker: <label>: ...`` on stderr (``baker build`` names the output)."""

    label = "note"
