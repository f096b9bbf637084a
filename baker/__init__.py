"""baker: offline bakes for stylized and translucent real-time rendering, written as glTF extensions and USD.

The Python API is :mod:`baker.api`; ``baker.bake`` is its :func:`~baker.api.bake`.
"""
from __future__ import annotations

from baker.version import __version__


def bake(path_or_asset, bakes=("thickness",), options=None, seed: int = 0, progress=None):
    """Bake ``bakes`` into an asset and return it (an ``Asset``); write it with :func:`baker.api.save`.

    ``options`` maps a bake name to its options dataclass instance or to a dict of option values.
    """
    from baker.api import bake as api_bake

    return api_bake(path_or_asset, bakes=bakes, options=options, seed=seed, progress=progress)
