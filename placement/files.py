"""Writing results: never overwrite without --force, never leave half a file."""

from __future__ import annotations

import json
import math
import os
import tempfile
from pathlib import Path

import numpy as np
from massline.placement.errors import MasslineError


def claim_output(path: str | Path, force: bool) -> Path:
    """Check before any work that ``path`` may be written; return it."""
    path = Path(path)
    if path.exists() and not force:
        raise MasslineError(f"{path} exists; pass --force to overwrite it or choose another path")
    if not path.parent.is_dir():
        raise MasslineError(f"folder {path.parent} does not exist: create it or choose another path")
    return path


def write_atomic(path: str | Path, text: str, force: bool = False) -> Path:
    """Write ``text`` to ``path`` through a temporary file renamed into place."""
    return write_atomic_bytes(path, text.encode(), force)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_atomic_bytes(path: str | Path, data: bytes, force: bool = False) -> Path:
    """Write ``data`` to ``path`` through a temporary file renamed into place."""
    path = claim_output(path, force)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def _plain(value):
    """JSON-ready: arrays to lists, NaN (an unobservable entry) and ±inf (no bound) to null."""
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    return value


def to_json(data: dict) -> str:
    return json.dumps(_plain(data), indent=2, allow_nan=False) + "\n"


def write_report(console, path: str | Path, build, force: bool = False) -> None:
    """Build an HTML report (``build()`` returns an object with ``.html``) under a status line, then write it."""
    with console.status("writing the report: rendering the body and its principal axes"):
        report = build()
    write_atomic(path, report.html, force)
    console.print(f"wrote {path} ({len(report.html) / 1e3:.0f} kB)")
