"""``massline demo``: the whole story on the bundled 3-D structure, written into one folder.

The story (:func:`massline.reports.demo_story.demo_story`): plan a test with room to spare and the support it
hangs on, simulate it with one fault concealed, identify and diagnose from the UFF alone, write the plan and the
three reports. Here: its progress, what it planned and simulated, the concealed fault beside what identify and
the diagnosis found, and where the reports are. The tool never reads what was concealed (``truth.json`` keeps it
for the reader).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

from massline.identify.diagnose.effects import Scene, named
from massline.identify.diagnose.notes import finding_note, fit_sentence, verdict
from massline.meshes import BUNDLED
from massline.cli.options import SEED as SEED_RANGE
from massline.cli.output import progress_bar
from massline.core.numbers import formatted, number, signed, value_with_sigma
from massline.core.properties import SUMMARY
from massline.reports.demo_story import BODY, BUDGET, FAULT, SEED, DemoStory, demo_story
from massline.virtual.planned_test import band_phrase
from massline.virtual.scenarios import FAULTS


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--out", default="massline-demo", metavar="DIR", help="output folder (default ./massline-demo)")
    parser.add_argument("--fault", default=FAULT, choices=FAULTS, help=f"the fault concealed (default {FAULT})")
    parser.add_argument(
        "--seed",
        type=SEED_RANGE,
        default=SEED,
        metavar="N",
        help=f"the seed that draws its size and place (default {SEED})",
    )
    parser.add_argument("--force", action="store_true", help="overwrite the files of an earlier demo in DIR")


def _line_index(lines, point, direction) -> int:
    """Index of the line through ``point`` along ``direction`` (as read back from the file)."""
    misfit = np.linalg.norm(lines.points - point, axis=1) + np.linalg.norm(lines.directions - direction, axis=1)
    return int(np.argmin(misfit))


def concealed(truth: dict, planned, recording, sensors: list[str], hits: list[str]) -> tuple[str, list, int | None]:
    """The fault in words, the channels (0-based, in the file's order) and the hit it sits on."""
    drawn = truth["faults"][0]  # the demo conceals one fault
    fault, size, lines = drawn["name"], drawn["size"], drawn["lines"] or []
    channels, hit = [], None
    if named(fault).perturbs == "exciter":
        k = lines[0] - 1
        hit = _line_index(recording.exciters, planned.exciters.points[k], planned.exciters.directions[k])
    else:
        for line in lines:
            k = line - 1
            channels.append(_line_index(recording.sensors, planned.sensors.points[k], planned.sensors.directions[k]))
    labels = tuple(sensors[c] for c in channels)
    scene = Scene(labels[0] if labels else None, labels, None if hit is None else hits[hit], truth["planned_band_hz"])
    text = named(fault).concealed(size, scene)
    return text, channels, hit


def _named(finding, fault: str, channels: list, hit: int | None) -> bool:
    """Whether the finding names the concealed fault at its place."""
    if finding is None or finding.effect != fault:
        return False
    return named(fault).located(finding, channels, hit)


def _errors(body, nominal) -> str:
    """Mass, CoG and principal moments against the mesh's, in one phrase."""
    mass = formatted(100 * (body.mass / nominal.mass - 1), "+.2f")
    cog = 1e3 * np.linalg.norm(body.cog - nominal.cog)
    moments = 100 * np.abs(body.principal_moments / nominal.principal_moments - 1).max()
    return f"mass {mass} %, CoG {cog:.2f} mm off, principal moments within {moments:.2f} %"


def properties_table(nominal, columns: list) -> Table:
    """The mesh's mass, CoG and principal moments, and each (name, body, std) of ``columns`` as its error
    against them ± its 1-σ (per cent; mm for the CoG)."""
    table = Table(
        title="Against the mesh: identify's and the diagnosis' error ± 1-σ",
        caption="errors in % of the mesh's value, in mm for the CoG",
    )
    table.add_column("quantity")
    table.add_column("mesh", justify="right")
    for name, _, _ in columns:
        table.add_column(name, justify="right")
    for q in SUMMARY:
        reference = q.value(nominal)
        cells = [number(reference * q.scale, 5)]
        for _, body, std in columns:
            if body is None:
                cells.append("no body")
                continue
            relative = 1e3 if q.unit == "mm" else 100 / reference
            error, sigma = (q.value(body) - reference) * relative, q.sigma(std) * abs(relative)
            shown, spread = value_with_sigma(error, sigma)
            cells.append(f"{signed(shown)} ± {spread}" + ("" if q.unit == "mm" else " %"))
        table.add_row(f"{q.name} ({q.unit})", *cells)
    return table


def run(args: argparse.Namespace, console: Console) -> None:
    start = time.perf_counter()
    out = Path(args.out)
    with progress_bar(console) as progress:
        story = demo_story(out, fault=args.fault, seed=args.seed, force=args.force, progress=progress)
        console.print(
            f"[bold]massline demo[/]: the bundled {BUNDLED[BODY].description}. Plan the test, simulate it with one "
            f"fault concealed, identify and diagnose from the UFF alone, and write the reports into {out}/."
        )
        told(console, story)
    paths, truth, planned = story.paths, story.truth, story.planned
    seconds = time.perf_counter() - start
    summary(console, args, paths, story.nominal, truth, planned, story.identified, story.diagnosis, seconds)


def told(console: Console, story: DemoStory) -> None:
    """What was planned and what was simulated, and where each went."""
    planned, paths = story.planned, story.paths
    console.print(
        f"planned {BUDGET.sensors} accelerometers and {BUDGET.exciters} hits on the structure: certified "
        f"D-efficiency ≥ {planned.d_efficiency_lower_bound:.1%}, predicted worst 1-σ "
        f"{planned.worst_relative_std:.2%}; support {story.support.describe()}, planned band "
        f"{band_phrase(story.band)} → {paths['plan']}"
    )
    console.print(
        f"simulated: FE modes from {story.first_elastic:.0f} Hz, the planned support, 1 % noise, every "
        f"channel up to 2 % sensitive across its axis, {len(story.recording.frequencies)} lines to "
        f"{story.fmax:.0f} Hz → {paths['uff']}"
    )


def band_story(found, planned: list | None) -> str:
    """identify's band beside the planned one, and why they differ, in one sentence."""
    text = f"identify chose the band {found.low:.1f}–{found.high:.1f} Hz"
    if planned is None:
        return text + " (the plan predicted none)"
    low, high = planned
    inside = "contains" if found.low <= low and found.high >= high else "does not contain"
    return (
        f"{text}; it {inside} the planned {low:.1f}–{high:.1f} Hz and is wider because identify fits the tails "
        "of the support and elastic modes, which the planned band keeps clear of"
    )


def summary(console, args, paths, nominal, truth, planned, identified, diagnosis, seconds) -> None:
    """What was planned, concealed, identified and diagnosed, and where the reports are."""
    result = diagnosis.result
    sensors, hits = diagnosis.sensors, diagnosis.hits
    fault, channels, hit = concealed(truth, planned, diagnosis.recording, sensors, hits)
    console.print(f"\n[bold]Concealed fault[/] ({args.fault}, seed {args.seed}; the tool was not told): {fault}.")
    console.print(
        f"[bold]identify[/]: {_errors(identified.body, nominal)} against the mesh; "
        f"{band_story(identified.band, truth['planned_band_hz'])}.",
    )
    for warning in identified.warnings:  # what the identification report lists, said here too
        console.print(f"[bold]identify's warning:[/] {warning}")
    said = verdict(diagnosis.findings, diagnosis.chi2)
    if said:
        console.print(f"[bold]diagnose[/]: {said}")
    for k, finding in enumerate(diagnosis.findings, 1):
        console.print(f"[bold]diagnose[/] {k}. {finding_note(finding, sensors, hits)}")
    ranks = [k for k, finding in enumerate(diagnosis.findings, 1) if _named(finding, args.fault, channels, hit)]
    named = (
        "[red]not named[/]"
        if not ranks
        else "named first, at its place"
        if ranks[0] == 1
        else f"[yellow]named at its place, as finding {ranks[0]}[/]"
    )
    before, after = result.relative_rms("before"), result.relative_rms("after")
    console.print(
        f"the concealed fault is {named}; {fit_sentence(diagnosis.chi2, before, after, diagnosis.result.noise)}"
        + (f"; after: {_errors(diagnosis.after_body, nominal)}" if diagnosis.after_body is not None else "")
    )
    columns = [("identify", identified.body, identified.std)]
    columns.append(("diagnose, after", diagnosis.after_body, None if diagnosis.after is None else diagnosis.after.std))
    console.print(properties_table(nominal, columns))
    console.print("[bold]Reports[/] (open in a browser; they print on A4):")
    for key, what in (
        ("placement", "placement report: where to put the accelerometers and hits"),
        ("identification", "identification report: FRFs, band, properties, principal axes"),
        ("diagnosis", "diagnosis report: findings, residual maps, properties before and after"),
    ):
        console.print(f"  {paths[key]}  ({what})")
    console.print(
        f"data: {paths['plan']}, {paths['uff']} (massline identify / diagnose read it), {paths['truth']} (what was "
        f"concealed). Done in {seconds:.0f} s."
    )
