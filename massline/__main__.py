"""The ``massline`` command's entry point.

Only the standard library is imported here, so that Ctrl-C at any moment (also while numpy, scipy or
VTK load) ends with one line, "massline: interrupted", and exit code 130. While the modules load, the
signal is only noted, and acted on once they are loaded (about a second): a KeyboardInterrupt raised
inside a library's import is swallowed (trimesh catches every exception around its optional imports),
leaves a half-initialised module that fails later (scipy: "has no attribute '_lib'"), is logged (cvxpy)
or printed as "Exception ignored" (importlib's module locks). Everything else is in :mod:`massline.cli.app`.
"""

from __future__ import annotations

import signal


class _Interrupt:
    """SIGINT is noted; once ``raising`` it also raises KeyboardInterrupt, as Python's own handler does."""

    def __init__(self):
        self.seen = False
        self.raising = False

    def __call__(self, signum, frame):
        self.seen = True
        if self.raising:
            raise KeyboardInterrupt


def _noting() -> _Interrupt:
    """The handler that notes SIGINT, installed unless the process was started with SIGINT ignored."""
    interrupt = _Interrupt()
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        signal.signal(signal.SIGINT, interrupt)
    return interrupt


_EARLY = _noting()  # first of all: even the standard library's imports below take tens of ms on a loaded machine

import os  # noqa: E402
import sys  # noqa: E402
from typing import NoReturn  # noqa: E402

INTERRUPTED = 130
BLAS_THREADS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def one_blas_thread() -> None:
    """One BLAS thread unless the user's environment says otherwise, set before numpy loads its BLAS.

    massline's linear algebra is many small solves (6 to 10 parameters, a few thousand spectral lines): a BLAS
    thread pool gains nothing there and contends with other work. ``python benchmarks/blas_threads.py --busy``
    (2 cores, one kept busy) printed: a 1200 × 4 least squares 2.36 ms with two threads, 0.80 ms with one;
    ``massline demo`` 43.8 s against 34.2 s. On an idle machine the demo took 30.7 s with two, 33.3 s with one.
    """
    for variable in BLAS_THREADS:
        os.environ.setdefault(variable, "1")


def main(argv: list[str] | None = None) -> int:
    """Run ``massline`` with ``argv`` (default: the command line); return the exit code."""
    global _EARLY
    interrupt, _EARLY = (_EARLY or _noting()), None  # the one installed at import serves the first run
    one_blas_thread()
    try:
        from massline.cli.app import run

        interrupt.raising = True
        if interrupt.seen:  # pressed while the modules loaded
            raise KeyboardInterrupt
        return run(argv)
    except KeyboardInterrupt:
        _exit_interrupted()


def _exit_interrupted() -> NoReturn:
    """Say "interrupted" and end the process with exit code 130.

    Not by returning: when the signal lands in code a library runs through ``PyRun_*``, the interpreter
    notes an unhandled KeyboardInterrupt for good and, at exit, kills itself with SIGINT (exit status −2
    instead of 130; seen 3 times in 100 interrupts while trimesh loaded).
    """
    print("massline: interrupted", file=sys.stderr)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(INTERRUPTED)


if __name__ == "__main__":
    sys.exit(main())
