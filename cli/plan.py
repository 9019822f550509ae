"""``massline plan``: the layout, its certificate and predicted accuracy, the support the test hangs on and the
massline band it predicts → DIR/plan.json."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

from massline.meshargs import add_mesh_arguments, body_from_arguments
from massline.options import SEED, count, finite, fraction, real
from massline.output import build_report, progress_bar, say_fe_model, say_material, write_report
from massline.placement.candidates import HAMMER_TIP, SENSOR_BASE, CandidateOptions
from massline.placement.diagnosable_plan import EVALUATIONS, cheapest_diagnosable, minimal_budget
from massline.core.errors import MasslineError
from massline.core.files import claim_folder, to_json, write_atomic
from massline.core.information import NoiseModel
from massline.core.lines import Lines
from massline.meshes.loader import UNITS
from massline.core.numbers import counted, formatted, number, sigma_text, vector_text
from massline.placement.on_surface import is_plate, plan
from massline.placement.mounts import motion_text, mounts
from massline.placement.plan_file import condition_systems, plan_to_dict
from massline.placement.planner import Budget
from massline.virtual.fe_process import FEInProcess
from massline.virtual.planned_test import band_phrase, plan_test, planned_band

LINE = ("X", "Y", "Z", "DX", "DY", "DZ")
MAX_LINES = 1000  # accelerometers or hits in one plan
MAX_FOOTPRINT_MM = 1000.0  # an accelerometer base or a hammer tip, across
MAX_CANDIDATES = 2_000_000  # sample points; memory is checked against the machine as well
# Peak memory of a plan, measured on the bundled structure (2 cores): 0.77 / 1.68 GB at 1e5 / 3e5 sample points,
# ~315 MB + 4.55 kB per point (with the exchanges among every candidate); --axes ×3.2 (3.8 GB at 3e5 before
# those exchanges); a margin for other meshes.
BASE_BYTES, BYTES_PER_CANDIDATE, AXES_FACTOR = 350e6, 4.8e3, 3.2


def _repeatable_six(parser: argparse.ArgumentParser, flag: str, names: tuple, help: str) -> None:
    """An option of six numbers in the mesh's units that may be given several times."""
    parser.add_argument(
        flag,
        type=finite("mesh units"),
        nargs=6,
        action="append",
        default=[],
        metavar=names,
        help=f"{help} (mesh units; repeatable)",
    )


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_mesh_arguments(parser)
    parser.add_argument(
        "--sensors",
        type=count(0, MAX_LINES),
        metavar="N",
        help="uniaxial accelerometers (default: the fewest that make the test diagnosable; 6 with other budget options)",
    )
    parser.add_argument(
        "--exciters", type=count(0, MAX_LINES), metavar="K", help="hammer hits (default: as --sensors; 3 with others)"
    )
    parser.add_argument(
        "--triaxial", type=count(0, MAX_LINES), metavar="N", help="triaxial accelerometers (3 lines each; default 0)"
    )
    parser.add_argument(
        "--minimal",
        action="store_true",
        help="the paper's minimal layout (6 lines × 3 hits, a plate's 3 × 3): identifies, cannot locate a fault",
    )
    parser.add_argument(
        "--search-evaluations",
        type=count(1, 10**9),
        metavar="N",
        help=f"diagnosability evaluations the search for the cheapest diagnosable layout may spend (default "
        f"{EVALUATIONS}); a search that spends them stops and plans the minimal layout, saying what it reached",
    )
    parser.add_argument(
        "--candidates",
        type=count(1, MAX_CANDIDATES),
        default=400,
        metavar="N",
        help="candidate points spread area-uniformly on the surface, a count (default 400)",
    )
    parser.add_argument("--axes", action="store_true", help="also allow global-axis directions (mounting blocks)")
    _repeatable_six(parser, "--exclude-box", ("X0", "Y0", "Z0", "X1", "Y1", "Z1"), "no candidate in this box")
    parser.add_argument(
        "--exclude-faces", type=count(0, 2**31), nargs="+", default=[], metavar="F", help="face indices to avoid"
    )
    parser.add_argument(
        "--sensor-base",
        type=real(0, MAX_FOOTPRINT_MM, "mm"),
        default=SENSOR_BASE * 1e3,
        metavar="MM",
        help="accelerometer base across (mm, default 10): sensors go half of it clear of every sharp edge (a crease "
        "over 30°), on flat faces or on curves that leave at most 1 mm under it (an adhesive film to 0.1 mm, "
        "then a cemented pad)",
    )
    parser.add_argument(
        "--tip",
        type=real(0, MAX_FOOTPRINT_MM, "mm"),
        default=HAMMER_TIP * 1e3,
        metavar="MM",
        help="hammer tip across (mm, default 6): hits land along the surface normal, on flat faces or curves, half "
        "of it clear of every sharp edge (a crease over 30°)",
    )
    parser.add_argument(
        "--edge-keepout",
        type=real(0, unit="mesh units"),
        default=0.0,
        metavar="D",
        help="keep at least D from every edge, sensors and hits alike (mesh units; default: half the base or tip)",
    )
    _repeatable_six(parser, "--fixed-sensor", LINE, "an accelerometer already mounted, snapped onto the surface")
    _repeatable_six(parser, "--fixed-exciter", LINE, "a hit already decided, snapped onto the surface")
    add_criterion_arguments(parser)
    parser.add_argument("--seed", type=SEED, default=0, metavar="N", help="seed of the surface sampling (default 0)")
    parser.add_argument("--out", default="plan", metavar="DIR", help="output folder (default ./plan)")
    parser.add_argument("--force", action="store_true", help="overwrite DIR/plan.json and DIR/report.html")


def add_criterion_arguments(parser: argparse.ArgumentParser) -> None:
    """The noise model the layout is judged on, the criterion maximised and how its certificate is solved."""
    parser.add_argument(
        "--noise-relative",
        type=fraction(low_open=True),
        default=0.01,
        metavar="R",
        help="massline error, fraction (default 0.01)",
    )
    parser.add_argument(
        "--noise-floor",
        type=fraction(),
        default=0.02,
        metavar="F",
        help="noise floor, fraction of 1/mass (default 0.02)",
    )
    parser.add_argument(
        "--relaxation",
        choices=["first-order", "cvxpy"],
        default="first-order",
        help="how the convex relaxation that certifies the layout is solved: first-order (default, fast at any "
        "size) or cvxpy (an interior-point solver, for small candidate sets)",
    )
    parser.add_argument(
        "--criterion",
        choices=["D", "A", "E"],
        default="D",
        help="D: log det F (default); A: −trace F⁻¹; E: smallest eigenvalue of F (F in relative parameters)",
    )


def _fixed(rows, scale, option: str) -> Lines | None:
    """The lines of a repeated six-number option, points in m; a zero direction is refused."""
    if not rows:
        return None
    rows = np.asarray(rows, dtype=float)
    for k, row in enumerate(rows, 1):
        if np.linalg.norm(row[3:]) == 0:
            raise MasslineError(f"{option} {k}: the direction DX DY DZ is zero: give the measuring or hit direction")
    return Lines(rows[:, :3] * scale, rows[:, 3:])


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
    """How far sliding the points on their flat faces moved them and what it gained over the candidate layout."""
    gain = plan.log_det - plan.candidate_log_det
    moved = 0.0 if plan.sliding is None else float(plan.sliding.moved.max(initial=0.0))
    sensor, hit = (1e3 * c for c in plan.clearances)
    by_criterion = (
        ""
        if plan.criterion.name == "D" or plan.sliding is None
        else f"raised {plan.criterion.title} by {plan.sliding.gain:.3g} and "
    )
    return (
        f"sliding the points on their flat faces (up to {1e3 * moved:.1f} mm; sensors ≥ {sensor:.3g} mm and hits "
        f"≥ {hit:.3g} mm from every edge) {by_criterion}changed log det F by {gain:+.3f} over the best candidate "
        f"layout (D-efficiency × {np.exp(gain / plan.model.p):.3f})"
    )


AXIS_UNDETERMINED = "any (equal moments)"  # an axis whose 1-σ passes 90°: its two moments are equal or nearly


def std_table(plan) -> Table:
    b, s = plan.model.nominal, plan.predicted_std
    table = Table(title="Predicted accuracy (Cramér–Rao, 1-σ)")
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


def chosen_budget(args: argparse.Namespace, planar: bool) -> Budget | None:
    """The budget asked for: --minimal's, the given one (6 sensors, 3 hits, no triaxial where not given), or
    None: the cheapest diagnosable."""
    given = [x for x in (args.sensors, args.exciters, args.triaxial) if x is not None]
    if args.minimal and given:
        raise MasslineError("--minimal is a budget of its own: drop --sensors, --exciters and --triaxial")
    if (args.minimal or given) and args.search_evaluations is not None:
        raise MasslineError(
            "--search-evaluations bounds the search for the cheapest diagnosable layout, which a given budget "
            "skips: drop it, or drop --minimal, --sensors, --exciters and --triaxial"
        )
    if args.minimal:
        return minimal_budget(planar)
    if not given:
        return None
    return Budget(
        6 if args.sensors is None else args.sensors,
        3 if args.exciters is None else args.exciters,
        args.triaxial or 0,
    )


def blocks_note(console: Console, result) -> None:
    """Which motion the normals miss and where the planner put mounting blocks for it
    (:func:`massline.placement.candidates.blocks_needed`)."""
    missed = {motion_text(t) for twists in result.blocks for t in twists}
    if not missed:
        return
    used = [sum(m.kind == "block" for m in mounts(result, k)) for k in (0, 1)]
    console.print(
        f"[yellow]mounting blocks:[/] no surface normal reads or drives the {' or the '.join(sorted(missed))} (a "
        f"turned part's axis), so lines may sit on blocks glued to the surface, read or struck on their sides along "
        f"it: {used[0]} accelerometer line(s) and {used[1]} hit(s) do (mount \"block\")"
    )


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


def available_memory() -> float:
    """Bytes the system can give a process without swapping (MemAvailable), or inf when unknown."""
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return float(line.split()[1]) * 1024
    except OSError:
        pass
    return float("inf")


def check_memory(candidates: int, axes: bool, available: float | None = None) -> None:
    """Refuse, before anything is allocated, a candidate count whose plan would not fit in memory."""
    per = BYTES_PER_CANDIDATE * (AXES_FACTOR if axes else 1.0)
    need = BASE_BYTES + per * candidates
    available = available_memory() if available is None else available
    if need > 0.8 * available:
        most = max(int((0.8 * available - BASE_BYTES) / per), 0)
        raise MasslineError(
            f"--candidates {candidates}: planning would need about {need / 1e9:.1f} GB of memory and "
            f"{available / 1e9:.1f} GB are available: give --candidates {most} or fewer (the default 400 "
            "already certifies ≥ 98 % D-efficiency on the bundled bodies)"
        )


def run(args: argparse.Namespace, console: Console) -> None:
    out = Path(args.out)
    target, report = claim_folder(out, ("plan.json", "report.html"), args.force)
    check_memory(args.candidates, args.axes)
    body = body_from_arguments(args)
    scale = UNITS[body.units]
    options = CandidateOptions(
        n_samples=args.candidates,
        axes=args.axes,
        exclude_boxes=tuple((tuple(np.array(b[:3]) * scale), tuple(np.array(b[3:]) * scale)) for b in args.exclude_box),
        exclude_faces=tuple(args.exclude_faces),
        sensor_base=args.sensor_base * 1e-3,
        hammer_tip=args.tip * 1e-3,
        edge_keepout=args.edge_keepout * scale,
        seed=args.seed,
    )
    noise = NoiseModel(args.noise_relative, args.noise_floor)
    budget = chosen_budget(args, is_plate(body))
    fixed = {
        "fixed_sensors": _fixed(args.fixed_sensor, scale, "--fixed-sensor"),
        "fixed_exciters": _fixed(args.fixed_exciter, scale, "--fixed-exciter"),
    }
    fe_solve = FEInProcess(body, str(args.mesh))  # beside the search: the plan takes the longer, not the sum
    try:
        result = searched(args, body, options, noise, budget, fixed, console, fe_solve.check)
    except BaseException:
        fe_solve.close()
        raise
    sensor_labels, hit_labels = result.point_labels
    console.print(layout_table("Accelerometers", result.sensors, result.sensor_nodes, sensor_labels, mounts(result, 0)))
    console.print(layout_table("Hammer hits", result.exciters, result.exciter_nodes, hit_labels, mounts(result, 1)))
    blocks_note(console, result)
    console.print(std_table(result))
    console.print(criterion_text(result))
    console.print(sliding_line(result))
    diagnosability_note(console, result)
    with progress_bar(console) as progress:
        fe = fe_solve.result(progress)
        test, fe = plan_test(body, str(args.mesh), result.sensors, result.exciters, fe=fe)
        say_material(console, fe)
    say_fe_model(console, fe)
    doc = plan_to_dict(result, str(args.mesh), body.units, body.density, test)
    console.print(f"support: {test['suspension']['description']}; massline band {band_phrase(planned_band(doc))}")
    out.mkdir(parents=True, exist_ok=True)
    write_atomic(target, to_json(doc), args.force)
    console.print(f"wrote {target}")
    write_report(console, report, lambda: build_report(target, console), args.force, status=None)


def searched(args, body, options, noise, budget, fixed: dict, console, check=lambda: None):
    """The plan: the cheapest diagnosable layout, or the budget's (``budget`` not None), its progress shown;
    ``check()`` at every step shown (it raises what ends the plan early: the FE model's refusal)."""
    with progress_bar(console) as bar:

        def progress(stage: str, f: float) -> None:
            check()
            bar(stage, f, 1.0)

        if budget is None:
            result = cheapest_diagnosable(
                body, options, noise, **fixed, relaxation=args.relaxation, progress=progress, criterion=args.criterion,
                evaluations=args.search_evaluations or EVALUATIONS,
            )  # fmt: skip
        else:
            result = plan(
                body, budget, options, noise, **fixed, relaxation=args.relaxation, criterion=args.criterion,
                progress=progress,
            )  # fmt: skip
    return result
