"""The ``massline`` command's entry point.

Only the standard library is imported here, so that Ctrl-C at any moment (also while numpy, scipy or
VTK load) ends with one line, "massline: interrupted", and exit code 130. Everything else is in
:mod:`massline.app`.
"""

from __future__ import annotations

import sys

INTERRUPTED = 130


def main(argv: list[str] | None = None) -> int:
    """Run ``massline`` with ``argv`` (default: the command line); return the exit code."""
    try:
        from massline.app import run

        return run(argv)
    except KeyboardInterrupt:
        print("massline: interrupted", file=sys.stderr)
        return INTERRUPTED


if __name__ == "__main__":
    sys.exit(main())
