"""baker: offline bakes for stylized and translucent real-time rendering, written as glTF extensions and USD."""
from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("baker")
except PackageNotFoundError:  # running from a source tree that was not installed
    __version__ = "0.1.0"


def bake(path_or_asset, bakes=("thickness",), options=None, seed: int = 0, progress=None):
    """Bake ``bakes`` into an asset and return it (``Asset``); save with ``asset.save(path)``.

    ``options`` maps a bake name to its options dataclass instance or to a dict of option values.
    """
    from .pipeline import bake as _bake

    return _bake(path_or_asset, bakes=bakes, options=options, seed=seed, progress=progress)
