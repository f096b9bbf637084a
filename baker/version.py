"""The installed version of baker (kept apart so that ``baker --version`` imports nothing else)."""
from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("baker")
except PackageNotFoundError:  # running from a source tree that was not installed
    __version__ = "0.1.0"
