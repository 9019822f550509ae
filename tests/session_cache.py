"""Work built once per test session and shared by every xdist worker: plans and command runs.

A plan of the structure takes 15 s and the demo 40 s; several modules need the same ones. The
first worker that asks builds the entry under a file lock in the session's folder (``MASSLINE_TEST_SHARED``,
made by the controller in ``conftest.pytest_configure`` and removed at its end); the others wait on the lock and
read it. An entry is keyed by what it depends on (the command line, or a name and its arguments), never by the
module that first asked, and is read only once whole (marked done; a build that failed is made again).

Entries are read-only: a test that changes a file copies it first.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import pickle
import shutil
import subprocess
import sys
import time
from pathlib import Path
from typing import Callable


def shared_root() -> Path:
    """The session's shared folder (a private one when run outside pytest's controller)."""
    root = os.environ.get("MASSLINE_TEST_SHARED")
    if not root:
        import tempfile

        root = os.environ["MASSLINE_TEST_SHARED"] = tempfile.mkdtemp(prefix="massline-shared-")
    return Path(root)


def key_of(*parts) -> str:
    """A short, filesystem-safe key for ``parts`` (their text)."""
    text = "\x1f".join(str(p) for p in parts)
    return hashlib.sha256(text.encode()).hexdigest()[:20]


def built(key: str, build: Callable[[Path], None]) -> Path:
    """The folder ``key``, built once by ``build(folder)`` under the session's lock for it."""
    root = shared_root()
    folder, done = root / key, root / f"{key}.done"
    with open(root / f"{key}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not done.exists():  # built in place (what it prints names its own folder), marked done when whole
            shutil.rmtree(folder, ignore_errors=True)
            folder.mkdir()
            build(folder)
            done.touch()
    return folder


def command(*args) -> Path:
    """The folder in which ``massline ARGS --out FOLDER/out`` ran once this session (its ``out`` beside
    ``stdout.txt``, ``stderr.txt`` and ``seconds.txt``, its wall time); a command that fails raises with its stderr."""

    def run(folder: Path) -> None:
        line = [sys.executable, "-m", "massline", *map(str, args), "--out", str(folder / "out")]
        start = time.perf_counter()
        done = subprocess.run(line, capture_output=True, text=True, cwd=folder)
        if done.returncode != 0:
            raise RuntimeError(f"{' '.join(line)} failed: {done.stderr}")
        (folder / "seconds.txt").write_text(f"{time.perf_counter() - start:.3f}")
        (folder / "stdout.txt").write_text(done.stdout)
        (folder / "stderr.txt").write_text(done.stderr)

    return built(key_of("command", *args), run)


def plan(*args) -> Path:
    """plan.json of ``massline plan ARGS`` (e.g. ``plan("bracket")``, ``plan("structure", "--minimal")``)."""
    return command("plan", *args) / "out" / "plan.json"


def value(name: str, compute: Callable[[], object], *args) -> object:
    """``compute()`` once this session for the key (``name``, ``args``), pickled for every worker: a plan or
    FE modes computed in process, where a module's own cache would compute them once per worker."""
    def build(folder: Path) -> None:
        with open(folder / "value.pickle", "wb") as file:
            pickle.dump(compute(), file, protocol=pickle.HIGHEST_PROTOCOL)

    folder = built(key_of("value", name, *args), build)
    with open(folder / "value.pickle", "rb") as file:
        return pickle.load(file)


def fe_modes(mesh, material, n: int, size: float | None = None):
    """``ElasticBody.from_mesh(mesh, material, size).modes(n)``, solved once this session (a bundled body's
    12 modes take seconds; many modules simulate the same bodies), kept as :mod:`massline.virtual.fe_cache`
    keeps them and rebuilt on their basis."""
    from massline.virtual.elastic import ElasticBody
    from massline.virtual.fe_cache import as_arrays, from_arrays, model_key

    solve = lambda: as_arrays(ElasticBody.from_mesh(mesh, material, size).modes(n))  # noqa: E731
    return from_arrays(value("FE modes", solve, model_key(mesh, material, size, n)), material)
