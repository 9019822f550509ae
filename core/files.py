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

from massline.core.errors import MasslineError, param

FORCE = param("force", "True", cli="")  # the overwrite switch, as an error names it


def _named(path: Path, option: str) -> str:
    return f"{option} {path}" if option else str(path)


def writable_folder(folder: Path, label: str) -> Path:
    """Raise unless files can be created in ``folder`` (or in the nearest existing folder above it, where
    ``folder`` will be made); probed by creating and removing a file, which also covers read-only mounts
    and a superuser's permissions. ``label`` ('--json out/a.json') opens the message."""
    existing = folder
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    if not existing.is_dir():
        raise MasslineError(f"{label}: {existing} is a file, not a folder: choose another path")
    try:
        fd, name = tempfile.mkstemp(dir=existing, prefix=".massline-probe-")
    except OSError as error:
        raise MasslineError(
            f"{label}: cannot write in folder {existing} ({error.strerror}): choose a writable folder"
        ) from None
    os.close(fd)
    os.unlink(name)
    return folder


STDOUT = "-"  # an output named "-" is the standard output (a pipe), never a file


def claim_output(path: str | Path, force: bool, option: str = "") -> Path:
    """Check before any work that the file ``path`` may be written (``option``, e.g. '--json', names it in
    the message): not a folder, not an existing file unless ``force``, in a folder that exists and is
    writable. Return it (``STDOUT`` as it is: nothing to check)."""
    if str(path) == STDOUT:
        return Path(STDOUT)
    path = Path(path)
    if path.is_dir():
        raise MasslineError(f"{_named(path, option)} is a folder: give a file name (e.g. {path / 'out'})")
    if path.exists() and not force:
        raise MasslineError(f"{_named(path, option)} exists; pass {FORCE} to overwrite it or choose another path")
    if not path.parent.is_dir():
        raise MasslineError(
            f"{_named(path, option)}: folder {path.parent} does not exist: create it or choose another path"
        )
    writable_folder(path.parent, _named(path, option))
    return path


def claim_outputs(named, force: bool) -> list[Path]:
    """``claim_output`` for each {option: path} given (None: not asked for), or each (option, path) pair (an
    option given several times: ``[("--export", "a.bdf"), ("--export", "a.urdf")]``); one file named twice is
    refused (the second write would meet the first). Return the paths given."""
    pairs = named.items() if isinstance(named, dict) else named
    given = [(option, Path(path)) for option, path in pairs if path]
    seen: dict[Path, str] = {}
    for option, path in given:
        key = path if str(path) == STDOUT else path.resolve()
        if key in seen:
            raise MasslineError(f"{seen[key]} and {option} both name {path}: give each output its own file")
        seen[key] = option
        claim_output(path, force, option)
    return [path for _, path in given]


def claim_folder(folder: str | Path, names, force: bool, option: str = param("folder")) -> list[Path]:
    """Check before any work that ``folder`` may hold the files ``names``: a folder (existing or to be made
    in a writable one) where none of them is a folder, or exists without ``force``. Return their paths."""
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise MasslineError(f"{option} {folder} is a file: give a folder")
    writable_folder(folder, _named(folder, option))
    paths = [folder / name for name in names]
    for path in paths:
        if path.is_dir():
            raise MasslineError(f"{option} {folder}: {path} is a folder, where a file goes: move it or choose another")
        if path.exists() and not force:
            raise MasslineError(f"{path} exists; pass {FORCE} to overwrite it or choose another {option}")
    return paths


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextmanager
def atomic_file(path: str | Path):
    """A temporary path beside ``path`` to write; on success it is fsynced and renamed over ``path``,
    on any failure removed. The caller checks ``path`` may be written (``claim_output``)."""
    path = Path(path)
    try:
        fd, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    except OSError as error:
        raise _unwritable(path, error) from None
    os.close(fd)
    temporary = Path(name)
    try:
        yield temporary
        with open(temporary, "rb+") as handle:
            os.fsync(handle.fileno())
        os.chmod(temporary, 0o666 & ~_umask())
        os.replace(temporary, path)
    except OSError as error:
        temporary.unlink(missing_ok=True)
        raise _unwritable(path, error) from None
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def _unwritable(path: Path, error: OSError) -> MasslineError:
    """A file system refusal met while writing (permissions changed, a folder put in the way, a full disk)."""
    return MasslineError(f"cannot write {path} ({error.strerror or error}): free the path or choose another")


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
