"""``massline plan``: the layout, its certificate and predicted accuracy, the support the test hangs on and the
massline band it predicts → DIR/plan.json."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

import numpy as np
from rich.console import Console

from massline.cli.meshargs import add_mesh_arguments, body_from_arguments
from massline.cli.plan_budget import add_budget_arguments, budget_entries, band_lines, predicted_accuracy, print_accuracy
from massline.cli.plan_after import add_after_arguments, check_alone, run_after
from massline.cli.options import SEED, add_sensor_mass_argument, count, finite, fraction, real
from massline.core.calibration import Calibration
from massline.cli.output import build_report, progress_bar, say_fe_model, say_material, write_report
from massline.placement.candidates import HAMMER_TIP, SENSOR_BASE, CandidateOptions
from massline.placement.reach import CABLE_RUN, HAMMER_HEAD, HAMMER_SWING, SENSOR_HEIGHT
from massline.placement.diagnosable_plan import EVALUATIONS, cheapest_diagnosable, minimal_budget
from massline.core.errors import MasslineError
from massline.core.housing_masses import HousingMasses
from massline.core.files import claim_folder, to_json, write_atomic
from massline.core.information import NoiseModel
from massline.core.lines import Lines
from massline.core.numbering import point_groups
from massline.meshes import BUNDLED
from massline.meshes.loader import UNITS
from massline.placement.on_surface import is_plate, monotone, plan
from massline.placement.mounts import mounts
from massline.placement.plan_file import plan_to_dict
from massline.cli.plan_console import (
    blocks_note,
    criterion_text,
    diagnosability_note,
    layout_table,
    reach_note,
    sliding_line,
)
from massline.placement.planner import Budget
from massline.virtual.acquisition import accelerometer_masses
from massline.virtual.fe_process import FEInProcess
from massline.virtual.housing_loading import assumed_loading, assumed_sentence, loading, loading_sentence
from massline.virtual.planned_test import band_phrase, plan_test, planned_band

LINE = ("X", "Y", "Z", "DX", "DY", "DZ")
MAX_LINES = 1000  # accelerometers or hits in one plan
MAX_FOOTPRINT_MM = 1000.0  # an accelerometer base or a hammer tip, across
MAX_CANDIDATES = 2_000_000  # sample points; memory is checked against the machine as well
# Peak memory of a plan (benchmarks/plan_memory.py, the bundled structure's minimal plan): 0.62 / 1.38 GB at 1e5 /
# 3e5 sample points, 240 MB + 3.79 kB per point; --axes ×3.2 (3.8 GB at 3e5, an earlier run); a margin for other
# meshes.
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
        help="uniaxial accelerometers (default: the fewest that make the test diagnosable and no less accurate than "
        "the minimal layout; 6 with other budget options)",
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
    parser.add_argument(
        "--axes",
        action="store_true",
        help="also allow global-axis directions (mounting blocks); without it a turned part, whose normals all meet "
        "its axis, gets blocks along its rotation: one line and one hit (three and two when diagnosable)",
    )
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
    add_reach_arguments(parser)
    parser.add_argument(
        "--edge-keepout",
        type=real(0, unit="mesh units"),
        default=0.0,
        metavar="D",
        help="keep at least D from every edge, sensors and hits alike (mesh units; default: half the base or tip)",
    )
    _repeatable_six(parser, "--fixed-sensor", LINE, "an accelerometer already mounted, snapped onto the surface")
    add_sensor_mass_argument(
        parser,
        "KG [POINT=KG ...]",
        "mass of each accelerometer housing, kg (a triaxial counts once), then POINT=KG for a --fixed-sensor "
        "point whose housing differs (numbered 1, 2, … in the order given): the plan states how they load the "
        "body and simulate puts them on (default 0, and the plan says what typical 5 g housings would add)",
    )
    _repeatable_six(parser, "--fixed-exciter", LINE, "a hit already decided, snapped onto the surface")
    add_criterion_arguments(parser)
    add_budget_arguments(parser)
    add_after_arguments(parser)
    parser.add_argument("--seed", type=SEED, default=0, metavar="N", help="seed of the surface sampling (default 0)")
    parser.add_argument("--out", default="plan", metavar="DIR", help="output folder (default ./plan)")
    parser.add_argument("--force", action="store_true", help="overwrite DIR/plan.json and DIR/report.html")


def add_reach_arguments(parser: argparse.ArgumentParser) -> None:
    """The instruments' sizes the reach is judged for (mm): the hammer's head and swing, the accelerometer's
    height and its cable's run."""
    sizes = (
        ("--hammer-head", HAMMER_HEAD, "hammer head across (mm, default 16): a hit needs a free cylinder this wide "
         "around its line of approach"),
        ("--hammer-swing", HAMMER_SWING, "run the hammer's head needs clear along the normal (mm, default 50): "
         "holes, bores, pockets and re-entrant corners narrower hold no hit"),
        ("--sensor-height", SENSOR_HEIGHT, "accelerometer height (mm, default 15): its housing must stand clear of "
         "the part"),
        ("--cable-run", CABLE_RUN, "clear run beyond the accelerometer's side for its connector and cable, in some "
         "direction from half its height (mm, default 20)"),
    )  # fmt: skip
    for flag, default, text in sizes:
        parser.add_argument(flag, type=real(0, MAX_FOOTPRINT_MM * 10, "mm"), default=default * 1e3, metavar="MM",
                            help=text)  # fmt: skip


def add_criterion_arguments(parser: argparse.ArgumentParser) -> None:
    """The noise model the layout is judged on, the criterion maximised and how its certificate is solved."""
    parser.add_argument(
        "--noise-relative",
        type=fraction(low_open=True),
        default=0.01,
        metavar="R",
        help="massline error the layout's criterion weighs each massline by, fraction (default 0.01; the accuracy "
        "predicted is the uncertainty budget's: --line-noise, --calibration)",
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


def planned_housings(tokens: list, fixed: Lines | None) -> HousingMasses:
    """``--sensor-mass``, refused before any work where a POINT names no ``--fixed-sensor`` point (the planner
    numbers its own points only once it has chosen them)."""
    masses = HousingMasses.parse(tokens)
    known = 0 if fixed is None else int(point_groups(fixed).max()) + 1
    unknown = sorted(k for k in masses.by_label if not 1 <= k <= known)
    if unknown:
        which = f"the --fixed-sensor points are 1 to {known}" if known else "no --fixed-sensor is given"
        raise MasslineError(
            f"--sensor-mass {unknown[0]}=…: POINT names a --fixed-sensor point ({which}; the plan numbers its own "
            "points once it has chosen them): give one KG for every housing, or the fixed sensor's number"
        )
    return masses


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


def mesh_entry(mesh: str, folder: Path) -> str:
    """plan.json's name of its mesh: a bundled name as given; a file's path relative to the plan's ``folder``, so
    that the plan works from any folder and moves with its mesh (read back by ``virtual.planned_test.plan_mesh``)."""
    if mesh in BUNDLED and not Path(mesh).is_file():
        return mesh
    return os.path.relpath(Path(mesh).resolve(), folder.resolve())


def run(args: argparse.Namespace, console: Console) -> None:
    check_alone(args)
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
        hammer_head=args.hammer_head * 1e-3,
        hammer_swing=args.hammer_swing * 1e-3,
        sensor_height=args.sensor_height * 1e-3,
        cable_run=args.cable_run * 1e-3,
        edge_keepout=args.edge_keepout * scale,
        seed=args.seed,
    )
    if args.after is not None:
        return run_after(args, console, body, options, mesh_entry(str(args.mesh), out))
    noise = NoiseModel(args.noise_relative, args.noise_floor)
    budget = chosen_budget(args, is_plate(body))
    fixed = {
        "fixed_sensors": _fixed(args.fixed_sensor, scale, "--fixed-sensor"),
        "fixed_exciters": _fixed(args.fixed_exciter, scale, "--fixed-exciter"),
    }
    housings = planned_housings(args.sensor_mass, fixed["fixed_sensors"])
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
    reach_note(console, result)
    console.print(criterion_text(result))
    console.print(sliding_line(result))
    diagnosability_note(console, result)
    with progress_bar(console) as progress:
        fe = fe_solve.result(progress)
        carried = accelerometer_masses(result.sensors, housings)
        test, fe = plan_test(body, str(args.mesh), result.sensors, result.exciters, fe=fe, housings=carried)
        say_material(console, fe)
    say_fe_model(console, fe)
    doc = plan_to_dict(result, mesh_entry(str(args.mesh), out), body.units, body.density, test)
    budget = predicted_accuracy(result, doc, args.line_noise, args.calibration or Calibration())
    doc |= {"uncertainty_budget": None} if budget is None else budget_entries(budget, result, doc, args.line_noise)
    print_accuracy(console, result, budget, len(band_lines(planned_band(doc))))
    if housings.any:
        doc["loading"] = loading(body.nominal, carried, housings, doc["predicted_std"])
        console.print(loading_sentence(doc["loading"]))
    else:
        doc["sensor_mass_assumed"] = assumed_loading(body.nominal, result.sensors, doc["predicted_std"])
        console.print(assumed_sentence(doc["sensor_mass_assumed"]))
    console.print(f"support: {test['suspension']['description']}; massline band {band_phrase(planned_band(doc))}")
    if test.get("rig"):
        console.print(f"rig: {test['rig']['description']}")
    out.mkdir(parents=True, exist_ok=True)
    write_atomic(target, to_json(doc), args.force)
    console.print(f"wrote {target}")
    write_report(console, report, lambda: build_report(target, console), args.force, status=None)


def searched(args, body, options, noise, budget, fixed: dict, console, check=lambda: None):
    """The plan: the cheapest diagnosable layout, or the budget's (``budget`` not None), its progress shown;
    ``check()`` at every step shown (it raises what ends the plan early: the FE model's refusal)."""
    with progress_bar(console) as bar:

        @monotone
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
        bar("layout chosen", 1.0, 1.0)  # once, at the end: the stages before never reach it
    return result
