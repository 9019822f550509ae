"""The mesh arguments shared by commands (MESH --units --density | --mass), and the mesh and material of a plan."""

from __future__ import annotations

import argparse
from pathlib import Path

from massline.meshes import BUNDLED
from massline.options import DENSITY, MASS
from massline.core.errors import MasslineError
from massline.meshes.loader import UNITS, BodyMesh, load_body
from massline.virtual.elastic import Material


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


def plan_mesh(doc: dict, plan_path: Path) -> BodyMesh:
    """The mesh a plan was made on: a bundled name, a path as given, or a path beside the plan."""
    name, units, density = doc.get("mesh"), doc.get("units", "m"), doc.get("density")
    if name in BUNDLED and not Path(name).exists():
        return load_body(BUNDLED[name].path, "m", density or BUNDLED[name].density)
    path = Path(name or "")
    if not path.exists() and (plan_path.parent / path).exists():
        path = plan_path.parent / path
    if not path.is_file():
        raise MasslineError(f"the plan's mesh '{name}' is not found: run from the folder where it was planned")
    return load_body(path, units, density)


def plan_material(text: str | None, body: BodyMesh, mesh_name: str | None, console) -> Material:
    """Young's modulus and Poisson's ratio: given (``--material``), bundled, or of the closest-density metal
    (said aloud)."""
    if text is None and mesh_name in BUNDLED:
        return Material(BUNDLED[mesh_name].youngs, BUNDLED[mesh_name].poisson, body.density)
    if text is None:
        text = Material.closest(body.density)
        console.print(f"[yellow]no --material given: assuming {text} from the density {body.density:g} kg/m³[/]")
    return Material.parse(text, body.density)
