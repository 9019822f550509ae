"""``massline report PLAN.json``: the placement report of a plan, as one HTML file (``massline plan`` writes it too).

Reads the plan and its mesh, shows the support the plan chose and the band it predicts (plan.json; for a
plan written before it kept them, predicted here with a soft cord and on foam from a coarse FE model),
renders the views off-screen and writes the page atomically.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from rich.console import Console

from massline.meshargs import plan_material, plan_mesh
from massline.output import write_report
from massline.core.errors import MasslineError
from massline.core.files import claim_output
from massline.meshes.loader import BodyMesh
from massline.placement.plan_file import band_from_dict, read_plan
from massline.reports.html import Report
from massline.reports.placement_report import BandRow, report_html
from massline.reports.plan_scene import scene_of
from massline.reports.rendering import render_views
from massline.support import elastic_modes, planned_band
from massline.virtual.band_prediction import predict_band
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


def band_row(role: str, suspension: str, band) -> BandRow:
    """One row of the report's band table."""
    return BandRow(
        f"{role}: {suspension}", band.suspension_top, band.low, band.high, band.first_elastic, band.tolerance
    )


def planned_bands(doc: dict) -> tuple[list[BandRow], str] | None:
    """The plan's support and band first, then the alternatives it weighed, and a note on the FE model behind
    them; None for a plan that keeps none."""
    band = planned_band(doc)
    if band is None:
        return None
    rows = [band_row("planned", doc["suspension"].get("description", "support"), band)]
    rows += [
        band_row("for comparison", a["suspension"], band_from_dict(a["band"])) for a in doc.get("alternatives", [])
    ]
    fe = doc.get("elastic", {})
    note = (
        f"Chosen by the plan: the support whose band is widest where every FRF stays within {100 * band.tolerance:g} "
        "% of its massline's scale (the tightest of 1, 2 and 5 % that holds a band an octave wide); `massline simulate` "
        "hangs the body on it and `simulate --check` predicts the same band. Elastic modes of the free body from "
        f"the finite-element model simulate builds ({fe.get('dofs')} DOF, quadratic tetrahedra of "
        f"{1e3 * fe.get('element_size', float('nan')):.1f} mm, E = {fe.get('youngs', float('nan')) / 1e9:.0f} GPa, "
        f"ν = {fe.get('poisson')}): " + ", ".join(f"{f:.0f}" for f in fe.get("frequencies_hz", [])[:3]) + " Hz. "
        "identify's band is wider: it fits the support's and the elastic modes' tails, which this band keeps "
        "clear of. Accelerometer masses are not included."
    )
    return rows, note


def predicted_bands(body: BodyMesh, mesh_name: str | None, sensors, exciters, console: Console):
    """The massline band with a soft cord and on foam, and a note on the FE model behind them (a plan that
    keeps no support)."""
    material = plan_material(None, body, mesh_name, console)
    size = max(default_size(body.mesh), size_for_dofs(body.mesh, FE_DOFS))
    modes = elastic_modes(body, material, size, MODES, console)
    rows = []
    for role, spec in SUSPENSIONS:
        try:
            suspension = Suspension.parse(spec, body.mesh, body.nominal)
            band = predict_band(SuspendedBody(body.nominal, modes, suspension), sensors, exciters)
        except MasslineError as err:  # e.g. foam under a body with no flat underside
            rows.append(BandRow(f"{role}: {spec} is not possible here ({err})", *[np.nan] * 5))
            continue
        rows.append(band_row(role, suspension.describe(), band))
    note = (
        "Every FRF within the tolerance of its massline's scale. Elastic modes of the free body from a finite-element "
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
    bands, fe_note = planned_bands(doc) or predicted_bands(body, doc.get("mesh"), sensors, exciters, console)
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
