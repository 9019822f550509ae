"""The ``massline`` command's entry point.

Only the standard library is imported here, so that Ctrl-C at any moment (also while numpy, scipy or
VTK load) ends with one line, "massline: interrupted", and exit code 130. Some libraries catch every
exception around their optional imports (trimesh does), which would swallow the KeyboardInterrupt: the
handler also notes the signal, and the note is read once the imports are done. Everything else is in
:mod:`massline.app`.
"""

from __future__ import annotations

import signal
import sys

INTERRUPTED = 130


class _Interrupt:
    """SIGINT raises KeyboardInterrupt, as Python's own handler does, and is remembered."""

    def __init__(self):
        self.seen = False

    def __call__(self, signum, frame):
        self.seen = True
        raise KeyboardInterrupt


def main(argv: list[str] | None = None) -> int:
    """Run ``massline`` with ``argv`` (default: the command line); return the exit code."""
    interrupt = _Interrupt()
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:  # not when started with SIGINT ignored
        signal.signal(signal.SIGINT, interrupt)
    try:
        from massline.app import run

        if interrupt.seen:  # swallowed by a library while it loaded
            raise KeyboardInterrupt
        return run(argv)
    except KeyboardInterrupt:
        print("massline: interrupted", file=sys.stderr)
        return INTERRUPTED


if __name__ == "__main__":
    sys.exit(main())
