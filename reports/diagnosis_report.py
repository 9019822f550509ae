"""The diagnosis report (``massline diagnose --report``): the findings, the fit before and after, residual
maps and overlays, the properties before and after, and the corrected body's principal axes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from massline.diagnose_command import DiagnosisRun
from massline.identify.diagnose.diagnosis import property_std
from massline.identify.diagnose.notes import finding_note
from massline.identify_command import quantities, sigmas
from massline.placement.mesh import BodyMesh
from massline.placement.rigid_body import RigidBody
from massline.report_command import Report
from massline.reports.diagnosis_figures import diagnosis_figure
from massline.reports.identification_figures import frf_figure, representative
from massline.reports.identification_report import (
    _body_line,
    _body_views,
    _legend,
    _page,
    _plot,
    _recording_line,
    _turn_it,
    _with_sigma,
    axes_table,
)
from massline.reports.placement_report import _e, _num, _table


def _flagged(findings) -> tuple[set, set]:
    """Sensor lines and hits the findings name (0-based)."""
    sensors = {c for x in findings for c in x.channels}
    hits = {x.exciter for x in findings if x.exciter is not None}
    return sensors, hits


def channel_table(run: DiagnosisRun) -> str:
    """Per channel: relative RMS residual before and after, also in units of the noise; the ones a finding names."""
    result, noise = run.result, run.noise
    before, after = result.relative_rms("before", axis=1), result.relative_rms("after", axis=1)
    named, _ = _flagged(result.findings)
    rows = [
        [
            _e(name),
            f"{100 * before[k]:.2f} %",
            f"{100 * after[k]:.2f} %",
            _num(before[k] / noise, ".2f"),
            _num(after[k] / noise, ".2f"),
            "named by a finding" if k in named else "",
        ]
        for k, name in enumerate(run.sensors)
    ]
    head = ["channel", "residual before", "after", "before / noise", "after / noise", ""]
    return _table(head, rows, "lrrrrl", [16, 17, 14, 15, 15, 23])


def before_after_table(run: DiagnosisRun, nominal: RigidBody | None) -> str:
    """Mass, CoG, principal moments before and after the diagnosis with their 1-σ, and the mesh's."""
    result = run.result
    before, after = result.estimates[0].body, result.corrected
    s0, s1 = property_std(result.estimates[0]), property_std(result.estimates[1])
    picked = ("mass", "CoG x", "CoG y", "CoG z", "principal moment 1", "principal moment 2", "principal moment 3")
    columns = []
    for body, std in ((before, s0), (after, s1), (nominal, None)):
        if body is None:
            columns.append(None)
            continue
        sig = sigmas(std) if std is not None else [None] * len(quantities(body))
        columns.append({q[0]: (q[1], q[3], s) for q, s in zip(quantities(body), sig)})
    rows = []
    for name in picked:
        unit = "mm" if name.startswith("CoG") else "kg" if name == "mass" else "kg·m²"
        cells = []
        for k, column in enumerate(columns):
            if column is None:
                cells.append("no body" if k < 2 else "—")
                continue
            value, scale, sigma = column[name]
            if run.planar and (name == "CoG z" or name.startswith("principal")):
                cells.append("unobservable" if k < 2 else _num(value * scale, ".6g"))
                continue
            cells.append(_with_sigma(value, sigma, scale))
        rows.append([_e(name), *cells, unit])
    return _table(
        ["property", "before ± 1-σ", "after ± 1-σ", "nominal (mesh)", "unit"], rows, "lrrrl", [22, 27, 27, 14, 10]
    )


def diagnose_report(run: DiagnosisRun, uff_path, mesh: BodyMesh | None = None) -> Report:
    """The diagnosis report of ``run`` (``massline diagnose --report``), against ``mesh`` when given."""
    result, recording, noise = run.result, run.recording, run.noise
    nominal = None if mesh is None else mesh.nominal
    sensors, hits = run.sensors, run.hits
    before, after = result.relative_rms("before"), result.relative_rms("after")
    if result.findings:
        findings = "<ol>" + "".join(f"<li>{_e(finding_note(x, sensors, hits))}</li>" for x in result.findings) + "</ol>"
    else:
        findings = f"<p>No findings: the rigid body fits every line within the noise ({before / noise:.2f}× it).</p>"
    fit_line = (
        f"<p>Fit: relative RMS residual <b>{100 * before:.2f} % before, {100 * after:.2f} % after</b> "
        f"({before / noise:.2f}× → {after / noise:.2f}× the noise of {100 * noise:.2f} %).</p>"
    )
    flagged_sensors, flagged_hits = _flagged(result.findings)
    body = result.corrected if result.corrected is not None else result.estimates[0].body
    scene = None
    renderings, views = [], '<p class="note">No body fits the recording: nothing to draw.</p>'
    if body is not None:
        flagged = (flagged_sensors, flagged_hits)
        scene, renderings, views = _body_views(mesh, recording, sensors, hits, body, run.planar, flagged)
        views = (
            _legend(scene, "corrected")
            + views
            + axes_table(body, property_std(result.estimates[1]), nominal, run.planar)
        )
    off_rigid = run.off_rigid()
    maps = diagnosis_figure(result, run.band, sensors, hits, off_rigid, grid=True)
    maps_caption = (
        "Top: each FRF's RMS residual over the band in units of its own noise, before and after the diagnosis. "
        "Bottom: the worst FRF before, as recorded, with both models (massline and tails as fitted)"
        + ("." if off_rigid is None else "; each recorded channel's distance from the rigid motions (model-free).")
    )
    levels = {"model before": result.before.masslines, "model after": result.after.masslines}
    first = _worst_of_findings(run)
    picks = representative(recording.sensors, recording.exciters, result.before.masslines, 6, first)
    band = run.band
    f_band = (float(band.frequencies[0]), float(band.frequencies[-1]))
    frfs = frf_figure(recording.frequencies, recording.frf, f_band, picks, sensors, hits, levels)
    swapped = bool(result.flips or result.swaps)
    frf_caption = (
        f"Recorded FRFs (the channels the findings name first) with the diagnosis band {_num(f_band[0], '.1f')}–"
        f"{_num(f_band[1], '.1f')} Hz ({_e(run.zones.rule)}) and each model's massline for that FRF"
        + ("; after the diagnosis, flipped or swapped channels are modelled as corrected" if swapped else "")
        + ". The properties are estimated over the band identify would use, "
        f"{_num(run.found.low, '.1f')}–{_num(run.found.high, '.1f')} Hz, with every FRF's tails."
    )
    parts = [
        f"<h1>Diagnosis: {_e(Path(uff_path).name)}</h1>",
        f'<p class="note">{_recording_line(recording, uff_path)} {_body_line(mesh)} The model: the '
        "rigid body, every channel reading a little across its axis (the datasheet's transverse sensitivity).</p>",
        "<section><h2>Findings</h2>" + findings + fit_line + "</section>",
        "<section><h2>Properties before and after</h2>"
        + before_after_table(run, nominal)
        + '<p class="note">After: with every finding modelled (and loading masses taken away).</p></section>',
        "<section><h2>Residual maps and overlays</h2>" + _plot(maps, "residual maps", maps_caption) + "</section>",
        "<section><h2>Fit per channel</h2>"
        + channel_table(run)
        + '<p class="note">Relative RMS residual of each channel over the band and every hit.</p></section>',
        "<section><h2>Principal axes on the body (after)</h2>" + views + "</section>",
    ]
    if scene is not None:
        parts.append(_turn_it(scene))
    parts.append(
        "<section><h2>FRFs and the band</h2>" + _plot(frfs, "FRFs with both models", frf_caption) + "</section>"
    )
    return Report(_page(f"Diagnosis: {Path(uff_path).name}", parts), renderings)


def _worst_of_findings(run: DiagnosisRun) -> list:
    """For each finding, the FRF of its channel (or hit) the nominal model fitted worst."""
    rss = run.result.before.rss
    picks = []
    for finding in run.result.findings:
        if finding.channels:
            i = finding.channels[0]
            picks.append((i, int(np.argmax(rss[i]))))
        elif finding.exciter is not None:
            j = finding.exciter
            picks.append((int(np.argmax(rss[:, j])), j))
    return picks
