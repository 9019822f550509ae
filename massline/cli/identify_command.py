"""``massline identify FILE.uff``: masslines from the recorded FRFs, then the properties with their 1-σ."""

from __future__ import annotations

import argparse

import numpy as np
from rich.console import Console
from rich.table import Table

from massline.identify.estimator import TRANSVERSE
from massline.identify.pipeline import (
    PAPER_METHODS,
    Identification,
    against_nominal,
    as_recording,
    identify_recording,
)
from massline.core.calibration import MAX_CALIBRATION, Calibration
from massline.core.housing_masses import HousingMasses
from massline.identify.weighing import RELATIVE_SD, WeighedMass
from massline.cli.meshargs import add_nominal_arguments, add_support_arguments, nominal_mesh, support_model, support_setup
from massline.cli.options import (
    BAND_EDGE,
    MAX_DRAWS,
    TRANSVERSE_PRIOR,
    add_calibration_argument,
    fraction,
    add_export_arguments,
    add_instrumentation_arguments,
    add_recording_argument,
    check_band,
    checked,
    claim_exports,
    source_of,
    count,
)
from massline.cli.output import check_exportable, write_exports, write_json, write_report
from massline.core.numbers import number, sigma_text, value_with_sigma
from massline.core.properties import QUANTITIES
from massline.cli.budget_console import budget_table
from massline.core.rigid_body import RigidBody


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_recording_argument(parser)
    parser.add_argument(
        "--band", type=BAND_EDGE, nargs=2, metavar=("LO", "HI"), help="massline band, Hz (default: found)"
    )
    parser.add_argument(
        "--method",
        default="best",
        choices=["best", *PAPER_METHODS],
        help="'best' (weighted, consistent, all masslines; default) or the paper's KINEMATICS+DYNAMICS",
    )
    parser.add_argument(
        "--transverse",
        type=TRANSVERSE_PRIOR,
        default=TRANSVERSE,
        metavar="FRACTION",
        help=f"prior 1-σ of each accelerometer's transverse sensitivity, a fraction (default {TRANSVERSE}; "
        "0: exact axes)",
    )
    parser.add_argument(
        "--bootstrap",
        type=count(0, MAX_DRAWS),
        default=100,
        metavar="N",
        help="bootstrap draws over the sensors (default 100; 0: none)",
    )
    add_instrumentation_arguments(parser)
    add_calibration_argument(parser, "they join the 1-σ's budget")
    parser.add_argument(
        "--sensor-mass-tolerance",
        type=fraction(MAX_CALIBRATION),
        default=0.0,
        metavar="FRACTION",
        help="1-σ of each accelerometer housing's mass (--sensor-mass), a fraction of it: it joins the bare body's "
        "budget (default 0: weighed housings)",
    )
    parser.add_argument(
        "--weighed-mass",
        type=checked(WeighedMass.parse),
        metavar="KG[±SD]",
        help="the bare body's mass read on a scale, a prior on the mass (SD in kg or P%%; default "
        f"{100 * RELATIVE_SD:g} %% of KG, a trade-class bench scale near its capacity)",
    )
    add_nominal_arguments(parser)
    add_support_arguments(parser)
    parser.add_argument(
        "--json",
        metavar="OUT",
        help="write the properties as JSON (mass, cog, inertia_cog, principal axes, std, …); - for stdout",
    )
    parser.add_argument("--report", metavar="OUT.html", help="write the identification report (one HTML page)")
    add_export_arguments(parser)
    parser.add_argument("--force", action="store_true", help="overwrite OUT, OUT.html and the --export files")


def results_table(body: RigidBody, std: dict, planar: bool, title: str, nominal: RigidBody | None = None) -> Table:
    table = Table(title=title)
    for col in ("quantity", "value", "± 1-σ", "unit") + (() if nominal is None else ("nominal (mesh)",)):
        table.add_column(col, justify="right")
    for q in QUANTITIES:
        value, sigma = q.value(body, planar) * q.scale, q.sigma(std) * q.scale
        extra = () if nominal is None else ("" if np.isnan(q.value(nominal)) else number(q.value(nominal) * q.scale),)
        if q.key == "principal_axes" and not np.isnan(sigma):
            table.add_row(q.name, "", sigma_text(sigma), q.unit, *extra)
            continue
        table.add_row(q.name, *value_with_sigma(value, sigma), q.unit, *extra)
    return table


def run(args: argparse.Namespace, console: Console) -> None:
    claim_exports(args, {"--json": args.json, "--report": args.report})
    check_band(args.band)
    sensor_mass, weighed = HousingMasses.parse(args.sensor_mass), args.weighed_mass
    mesh = nominal_mesh(args)
    setup = support_setup(args, mesh)
    recording = as_recording(args.uff)
    check_exportable(args.export, recording)
    found = identify_recording(
        recording, args.band, args.transverse, draws=args.bootstrap, method=args.method, sensor_mass=sensor_mass,
        exciter_mass=args.exciter_mass, weighed=weighed, support=support_model(setup, console),
        calibration=(args.calibration or Calibration()).with_housings(args.sensor_mass_tolerance),
    )  # fmt: skip
    found = against_nominal(found, None if mesh is None else mesh.nominal)
    band, fit = found.band, found.fit
    for note in found.notes:
        console.print(f"note: {note}")
    if recording.runs:
        console.print(f"runs: {', '.join(recording.runs)} ({len(recording.repeats)} pairs measured in several)")
    console.print(
        f"massline band {band.low:.1f}–{band.high:.1f} Hz ({band.rule}); band fits: median RMS residual "
        f"{np.nanmedian(fit.quality):.2%} of the massline, worst {np.nanmax(fit.quality):.2%}; suspension and "
        f"residual-flexibility tails removed (a plain average would be off by up to {np.nanmax(fit.bias):.1%})"
    )
    noise = found.noise_payload
    ratio = noise["fit_over_noise"]
    left = f"; the band fits leave {ratio:.2f}× it" if np.isfinite(ratio) else ""
    console.print(f"noise {noise['relative']:.2%} of the FRFs over the band (RMS, from the {noise['method']}){left}")
    for line in mass_lines(found):
        console.print(line)
    body = "bare body, accelerometers off" if found.housings.count else "frame of the file"
    title = f"{source_of(args.uff)}: identified properties ({args.method}; {body}; ± the budget below)"
    nominal = None if mesh is None else mesh.nominal
    console.print(results_table(found.body, found.std, found.planar, title, nominal))
    console.print(budget_table(found.budget, found.body, found.planar, "uncertainty budget"))
    for sentence in found.budget_payload["limits"]:
        console.print(f"budget: {sentence}")
    console.print(
        f"reduced χ² {number(found.best.chi2, 3)} over {int(np.isfinite(found.sigma).sum())} masslines"
        + ("; physical-consistency constraint active" if found.best.constrained else "")
    )
    for warning in found.warnings:
        console.print(f"[bold]warning:[/bold] {warning}")
    if args.json:
        write_json(console, args.json, found.payload, args.force)
    if args.report:
        from massline.reports.identification_report import identify_report

        write_report(console, args.report, lambda: identify_report(found, source_of(args.uff), mesh), args.force)
    write_exports(console, found, args)


def mass_lines(found: Identification) -> list[str]:
    """What was taken off the body as tested and what the scale said, one sentence each (none without)."""
    lines = []
    if found.exciter_mass:
        lines.append(
            f"exciter mass: each column fitted with a {number(1e3 * found.exciter_mass, 4)} g force gauge at its "
            f"drive point ({len(found.recording.exciters)} drive points); the body reported is without them"
        )
    housings = found.housings
    if housings.count:
        lines.append(
            f"sensor mass: {housings.describe()} = {number(1e3 * housings.total, 4)} g subtracted; as tested (accelerometers on) the body weighed "
            f"{' ± '.join(value_with_sigma(found.tested.mass, found.tested_std['mass']))} kg"
        )
    if found.weighed is not None:
        z = found.best.weighed_z
        agreement = f"; the masslines and the scale differ by {number(abs(z), 2)}σ" if np.isfinite(z) else ""
        lines.append(
            f"weighed mass {number(found.weighed.mass, 6)} ± {number(found.weighed.sd, 2)} kg (bare body) used as "
            f"a prior on the mass{agreement}"
        )
    return lines
