"""The identification report: one self-contained HTML page, printable on A4, readable offline; and the
page pieces the diagnosis report (:mod:`.diagnosis_report`) shares with it.

Assembly only: what ``massline identify`` (:class:`massline.identify.pipeline.Identification`) or ``massline
diagnose`` (:class:`massline.identify.diagnose.pipeline.DiagnosisRun`) found, and the nominal mesh when one was given, come
in; the page goes out, with the pictures of :mod:`.rendering` (the body, its channels and the principal
axes of :mod:`.body_scene`), the plots of :mod:`.identification_figures` and :mod:`.diagnosis_figures`,
and the 3-D view of :mod:`.viewer3d`. The page's look and its small HTML helpers are :mod:`.html`'s. Values are in the recording's frame; lengths are shown in mm.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from massline.core import __version__
from massline.identify.pipeline import Identification
from massline.meshes.loader import BodyMesh
from massline.core.numbers import counted, formatted, number, sigma_text, signed, value_with_sigma, vector_text
from massline.core.properties import QUANTITIES
from massline.core.rigid_body import RigidBody
from massline.reports.budget_section import budget_section
from massline.reports.body_scene import identification_scene, principal_frame
from massline.reports.html import (
    Report,
    escape,
    html_table,
    num,
    page,
    plot_figure,
    rendering_figure,
    with_sigma,
)
from massline.reports.identification_figures import fit_figure, frf_figure, representative
from massline.reports.plan_scene import AXIS, FLAGGED, Scene
from massline.reports.rendering import render_views
from massline.reports.viewer3d import viewer_html


def recording_line(recording, path) -> str:
    f = recording.frequencies
    n_s, n_e = recording.frf.shape[:2]
    missing = int((~recording.present).sum())
    runs = f" Runs: {escape(', '.join(recording.runs))}." if recording.runs else ""
    gaps = f" {missing} of {n_s * n_e} pairs not measured." if missing else ""
    return (
        f"Recording {escape(Path(path).name)}: {counted(n_s, 'accelerometer channel')} × {counted(n_e, 'hit')}, {len(f)} spectral lines, "
        f"{num(f[0], '.3g')}–{num(f[-1], '.4g')} Hz.{runs}{gaps} Frame of the file; written by massline {__version__}."
    )


def properties_table(body: RigidBody, std: dict, nominal: RigidBody | None, planar: bool) -> str:
    """Every property with its 1-σ, beside the mesh's value when there is one (difference, and in σ)."""
    rows = []
    for q in QUANTITIES:
        if q.key == "principal_axes":
            continue
        value, sigma, scale = q.value(body, planar), q.sigma(std), q.scale
        if planar and not np.isfinite(sigma):
            value = np.nan
        cells = [escape(q.name), with_sigma(value, sigma, scale)]
        if nominal is not None:
            reference = q.value(nominal)
            difference = value - reference
            in_sigma = difference / sigma if np.isfinite(sigma) and sigma > 0 else np.nan
            cells += [number(reference * scale), difference_text(difference, sigma, scale), num(in_sigma, "+.1f")]
        rows.append([*cells, q.unit])
    head = ["property", "identified ± 1-σ", "unit"]
    if nominal is not None:
        head[2:2] = ["nominal (mesh)", "difference", "in σ"]
        return html_table(head, rows, "lrrrrl", [22, 27, 17, 14, 8, 12])
    return html_table(head, rows, "lrl", [35, 45, 20])


def difference_text(difference: float, sigma: float, scale: float) -> str:
    """A signed difference (× ``scale``) to its σ's digits ("—" when unobservable)."""
    if not np.isfinite(difference):
        return "—"
    shown = value_with_sigma(difference * scale, sigma * scale)[0] if np.isfinite(sigma) else number(difference * scale)
    return signed(shown) if any(c in "123456789" for c in shown.partition("e")[0]) else "0"


def _angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    """Angle between two axes (no sign), degrees."""
    return float(np.degrees(np.arccos(np.clip(abs(a @ b), 0.0, 1.0))))


def axes_table(body: RigidBody, std: dict | None, nominal: RigidBody | None, planar: bool) -> str:
    """The principal axes drawn: direction, moment ± 1-σ, radius of gyration, the axis' 1-σ and its angle to
    the mesh's axis of the same rank."""
    moments, axes = principal_frame(body, planar)
    if nominal is not None:
        _, reference = principal_frame(nominal, planar)
    rows = []
    for k in range(axes.shape[1]):
        sigma = None if std is None else std["principal_moments"][k]
        row = [f"I{k + 1}", vector_text(axes[:, k], 3), with_sigma(moments[k], sigma, 1.0)]
        row += [num(1e3 * np.sqrt(max(moments[k], 0.0) / body.mass), ".1f")]
        row += ["" if std is None else sigma_text(std["principal_axes_deg"][k])]
        if nominal is not None:
            row.append(num(_angle_deg(axes[:, k], reference[:, k]), ".2f"))
        rows.append(row)
    head = ["axis", "direction (x, y, z)", "moment (kg·m²)", "radius of gyration (mm)", "axis 1-σ (°)"]
    if nominal is not None:
        head.append("to the mesh's axis (°)")
        return html_table(head, rows, "lrrrrr", [7, 27, 22, 16, 12, 16])
    return html_table(head, rows, "lrrrr", [8, 32, 26, 18, 16])


def legend(scene: Scene, what: str) -> str:
    flagged = any(m.kind == FLAGGED for m in scene.markers)
    mark = ' <span style="color:#e16e00;font-weight:bold">Orange</span>: a channel or hit a finding names.'
    return (
        '<p class="note"><span class="sensor">Blue</span>: accelerometers, numbered by their UFF node (arrow along '
        'the measuring direction; triaxials: three arrows); <span class="hit">red</span>: hammer hits (node), arrow '
        'into the surface; <span style="color:#14873c;font-weight:bold">green I1–I3</span>: the principal axes of '
        f"the {what} body from its CoG (the black and white disc), each as long as the radius of gyration about it "
        "(ascending moments). The body is drawn see-through; parallel projections, axes in the corner."
        + (mark if flagged else "")
        + "</p>"
    )


def _views(scene: Scene) -> tuple[list, str]:
    """The four labelled views of the scene, and their figures (naming the channels a view hides)."""
    renderings = render_views(scene)
    markers = [m for m in scene.markers if m.kind != AXIS]
    return renderings, '<div class="views">' + "".join(rendering_figure(r, markers) for r in renderings) + "</div>"


def turn_it(scene: Scene) -> str:
    return (
        '<section class="screen"><h2>Turn it</h2><p class="note">Drag to turn the body (screen only).</p>'
        + viewer_html(scene)
        + "</section>"
    )


def body_line(mesh: BodyMesh | None) -> str:
    if mesh is None:
        return (
            "No mesh was given (--mesh): the body is drawn as the hull of the test points and there are no nominal "
            "values to compare with."
        )
    density, mass = num(mesh.density, "g"), num(mesh.nominal.mass)
    return f"Nominal body: mesh {escape(mesh.name)}, density {density} kg/m³, mass {mass} kg."


def body_views(mesh, recording, sensors, hits, body, planar, flagged=((), ())):
    """The scene of ``body`` with the test's channels (findings' ones ``flagged``), and its rendered views."""
    scene = identification_scene(
        None if mesh is None else mesh.mesh,
        recording.sensors,
        recording.exciters,
        sensors,
        hits,
        body,
        planar,
        *flagged,
    )
    return (scene, *_views(scene))


def warnings_block(warnings) -> str:
    """The identification's warnings, first on the page (empty when nothing is suspect)."""
    if not warnings:
        return ""
    items = "".join(f"<li>{escape(w.text)}</li>" for w in warnings)
    return f'<section class="warnings"><h2>Warnings</h2><ul>{items}</ul></section>'


def identify_report(found: Identification, uff_path, mesh: BodyMesh | None = None) -> Report:
    """The identification report of ``found`` (``massline identify --report``), against ``mesh`` when given."""
    recording, zones, fit = found.recording, found.band, found.fit
    sensors, hits = recording.sensor_channels, recording.exciter_channels
    nominal = None if mesh is None else mesh.nominal
    scene, renderings, views = body_views(mesh, recording, sensors, hits, found.body, found.planar)
    present = np.isfinite(fit.values)
    picks = [p for p in representative(recording.sensors, recording.exciters, np.nan_to_num(fit.values)) if present[p]]
    notes = {
        (i, j): f"massline {with_sigma(fit.values[i, j], fit.std[i, j], 1.0)}, fit RMS {100 * fit.quality[i, j]:.2f} %"
        for i, j in picks
    }
    frfs = frf_figure(
        recording.frequencies,
        recording.frf,
        (zones.low, zones.high),
        picks,
        sensors,
        hits,
        {"massline (band fit)": fit.values},
        (zones.suspension_top, zones.first_elastic),
        notes,
    )
    model = found.data.values - found.best.residual
    fitted = fit_figure(found.data.values, found.sigma, model, sensors, hits)
    band_note = (
        f"Band {num(zones.low, '.1f')}–{num(zones.high, '.1f')} Hz ({escape(zones.rule)}"
        + resonances_note(zones)
        + "). Every FRF is fitted there with A + B/ω² + Cω² + Dω⁴ so that the suspension and "
        f"residual-flexibility tails do not bias its massline A. Band fits: median RMS residual "
        f"{100 * np.nanmedian(fit.quality):.2f} % of the massline, worst {100 * np.nanmax(fit.quality):.2f} %; a "
        f"plain average over the band would be off by up to {100 * np.nanmax(fit.bias):.1f} %." + noise_note(found)
    )
    method = "weighted estimate over all masslines, physically consistent" if found.method == "best" else found.method
    fit_note = (
        f"Reduced χ² {number(found.best.chi2, 3)} over {int(np.isfinite(found.sigma).sum())} masslines"
        + ("; the physical-consistency constraint is active" if found.best.constrained else "")
        + ". The ± is the uncertainty budget's (below): the noise (the information's, widened by a reduced χ² "
        "beyond what the calibration explains, or a bootstrap over the sensors), the transverse sensitivity's prior, "
        "the accelerometers' and force transducer's calibration and the tails' truncation, in quadrature."
        + masses_note(found)
    )
    summary = _summary(found.body, found.std, nominal, found.planar)
    parts = [
        f"<h1>Identification: {escape(Path(uff_path).name)}</h1>",
        f'<p class="note">{recording_line(recording, uff_path)} {body_line(mesh)}</p>',
        f"<p>{summary}</p>",
        warnings_block(found.warnings),
        f"<section><h2>Properties ({escape(method)})</h2>"
        + properties_table(found.body, found.std, nominal, found.planar)
        + f'<p class="note">{fit_note} J about the CoG, tensor sign (off-diagonals are minus the products of '
        "inertia).</p></section>",
        "<section><h2>Principal axes on the body</h2>"
        + legend(scene, "identified")
        + views
        + axes_table(found.body, found.std, nominal, found.planar)
        + "</section>",
        budget_section(found.budget, found.body, found.planar),
        turn_it(scene),
        "<section><h2>FRFs and the massline band</h2>"
        + plot_figure(frfs, "representative FRFs", band_note)
        + "</section>",
        "<section><h2>How well the identified body fits the masslines</h2>"
        + plot_figure(fitted, "masslines against the identified body", "Each point is one FRF's massline with its 1-σ.")
        + "</section>",
    ]
    return Report(page(f"Identification: {Path(uff_path).name}", parts), renderings)


def noise_note(found: Identification) -> str:
    """' The recording's noise: 1.00 % of the FRFs (RMS, from the coherence); the band fits leave 1.00× it.'"""
    noise = found.noise_payload
    if noise is None:
        return ""
    ratio = noise["fit_over_noise"]
    left = f"; the band fits leave {ratio:.2f}× it" if np.isfinite(ratio) else ""
    return (
        f" The recording's noise: {100 * noise['relative']:.2f} % of the FRFs over the band (RMS, from the "
        f"{escape(noise['method'])}){left}."
    )


def resonances_note(band) -> str:
    """'; the highest support mode resolved at 2.78 Hz, below it; the first elastic mode at 2007 Hz, above it;
    dash-dot': the resonances the record resolves around the band (a stiff support's bounce may lie above it:
    :func:`massline.identify.resonances.bounding_modes`), as identify's warnings and diagnose's findings quote
    them; empty when it resolves neither."""
    named = [
        f"{what} at {num(hz, form)} Hz, {'below' if hz < band.low else 'above'} it"
        for what, hz, form in (
            ("the highest support mode resolved", band.suspension_top, ".3g"),
            ("the first elastic mode", band.first_elastic, ".4g"),
        )
        if np.isfinite(hz)
    ]
    return "".join(f"; {x}" for x in named) + ("; dash-dot" if named else "")


def masses_note(found: Identification) -> str:
    """What was taken off the body as tested and what the scale said, as sentences (empty without either)."""
    text = ""
    housings = found.housings
    if housings.count:
        text += (
            f" The {escape(housings.describe())} ({num(1e3 * housings.total, 'g')} g in all) are subtracted: the properties are the bare body's; as tested it "
            f"weighed {with_sigma(found.tested.mass, found.tested_std['mass'], 1.0)} kg."
        )
    if found.weighed is not None:
        text += (
            f" The scale's reading of the bare body, {num(found.weighed.mass, 'g')} ± {num(found.weighed.sd, '.2g')} "
            "kg, is a prior on the mass."
        )
    return text


def _summary(body: RigidBody, std: dict, nominal: RigidBody | None, planar: bool) -> str:
    """One sentence: mass, CoG and principal moments with their 1-σ, and how far they are from the mesh's."""
    cog = (value_with_sigma(c, s)[0] if np.isfinite(s) else "—" for c, s in zip(1e3 * body.cog, 1e3 * std["cog"]))
    text = f"<b>Mass {with_sigma(body.mass, std['mass'], 1.0)} kg</b>, CoG (" + ", ".join(cog) + ") mm"
    if not planar:
        moments = (value_with_sigma(v, s)[0] for v, s in zip(body.principal_moments, std["principal_moments"]))
        text += ", principal moments " + ", ".join(moments) + " kg·m²"
    if nominal is not None:
        text += f"; against the mesh: mass {formatted(100 * (body.mass / nominal.mass - 1), '+.2f')} %"
        cog = np.linalg.norm((body.cog - nominal.cog)[: 2 if planar else 3])
        text += f", CoG {num(1e3 * cog, '.2f')} mm off"
        if not planar:
            worst = np.abs(body.principal_moments / nominal.principal_moments - 1).max()
            text += f", principal moments within {100 * worst:.2f} %"
    return text + "."
