"""The ``massline`` command: argument parsing and error reporting only.

Exit codes: 0 success, 2 bad input (a one-line message, no traceback),
1 internal error.
"""

from __future__ import annotations

import argparse
import os
import sys

from rich.console import Console

from massline import __version__
from massline.meshargs import add_mesh_arguments, body_from_arguments
from massline.placement.errors import MasslineError
from massline.placement.files import claim_output, to_json, write_atomic
from massline.tables import body_table

from . import demo, diagnose_command, identify_command, plan, report_command, simulate

DESCRIPTION = """\
Find a body's mass, centre of gravity and inertia tensor from a modal test on the softly
suspended body: plan where the accelerometers and hammer hits go, identify the properties
with their uncertainty from the FRFs your test software exports (UFF), and say which physics
a recording shows that the rigid body does not."""

EPILOG = """\
a test, step by step:
  massline props part.stl --units mm --density 2700     what the CAD says
  massline plan part.stl --units mm --density 2700      where to put sensors and hits
  massline identify test.uff --json result.json         the properties, with their ±
  massline diagnose test.uff --mesh part.stl --units mm --density 2700
  massline demo                                         the whole story on a bundled body

'massline COMMAND --help' tells more. Exit codes: 0 done, 2 bad input (one line on stderr),
1 internal error."""


def cmd_props(args: argparse.Namespace, console: Console) -> None:
    """Nominal mass, CoG and inertia of a mesh."""
    if args.json:
        claim_output(args.json, args.force)
    body = body_from_arguments(args)
    nominal = body.nominal
    console.print(body_table(nominal, f"{body.name}: nominal properties ({body.density:g} kg/m³, frame of the mesh)"))
    if args.json:
        payload = {**nominal.as_dict(), "std": None, "band_hz": None, "planar": False}
        write_atomic(args.json, to_json(payload), args.force)
        console.print(f"wrote {args.json}")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="massline",
        description=DESCRIPTION,
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"massline {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND", title="commands")

    props = sub.add_parser("props", help="nominal mass, CoG and inertia of a mesh")
    add_mesh_arguments(props)
    props.add_argument("--json", metavar="OUT", help="also write the properties as JSON (identify's keys)")
    props.add_argument("--force", action="store_true", help="overwrite OUT if it exists")
    props.set_defaults(run=cmd_props)

    commands = (
        ("plan", plan, "the best sensor and exciter layout on a mesh, certified"),
        ("simulate", simulate, "the virtual test of a plan, written as a UFF recording"),
        ("report", report_command, "the placement report of a plan, as one HTML file"),
        ("identify", identify_command, "mass, CoG and inertia with their 1-σ from a UFF recording"),
        ("diagnose", diagnose_command, "which physics the model left out, modelled and refitted"),
        ("demo", demo, "the whole story on the bundled structure: plan, test, identify, diagnose"),
    )
    for name, module, text in commands:
        command = sub.add_parser(name, help=text)
        module.add_arguments(command)
        command.set_defaults(run=module.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    console = Console()
    try:
        args.run(args, console)
    except MasslineError as err:
        print(f"massline: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("massline: interrupted", file=sys.stderr)
        return 130
    except Exception as err:  # an internal error: say so, keep the traceback for debugging
        if os.environ.get("MASSLINE_DEBUG"):
            raise
        print(
            f"massline: internal error: {type(err).__name__}: {err} (set MASSLINE_DEBUG=1 for the traceback)",
            file=sys.stderr,
        )
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
