"""Every ``baker`` verb: the modules of this package (bake, build, inspect, preview, validate) and the commands
techniques declare (``Technique.commands``). Each module has ``add_parser(subparsers)``, which sets ``func(args)``;
modules import their heavy parts only inside ``func``, so building the parser stays cheap."""
from __future__ import annotations

import argparse
import importlib
import pkgutil

from baker import registry
from baker.version import __version__


def command_modules() -> list:
    """The core verbs (this package, in name order), then every technique's commands."""
    core = [importlib.import_module(f"{__name__}.{info.name}") for info in pkgutil.iter_modules(__path__)]
    return core + registry.command_modules()


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="baker", description="Bake real-time rendering data into glTF and USD assets.")
    parser.add_argument("--version", action="version", version=f"baker {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for module in command_modules():
        module.add_parser(sub)
    return parser


def run(argv) -> int:
    """Parse ``argv`` (without the program name) and run that command; returns its exit code. Errors the user can act
    on raise :class:`~baker.errors.BakerError`, anything else propagates with its traceback."""
    args = build_parser().parse_args(argv)
    return args.func(args)
