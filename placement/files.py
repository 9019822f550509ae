"""Writing results: never overwrite without ``force``, never leave half a file.

Every file massline writes (plans, recordings, JSON, pictures, reports) goes through ``atomic_file``:
written beside its destination under a temporary name, flushed to disk, then renamed into place, so
that a reader sees the old file or the whole new one and a failure leaves nothing behind.
"""

from __future__ import annotations

import json
import math
import os
import tempfile
from contextlib import contextmanager
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


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextmanager
def atomic_file(path: str | Path):
    """A temporary path beside ``path`` to write; on success it is fsynced and renamed over ``path``,
    on any failure removed. The caller checks ``path`` may be written (``claim_output``)."""
    path = Path(path)
    fd, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    temporary = Path(name)
    try:
        yield temporary
        with open(temporary, "rb+") as handle:
            os.fsync(handle.fileno())
        os.chmod(temporary, 0o666 & ~_umask())
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def write_atomic(path: str | Path, data: str | bytes, force: bool = False) -> Path:
    """Write ``data`` (text as UTF-8) to ``path`` whole or not at all (``atomic_file``)."""
    path = claim_output(path, force)
    with atomic_file(path) as temporary:
        temporary.write_bytes(data.encode() if isinstance(data, str) else data)
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
    """``data`` as indented JSON, NaN and ±inf as null."""
    return json.dumps(_plain(data), indent=2, allow_nan=False) + "\n"
