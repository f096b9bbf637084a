"""``python -m baker``: the same entry point as the ``baker`` command."""
from baker.cli import entry

entry()
