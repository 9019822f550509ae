"""The placement report: one self-contained HTML page, printable on A4, readable offline.

Pure assembly: the plan document (plan.json), the scene of :mod:`.plan_scene`,
the pictures of :mod:`.rendering` and the predicted massline bands come in, one
HTML string goes out (with the 3-D view of :mod:`.viewer3d`). Pictures are embedded as base64 PNG; nothing is
fetched from a network. Coordinates are in the mesh's frame O xyz and shown in
mm; plan.json holds them in m.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from massline.core import __version__
from massline.core.numbers import counted
from massline.placement.mountable import SHARP_EDGE_DEG
from massline.placement.mounts import Mount
from massline.placement.reach import reach_sentence
from massline.reports.html import STYLE, escape, html_table, num, rendering_figure
from massline.reports.plan_scene import ADDED, HIT, SENSOR, Scene, face_name
from massline.reports.rendering import Rendering
from massline.reports.next_run_section import next_run_html
from massline.reports.viewer3d import viewer_html
from massline.virtual.housing_loading import assumed_sentence, loading_sentence

ONE_SIDE = (
    "the best layout of candidate points changing the sensors alone or the exciters alone"  # what the bounds cover
)


@dataclass(frozen=True)
class BandRow:
    """One suspension's predicted massline band: its description, edges (Hz) and tolerance (every FRF within it
    of its massline)."""

    suspension: str
    suspension_top: float
    low: float
    high: float
    first_elastic: float
    tolerance: float


def _direction(d: np.ndarray) -> str:
    """'+z' for an axis, else the unit vector with two decimals."""
    k = int(np.argmax(np.abs(d)))
    if abs(d[k]) > 0.9999:
        return f"{'+' if d[k] > 0 else '−'}{'xyz'[k]}"
    return "(" + ", ".join(num(c + 0.0, ".2f") for c in d) + ")"


def fixed_labels(doc: dict, scene: Scene) -> set:
    """Labels of the markers whose lines the plan holds as fixed (mounted or decided before planning)."""
    fixed = {
        kind: {i for i, entry in enumerate(doc[key]) if entry.get("fixed")}
        for kind, key in ((SENSOR, "sensors"), (HIT, "exciters"))
    }
    return {m.label for m in scene.markers if fixed.get(m.kind, set()) & set(m.lines)}


def mount_texts(doc: dict, scene: Scene) -> dict:
    """How each marker is mounted (plan.json ``mount``, :mod:`massline.placement.mounts`), by label, in the
    console's words (``Mount.text``: flat, film 0.05 mm, pad 0.47 mm, curved, block, fixed); plans written before
    it was kept give none."""
    out = {}
    for m in scene.markers:
        entries = doc["sensors" if m.kind == SENSOR else "exciters"]
        mount = entries[m.lines[0]].get("mount") if m.lines and m.lines[0] < len(entries) else None
        if mount:
            gap = _float(mount.get("gap_m"))
            out[m.label] = Mount(str(mount.get("kind")), 0.0 if np.isnan(gap) else gap).text
    return out


def points_table(scene: Scene, fixed: set = frozenset(), mounted: dict | None = None) -> str:
    """Number (marked when ``fixed``), plan lines, coordinates (mm), direction, the face and how it is mounted
    (``mounted``, by label) of every accelerometer and hit."""
    mounted = mounted or {}
    rows = []
    for m, n, f in zip(scene.markers, scene.normals, scene.faces):
        css = {SENSOR: "sensor", ADDED: "added"}.get(m.kind, "hit")
        what = "triaxial: " + ", ".join(_direction(d) for d in m.directions) if len(m.directions) == 3 else ""
        face = face_name(n)
        face = f"oblique, n = {_direction(n)}" if face == "oblique" else face
        rows.append(
            [
                f'<span class="{css}">{m.label}</span>' + (" (fixed)" if m.label in fixed else ""),
                ", ".join(str(i + 1) for i in m.lines),
                *(num(c * 1e3, ".1f") for c in m.point),
                what or _direction(m.directions[0]),
                f"{face} (triangle {f})",
                mounted.get(m.label, ""),
            ]
        )
    head = ["#", "plan line", "x (mm)", "y (mm)", "z (mm)", "direction", "face", "mount"]
    return html_table(head, rows, "llrrrlll", [6, 8, 9, 9, 9, 20, 24, 15])


def _moments(doc: dict) -> np.ndarray:
    """Nominal principal moments matching predicted_std's: in-plane ones (and nan) for a plate."""
    J = np.asarray(doc["nominal"]["inertia_cog"])
    if doc.get("planar"):
        return np.append(np.linalg.eigvalsh(J[:2, :2]), np.nan)
    return np.asarray(doc["nominal"]["principal_moments"])


def _float(value) -> float:
    """A plan.json number; null (unobservable) is nan."""
    return np.nan if value is None else float(value)


def housings_html(doc: dict) -> str:
    """What the accelerometers' housings do to the body, as the console said it: the masses given
    (plan.json ``loading``), or the weightless assumption and what typical housings would add
    (``sensor_mass_assumed``); nothing for plans written before either was kept."""
    if doc.get("loading"):
        return f'<p class="note">{escape(loading_sentence(doc["loading"]))}.</p>'
    if doc.get("sensor_mass_assumed"):
        return f'<p class="note">{escape(assumed_sentence(doc["sensor_mass_assumed"]))}.</p>'
    return ""


def budget_note(doc: dict) -> str:
    """What the predicted 1-σ is: the uncertainty budget's sources and what limits each property, or Cramér–Rao."""
    budget = doc.get("uncertainty_budget")
    if not budget:
        return '<p class="note">Cramér–Rao bounds of the criterion\'s noise model (no massline band predicted).</p>'
    c = budget["calibration"]
    said = " ".join(escape(s[0].upper() + s[1:]) + "." for s in budget["limits"])
    return (
        f'<p class="note">The uncertainty budget identify will state: the noise of {budget["band_lines"]} lines in '
        f"the band at {100 * budget['line_noise']:g} % each, each channel's transverse sensitivity "
        f"({100 * c['transverse']:g} % prior), each accelerometer's ({100 * c['sensor']:g} %) and the force "
        f"transducer's ({100 * c['force']:g} %) calibration, in quadrature. {said}</p>"
    )


def accuracy_table(doc: dict) -> str:
    """Nominal value and predicted 1-σ of every property (the uncertainty budget's; Cramér–Rao for a plan without a
    band), with units."""
    nom, std = doc["nominal"], doc["predicted_std"]
    J = np.asarray(nom["inertia_cog"])
    J = np.where(np.abs(J) < 1e-12 * np.abs(J).max(), 0.0, J)  # rounding noise of zero products of inertia
    sJ = [[_float(v) for v in row] for row in std["inertia_cog"]]
    rows = [("mass", nom["mass"], _float(std["mass"]), "kg", True)]
    rows += [(f"CoG {a}", nom["cog"][k] * 1e3, _float(std["cog"][k]) * 1e3, "mm", False) for k, a in enumerate("xyz")]
    pairs = [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2)]
    rows += [(f"J<sub>{'xyz'[i]}{'xyz'[j]}</sub> about CoG", J[i, j], sJ[i][j], "kg·m²", i == j) for i, j in pairs]
    moments, sigmas = _moments(doc), std["principal_moments"]
    rows += [(f"principal moment {k + 1}", moments[k], _float(sigmas[k]), "kg·m²", True) for k in range(3)]
    axes = np.asarray(nom["principal_axes"])
    for k in range(3):
        shown = "" if doc.get("planar") else _direction(axes[:, k])
        rows.append((f"principal axis {k + 1}", shown, _float(std["principal_axes_deg"][k]), "°", False))
    out = []
    for name, value, sigma, unit, relative in rows:
        text = value if isinstance(value, str) else num(value, ".5g")
        rel = num(100 * sigma / abs(value), ".2f") + " %" if relative and np.isfinite(sigma) else ""
        out.append([name, text, num(sigma, ".3g") if np.isfinite(sigma) else "unobservable", unit, rel])
    return html_table(["property", "nominal", "± 1-σ", "unit", "relative"], out, "lrrlr", [30, 25, 17, 12, 16])


def criterion_html(doc: dict) -> str:
    """The certificate, the condition numbers, the noise model and the candidate count."""
    c, noise = doc["criterion"], doc.get("noise", {})
    names = c.get("parameters", [])
    efficiency = num(100 * c["d_efficiency_lower_bound"], ".1f")
    systems = c.get("condition_systems", {})
    worst = num(100 * _float(c.get("worst_relative_std")), ".2f")
    relative, floor = (num(100 * _float(noise.get(k)), ".3g") for k in ("relative", "floor"))
    rows = []
    if "name" in c:
        chosen = num(100 * c["efficiency_lower_bound"], ".1f")
        rows += [
            [f"criterion {escape(c['name'])}", f"{escape(c['title'])} = {num(c['value'], '.4g')}"],
            [f"certified {escape(c['name'])}-efficiency", f"≥ {chosen} % of {ONE_SIDE}"],
            ["smallest eigenvalue of F", f"{num(c['smallest_eigenvalue'], '.4g')} (relative parameters)"],
        ]
    rows += [["certified D-efficiency", f"≥ {efficiency} % of {ONE_SIDE}"]] if c.get("name") != "D" else []
    rows += [
        ["log det F", f"{num(c['log_det'], '.3f')} over {len(names)} parameters: {escape(', '.join(names))}"],
        *[
            [f"condition number, {escape(systems.get(k, k))}", num(v, ".3g")]
            for k, v in c.get("condition_numbers", {}).items()
        ],
        ["worst relative 1-σ", f"{worst} % (mass, CoG against the radius of gyration, principal moments)"],
        ["noise model", f"{relative} % of each massline + {floor} % of 1/m"],
    ]
    rows += mounting_rows(doc)
    lines = doc.get("candidates", {}).get("lines") or {}
    if lines:
        rows.append(["candidate lines", ", ".join(f"{v} {escape(k)}" for k, v in lines.items())])
    return html_table(None, rows, "ll", [30, 70])


def diagnosability_html(doc: dict) -> str:
    """Whether one faulty channel or hit can be located, its cost over the minimal layout, and each
    channel's leverage with the faults it could hide ('' for a plan.json written before it was stated)."""
    d = doc.get("diagnosability")
    if not d:
        return ""
    verdict = "yes: one faulty channel or hit can be located" if d["diagnosable"] else "no: " + "; ".join(d["failures"])
    rows = [["diagnosable", escape(verdict)]]
    c = d.get("cost")
    if c:
        rows.append(
            [
                "cost over the minimal layout",
                f"{counted(c['extra_lines'], 'line')} and {counted(c['extra_hits'], 'hit')} over {c['minimal_lines']} × {c['minimal_hits']}; "
                f"worst relative 1-σ {num(100 * c['worst_relative_std'], '.2f')} % against "
                f"{num(100 * c['minimal_worst_relative_std'], '.2f')} %",
            ]
        )
    if d.get("search"):
        rows.append(["diagnosable search", escape(d["search"]["sentence"])])
    rows.append(["hit leverage", ", ".join(num(h, ".2f") for h in d["hit_leverage"])])
    channels = [
        [str(k + 1), num(h, ".2f"), num(r, ".3f"), escape(", ".join(hidden) or "none")]
        for k, (h, r, hidden) in enumerate(zip(d["channel_leverage"], d["channel_confusion"], d["hidden"]))
    ]
    note = (
        f'<p class="note">A channel of leverage above {num(d["h_max"], ".2f")}, or whose fault looks like another '
        f"channel's (signature correlation above {num(d['r_max'], '.2f')}), cannot be checked by the others: a gain, "
        "polarity or direction fault there is absorbed or blamed elsewhere. A hit of leverage above "
        f"{num(d['h_max'], '.2f')} is one the others cannot do without.</p>"
    )
    head = ["channel", "leverage", "confusion", "faults it could hide"]
    return html_table(None, rows, "ll", [30, 70]) + html_table(head, channels, "lrrl", [15, 15, 15, 55]) + note


def mounting_rows(doc: dict) -> list:
    """Where points may go (clearance from edges) and what sliding them on their faces gained."""
    mounting, sliding = doc.get("mounting"), doc["criterion"].get("sliding")
    rows = []
    if mounting:
        sensor, hit = (num(1e3 * _float(mounting.get(k)), ".3g") for k in ("sensor_clearance_m", "hit_clearance_m"))
        rows.append(
            [
                "mountable points",
                f"on smooth faces, accelerometers ≥ {sensor} mm and hits ≥ {hit} mm from every sharp edge (a crease "
                f"over {SHARP_EDGE_DEG:g}°); on a curve the gap under a base is filled by adhesive or a cemented pad",
            ]
        )
    reach = (mounting or {}).get("reach")
    if reach:
        mm = {k: num(1e3 * _float(v), ".3g") for k, v in reach.items()}
        candidates = doc.get("candidates", {})
        rows.append(
            [
                "reach",
                f"every hit with its hammer's approach clear (a {mm['hammer_head_m']} mm head over a "
                f"{mm['hammer_swing_m']} mm swing along the normal), every accelerometer with its housing "
                f"({mm['sensor_base_m']} mm across, {mm['sensor_height_m']} mm tall) and a {mm['cable_run_m']} mm way "
                f"out for its cable clear of the part. "
                + escape(reach_sentence(candidates.get("dropped") or {}, candidates.get("points") or 0)),
            ]
        )
    if sliding:
        gain, moved = _float(sliding.get("gain")), 1e3 * _float(sliding.get("largest_move_m"))
        rows.append(
            [
                "sliding off the candidate grid",
                f"log det F {num(gain, '+.3f')} over the certified candidate layout (D-efficiency × "
                f"{num(np.exp(gain / max(len(doc['criterion'].get('parameters', [])), 1)), '.3f')}); "
                f"points moved up to {num(moved, '.1f')} mm on their faces",
            ]
        )
    return rows


def band_html(rows: list[BandRow], fe_note: str) -> str:
    """The predicted massline band for each suspension, and how the elastic modes were found."""
    out = []
    for r in rows:
        exists = np.isfinite(r.low) and r.high > r.low
        span = f"{num(r.low, '.1f')} – {num(r.high, '.1f')}" if exists else "no band"
        width = f"{num(r.high / r.low, '.1f')}×" if exists else "—"
        within = num(100 * r.tolerance, "g") + " %" if np.isfinite(r.tolerance) else "—"
        out.append(
            [escape(r.suspension), num(r.suspension_top, ".2f"), span, within, num(r.first_elastic, ".0f"), width]
        )
    head = ["suspension", "top susp. mode (Hz)", "band (Hz)", "every FRF within", "1st elastic (Hz)", "width"]
    return html_table(head, out, "lrrrrr", [36, 12, 16, 12, 12, 12]) + f'<p class="note">{escape(fe_note)}</p>'


def rig_html(rig: dict | None) -> str:
    """How the body is hung (plan.json ``rig``): the apex above the CoG and each bridle leg's attachment point on
    the surface, its length and tension ('' for a plan that keeps none)."""
    if not rig:
        return ""
    if "apex" not in rig:
        return f'<p class="note">Rig: {escape(rig.get("description", ""))}.</p>'
    apex = ", ".join(num(1e3 * c, ".1f") for c in rig["apex"])
    legs = rig.get("legs") or []
    if not legs:
        return f'<p class="note">Rig: the cord is tied on the surface at ({apex}) mm, straight above the CoG.</p>'
    rows = [
        [str(k + 1), *(num(1e3 * c, ".1f") for c in leg["attachment"]), num(1e3 * leg["length_m"], ".0f"),
         num(leg["tension_n"], ".2g")]
        for k, leg in enumerate(legs)
    ]  # fmt: skip
    head = ["leg", "x (mm)", "y (mm)", "z (mm)", "length (mm)", "tension (N)"]
    note = (
        f'<p class="note">Rig (drawn in the views): the cord hangs from its hook to the apex ({apex}) mm, straight '
        f"above the CoG, where a bridle of {len(legs)} stiff legs (wire or rope) meets; each leg is tied at its point "
        "on the surface (an eyelet, a clamp or a shackle; each has a clamp's room along its normal and runs clear of "
        "the body) and cut to the length given, so that the body hangs level, as if the cord were tied at the apex, "
        "which is how the band above was predicted.</p>"
    )
    return note + html_table(head, rows, "lrrrrr", [10, 18, 18, 18, 18, 18])


def report_html(
    doc: dict, body_line: str, scene: Scene, renderings: list[Rendering], bands: list[BandRow], fe_note: str
) -> str:
    """The whole report page.

    Parameters
    ----------
    doc : dict
        plan.json as read.
    body_line : str
        Mesh, units, density, mass and size in one line.
    scene : Scene
        The markers, the face each is on and their arrows.
    renderings : list of Rendering
        The views, each with its labelled picture.
    bands : list of BandRow
        Predicted massline bands, the planned suspension first.
    fe_note : str
        How the first elastic frequency was found.
    """
    markers = scene.markers
    n_acc = sum(m.kind == SENSOR or (m.kind == ADDED and m.label.isdigit() and int(m.label) < 100) for m in markers)
    title = f"Test plan: {escape(Path(doc.get('mesh') or 'mesh').name)}"
    legend = (
        '<p class="note"><span class="sensor">A1 …</span> accelerometers, arrow along the measuring direction '
        '(triaxials: three arrows, one number); <span class="hit">H1 …</span> hammer hits, arrow into the surface '
        "at the hit point (moved aside where a hit shares an accelerometer's point); the black and white disc "
        "marks the nominal centre of gravity (drawn on top even where the body hides it); brown lines: the support's "
        "cord and its bridle's legs, a dot where each leg is tied (also drawn on top); axes in the corner. "
        "Parallel projections in the mesh's frame.</p>"
    )
    parts = [
        f"<h1>{title}</h1>",
        f'<p class="note">{escape(body_line)}. {n_acc} accelerometers ({len(doc["sensors"])} channels), '
        f"{len(markers) - n_acc} hammer hits. Written by massline {__version__}.</p>",
        "<section><h2>Layout</h2>" + legend,
        '<div class="views">' + "".join(rendering_figure(r, markers) for r in renderings) + "</div></section>",
        '<section class="screen"><h2>Turn it</h2><p class="note">Drag to turn the body (screen only).</p>'
        + viewer_html(scene)
        + "</section>",
        "<section><h2>Points</h2>" + points_table(scene, fixed_labels(doc, scene), mount_texts(doc, scene)),
        "<p class=\"note\">Coordinates in the mesh's frame; 'plan line' numbers the lines of plan.json "
        "(sensors and exciters counted separately, from 1), as <code>massline simulate --effect NAME=SIZE@N</code> "
        "numbers them.</p></section>",
        "<section><h2>Predicted accuracy (1-σ)</h2>" + accuracy_table(doc) + budget_note(doc) + housings_html(doc)
        + "</section>",
        next_run_html(doc),
        "<section><h2>Conditioning and optimality</h2>" + criterion_html(doc) + "</section>"
        if doc.get("criterion")
        else "",
        "<section><h2>Diagnosability</h2>" + diagnosability_html(doc) + "</section>"
        if doc.get("diagnosability")
        else "",
        "<section><h2>Massline band and suspension</h2>" + band_html(bands, fe_note) + rig_html(doc.get("rig"))
        + "</section>",
    ]
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<title>{title}</title><style>{STYLE}</style></head>\n<body>\n" + "\n".join(parts) + "\n</body></html>\n"
    )
