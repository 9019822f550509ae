"""``massline report PLAN.json``: the placement report of a plan, as one HTML file (``massline plan`` writes it too).

Reads the plan and its mesh, predicts the massline band with the recommended
suspension (FE elastic modes, as ``massline simulate`` finds them), renders the
views off-screen and writes the page atomically.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from rich.console import Console

from massline.meshargs import plan_material, plan_mesh
from massline.output import write_report
from massline.placement.errors import MasslineError
from massline.placement.files import claim_output
from massline.placement.mesh import BodyMesh
from massline.placement.plan_file import read_plan
from massline.reports.html import Report
from massline.reports.placement_report import BandRow, report_html
from massline.reports.plan_scene import scene_of
from massline.reports.rendering import render_views
from massline.simulate import elastic_modes
from massline.virtual.band import TOLERANCE, predict_band
from massline.virtual.suspended import SuspendedBody
from massline.virtual.suspension import Suspension
from massline.virtual.tetmesh import default_size, size_for_dofs

MODES = 12  # elastic modes kept for the band prediction
FE_DOFS = 8000  # a coarse FE model: the first elastic frequencies within ~2 % of simulate's default mesh
SUSPENSIONS = (("recommended", "cord"), ("for comparison", "foam"))  # roles and --suspension specs


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("plan", metavar="PLAN.json", help="a plan written by 'massline plan'")
    parser.add_argument("--out", metavar="OUT.html", help="the report to write (default: report.html beside the plan)")
    parser.add_argument("--force", action="store_true", help="overwrite OUT.html if it exists")


def predicted_bands(body: BodyMesh, mesh_name: str | None, sensors, exciters, console: Console):
    """The massline band with the recommended cord and on foam, and a note on the FE model behind them."""
    material = plan_material(None, body, mesh_name, console)
    size = max(default_size(body.mesh), size_for_dofs(body.mesh, FE_DOFS))
    modes = elastic_modes(body, material, size, MODES, console)
    rows = []
    for role, spec in SUSPENSIONS:
        try:
            suspension = Suspension.parse(spec, body.mesh, body.nominal)
            band = predict_band(SuspendedBody(body.nominal, modes, suspension), sensors, exciters)
        except MasslineError as err:  # e.g. foam under a body with no flat underside
            rows.append(BandRow(f"{role}: {spec} is not possible here ({err})", np.nan, np.nan, np.nan, np.nan))
            continue
        rows.append(
            BandRow(f"{role}: {suspension.describe()}", band.suspension_top, band.low, band.high, band.first_elastic)
        )
    note = (
        f"FRFs within {100 * TOLERANCE:g} % of the massline. Elastic modes of the free body from a finite-element "
        f"model (coarse: {modes.n_dofs} DOF, quadratic tetrahedra of {modes.element_size * 1e3:.1f} mm, E = "
        f"{material.youngs / 1e9:.0f} GPa, ν = {material.poisson:g}): "
        + ", ".join(f"{f:.0f}" for f in modes.frequencies_hz[:3])
        + " Hz. The cord is tied straight above the CoG; its stiffness gives a 0.25 m static "
        "stretch (bounce near 1 Hz). Accelerometer masses are not included."
    )
    return rows, note


def build_report(plan_path: str | Path, console: Console) -> Report:
    """Everything the page shows, computed from the plan file and its mesh."""
    plan_path = Path(plan_path)
    sensors, exciters, doc = read_plan(plan_path)
    body = plan_mesh(doc, plan_path)
    nominal = body.nominal
    bands, fe_note = predicted_bands(body, doc.get("mesh"), sensors, exciters, console)
    scene = scene_of(body.mesh, sensors, exciters, nominal.cog)
    with console.status("rendering the views"):
        renderings = render_views(scene)
    size = " × ".join(f"{e * 1e3:.0f}" for e in np.ptp(body.mesh.vertices, axis=0))
    body_line = (
        f"Mesh {doc.get('mesh')} (file units {doc.get('units', 'm')}), density {body.density:g} kg/m³, "
        f"mass {nominal.mass:.4g} kg, {size} mm (x × y × z)"
    )
    page = report_html(doc, body_line, scene, renderings, bands, fe_note)
    return Report(page, renderings)


def run(args: argparse.Namespace, console: Console) -> None:
    plan_path = Path(args.plan)
    out = claim_output(Path(args.out) if args.out else plan_path.with_name("report.html"), args.force, "--out")
    write_report(console, out, lambda: build_report(plan_path, console), args.force, status=None)
