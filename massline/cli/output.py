"""What a command shows and writes: its console, the progress of a library pipeline, the FE model it solved,
and a report written whole after a status line."""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path

from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.status import Status

import sys
import time
from typing import TYPE_CHECKING

from massline.core.files import STDOUT, to_json, write_atomic
from massline.export import PLATE_UNOBSERVED, check_observed, format_of

if TYPE_CHECKING:  # the placement report's renderer and the FE model load only where a report is built
    from massline.reports.html import Report
    from massline.virtual.planned_test import FEModel

STATUS = "writing the report: building the page and rendering its pictures"
UNWRAPPED = 100_000  # columns of a console that is not a terminal: lines are never broken

QUIET_S = 1.0  # s of work before progress lines start (a quick refusal stays one line)


def console_for(stream) -> Console:
    """A console on ``stream``: a terminal's width there, else no wrapping (a file or a pipe gets whole
    sentences and paths, one per line)."""
    terminal = hasattr(stream, "isatty") and stream.isatty()
    if terminal:
        return Console(file=stream)
    return Console(file=stream, width=UNWRAPPED, soft_wrap=True)


def write_json(console, path: str | Path, document: dict, force: bool = False) -> None:
    """Write ``document`` as JSON to ``path``, whole, and say so; to the standard output when ``path`` is
    ``-`` (the console then speaks on stderr: see :func:`console_stream`)."""
    text = to_json(document)
    if str(path) == STDOUT:
        sys.stdout.write(text if text.endswith("\n") else text + "\n")
        sys.stdout.flush()
        return
    write_atomic(path, text, force)
    console.print(f"wrote {path}")


def console_stream(args):
    """Where a command's console goes: stderr when its results go to stdout (``--json -``), else stdout."""
    return sys.stderr if getattr(args, "json", None) == STDOUT else sys.stdout


def write_report(console, path: str | Path, build, force: bool = False, status: str | None = STATUS) -> Path:
    """Build an HTML report (``build()`` returns an object with ``.html``), then write it whole.

    ``status``: a line shown while it is built; None when ``build`` shows its own progress.
    """
    if status is None:
        report = build()
    else:
        with console.status(status):
            report = build()
    write_atomic(path, report.html, force)
    console.print(f"wrote {path} ({len(report.html) / 1e3:.0f} kB)")
    return Path(path)


def check_exportable(paths: list[str], recording) -> None:
    """Before the identification: refuse ``--export`` files that cannot hold what ``recording`` can show (a
    plate's test leaves z_G and J's z row and column unobserved: only CSV holds that)."""
    from massline.identify.pipeline import is_planar  # identify's stack: loaded by the commands that identify

    planar = is_planar(recording.sensors, recording.exciters)
    for path in paths:
        check_observed(path, PLATE_UNOBSERVED if planar else ())


def write_exports(console, found, args) -> None:
    """Write each ``--export`` file of ``found`` (an identification or a diagnosis), in ``--export-units``, the
    bare body or with ``--export-as-tested`` the body as tested, and say so."""
    for path in args.export:
        found.export(path, args.export_units, as_tested=args.export_as_tested, force=args.force,
                     source=Path(args.uff[0]).name)  # fmt: skip
        console.print(f"wrote {path} ({format_of(path).name}, {args.export_units})")


def plain_progress(stream, steps: int = 4, quiet: float = QUIET_S):
    """``progress(stage, done, total)`` as plain lines on ``stream``, each with the seconds since the first: one
    when the stage changes and, within a stage, one each time another ``1/steps`` of ``total`` is done — a few
    lines a stage, not a flood, and no bar's control characters for a log file. Nothing in the first ``quiet``
    seconds: work that ends (or is refused) by then leaves its one line alone."""
    start, last = time.perf_counter(), {"stage": None, "step": -1}

    def progress(stage: str, done: float, total: float | None) -> None:
        step = int(steps * done / total) if total else -1
        if stage == last["stage"] and step <= last["step"] or time.perf_counter() - start < quiet:
            return
        last.update(stage=stage, step=step)
        share = f" ({100 * done / total:.0f} %)" if total else ""
        stream.write(f"[{time.perf_counter() - start:6.1f} s] {stage}{share}\n")
        stream.flush()

    return progress


@contextmanager
def progress_bar(console: Console):
    """Show a library pipeline's progress on ``console`` through the callback yielded, ``progress(stage, done,
    total)`` (the pipelines' None-able argument): a bar over the stages of a known count, a spinner for a stage of
    unknown length (``total`` None). Shown from the first call, transient, gone when the block ends; on a console
    that is not a terminal, plain lines on stderr instead (:func:`plain_progress`: the console's file or pipe
    gets results only, not a bar's blank line)."""
    if not console.is_terminal:
        yield plain_progress(sys.stderr)
        return
    shown: dict = {}  # "live": the bar (Progress) or spinner (Status) on show; "task": the bar's task

    def end() -> None:
        live = shown.pop("live", None)
        if live is not None:
            live.stop()

    def progress(stage: str, done: float, total: float | None) -> None:
        live = shown.get("live")
        if total is None:
            if isinstance(live, Status):
                live.update(stage)
                return
            end()
            shown["live"] = console.status(stage)
            shown["live"].start()
            return
        if not isinstance(live, Progress):
            end()
            live = shown["live"] = Progress(
                TextColumn("{task.description}"), BarColumn(), TimeElapsedColumn(), console=console, transient=True
            )
            live.start()
            shown["task"] = live.add_task(stage, total=total)
        live.update(shown["task"], completed=done, total=total, description=stage)

    try:
        yield progress
    finally:
        end()


def say_material(console: Console, fe: FEModel, option: bool = False) -> None:
    """The material assumed for the FE model, when none was given (nothing otherwise); ``option``: the command
    has ``--material`` (simulate), else the sentence names the command that has it."""
    if fe.assumed is not None:
        given = "no --material given" if option else "no material in the plan ('massline simulate --material' sets one)"
        console.print(f"[yellow]{given}: assuming {fe.assumed} from the density {fe.material.density:g} kg/m³[/]")


def say_fe_model(console: Console, fe: FEModel) -> None:
    """The FE model's size and first elastic frequencies, and whether they were kept from an earlier run."""
    modes = fe.modes
    console.print(
        f"FE model: {modes.n_dofs} DOF, quadratic tetrahedra of {modes.element_size * 1e3:.1f} mm; elastic modes "
        + ", ".join(f"{f:.0f}" for f in modes.frequencies_hz[:5])
        + " … Hz"
        + (" (kept from an earlier run)" if fe.kept else "")
    )


def build_report(plan_path: str | Path, console: Console) -> Report:
    """The placement report of a plan file (:func:`massline.reports.placement_assembly.build_placement_report`),
    its progress shown on ``console``, and the FE model of an older plan's band prediction said."""
    from massline.reports.placement_assembly import build_placement_report

    with progress_bar(console) as progress:
        built = build_placement_report(plan_path, progress)
        if built.fe is not None:
            say_material(console, built.fe)
    if built.fe is not None:
        say_fe_model(console, built.fe)
    return built.report
