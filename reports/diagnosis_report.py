"""The diagnosis report (``massline diagnose --report``): the findings, the fit before and after, residual
maps and overlays, the properties before and after, and the corrected body's principal axes."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from massline.identify.diagnose.screens import roomy
from massline.identify.diagnose.notes import finding_note, fit_sentence, verdict
from massline.identify.diagnose.diagnosis_run import DiagnosisRun
from massline.meshes.loader import BodyMesh
from massline.core.numbers import number
from massline.core.properties import SUMMARY
from massline.core.rigid_body import RigidBody
from massline.reports.diagnosis_figures import diagnosis_figure
from massline.reports.html import Report, escape, html_table, num, page, plot_figure, with_sigma
from massline.reports.identification_figures import frf_figure, representative
from massline.reports.identification_report import (
    axes_table,
    body_line,
    body_views,
    legend,
    recording_line,
    turn_it,
)


def _flagged(findings) -> tuple[set, set]:
    """Sensor lines and hits the findings name (0-based)."""
    sensors = {c for x in findings for c in x.channels}
    hits = {x.exciter for x in findings if x.exciter is not None}
    return sensors, hits


def channel_table(run: DiagnosisRun) -> str:
    """Per channel: relative RMS residual before and after, also in units of the noise; the ones a finding names."""
    result, noise = run.result, run.result.noise
    before, after = result.relative_rms("before", axis=1), result.relative_rms("after", axis=1)
    named, _ = _flagged(run.findings)
    rows = [
        [
            escape(name),
            f"{100 * before[k]:.2f} %",
            f"{100 * after[k]:.2f} %",
            num(before[k] / noise, ".2f"),
            num(after[k] / noise, ".2f"),
            "named by a finding" if k in named else "",
        ]
        for k, name in enumerate(run.sensors)
    ]
    head = ["channel", "residual before", "after", "before / noise", "after / noise", ""]
    return html_table(head, rows, "lrrrrl", [16, 17, 14, 15, 15, 23])


def before_after_table(run: DiagnosisRun, nominal: RigidBody | None) -> str:
    """Mass, CoG, principal moments before and after the diagnosis with their 1-σ, and the mesh's."""
    before = (None, None) if run.before is None else (run.before.body, run.before.std)
    columns = [before, (run.after_body, None if run.after is None else run.after.std), (nominal, None)]
    rows = []
    for q in SUMMARY:
        cells = []
        for k, (body, std) in enumerate(columns):
            if body is None:
                cells.append(("refused", "no body")[k] if k < 2 else "—")
                continue
            if std is None:  # the mesh's
                cells.append(number(q.value(body) * q.scale))
                continue
            cells.append(with_sigma(q.value(body, run.planar), q.sigma(std), q.scale))
        rows.append([escape(q.name), *cells, q.unit])
    return html_table(
        ["property", "before ± 1-σ", "after ± 1-σ", "nominal (mesh)", "unit"], rows, "lrrrl", [22, 27, 27, 14, 10]
    )


def caveats(run: DiagnosisRun) -> str:
    """What limits the diagnosis: no redundancy, identify's refusal or warnings (a warnings block, or '')."""
    warned = () if run.before is None else run.before.warnings
    lines = [note.text for note in run.notes] + [f"identify: {w.text}" for w in warned]
    if not roomy(run.layout):
        lines.insert(
            0,
            f"{len(run.layout.sensors)} sensor channels leave no redundancy: a faulty channel cannot be told from "
            "the body's properties (diagnosis needs at least 8 channels, 5 for a plate)",
        )
    if not lines:
        return ""
    return '<div class="warnings"><ul>' + "".join(f"<li>{escape(x)}</li>" for x in lines) + "</ul></div>"


def diagnose_report(run: DiagnosisRun, uff_path, mesh: BodyMesh | None = None) -> Report:
    """The diagnosis report of ``run`` (``massline diagnose --report``), against ``mesh`` when given."""
    result, recording, noise = run.result, run.recording, run.result.noise
    nominal = None if mesh is None else mesh.nominal
    sensors, hits = run.sensors, run.hits
    before, after = result.relative_rms("before"), result.relative_rms("after")
    if run.findings:
        findings = (
            "<ol>" + "".join(f"<li>{escape(finding_note(x, sensors, hits))}</li>" for x in run.findings) + "</ol>"
        )
    said = verdict(run.findings, run.chi2)
    if said:
        findings = f"<p>{escape(said[0].upper() + said[1:])}.</p>" + (findings if run.findings else "")
    findings = caveats(run) + findings
    fit_line = f"<p>{escape(fit_sentence(run.chi2, before, after, noise).replace('fit:', 'Fit:', 1))}.</p>"
    flagged_sensors, flagged_hits = _flagged(run.findings)
    body = run.after_body
    std = None if run.after is None else run.after.std
    scene = None
    renderings, views = [], '<p class="note">No body fits the recording: nothing to draw.</p>'
    if body is not None:
        flagged = (flagged_sensors, flagged_hits)
        scene, renderings, views = body_views(mesh, recording, sensors, hits, body, run.planar, flagged)
        views = legend(scene, "corrected") + views + axes_table(body, std, nominal, run.planar)
    off_rigid = run.off_rigid()
    maps = diagnosis_figure(result, run.data, run.noise, sensors, hits, off_rigid, grid=True)
    maps_caption = (
        "Top: each FRF's RMS residual over the band in units of its own noise, before and after the diagnosis. "
        "Bottom: the worst FRF before, as recorded, with both models (massline and tails as fitted)"
        + ("." if off_rigid is None else "; each recorded channel's distance from the rigid motions (model-free).")
    )
    levels = {"model before": result.before.masslines, "model after": result.after.masslines}
    first = _worst_of_findings(run)
    picks = representative(recording.sensors, recording.exciters, result.before.masslines, 6, first)
    band = run.data
    f_band = (float(band.frequencies[0]), float(band.frequencies[-1]))
    frfs = frf_figure(recording.frequencies, recording.frf, f_band, picks, sensors, hits, levels)
    swapped = bool(result.fixes)
    frf_caption = (
        f"Recorded FRFs (the channels the findings name first) with the diagnosis band {num(run.band.low, '.1f')}–"
        f"{num(run.band.high, '.1f')} Hz ({escape(run.band.rule)}) and each model's massline for that FRF"
        + ("; after the diagnosis, flipped or swapped channels are modelled as corrected" if swapped else "")
        + ". The properties are identify's, on its band "
        f"{num(run.estimation_band.low, '.1f')}–{num(run.estimation_band.high, '.1f')} Hz, with every FRF's tails."
    )
    parts = [
        f"<h1>Diagnosis: {escape(Path(uff_path).name)}</h1>",
        f'<p class="note">{recording_line(recording, uff_path)} {body_line(mesh)} The model: the '
        "rigid body, every channel reading a little across its axis (the datasheet's transverse sensitivity).</p>",
        "<section><h2>Findings</h2>" + findings + fit_line + "</section>",
        "<section><h2>Properties before and after</h2>"
        + before_after_table(run, nominal)
        + '<p class="note">Before: identify on the file as it came. After: identify on the recording with every '
        "fault undone (and loading masses taken away); with no fault, the same.</p></section>",
        "<section><h2>Residual maps and overlays</h2>"
        + plot_figure(maps, "residual maps", maps_caption)
        + "</section>",
        "<section><h2>Fit per channel</h2>"
        + channel_table(run)
        + '<p class="note">Relative RMS residual of each channel over the band and every hit.</p></section>',
        "<section><h2>Principal axes on the body (after)</h2>" + views + "</section>",
    ]
    if scene is not None:
        parts.append(turn_it(scene))
    parts.append(
        "<section><h2>FRFs and the band</h2>" + plot_figure(frfs, "FRFs with both models", frf_caption) + "</section>"
    )
    return Report(page(f"Diagnosis: {Path(uff_path).name}", parts), renderings)


def _worst_of_findings(run: DiagnosisRun) -> list:
    """For each finding, the FRF of its channel (or hit) the nominal model fitted worst."""
    rss = run.result.before.rss
    picks = []
    for finding in run.findings:
        if finding.channels:
            i = finding.channels[0]
            picks.append((i, int(np.argmax(rss[i]))))
        elif finding.exciter is not None:
            j = finding.exciter
            picks.append((int(np.argmax(rss[:, j])), j))
    return picks
