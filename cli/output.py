"""What a command shows and writes: its console, and a report written whole after a status line."""

from __future__ import annotations

from pathlib import Path

from rich.console import Console

from massline.core.files import write_atomic

STATUS = "writing the report: building the page and rendering its pictures"
UNWRAPPED = 100_000  # columns of a console that is not a terminal: lines are never broken


def console_for(stream) -> Console:
    """A console on ``stream``: a terminal's width there, else no wrapping (a file or a pipe gets whole
    sentences and paths, one per line)."""
    terminal = hasattr(stream, "isatty") and stream.isatty()
    if terminal:
        return Console(file=stream)
    return Console(file=stream, width=UNWRAPPED, soft_wrap=True)


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
