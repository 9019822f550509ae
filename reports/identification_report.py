"""The identification report: one self-contained HTML page, printable on A4, readable offline; and the
page pieces the diagnosis report (:mod:`.diagnosis_report`) shares with it.

Assembly only: what ``massline identify`` (:class:`.identify_command.Identification`) or ``massline
diagnose`` (:class:`.diagnose_command.DiagnosisRun`) found, and the nominal mesh when one was given, come
in; the page goes out, with the pictures of :mod:`.rendering` (the body, its channels and the principal
axes of :mod:`.body_scene`), the plots of :mod:`.identification_figures` and :mod:`.diagnosis_figures`,
and the 3-D view of :mod:`.viewer3d`. The page's look and its small HTML helpers are the placement
report's. Values are in the recording's frame; lengths are shown in mm.
"""

from __future__ import annotations

import base64
from pathlib import Path

import numpy as np
from massline import __version__
from massline.diagnose_command import labels
from massline.identify_command import Identification, quantities, sigmas
from massline.placement.mesh import BodyMesh
from massline.placement.rigid_body import RigidBody
from massline.report_command import Report
from massline.reports.body_scene import identification_scene, principal_frame
from massline.reports.identification_figures import fit_figure, frf_figure, representative
from massline.reports.placement_report import STYLE, _e, _figure, _num, _table
from massline.reports.plan_scene import AXIS, FLAGGED, Scene
from massline.reports.rendering import render_views
from massline.reports.viewer3d import viewer_html


def png_uri(data: bytes) -> str:
    """PNG bytes as a data: URI."""
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


def _plot(data: bytes, alt: str, caption: str) -> str:
    """A plot as a figure with its caption."""
    return f'<figure><img src="{png_uri(data)}" alt="{_e(alt)}"><figcaption>{caption}</figcaption></figure>'


def _page(title: str, parts: list[str]) -> str:
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<title>{_e(title)}</title><style>{STYLE}</style></head>\n<body>\n" + "\n".join(parts) + "\n</body></html>\n"
    )


def _recording_line(recording, path) -> str:
    f = recording.frequencies
    n_s, n_e = recording.frf.shape[:2]
    return (
        f"Recording {_e(Path(path).name)}: {n_s} accelerometer channels × {n_e} hits, {len(f)} spectral lines, "
        f"{_num(f[0], '.3g')}–{_num(f[-1], '.4g')} Hz. Frame of the file; written by massline {__version__}."
    )


def _fixed(value: float, digits: int) -> str:
    """A number with ``digits`` decimals and no minus sign on zero."""
    return _num(round(float(value), digits) + 0.0, f".{digits}f")


def _with_sigma(value: float, sigma: float, scale: float) -> str:
    if not np.isfinite(value):
        return "unobservable"
    shown = _num(value * scale, ".6g")
    return shown if sigma is None or not np.isfinite(sigma) else f"{shown} ± {_num(sigma * scale, '.2g')}"


def properties_table(body: RigidBody, std: dict, nominal: RigidBody | None, planar: bool) -> str:
    """Every property with its 1-σ, beside the mesh's value when there is one (difference, and in σ)."""
    rows = []
    reference = quantities(nominal) if nominal is not None else [None] * len(quantities(body))
    for (name, value, unit, scale), sigma, ref in zip(quantities(body), sigmas(std), reference):
        if name.startswith("principal axis"):
            continue
        if planar and not np.isfinite(sigma):
            value = np.nan
        cells = [_e(name), _with_sigma(value, sigma, scale)]
        if ref is not None:
            difference = value - ref[1]
            in_sigma = difference / sigma if np.isfinite(sigma) and sigma > 0 else np.nan
            cells += [
                _num(ref[1] * scale, ".6g"),
                _num(difference * scale, "+.3g"),
                _num(round(in_sigma, 1) + 0.0, "+.1f"),
            ]
        rows.append([*cells, unit])
    head = ["property", "identified ± 1-σ", "unit"]
    if nominal is not None:
        head[2:2] = ["nominal (mesh)", "difference", "in σ"]
        return _table(head, rows, "lrrrrl", [22, 27, 17, 14, 8, 12])
    return _table(head, rows, "lrl", [35, 45, 20])


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
        direction = "(" + ", ".join(_fixed(c, 3) for c in axes[:, k]) + ")"
        row = [f"I{k + 1}", direction, _with_sigma(moments[k], sigma, 1.0)]
        row += [_num(1e3 * np.sqrt(max(moments[k], 0.0) / body.mass), ".1f")]
        row += ["" if std is None else _num(std["principal_axes_deg"][k], ".2g")]
        if nominal is not None:
            row.append(_num(_angle_deg(axes[:, k], reference[:, k]), ".2f"))
        rows.append(row)
    head = ["axis", "direction (x, y, z)", "moment (kg·m²)", "radius of gyration (mm)", "axis 1-σ (°)"]
    if nominal is not None:
        head.append("to the mesh's axis (°)")
        return _table(head, rows, "lrrrrr", [7, 27, 22, 16, 12, 16])
    return _table(head, rows, "lrrrr", [8, 32, 26, 18, 16])


def _legend(scene: Scene, what: str) -> str:
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
    return renderings, '<div class="views">' + "".join(_figure(r, markers) for r in renderings) + "</div>"


def _turn_it(scene: Scene) -> str:
    return (
        '<section class="screen"><h2>Turn it</h2><p class="note">Drag to turn the body (screen only).</p>'
        + viewer_html(scene)
        + "</section>"
    )


def _body_line(mesh: BodyMesh | None) -> str:
    if mesh is None:
        return (
            "No mesh was given (--mesh): the body is drawn as the hull of the test points and there are no nominal "
            "values to compare with."
        )
    density, mass = _num(mesh.density, "g"), _num(mesh.nominal.mass)
    return f"Nominal body: mesh {_e(mesh.name)}, density {density} kg/m³, mass {mass} kg."


def _body_views(mesh, recording, sensors, hits, body, planar, flagged=((), ())):
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


def identify_report(found: Identification, uff_path, mesh: BodyMesh | None = None) -> Report:
    """The identification report of ``found`` (``massline identify --report``), against ``mesh`` when given."""
    recording, zones, fit = found.recording, found.zones, found.fit
    sensors, hits = labels(recording)
    nominal = None if mesh is None else mesh.nominal
    scene, renderings, views = _body_views(mesh, recording, sensors, hits, found.body, found.planar)
    picks = representative(recording.sensors, recording.exciters, fit.values)
    notes = {
        (i, j): f"massline {_num(fit.values[i, j], '.4g')} ± {_num(fit.std[i, j], '.2g')}, "
        f"fit RMS {100 * fit.quality[i, j]:.2f} %"
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
    bounds = [
        f"the highest suspension resonance at {_num(zones.suspension_top, '.2f')} Hz"
        if np.isfinite(zones.suspension_top)
        else "",
        f"the first elastic one at {_num(zones.first_elastic, '.0f')} Hz" if np.isfinite(zones.first_elastic) else "",
    ]
    bounds = " and ".join(b for b in bounds if b)
    band_note = (
        f"Band {_num(zones.low, '.1f')}–{_num(zones.high, '.1f')} Hz ({_e(zones.rule)}"
        + (f"; above {bounds}" if bounds else "")
        + ", dash-dot). Every FRF is fitted there with A + B/ω² + Cω² + Dω⁴ so that the suspension and "
        f"residual-flexibility tails do not bias its massline A. Band fits: median RMS residual "
        f"{100 * np.median(fit.quality):.2f} % of the massline, worst {100 * fit.quality.max():.2f} %; a plain "
        f"average over the band would be off by up to {100 * fit.bias.max():.1f} %."
    )
    method = "weighted estimate over all masslines, physically consistent" if found.method == "best" else found.method
    fit_note = (
        f"Reduced χ² {_num(found.best.chi2, '.3g')} over {found.data.values.size} masslines"
        + ("; the physical-consistency constraint is active" if found.best.constrained else "")
        + ". The ± is the larger of the information-based 1-σ (scaled by the reduced χ²) and a bootstrap over the "
        "sensors."
    )
    summary = _summary(found.body, found.std, nominal, found.planar)
    parts = [
        f"<h1>Identification: {_e(Path(uff_path).name)}</h1>",
        f'<p class="note">{_recording_line(recording, uff_path)} {_body_line(mesh)}</p>',
        f"<p>{summary}</p>",
        f"<section><h2>Properties ({_e(method)})</h2>"
        + properties_table(found.body, found.std, nominal, found.planar)
        + f'<p class="note">{fit_note} J about the CoG, tensor sign (off-diagonals are minus the products of '
        "inertia).</p></section>",
        "<section><h2>Principal axes on the body</h2>"
        + _legend(scene, "identified")
        + views
        + axes_table(found.body, found.std, nominal, found.planar)
        + "</section>",
        _turn_it(scene),
        "<section><h2>FRFs and the massline band</h2>" + _plot(frfs, "representative FRFs", band_note) + "</section>",
        "<section><h2>How well the identified body fits the masslines</h2>"
        + _plot(fitted, "masslines against the identified body", "Each point is one FRF's massline with its 1-σ.")
        + "</section>",
    ]
    return Report(_page(f"Identification: {Path(uff_path).name}", parts), renderings)


def _summary(body: RigidBody, std: dict, nominal: RigidBody | None, planar: bool) -> str:
    """One sentence: mass, CoG and principal moments with their 1-σ, and how far they are from the mesh's."""
    text = (
        f"<b>Mass {_num(body.mass, '.5g')} ± {_num(std['mass'], '.2g')} kg</b>, CoG ("
        + ", ".join(_fixed(1e3 * c, 1) if np.isfinite(s) else "—" for c, s in zip(body.cog, std["cog"]))
        + ") mm"
    )
    if not planar:
        text += ", principal moments " + ", ".join(_num(v, ".4g") for v in body.principal_moments) + " kg·m²"
    if nominal is not None:
        text += f"; against the mesh: mass {100 * (body.mass / nominal.mass - 1):+.2f} %"
        cog = np.linalg.norm((body.cog - nominal.cog)[: 2 if planar else 3])
        text += f", CoG {_num(1e3 * cog, '.2f')} mm off"
        if not planar:
            worst = np.abs(body.principal_moments / nominal.principal_moments - 1).max()
            text += f", principal moments within {100 * worst:.2f} %"
    return text + "."
