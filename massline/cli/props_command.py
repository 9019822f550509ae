"""``massline props MESH``: the nominal mass, CoG and inertia of a mesh."""

from __future__ import annotations

import argparse

from rich.console import Console

from massline.cli.meshargs import add_mesh_arguments, body_from_arguments
from massline.core.files import claim_output
from massline.core.properties import JSON_UNITS
from massline.cli.output import write_json
from massline.cli.tables import body_table


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_mesh_arguments(parser)
    parser.add_argument(
        "--json", metavar="OUT", help="also write the properties as JSON (identify's keys); - for stdout"
    )
    parser.add_argument("--force", action="store_true", help="overwrite OUT if it exists")


def run(args: argparse.Namespace, console: Console) -> None:
    if args.json:
        claim_output(args.json, args.force, "--json")
    body = body_from_arguments(args)
    nominal = body.nominal
    console.print(body_table(nominal, f"{body.name}: nominal properties ({body.density:g} kg/m³, frame of the mesh)"))
    if args.json:
        payload = {**nominal.as_dict(), "std": None, "band_hz": None, "planar": False, "units": JSON_UNITS}
        write_json(console, args.json, payload, args.force)
