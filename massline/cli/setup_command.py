"""``massline setup PLAN.json``: what a technician loads into test software — the points as a Universal File's
nodes, each in a coordinate system whose +Z is its direction, and a channel table (CSV)
(:func:`massline.placement.setup_export.export_setup`)."""

from __future__ import annotations

import argparse
import csv

from rich.console import Console
from rich.table import Table

from massline.meshes.loader import UNITS
from massline.placement.plan_file import read_plan
from massline.placement.setup_export import FILES, export_setup
from massline.virtual.planned_test import plan_mesh


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("plan", metavar="PLAN.json", help="a plan written by 'massline plan'")
    parser.add_argument(
        "--out", metavar="DIR", help=f"folder for {' and '.join(FILES)} (default: the plan's folder)"
    )
    parser.add_argument(
        "--units", choices=sorted(UNITS), help="length unit of the files (dataset 164, the table; default: the plan's)"
    )
    parser.add_argument(
        "--nodes",
        type=int,
        choices=(2411, 15),
        default=2411,
        help="nodes in dataset 2411 with systems in 2420 (default; exact) or in 15 with 18 (six digits)",
    )
    parser.add_argument(
        "--no-wireframe", action="store_true", help="leave the part's edges (dataset 82, from the plan's mesh) out"
    )
    parser.add_argument("--force", action="store_true", help=f"overwrite {' and '.join(FILES)}")


def channel_table(path) -> Table:
    """channels.csv as the console shows it: each channel's node, its direction in the node's system, its mount
    and the edges to mark it from."""
    with open(path, newline="") as handle:
        rows = list(csv.DictReader(handle))
    shown = ["channel", "role", "node", "direction", "mount"] + [c for c in rows[0] if c.startswith(("edge", "from"))]
    table = Table(title="Channels (channels.csv)")
    for column in shown:
        table.add_column(column, justify="right")
    for row in rows:
        table.add_row(*(row[c] for c in shown))
    return table


def run(args: argparse.Namespace, console: Console) -> None:
    mesh = None
    if not args.no_wireframe:
        _, _, doc = read_plan(args.plan)
        mesh = plan_mesh(doc, args.plan).mesh
    setup = export_setup(
        args.plan, args.out, units=args.units, nodes_dataset=args.nodes, mesh=mesh, force=args.force
    )
    console.print(channel_table(setup.channels))
    console.print(
        f"{setup.nodes} nodes, each in its own coordinate system (its +Z the accelerometer's axis or the hit's "
        f"direction; a triaxial's channels +X, +Y, +Z), {setup.units}: {setup.accelerometer_channels} accelerometer "
        f"channels and the hammer's channel {setup.accelerometer_channels + 1} over {setup.hits} runs"
    )
    outline = f", the part's {setup.edges} sharp edges as its wireframe" if setup.edges else ""
    console.print(f"wrote {setup.uff}{outline}")
    console.print(f"wrote {setup.channels}")
