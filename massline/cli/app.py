"""The ``massline`` command: its options, its console and its exit codes.

Exit codes: 0 success, 2 bad input (one line on stderr naming the problem, no traceback), 1 internal
error, 130 interrupted (Ctrl-C), 141 output pipe closed by the reader. Warnings of the libraries
(numpy's RuntimeWarnings, cvxpy's "Solution may be inaccurate") never reach the user: the command
says what matters in its own words; ``MASSLINE_DEBUG=1`` shows them and the traceback of an internal
error.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import os
import sys
import warnings

from massline.core import __version__
from massline.cli.options import FLAGS, Parser
from massline.cli.output import console_for, console_stream
from massline.core.errors import MasslineError

DESCRIPTION = """\
Find a body's mass, centre of gravity and inertia tensor from a modal test on the softly
suspended body: plan where the accelerometers and hammer hits go, identify the properties
with their uncertainty from the FRFs your test software exports (UFF), and say which physics
a recording shows that the rigid body does not."""

EPILOG = """\
a test, step by step:
  massline props part.stl --units mm --density 2700     what the CAD says
  massline plan part.stl --units mm --density 2700      where to put sensors and hits
  massline setup plan/plan.json                         the points and channels for the test software
  massline identify test.uff --json result.json         the properties, with their ±
  massline diagnose test.uff --mesh part.stl --units mm --density 2700
  massline demo                                         the whole story on a bundled body

'massline COMMAND --help' tells more. Exit codes: 0 done, 2 bad input (one line on stderr),
1 internal error, 130 interrupted."""

COMMANDS = (  # name, its module in massline.cli (imported only when that command runs), its help line
    ("props", "props_command", "the nominal mass, CoG and inertia of a surface mesh (CAD export)"),
    ("plan", "plan", "the best accelerometer and hammer-hit layout on a mesh, with its certified quality"),
    ("setup", "setup_command", "the plan for the test software: nodes in their own coordinate systems (UFF), channels (CSV)"),
    ("simulate", "simulate", "the virtual test of a plan, written as a UFF recording like a lab's export"),
    ("report", "report_command", "the placement report of a plan: one HTML page that prints on A4"),
    ("identify", "identify_command", "mass, CoG and inertia with their 1-σ from a UFF recording"),
    ("diagnose", "diagnose_command", "which physics a recording shows that the rigid body does not"),
    ("demo", "demo", "the whole story on a bundled body: plan, test, identify, diagnose"),
)
BROKEN_PIPE = 141


def build_parser(argv: list[str] | None = None) -> argparse.ArgumentParser:
    """The parser of every command, each command's own options only for the one ``argv`` names (all when
    ``argv`` is None): a command's module loads what its work needs (identify does not load the planner, the FE
    model or the reports' renderer), about a second of imports that a run of another command does not pay."""
    chosen = None if argv is None else next((a for a in argv if not a.startswith("-")), "")
    parser = Parser(
        prog="massline", description=DESCRIPTION, epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--version", action="version", version=f"massline {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND", title="commands")
    for name, module_name, text in COMMANDS:
        command = sub.add_parser(name, help=text, description=text[0].upper() + text[1:] + ".")
        if chosen is None or chosen == name:
            module = importlib.import_module(f"{__package__}.{module_name}")
            module.add_arguments(command)
            command.set_defaults(run=module.run)
    return parser


def run(argv: list[str] | None = None, show_warnings: bool | None = None) -> int:
    """Parse ``argv`` and run the command; return the exit code.

    Warnings are kept from the user unless ``show_warnings`` (default: ``MASSLINE_DEBUG`` set), when each one
    is a line on stderr: the tests run commands so, and fail on any.
    """
    debug = bool(os.environ.get("MASSLINE_DEBUG"))
    show_warnings = debug if show_warnings is None else show_warnings
    if not debug:  # libraries' log records (trimesh on a damaged file) are no message for the user
        logging.getLogger().addHandler(logging.NullHandler())
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        try:
            return _command(argv, debug)
        finally:
            for w in caught if show_warnings else ():
                where = f"{w.filename}:{w.lineno}"
                print(f"massline: debug: {w.category.__name__}: {w.message} ({where})", file=sys.stderr)


def _command(argv: list[str] | None, debug: bool) -> int:
    try:
        argv = sys.argv[1:] if argv is None else argv
        parser = build_parser(argv)
        if not argv:  # bare 'massline': what it does and its commands
            parser.print_help()
            return 0
        args = parser.parse_args(argv)
        args.run(args, console_for(console_stream(args)))
    except SystemExit as done:  # --help, --version or a one-line usage error
        return int(done.code or 0)
    except MasslineError as err:  # the library's parameters in its message named by the command line's flags
        print(f"massline: error: {' '.join(err.spelled(FLAGS).split())}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # the reader (e.g. 'head') closed the pipe: stop quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return BROKEN_PIPE
    except Exception as err:  # an internal error: say so, keep the traceback for debugging
        if debug:
            raise
        print(
            f"massline: internal error: {type(err).__name__}: {err} (set MASSLINE_DEBUG=1 for the traceback)",
            file=sys.stderr,
        )
        return 1
    return 0
