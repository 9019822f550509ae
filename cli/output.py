"""Writing a report from a command: a status line while it is built, then one atomic write."""

from __future__ import annotations

from pathlib import Path

from massline.placement.files import write_atomic

STATUS = "writing the report: building the page and rendering its pictures"


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
