"""The mesh arguments shared by commands (MESH --units --density | --mass)."""

from __future__ import annotations

import argparse
from pathlib import Path

from rich.console import Console

from massline.core.errors import MasslineError
from massline.meshes import BUNDLED
from massline.cli.options import DENSITY, MASS
from massline.meshes.loader import UNITS, BodyMesh, load_body
from massline.cli.output import progress_bar, say_fe_model, say_material
from massline.virtual.elastic import MATERIALS
from massline.virtual.support_model import SupportModel, SupportSetup


def add_mesh_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "mesh", metavar="MESH", help=f"surface mesh (STL/OBJ/PLY) or a bundled body: {', '.join(BUNDLED)}"
    )
    parser.add_argument("--units", choices=sorted(UNITS), help="length unit of the mesh file (required for files)")
    material = parser.add_mutually_exclusive_group()
    material.add_argument("--density", type=DENSITY, metavar="KG_M3", help="material density, kg/m³")
    material.add_argument("--mass", type=MASS, metavar="KG", help="total mass, kg (uniform density)")


def bundled_name(mesh: str) -> str | None:
    """``mesh`` (a mesh argument) when it names a bundled body (and no file of that name is there), else None."""
    return mesh if mesh in BUNDLED and not Path(mesh).exists() else None


def body_from_arguments(args: argparse.Namespace) -> BodyMesh:
    """Load the mesh named on the command line; bundled bodies know units and density."""
    name = bundled_name(args.mesh)
    if name is not None:
        bundled = BUNDLED[name]
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


def add_support_arguments(parser: argparse.ArgumentParser) -> None:
    """--suspension SPEC [--material NAME|E,NU] (identify, diagnose): the test's support, modelled with --mesh."""
    parser.add_argument(
        "--suspension",
        metavar="SPEC",
        help="the support the body hung on, as simulate takes it: 'cord[:k=N/m,L=m,at=X;Y;Z]' (default: tied above "
        "the mesh's CoG) or 'foam[:k=N/m,shear=r]'; needs --mesh: the support's action through the mesh's FE model "
        "(a stiff cord or foam squeezes the band) is taken off the FRFs, its springs' stiffness and the elastic "
        "frequencies fitted to the record's resonances (default: none taken off)",
    )
    parser.add_argument(
        "--material",
        metavar="NAME|E,NU",
        help=f"the FE model's material for --suspension: {', '.join(MATERIALS)}, or Young's modulus (Pa) and "
        "Poisson's ratio (default: the bundled body's, else the metal closest in density)",
    )


def support_setup(args: argparse.Namespace, mesh: BodyMesh | None) -> SupportSetup | None:
    """--suspension and --material checked before any work (None: no support to take off)."""
    if args.suspension is None:
        if args.material is not None:
            raise MasslineError("--material is the FE model's of --suspension: give --suspension too, or leave it out")
        return None
    if mesh is None:
        raise MasslineError("--suspension needs --mesh: the support acts through the body's FE model, built from it")
    return SupportSetup.parse(args.suspension, mesh, bundled_name(args.mesh), args.material)


def support_model(setup: SupportSetup | None, console: Console) -> SupportModel | None:
    """The support model of ``setup`` (its FE model solved with a progress bar, or kept), said on ``console``."""
    if setup is None:
        return None
    with progress_bar(console) as progress:
        model, fe = setup.model(progress)
        say_material(console, fe, option=True)
    say_fe_model(console, fe)
    return model
