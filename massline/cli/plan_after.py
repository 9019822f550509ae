"""``massline plan MESH --after RECORDING.uff``: the next run from the first — the recording's layout fixed, its
information the prior, the additions that most cut a property's 1-σ → DIR/plan.json (the second run: the first
run's lines and the best addition's, marked) and DIR/report.html."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

from massline.cli.output import build_report, write_report
from massline.core.errors import MasslineError
from massline.core.files import claim_folder, to_json, write_atomic
from massline.core.lines import Lines
from massline.core.model import RigidModel
from massline.core.numbering import point_labels
from massline.core.numbers import formatted, vector_text
from massline.identify.measured_layout import measured_layout
from massline.meshes.loader import BodyMesh
from massline.placement.candidates import CandidateOptions, candidate_lines, candidate_points
from massline.placement.footprints import Footprint, Sites
from massline.placement.next_run import (
    Measured,
    NextRun,
    Proposal,
    Room,
    check_on_surface,
    check_target,
    plan_next_run,
)
from massline.placement.on_surface import is_plate

UNIT = {"mass": ("kg", 1.0), "cog": ("mm", 1e3), "J": ("kg·m²", 1.0)}
ALONE = ("--minimal", "--sensors", "--exciters", "--triaxial", "--fixed-sensor", "--fixed-exciter", "--sensor-mass")


def add_after_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--after",
        metavar="RECORDING.uff",
        help="plan the next run from this first run's recording: its layout fixed, its information the prior (the "
        "recording's noise and band, not --noise-relative and --noise-floor); the additions that most cut a "
        "property's 1-σ are proposed (default: plan from nothing)",
    )
    parser.add_argument(
        "--target",
        metavar="PROPERTY",
        help="with --after: the property whose 1-σ the additions cut (mass, cog_x, cog_y, cog_z, Jxx, Jyy, Jzz, "
        "Jxy, Jyz, Jxz, J1, J2, J3: principal moments, ascending; default: the worst relative 1-σ)",
    )
    parser.add_argument(
        "--additions",
        type=int,
        choices=(1, 2, 3),
        default=2,
        help="with --after: the most items (accelerometers and hits) a proposal adds (default 2; 3 adds three "
        "accelerometers)",
    )


def check_alone(args: argparse.Namespace) -> None:
    """--after plans additions only: refuse the budget options with it, and --target without it."""
    if args.after is None:
        if args.target is not None:
            raise MasslineError("--target names the property a next run cuts: give --after RECORDING.uff with it")
        return
    given = [flag for flag in ALONE if getattr(args, flag[2:].replace("-", "_")) not in (None, False, [])]
    if given:
        raise MasslineError(f"--after fixes the recording's layout and proposes additions: drop {given[0]}")


def unit_of(target: str) -> tuple[str, float]:
    """The unit a target's 1-σ is printed in, and its factor from SI."""
    return UNIT["mass" if target == "mass" else "cog" if target.startswith("cog") else "J"]


def run_after(
    args: argparse.Namespace, console: Console, body: BodyMesh, options: CandidateOptions, mesh: str
) -> None:
    """The next run's plan (module docstring); ``mesh``: plan.json's name of the mesh."""
    out = Path(args.out)
    target_path, report = claim_folder(out, ("plan.json", "report.html"), args.force)
    model = RigidModel(body.nominal, is_plate(body))
    check_target(model, args.target)
    layout = measured_layout(args.after)
    recording = layout.recording
    check_on_surface(body.mesh, recording.sensors, recording.sensor_channels, "accelerometer channel")
    check_on_surface(body.mesh, recording.exciters, recording.exciter_channels, "hit")
    first = Measured(
        sensors=recording.sensors, exciters=recording.exciters, magnitude=layout.magnitude, sigma=layout.sigma,
        transverse=layout.transverse,
    )  # fmt: skip
    points = candidate_points(body.mesh, options)
    sensor_side, hit_side = candidate_lines(points, options.axes, model.planar, False)
    room = Room(
        body.mesh, Footprint(options.sensor_base, options.hammer_tip),
        *(Sites(points.points[side.node], points.normals[side.node]) for side in (sensor_side, hit_side)),
    )  # fmt: skip
    result = plan_next_run(model, first, (sensor_side.lines, hit_side.lines), args.target, args.additions, room)
    say(console, result, layout)
    doc = next_run_doc(result, layout, args, body) | {"mesh": mesh}
    out.mkdir(parents=True, exist_ok=True)
    write_atomic(target_path, to_json(doc), args.force)
    console.print(f"wrote {target_path}")
    write_report(console, report, lambda: build_report(target_path, console), args.force, status=None)


def what(proposal: Proposal) -> str:
    """'2 hits', '1 accelerometer + 1 hit'."""
    parts = [f"{n} {word}{'s' if n > 1 else ''}" for n, word in
             ((len(proposal.sensors), "accelerometer"), (len(proposal.exciters), "hit")) if n]  # fmt: skip
    return " + ".join(parts)


def where(proposal: Proposal) -> str:
    """Each added line's point (mm) and direction, one a line."""
    lines = [(f"acc {vector_text(1e3 * p, 4)} along {vector_text(d, 3)}") for p, d in
             zip(proposal.sensors.points, proposal.sensors.directions)]  # fmt: skip
    lines += [f"hit {vector_text(1e3 * p, 4)} along {vector_text(d, 3)}" for p, d in
              zip(proposal.exciters.points, proposal.exciters.directions)]  # fmt: skip
    return "\n".join(lines)


def say(console: Console, result: NextRun, layout) -> None:
    """The first run's figure, then one row per proposal: what, where (mm), the 1-σ after both runs, the gain."""
    unit, scale = unit_of(result.target)
    band = layout.band
    console.print(
        f"first run: {len(result.runs.first.sensors)} accelerometer lines × {len(result.runs.first.exciters)} hits, "
        f"band {band.low:.4g}–{band.high:.4g} Hz, noise {100 * layout.noise_relative:.3g} % (the recording's); "
        f"{result.target} 1-σ {formatted(scale * result.std_before, '.3g')} {unit} after it"
        + ("" if result.identified else " (the first run does not identify the body)")
    )
    console.print(f"the first run repeated unchanged: {formatted(scale * result.std_repeated, '.3g')} {unit}")
    table = Table(title=f"Additions for the second run, best first (1-σ of {result.target} after both runs)")
    for col in ("#", "what", "where (mm)", f"1-σ after ({unit})", "gain"):
        table.add_column(col, justify="right")
    for k, p in enumerate(result.proposals, 1):
        gain = result.std_before / p.std_after
        restores = " restores identifiability" if result.restores(p) else ""
        table.add_row(str(k), what(p), where(p), formatted(scale * p.std_after, ".3g"),
                      ("×∞" if not np.isfinite(gain) else f"×{gain:.3g}") + restores)  # fmt: skip
    console.print(table)
    console.print(
        f"plan.json holds the second run: the first run's lines (\"run\": 1) and addition 1 (\"run\": 2, \"added\": "
        f"true); identify both runs together over the first run's band: --band {band.low:.6g} {band.high:.6g}"
    )


def entries(lines: Lines, labels, added: np.ndarray) -> list:
    """plan.json's lines: the first run's ``"run": 1`` (fixed), the additions ``"run": 2, "added": true``."""
    return [
        {"node": int(label), "candidate": None, "point": p.tolist(), "direction": d.tolist(), "triaxial": None,
         "run": 2 if a else 1, "added": bool(a)} | ({} if a else {"fixed": True})
        for p, d, label, a in zip(lines.points, lines.directions, labels, added)
    ]  # fmt: skip


def next_run_doc(result: NextRun, layout, args: argparse.Namespace, body: BodyMesh) -> dict:
    """plan.json of the second run: the first run's lines then the best addition's, each marked, and what was
    proposed; the mesh's nominal body, so that ``massline simulate`` runs it."""
    first, best = result.runs.first, result.proposals[0]
    S, E = first.sensors + best.sensors, first.exciters + best.exciters
    s_labels, e_labels = point_labels(S, E)
    unit, scale = unit_of(result.target)
    return {
        "units": body.units,
        "density": body.density,
        "planar": result.runs.model.planar,
        "nominal": body.nominal.as_dict(),
        "sensors": entries(S, s_labels, np.arange(len(S)) >= len(first.sensors)),
        "exciters": entries(E, e_labels, np.arange(len(E)) >= len(first.exciters)),
        "after": {
            "recording": str(args.after),
            "band_hz": [layout.band.low, layout.band.high],
            "noise_relative": layout.noise_relative,
            "noise_model": {"relative": result.runs.noise.relative, "floor": result.runs.noise.floor},
            "target": result.target,
            "unit": unit,
            "std_before": scale * result.std_before,
            "std_repeated": scale * result.std_repeated,
            "identified": result.identified,
            "proposals": [
                {"what": what(p), "sensors": [{"point": x.tolist(), "direction": d.tolist()} for x, d in
                                               zip(p.sensors.points, p.sensors.directions)],
                 "exciters": [{"point": x.tolist(), "direction": d.tolist()} for x, d in
                              zip(p.exciters.points, p.exciters.directions)],
                 "std_after": scale * p.std_after, "restores_identifiability": result.restores(p)}
                for p in result.proposals
            ],
        },
        "noise": {"relative": result.runs.noise.relative, "floor": result.runs.noise.floor},
        "predicted_std": result.std_after_both(best),
    }  # fmt: skip
