"""The mesh arguments shared by commands (MESH --units --density | --mass)."""

from __future__ import annotations

import argparse
from pathlib import Path

from massline.meshes import BUNDLED
from massline.options import DENSITY, MASS
from massline.meshes.loader import UNITS, BodyMesh, load_body


def add_mesh_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "mesh", metavar="MESH", help=f"surface mesh (STL/OBJ/PLY) or a bundled body: {', '.join(BUNDLED)}"
    )
    parser.add_argument("--units", choices=sorted(UNITS), help="length unit of the mesh file (required for files)")
    material = parser.add_mutually_exclusive_group()
    material.add_argument("--density", type=DENSITY, metavar="KG_M3", help="material density, kg/m³")
    material.add_argument("--mass", type=MASS, metavar="KG", help="total mass, kg (uniform density)")


def body_from_arguments(args: argparse.Namespace) -> BodyMesh:
    """Load the mesh named on the command line; bundled bodies know units and density."""
    bundled = BUNDLED.get(args.mesh)
    if bundled is not None and not Path(args.mesh).exists():
        density = args.density if args.density is not None or args.mass is not None else bundled.density
        return load_body(bundled.path, args.units or "m", density, args.mass)
    return load_body(args.mesh, args.units, args.density, args.mass)


def add_nominal_arguments(parser: argparse.ArgumentParser) -> None:
    """An optional nominal body for commands that read a recording: --mesh MESH [--units] [--density | --mass]."""
    parser.add_argument("--mesh", metavar="MESH", help="the nominal body's surface mesh or a bundled body")
    parser.add_argument("--units", choices=sorted(UNITS), help="length unit of the mesh file")
    material = parser.add_mutually_exclusive_group()
    material.add_argument("--density", type=DENSITY, metavar="KG_M3", help="material density, kg/m³")
    material.add_argument("--mass", type=MASS, metavar="KG", help="total mass, kg (uniform density)")


def nominal_mesh(args: argparse.Namespace) -> BodyMesh | None:
    """The mesh given with --mesh (bundled bodies know units and density), None without one."""
    return body_from_arguments(args) if args.mesh else None
