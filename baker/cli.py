"""The ``baker`` command: parse, run, report. No algorithm lives here.

Exit codes: 0 success, 1 validation errors found, 2 bad input or usage.
"""
from __future__ import annotations

import sys

from baker import commands
from baker.errors import BakerError


def main(argv=None) -> int:
    try:
        return commands.run(sys.argv[1:] if argv is None else argv)
    except BakerError as exc:
        print(f"baker: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("baker: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader of our output went away (`baker inspect x.glb | head`): not an error of ours
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # no second error when Python flushes at exit
        return 141


if __name__ == "__main__":
    sys.exit(main())
