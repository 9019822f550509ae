"""What ``massline plan`` prints: the layout's tables (with each point's mount), the predicted accuracy, the
criterion and its certificate, sliding, the mounting blocks and the diagnosability."""

from __future__ import annotations

import numpy as np
from rich.console import Console
from rich.table import Table

from massline.core.lines import Lines
from massline.core.numbers import counted, formatted, number, sigma_text, vector_text
from massline.placement.mounts import motion_text, mounts
from massline.placement.reach import reach_sentence
from massline.placement.plan_file import condition_systems


def layout_table(title: str, lines: Lines, nodes, labels, mounted) -> Table:
    """One row per line: its point's label (the test's numbering, as in plan.json, the report and the Universal
    File), where it is, which way it reads and how it is mounted (:mod:`massline.placement.mounts`); "fixed" for a
    line the user gave."""
    table = Table(title=title)
    for col in ("#", "point", "x (mm)", "y (mm)", "z (mm)", "direction", "triaxial", "mount"):
        table.add_column(col, justify="right")
    rows = zip(nodes, labels, lines.points, lines.directions, lines.triaxial, mounted)
    for k, (n, label, p, d, t, m) in enumerate(rows, 1):
        table.add_row(
            str(k),
            str(label) + ("" if n >= 0 else " (fixed)"),
            *(formatted(v * 1e3, ".1f") for v in p),
            vector_text(d, 3),
            "" if t < 0 else str(t),
            m.text,
        )
    return table


def sliding_line(plan) -> str:
    """How far sliding the points on the surface moved them and what it gained over the candidate layout."""
    gain = plan.log_det - plan.candidate_log_det
    moved = 0.0 if plan.sliding is None else float(plan.sliding.moved.max(initial=0.0))
    sensor, hit = (1e3 * c for c in plan.clearances)
    by_criterion = (
        ""
        if plan.criterion.name == "D" or plan.sliding is None
        else f"raised {plan.criterion.title} by {plan.sliding.gain:.3g} and "
    )
    return (
        f"sliding the points on the surface (up to {1e3 * moved:.1f} mm; sensors ≥ {sensor:.3g} mm and hits "
        f"≥ {hit:.3g} mm from every edge) {by_criterion}changed log det F by {gain:+.3f} over the best candidate "
        f"layout (D-efficiency × {np.exp(gain / plan.model.p):.3f})"
    )


AXIS_UNDETERMINED = "any (equal moments)"  # an axis whose 1-σ passes 90°: its two moments are equal or nearly


def std_table(plan) -> Table:
    b, s = plan.model.nominal, plan.predicted_std
    table = Table(title="Predicted accuracy (Cramér–Rao of the criterion's noise model, 1-σ; no band predicted)")
    for col in ("quantity", "nominal", "± 1-σ", "unit", "relative"):
        table.add_column(col, justify="right")
    rows = [("mass", b.mass, s["mass"], "kg", b.mass)]
    rows += [
        (f"CoG {a}", b.cog[k] * 1e3, s["cog"][k] * 1e3, "mm", b.radius_of_gyration * 1e3) for k, a in enumerate("xyz")
    ]
    moments = (
        b.principal_moments if not plan.model.planar else np.append(np.linalg.eigvalsh(b.inertia_cog[:2, :2]), np.nan)
    )
    rows += [
        (f"principal moment {k + 1}", moments[k], s["principal_moments"][k], "kg·m²", moments[k]) for k in range(3)
    ]
    rows += [(f"principal axis {k + 1}", np.nan, s["principal_axes_deg"][k], "°", np.nan) for k in range(3)]
    for name, value, sigma, unit, ref in rows:
        if np.isnan(sigma):
            table.add_row(name, number(value, 5, scale=ref), "unobservable", unit, "")
            continue
        table.add_row(
            name,
            "" if np.isnan(value) else number(value, 5, scale=ref),
            AXIS_UNDETERMINED if unit == "°" and sigma > 90 else sigma_text(sigma),
            unit,
            "" if np.isnan(ref) else f"{sigma / ref:.2%}",
        )
    return table


def certificate_note(certificate) -> str:
    """" (its branch and bound stopped after N relaxation steps; …)" when its budget ended it, else ""."""
    if certificate is None or not certificate.stopped:
        return ""
    return f" (its branch and bound stopped after its {certificate.limit} {certificate.unit}: a tighter bound may hold)"


def criterion_text(result) -> str:
    """The criterion, its certificate, λ_min, the D certificate and the paper's condition numbers."""
    c, systems = result.criterion, condition_systems(result.model.planar)
    d_too = "" if c.name == "D" else f", D-efficiency ≥ {result.d_efficiency_lower_bound:.1%}"
    lines = [
        f"criterion {c.name}: {c.title} = {result.value:.4g}; the candidate layout's certified {c.name}-efficiency ≥ "
        f"{result.efficiency_lower_bound:.1%} of the best layout changing the sensors alone or the exciters alone"
        + certificate_note(result.certificate),
        f"log det F = {result.log_det:.3f} ({result.model.p} parameters){d_too}; smallest eigenvalue of F "
        f"(relative parameters) {result.smallest_eigenvalue:.4g}",
        "condition numbers: " + ", ".join(f"{systems.get(k, k)} {v:.3g}" for k, v in result.condition.items()),
    ]
    return "\n".join(lines)


def blocks_note(console: Console, result) -> None:
    """Which motion the normals miss and where the planner put mounting blocks for it
    (:func:`massline.placement.candidates.blocks_needed`)."""
    missed = {motion_text(t) for twists in result.blocks for t in twists}
    if not missed:
        return
    used = [sum(m.kind == "block" for m in mounts(result, k)) for k in (0, 1)]
    axis = " (a turned part's axis)" if all("rotation" in m for m in missed) else ""
    console.print(
        f"[yellow]mounting blocks:[/] no surface normal reads or drives the {' or the '.join(sorted(missed))}{axis}, "
        f"so {used[0]} "
        f"accelerometer line(s) and {used[1]} hit(s) sit on blocks glued to the surface, read or struck on their "
        f"sides along it (mount \"block\"): as few as the motion needs (one line and one hit read and drive it, three "
        f"lines and two hits check each other; more where fewer leave no well-posed layout), the rest on the surface"
    )


def reach_note(console: Console, result) -> None:
    """How many candidate places the hammer's approach, the accelerometer's housing and its cable took
    (:mod:`massline.placement.reach`)."""
    points = result.candidates
    if points is not None and points.reach is not None:
        console.print(reach_sentence(points.excluded, len(points)))


def diagnosability_note(console: Console, result) -> None:
    """Diagnosable or not, what it costs against the minimal layout, which channels could hide a fault."""
    d = result.diagnosability
    if d.diagnosable:
        console.print(
            f"diagnosable: every channel (leverage ≤ {d.channel_leverage.max():.2f}) and every hit "
            f"(≤ {d.hit_leverage.max():.2f}) is checked by the others: one faulty channel or hit can be located"
        )
    else:
        console.print("[yellow]not diagnosable:[/] " + "; ".join(d.failures))
        weak = d.weak_channels
        if weak:
            console.print(
                f"channels {', '.join(str(k + 1) for k in weak)} could hide a gain, polarity or direction fault"
            )
    if result.search is not None:
        colour = "yellow" if result.search.stopped else "default"
        console.print(f"[{colour}]diagnosable search: {result.search.sentence}[/]")
    if result.minimal is not None:
        m = result.minimal
        console.print(
            f"diagnosability costs {counted(len(result.sensors) - len(m.sensors), 'line')} and "
            f"{counted(len(result.exciters) - len(m.exciters), 'hit')} over the minimal {len(m.sensors)} × {len(m.exciters)} "
            f"layout (--minimal); predicted worst 1-σ {result.worst_relative_std:.2%} against its "
            f"{m.worst_relative_std:.2%}"
        )
