"""Every ``baker`` verb: the modules of this package (bake, build, inspect, preview, validate) and the commands
techniques declare (``Technique.commands``). Each module has ``add_parser(subparsers)``, which sets ``func(args)``;
modules import their heavy parts only inside ``func``, so building the parser stays cheap."""
from __future__ import annotations

import argparse
import importlib
import pkgutil

from baker import compile_note, registry
from baker.version import __version__


def command_modules() -> list:
    """The core verbs (this package, in name order), then every technique's commands."""
    core = [importlib.import_module(f"{__name__}.{info.name}") for info in pkgutil.iter_modules(__path__)]
    return core + registry.command_modules()


class ShortUsageParser(argparse.ArgumentParser):
    """An argument parser whose usage errors are short: the command's one-line synopsis (its positionals and required
    options, then ``[options]``), the error, and where the full list is. argparse's own usage line lists every option,
    which for ``baker bake`` (flags made from every technique's options) ran to 72 lines before the one that
    mattered. Subparsers inherit the class, so every verb behaves alike; ``--help`` keeps the full list."""

    def synopsis(self) -> str:
        words = [self.prog]
        for action in self._actions:
            if action.help == argparse.SUPPRESS:
                continue
            if not action.option_strings:
                words.append(action.metavar or (action.dest.upper() if action.nargs is None else f"{action.dest.upper()}..."))
            elif action.required:
                words.append(f"{action.option_strings[0]} {action.metavar or action.dest.upper()}")
        if any(a.option_strings and not a.required and a.help != argparse.SUPPRESS for a in self._actions):
            words.append("[options]")
        return " ".join(words)

    def error(self, message: str):
        self.exit(2, f"usage: {self.synopsis()}\n{self.prog}: error: {message}\nsee '{self.prog} --help'\n")


def build_parser() -> argparse.ArgumentParser:
    parser = ShortUsageParser(prog="baker", description="Bake real-time rendering data into glTF and USD assets.")
    parser.add_argument("--version", action="version", version=f"baker {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for module in command_modules():
        module.add_parser(sub)
    parser.verbs = sub  # run() hands an unrecognized argument to the verb's own parser
    return parser


def run(argv) -> int:
    """Parse ``argv`` (without the program name) and run that command; returns its exit code. Errors the user can act
    on raise :class:`~baker.errors.BakerError`, anything else propagates with its traceback."""
    parser = build_parser()
    args, unknown = parser.parse_known_args(argv)
    if unknown:  # reported by the verb's parser, so the synopsis and the help pointer are the verb's
        parser.verbs.choices[args.command].error(f"unrecognized arguments: {' '.join(unknown)}")
    compile_note.expect(list(argv))  # a cold numba cache says so once, as the first kernel compiles
    try:
        return args.func(args)
    finally:
        compile_note.disarm()
