"""baker: offline bakes for stylized and translucent real-time rendering, written as glTF extensions and USD.

The Python API is :mod:`baker.api`; ``baker.bake`` is its :func:`~baker.api.bake`.
"""
from __future__ import annotations

import os
import sys

from baker.version import __version__

# numba caches compiled kernels (cache=True) beside their source by default, which fails silently for a package
# folder that is read-only (a wheel installed by root, a container image) and recompiles on every run; a user cache
# folder works for every install. baker's own kernels go to $XDG_CACHE_HOME/baker/numba/<build> whatever this says
# (baker/numba_cache.py, registered below); NUMBA_CACHE_DIR still places any other cached function and the warm
# stamp of `baker build`. Set before numba is imported; an explicit NUMBA_CACHE_DIR wins.
if "NUMBA_CACHE_DIR" not in os.environ:
    os.environ["NUMBA_CACHE_DIR"] = os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "baker", "numba")


class _NumbaCacheLocatorHook:
    """Registers :class:`baker.numba_cache.BakerCacheLocator` the moment ``numba.core.caching`` is imported, before
    any kernel is decorated, without importing numba here (``baker --help`` stays light): baker's kernels then load
    from a cache keyed on their place in the package and their content, which the wheel ships compiled."""

    def find_spec(self, name, path, target=None):
        if name != "numba.core.caching":
            return None
        import importlib
        import importlib.machinery

        spec = importlib.machinery.PathFinder.find_spec(name, path)
        if spec is None or spec.loader is None:
            return spec
        execute = spec.loader.exec_module

        def exec_module(module):
            execute(module)
            sys.meta_path[:] = [f for f in sys.meta_path if f is not self]
            # importing it registers the locator (at its end, also when it is the module importing numba now)
            importlib.import_module("baker.numba_cache")

        spec.loader.exec_module = exec_module
        return spec


if "numba.core.caching" in sys.modules:  # numba came first: its kernels' caches are made, baker's are not yet
    import baker.numba_cache  # noqa: F401 (registers the locator)
else:
    sys.meta_path.insert(0, _NumbaCacheLocatorHook())


def bake(path_or_asset, bakes=("thickness",), options=None, seed: int = 0, progress=None, allow_outside=None,
         max_memory: int | None = None, attribute_layout: str = "blender", source=None, cage=None,
         cage_distance: float | None = None):
    """Bake ``bakes`` into an asset and return it (an ``Asset``); write it with :func:`baker.api.save`.

    ``options`` maps a bake name to its options dataclass instance or to a dict of option values;
    ``allow_outside`` and ``max_memory`` are those of :func:`baker.api.bake` (more folders the asset's URIs may
    point into; a memory limit in bytes, None for none). ``attribute_layout``: ``"blender"`` (default: custom
    vertex attributes padded to one width per mesh, which Blender 4.5 imports) or ``"native"`` (each at its own
    width: SCALAR, VEC2, VEC3). ``source``, ``cage``, ``cage_distance``: bake from a high mesh through a cage
    (``baker bake --from HIGH --cage MESH --cage-distance D``).
    """
    from baker.api import bake as api_bake

    return api_bake(path_or_asset, bakes=bakes, options=options, seed=seed, progress=progress,
                    allow_outside=allow_outside, max_memory=max_memory, attribute_layout=attribute_layout,
                    source=source, cage=cage, cage_distance=cage_distance)
