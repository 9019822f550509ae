"""``massline diagnose FILE.uff``: where the recording departs from the rigid body, and which physics was left out."""

from __future__ import annotations

import argparse

import numpy as np
from rich.console import Console
from rich.table import Table

from massline.identify.diagnose.screens import roomy
from massline.identify.diagnose.notes import finding_note, fit_sentence, verdict
from massline.identify.diagnose.corrected_file import corrected_paths, written_faults
from massline.identify.diagnose.diagnosis_run import DiagnosisRun
from massline.identify.diagnose.pipeline import diagnose_recording
from massline.identify.estimator import TRANSVERSE
from massline.identify.pipeline import as_recording
from massline.cli.meshargs import add_nominal_arguments, add_support_arguments, nominal_mesh, support_model, support_setup
from massline.core.housing_masses import HousingMasses
from massline.cli.options import (
    BAND_EDGE,
    TRANSVERSE_PRIOR,
    add_export_arguments,
    add_instrumentation_arguments,
    add_recording_argument,
    check_band,
    claim_exports,
    source_of,
)
from massline.cli.output import check_exportable, write_exports, write_json, write_report
from massline.core.errors import MasslineError
from massline.core.files import claim_outputs, write_atomic
from massline.uff.runs import run_paths
from massline.core.numbers import number, value_with_sigma
from massline.core.properties import SUMMARY


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_recording_argument(parser)
    parser.add_argument(
        "--band",
        type=BAND_EDGE,
        nargs=2,
        metavar=("LO", "HI"),
        help="the band the diagnosis examines, Hz (the plan's; default identify's); the properties are identify's",
    )
    add_nominal_arguments(parser)
    add_support_arguments(parser)
    add_instrumentation_arguments(parser)
    parser.add_argument(
        "--transverse",
        type=TRANSVERSE_PRIOR,
        default=TRANSVERSE,
        metavar="FRACTION",
        help=f"prior 1-σ of each accelerometer's transverse sensitivity, a fraction (default {TRANSVERSE}; "
        "0: exact axes)",
    )
    parser.add_argument("--json", metavar="OUT", help="write the findings, fit and properties as JSON; - for stdout")
    parser.add_argument("--plot", metavar="PNG", help="residual maps and FRF overlays before and after")
    parser.add_argument("--report", metavar="OUT.html", help="write the diagnosis report (one HTML page)")
    parser.add_argument(
        "--write-corrected",
        metavar="FIXED.uff",
        help="write the recording with the faults named undone (signs, gains, swaps, a chain's factor on the FRFs; "
        "moved and turned lines in the geometry), a header record listing each correction with its ± and each "
        "finding not corrected",
    )
    add_export_arguments(parser)
    parser.add_argument(
        "--force", action="store_true", help="overwrite OUT, PNG, OUT.html, FIXED.uff and the --export files"
    )


def properties_table(found: DiagnosisRun, nominal, planar: bool = False) -> Table:
    """Mass, CoG and principal moments before and after, both to the digits the 1-σ (after) supports."""
    table = Table(title="properties before and after the diagnosis (frame of the file; ± 1-σ as identify gives it)")
    came = "the file as it came" + (
        ", the support's departure taken off" if any(n.code == "support_modelled" for n in found.notes) else ""
    )
    table.caption = f"identify's estimate on {came}, and on the recording with the faults undone"
    for col in ("quantity", "before", "after", "± 1-σ", "nominal (mesh)", "unit"):
        table.add_column(col, justify="right")
    before = None if found.before is None else found.before.body
    after, std = found.after_body, None if found.after is None else found.after.std
    for q in SUMMARY:
        sigma = None if std is None else q.sigma(std) * q.scale
        old = "refused" if before is None else value_with_sigma(q.value(before, planar) * q.scale, sigma)[0]
        new, spread = ("no body", "") if after is None else value_with_sigma(q.value(after, planar) * q.scale, sigma)
        shown = "" if nominal is None else number(q.value(nominal) * q.scale)
        table.add_row(q.name, old, new, spread, shown, q.unit)
    return table


def print_screens(console: Console, screens: dict, sensors: list[str]) -> None:
    """The model-free screens in a line or two."""
    if screens["channel_consistency"] is not None:
        worst = np.argsort(screens["channel_consistency"])[::-1][:3]
        listed = ", ".join(f"{sensors[k]} ({screens['channel_consistency'][k]:.1%})" for k in worst)
        console.print(f"model-free: channels farthest from the others' rigid motion (LOCO misfit): {listed}")
    if screens["negative_driving_points"]:
        pairs = ", ".join(f"sensor {sensors[i - 1]} × hit {j}" for i, j in screens["negative_driving_points"])
        console.print(f"model-free: driving points with a non-positive massline: {pairs}")


def run(args: argparse.Namespace, console: Console) -> None:
    check_band(args.band)
    fixed = corrected_paths(args.write_corrected, args.uff) if args.write_corrected else []
    claim_exports(args, {"--json": args.json, "--plot": args.plot, "--report": args.report})
    read = {p.resolve() for p in run_paths(args.uff)}
    if any(path.resolve() in read for path in fixed):
        raise MasslineError(f"--write-corrected {args.write_corrected} names a recording read: give another file")
    claim_outputs([("--write-corrected", path) for path in fixed], args.force)
    mesh = nominal_mesh(args)
    nominal = None if mesh is None else mesh.nominal
    setup = support_setup(args, mesh)
    recording = as_recording(args.uff)
    check_exportable(args.export, recording)
    support = support_model(setup, console)
    with console.status("diagnosing: discrete faults, then the effect library one at a time"):
        known = {"sensor_mass": HousingMasses.parse(args.sensor_mass), "exciter_mass": args.exciter_mass}
        found = diagnose_recording(recording, args.band, nominal, args.transverse, **known, support=support)
    zones, band, noise, result, sensors = found.band, found.data, found.result.noise, found.result, found.sensors
    for note in found.notes:
        console.print(f"note: {note}")
    if recording.runs:
        missing = int((~recording.present).sum())
        gaps = f"; {missing} pair{'s' * (missing != 1)} not measured" if missing else ""
        console.print(f"runs: {', '.join(recording.runs)}{gaps}")
    console.print(
        f"band {zones.low:.1f}–{zones.high:.1f} Hz ({zones.rule}), {len(band.frequencies)} lines × "
        f"{band.frf.shape[0]}×{band.frf.shape[1]} FRFs; noise {noise:.2%} of the FRFs (RMS, from the "
        f"{found.noise.method})"
    )
    if not roomy(found.layout):
        console.print(
            f"[yellow]note:[/] {len(found.layout.sensors)} sensor channels leave no redundancy: a faulty channel "
            "cannot be told from the body's properties (diagnosis needs at least 8 channels, 5 for a plate)"
        )
    print_screens(console, found.screens, sensors)
    before, after = result.relative_rms("before"), result.relative_rms("after")
    said = verdict(found.findings, found.chi2)
    if said:
        console.print(said)
    for k, finding in enumerate(found.findings, 1):
        console.print(f"{k}. {finding_note(finding, sensors, found.hits)}")
    for warning in () if found.before is None else found.before.warnings:
        console.print(f"[bold]identify's warning:[/bold] {warning}")
    console.print(fit_sentence(found.chi2, before, after, noise))
    console.print(properties_table(found, nominal, found.planar))
    if args.plot:
        from massline.reports.diagnosis_figures import diagnosis_figure  # matplotlib: loaded when used

        figure = diagnosis_figure(result, band, found.noise, sensors, found.hits, found.off_rigid())
        write_atomic(args.plot, figure, args.force)
        console.print(f"wrote {args.plot}")
    if args.json:
        write_json(console, args.json, found.document, args.force)
    if args.report:
        from massline.reports.diagnosis_report import diagnose_report

        write_report(console, args.report, lambda: diagnose_report(found, source_of(args.uff), mesh), args.force)
    write_exports(console, found, args)
    if args.write_corrected:
        written = found.write_corrected(args.uff, args.write_corrected, force=args.force)
        faults, rest = len(written_faults(found.findings)), len(found.findings) - len(written_faults(found.findings))
        console.print(f"wrote {', '.join(map(str, written))} ({faults} correction{'s' * (faults != 1)}, {rest} "
                      f"finding{'s' * (rest != 1)} not corrected; each listed in its header)")  # fmt: skip
