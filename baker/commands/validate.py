"""``baker validate FILE...``: schemas, each technique's semantic checks and Khronos' glTF-Validator
(:mod:`baker.validate`); exit 1 on errors, 2 when a file is missing or cannot be parsed (truncated) or Khronos' validator cannot run (unless
``--no-khronos``). ``--install-khronos`` installs the pinned validator into the user cache first."""
from __future__ import annotations


def add_parser(sub) -> None:
    v = sub.add_parser("validate", help="check BAKER_* extensions, the structure baker needs and Khronos' "
                       "glTF-Validator (exit 1 on errors)")
    v.add_argument("files", nargs="*", help="glTF or GLB files, or USD (.usda .usdc .usdz) baker wrote (its baked data "
                   "read back; Khronos' validator does not apply)")
    v.add_argument("--format", choices=("text", "json"), default="text", help="report format")
    v.add_argument("--no-khronos", action="store_true",
                   help="check without Khronos' glTF-Validator (by default it runs, and its absence is an error)")
    v.add_argument("--install-khronos", action="store_true",
                   help="install the pinned Khronos glTF-Validator (npm gltf-validator) into "
                        "$XDG_CACHE_HOME/baker/node, then validate FILEs if any")
    v.add_argument("-q", "--quiet", action="store_true", help="print only errors")
    v.add_argument("--allow-outside", action="append", metavar="PATH", help="also read buffer/image URIs under PATH "
                   "(default: only inside the asset's folder); repeatable")
    v.set_defaults(func=run, parser=v)


def run(args) -> int:
    if not args.files and not args.install_khronos:
        args.parser.error("the following arguments are required: files")
    from baker.validate import install_khronos, main

    if args.install_khronos:
        install_khronos()
        if not args.files:
            return 0
    return main(args.files, fmt=args.format, khronos=not args.no_khronos, quiet=args.quiet,
                allow_outside=args.allow_outside)
