"""A test left as several runs: one Universal File per run (or a folder of them), merged into one recording.

A shaker moved between runs, a roving accelerometer re-mounted, a second run at a finer resolution: each run is
exported on its own. :func:`read_runs` reads every file as :func:`.reader.read_uff` does (each in its own units
and coordinate systems, placed in the one global frame) and merges them: nodes by label (a node placed apart in
two files, beyond ``NODE_TOLERANCE``, is refused with both positions), every FRF kept with its run.
:func:`union_axis` puts FRFs of different axes on the union of their lines, and :func:`combined` joins the
measurements of a pair made more than once, weighted by their coherence.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from massline.core.errors import MasslineError
from massline.uff.reader import UffContents, read_uff

SUFFIXES = {".uff", ".unv"}
NODE_TOLERANCE = 1e-4  # m: two files' coordinates of one node (exporters write ~6 digits of mm)
FRAME_TOLERANCE = 1e-3  # the largest difference between two files' displacement axes of one node (~0.06°)
LINE_TOLERANCE = 1e-6  # relative: two axes' lines closer than this are one line
WEIGHT_FLOOR = 1e-12  # a measurement's least weight γ²/(1 − γ²) in a join (a coherence of 0)


def run_paths(paths) -> list[Path]:
    """The files to read: each path given, a folder as its UFF/UNV files in name order.

    Raises
    ------
    MasslineError
        A folder without UFF/UNV files; a file given twice.
    """
    found = []
    for path in map(Path, paths):
        if path.is_dir():
            inside = sorted(p for p in path.iterdir() if p.suffix.lower() in SUFFIXES and p.is_file())
            if not inside:
                raise MasslineError(f"folder {path} holds no .uff or .unv file: give the files of the test's runs")
            found += inside
        else:
            found.append(path)
    twice = [p for k, p in enumerate(found) if p.resolve() in {q.resolve() for q in found[:k]}]
    if twice:
        raise MasslineError(f"file {twice[0]} is given twice: give each run's file once")
    return found


def _nodes(contents: list[UffContents]) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Node labels, points (m), frames and systems of every file, each label once; refused where files disagree."""
    placed: dict[int, tuple] = {}
    for c in contents:
        for k, label in enumerate(map(int, c.node_ids)):
            here = (c.node_points[k], c.node_frames[k], c.node_systems[k], c.path)
            first = placed.setdefault(label, here)
            if np.linalg.norm(first[0] - here[0]) > NODE_TOLERANCE:
                a, b = (" ".join(f"{v * 1e3:.6g}" for v in p[0]) for p in (first, here))
                raise MasslineError(
                    f"node {label} is at ({a}) mm in {first[3]} and ({b}) mm in {here[3]}: the runs' geometries "
                    "disagree; export every run with the same geometry (or renumber the moved point)"
                )
            if np.abs(first[1] - here[1]).max() > FRAME_TOLERANCE:
                raise MasslineError(
                    f"node {label} has other displacement axes in {here[3]} than in {first[3]}: a channel's "
                    "direction would change between runs; export every run in the same coordinate systems"
                )
    labels = np.array(list(placed), dtype=int)
    rows = list(placed.values())
    if not rows:
        return labels, np.zeros((0, 3)), np.zeros((0, 3, 3)), np.zeros(0, dtype=int)
    return labels, np.array([r[0] for r in rows]), np.array([r[1] for r in rows]), np.array([r[2] for r in rows])


def merged(contents: list[UffContents]) -> UffContents:
    """One file's worth of what several runs' files hold: nodes merged by label, every FRF with its run."""
    if len(contents) == 1:
        return contents[0]
    labels, points, frames, systems_of = _nodes(contents)
    names = [c.path.name if len({d.path.name for d in contents}) == len(contents) else str(c.path) for c in contents]
    frfs = tuple(replace(frf, run=name) for c, name in zip(contents, names) for frf in c.frfs)
    return UffContents(
        path=contents[0].path.parent if len({c.path.parent for c in contents}) == 1 else contents[0].path,
        datasets=tuple(n for c in contents for n in c.datasets),
        functions=tuple(f for c in contents for f in c.functions),
        node_ids=labels,
        node_points=points,
        node_frames=frames,
        node_systems=systems_of,
        systems={label: s for c in contents for label, s in c.systems.items()},
        frfs=frfs,
        description=next((c.description for c in contents if c.description), ""),
        warnings=[f"{name}: {note}" for c, name in zip(contents, names) for note in c.warnings],
        windows=tuple(w for c in contents for w in c.windows),
        runs=tuple(names),
    )


def read_runs(paths) -> UffContents:
    """What the Universal Files of a test's runs hold, merged (:func:`merged`); ``paths``: files or folders.

    Raises
    ------
    MasslineError (a ValueError)
        As :func:`.reader.read_uff` for each file; a node placed apart in two files; an empty folder.
    """
    return merged([read_uff(path) for path in run_paths(paths)])


def union_axis(axes: list[np.ndarray]) -> tuple[np.ndarray, list[np.ndarray]]:
    """The union of several frequency axes (Hz) and where each axis's lines sit in it.

    Lines closer than ``LINE_TOLERANCE`` (relative to the highest frequency) are one line.
    """
    every = np.concatenate(axes)
    order = np.sort(every)
    scale = max(1.0, np.abs(order).max(initial=0.0))
    starts = np.concatenate([[True], np.diff(order) > LINE_TOLERANCE * scale])
    union = order[starts]
    return union, [lines_in(union, a) for a in axes]


def lines_in(union: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """Where the lines of ``axis`` (Hz) sit in ``union`` (:func:`union_axis`'s, which holds them all)."""
    if len(axis) == len(union) and np.array_equal(axis, union):
        return np.arange(len(union))
    scale = max(1.0, np.abs(union).max(initial=0.0))
    return np.clip(np.searchsorted(union, axis - LINE_TOLERANCE * scale), 0, len(union) - 1)


def coherence_weights(coherence: np.ndarray | None) -> np.ndarray | None:
    """γ²/(1 − γ²) of every line: the inverse of an H1 estimate's relative variance (None without coherence)."""
    if coherence is None:
        return None
    gamma2 = np.clip(coherence, 0.0, 1 - 1e-6)
    return gamma2 / (1 - gamma2)


def combined(frf: np.ndarray, weights: np.ndarray | None) -> tuple[np.ndarray, np.ndarray | None]:
    """Several measurements of one pair (k, n_f) joined line by line, and the coherence of the join.

    Each line is the mean of the measurements present there (finite), weighted by w = γ²/(1 − γ²), the inverse
    of an H1 estimate's relative variance (equal weights without ``weights``); the join's coherence is
    W/(1 + W) with W = Σ w, what one measurement of that weight would carry. NaN where none is present.
    """
    present = np.isfinite(frf)
    w = np.ones(frf.shape) if weights is None else np.maximum(np.nan_to_num(weights), WEIGHT_FLOOR)
    w = np.where(present, w, 0.0)
    total = w.sum(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = (np.where(present, frf, 0) * w).sum(axis=0) / total
    mean[~present.any(axis=0)] = np.nan
    if weights is None:
        return mean, None
    gamma2 = np.where(present.any(axis=0), total / (1 + total), np.nan)
    return mean, gamma2
