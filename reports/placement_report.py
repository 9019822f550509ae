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

from massline import __version__
from massline.reports.html import STYLE, escape, html_table, num, rendering_figure
from massline.reports.plan_scene import HIT, SENSOR, Scene, face_name
from massline.reports.rendering import Rendering
from massline.reports.viewer3d import viewer_html


@dataclass(frozen=True)
class BandRow:
    """One suspension's predicted massline band: its description and edges, Hz."""

    suspension: str
    suspension_top: float
    low: float
    high: float
    first_elastic: float


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


def points_table(scene: Scene, fixed: set = frozenset()) -> str:
    """Number (marked when ``fixed``), plan lines, coordinates (mm), direction and the face of every
    accelerometer and hit."""
    rows = []
    for m, n, f in zip(scene.markers, scene.normals, scene.faces):
        css = "sensor" if m.kind == SENSOR else "hit"
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
            ]
        )
    head = ["#", "plan line", "x (mm)", "y (mm)", "z (mm)", "direction", "face"]
    return html_table(head, rows, "llrrrll", [6, 8, 10, 10, 10, 24, 32])


def _moments(doc: dict) -> np.ndarray:
    """Nominal principal moments matching predicted_std's: in-plane ones (and nan) for a plate."""
    J = np.asarray(doc["nominal"]["inertia_cog"])
    if doc.get("planar"):
        return np.append(np.linalg.eigvalsh(J[:2, :2]), np.nan)
    return np.asarray(doc["nominal"]["principal_moments"])


def _float(value) -> float:
    """A plan.json number; null (unobservable) is nan."""
    return np.nan if value is None else float(value)


def accuracy_table(doc: dict) -> str:
    """Nominal value and predicted 1-σ (Cramér–Rao) of every property, with units."""
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
    worst = num(100 * _float(c.get("worst_relative_std")), ".2f")
    relative, floor = (num(100 * _float(noise.get(k)), ".3g") for k in ("relative", "floor"))
    rows = [
        ["certified D-efficiency", f"≥ {efficiency} % of the best layout of candidate points"],
        ["log det F", f"{num(c['log_det'], '.3f')} over {len(names)} parameters: {escape(', '.join(names))}"],
        *[[f"condition number, {escape(k)}", num(v, ".3g")] for k, v in c.get("condition_numbers", {}).items()],
        ["worst relative 1-σ", f"{worst} % (mass, CoG against the radius of gyration, principal moments)"],
        ["noise model", f"{relative} % of each massline + {floor} % of 1/m"],
    ]
    rows += mounting_rows(doc)
    lines = doc.get("candidates", {}).get("lines") or {}
    if lines:
        rows.append(["candidate lines", ", ".join(f"{v} {escape(k)}" for k, v in lines.items())])
    return html_table(None, rows, "ll", [30, 70])


def mounting_rows(doc: dict) -> list:
    """Where points may go (clearance from edges) and what sliding them on their faces gained."""
    mounting, sliding = doc.get("mounting"), doc["criterion"].get("sliding")
    rows = []
    if mounting:
        sensor, hit = (num(1e3 * _float(mounting.get(k)), ".3g") for k in ("sensor_clearance_m", "hit_clearance_m"))
        rows.append(
            ["mountable points", f"on flat faces, accelerometers ≥ {sensor} mm and hits ≥ {hit} mm from every edge"]
        )
    if sliding:
        gain, moved = _float(sliding.get("gain")), 1e3 * _float(sliding.get("largest_move_m"))
        rows.append(
            [
                "sliding off the candidate grid",
                f"log det F + {num(gain, '.3f')} over the certified candidate layout (D-efficiency × "
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
        out.append([escape(r.suspension), num(r.suspension_top, ".2f"), span, num(r.first_elastic, ".0f"), width])
    head = ["suspension", "top susp. mode (Hz)", "band (Hz)", "1st elastic (Hz)", "width"]
    return html_table(head, out, "lrrrr", [42, 14, 18, 14, 12]) + f'<p class="note">{escape(fe_note)}</p>'


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
        Predicted massline bands, the recommended suspension first.
    fe_note : str
        How the first elastic frequency was found.
    """
    markers = scene.markers
    n_acc = sum(m.kind == SENSOR for m in markers)
    title = f"Test plan: {escape(Path(doc.get('mesh') or 'mesh').name)}"
    legend = (
        '<p class="note"><span class="sensor">A1 …</span> accelerometers, arrow along the measuring direction '
        '(triaxials: three arrows, one number); <span class="hit">H1 …</span> hammer hits, arrow into the surface '
        "at the hit point (moved aside where a hit shares an accelerometer's point); the black and white disc "
        "marks the nominal centre of gravity (drawn on top even where the body hides it); axes in the corner. "
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
        "<section><h2>Points</h2>" + points_table(scene, fixed_labels(doc, scene)),
        "<p class=\"note\">Coordinates in the mesh's frame; 'plan line' numbers the lines of plan.json "
        "(sensors and exciters counted separately, from 1), as <code>massline simulate --effect NAME=SIZE@N</code> "
        "numbers them.</p></section>",
        "<section><h2>Predicted accuracy (1-σ, Cramér–Rao)</h2>" + accuracy_table(doc) + "</section>",
        "<section><h2>Conditioning and optimality</h2>" + criterion_html(doc) + "</section>",
        "<section><h2>Massline band and suspension</h2>" + band_html(bands, fe_note) + "</section>",
    ]
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<title>{title}</title><style>{STYLE}</style></head>\n<body>\n" + "\n".join(parts) + "\n</body></html>\n"
    )
