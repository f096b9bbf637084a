"""``baker validate FILE...``: schemas, each technique's semantic checks and Khronos' glTF-Validator
(:mod:`baker.validate`); exit 1 on errors."""
from __future__ import annotations


def add_parser(sub) -> None:
    v = sub.add_parser("validate", help="check BAKER_* extensions and the structure baker needs (exit 1 on errors)")
    v.add_argument("files", nargs="+", help="glTF or GLB files")
    v.add_argument("--format", choices=("text", "json"), default="text", help="report format")
    v.add_argument("--no-khronos", action="store_true", help="do not run Khronos' gltf-validator even if present")
    v.add_argument("-q", "--quiet", action="store_true", help="print only errors")
    v.set_defaults(func=run)


def run(args) -> int:
    from baker.validate import main

    return main(args.files, fmt=args.format, khronos=not args.no_khronos, quiet=args.quiet)
