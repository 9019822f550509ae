"""The placement report of a plan file, assembled: the plan and its mesh, the bands, the views, the page.

Shows the support the plan chose and the band it predicts (plan.json; for a plan written before it kept them,
predicted here with a soft cord and on foam from a coarse FE model), renders the views off-screen and builds the
page (:mod:`.placement_report`). ``massline plan`` and ``massline report`` write it; the demo too.

``progress(stage, done, total)``, when given, is called as each stage starts: the FE solve of an older plan
(:mod:`massline.virtual.planned_test`), then "rendering the views" (``total`` None: its length is not known).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from massline.core.band import band_from_dict
from massline.core.errors import MasslineError
from massline.meshes.loader import BodyMesh
from massline.placement.plan_file import read_plan
from massline.reports.html import Report
from massline.reports.next_run_section import marked_added
from massline.reports.placement_report import BandRow, report_html
from massline.reports.plan_scene import rig_segments, scene_of
from massline.reports.rendering import render_views
from massline.virtual.band_prediction import predict_band
from massline.virtual.planned_test import FEModel, assumed_material, body_material, fe_model, plan_mesh, planned_band
from massline.virtual.suspended import SuspendedBody
from massline.virtual.suspension import Suspension
from massline.virtual.tetmesh import default_size, size_for_dofs

MODES = 12  # elastic modes kept for the band prediction
FE_DOFS = 8000  # a coarse FE model: the first elastic frequencies within ~2 % of simulate's default mesh
SUSPENSIONS = (("recommended", "cord"), ("for comparison", "foam"))  # roles and --suspension specs


@dataclass(frozen=True, eq=False)
class PlacementReport:
    """The placement report and, for a plan that keeps no band, the FE model its bands were predicted on.

    Attributes
    ----------
    report : Report
        The page (``html``) and its pictures (``renderings``).
    fe : FEModel or None
        The coarse FE model of an older plan's band prediction; None when the plan keeps its band.
    """

    report: Report
    fe: FEModel | None = None

    @property
    def html(self) -> str:
        return self.report.html


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


def predicted_bands(body: BodyMesh, mesh_name: str | None, sensors, exciters, progress=None):
    """The massline band with a soft cord and on foam, a note on the FE model behind them and that model
    (a plan that keeps no support)."""
    material = body_material(body, mesh_name)
    size = max(default_size(body.mesh), size_for_dofs(body.mesh, FE_DOFS))
    fe = fe_model(body, material, size=size, n=MODES, progress=progress, assumed=assumed_material(body, mesh_name))
    modes = fe.modes
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
    return rows, note, fe


def build_placement_report(plan_path: str | Path, progress=None) -> PlacementReport:
    """Everything the page shows, computed from the plan file ``plan_path`` and its mesh.

    ``progress(stage, done, total)``: see the module docstring; None is silent.
    """
    plan_path = Path(plan_path)
    sensors, exciters, doc = read_plan(plan_path)
    body = plan_mesh(doc, plan_path)
    nominal = body.nominal
    planned, fe = planned_bands(doc), None
    if planned is None:
        *planned, fe = predicted_bands(body, doc.get("mesh"), sensors, exciters, progress)
    bands, fe_note = planned
    scene = replace(scene_of(body.mesh, sensors, exciters, nominal.cog), rig=rig_segments(doc.get("rig"), body.mesh))
    scene = marked_added(doc, scene)
    if progress is not None:
        progress("rendering the views", 0, None)  # a stage of unknown length
    renderings = render_views(scene)
    size = " × ".join(f"{e * 1e3:.0f}" for e in np.ptp(body.mesh.vertices, axis=0))
    body_line = (
        f"Mesh {doc.get('mesh')} (file units {doc.get('units', 'm')}), density {body.density:g} kg/m³, "
        f"mass {nominal.mass:.4g} kg, {size} mm (x × y × z)"
    )
    page = report_html(doc, body_line, scene, renderings, bands, fe_note)
    return PlacementReport(Report(page, renderings), fe)
