"""The recording handed back repaired: the diagnosed file with the faults it names undone, in the file's own terms.

The faults are undone as the diagnosis undid them for the properties after (:func:`.corrections.corrected`, each
effect's ``correct``): nothing is undone twice or otherwise. What their undoing does to the FRFs is read off by
two probes: the corrected recording of ones gives each sensor row's factor a_t(f) (a gain's 1/g, a polarity's −1,
a chain's 1/F(f)), that of the row numbers gives the row each row's data come from (a swap); a correction that
is no such factor and exchange of rows (one mixing the columns) cannot be written and is refused. What it does to
the lines (a sensor's point or axis, a hit's) is the corrected recording's lines. The file is then amended
(:mod:`massline.uff.amended`): a factor on the records' values, a negative constant factor as the channel's code
turned (the sign in the channel table, not in the data), exchanged rows' records restored to their places, moved
and turned lines as nodes and coordinate systems (:mod:`massline.uff.channel_geometry`).

A diagnosis of several runs' files (merged by node label, :mod:`massline.uff.runs`) is written back as one
corrected file per run, each amended alike.

The header lists each correction with its ± (the finding's sentence) and what was changed in the file, then what
was not corrected: findings no effect explains, test physics (modelled by identify in every band fit), a mass
loading (undone on the body) and a gauge's mass (an identify option), each with how.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from massline.core.errors import MasslineError
from massline.identify.diagnose.corrections import corrected
from massline.identify.diagnose.effects import named
from massline.identify.diagnose.notes import finding_note
from massline.uff.amended import Amendment, write_amended
from massline.uff.channel_geometry import placed
from massline.uff.grid import to_recording
from massline.uff.runs import read_runs, run_paths

EXACT = 1e-9  # a probe's row number read back within this of an integer; a factor the same on every column


def written_faults(findings: list) -> list:
    """The faults undone on the recording: those the corrected file carries."""
    return [f for f in findings if f.kind == "fault" and named(f.effect).undone_on == "recording"]


def row_operation(recording, faults: list) -> tuple[np.ndarray, np.ndarray]:
    """Each sensor row's factor a_t(f) (n_s, n_f) on ``recording``'s lines and the row its data come from, so that
    the corrected FRFs are a_t(f) · H[source(t), j](f); a MasslineError when the correction is not of that form."""
    n_s, n_e, n_f = recording.frf.shape
    ones = replace(recording, frf=np.ones((n_s, n_e, n_f), complex), coherence=None, repeats=())
    numbered = replace(ones, frf=np.broadcast_to(np.arange(1.0, n_s + 1)[:, None, None], ones.frf.shape).copy())
    factor = corrected(ones, faults).frf
    source = corrected(numbered, faults).frf / factor - 1
    rows = np.rint(source.real[:, 0, 0]).astype(int)
    exact = np.abs(source - rows[:, None, None]).max(initial=0.0) < EXACT
    same = np.abs(factor - factor[:, :1]).max(initial=0.0) <= EXACT * np.abs(factor).max(initial=1.0)
    if not (exact and same and sorted(rows) == list(range(n_s))):
        raise MasslineError(
            "the faults found undo the FRFs in a way a Universal File's records cannot hold (not a factor per "
            "channel and an exchange of channels): no corrected file written"
        )
    return factor[:, 0], rows


def flipped(factor: np.ndarray) -> np.ndarray:
    """(n_s,) bool: the rows whose factor is a negative real number at every line (a sign: the code's)."""
    return np.all((factor.real < 0) & (np.abs(factor.imag) <= EXACT * np.abs(factor)), axis=1)


def amendment(run, sources: list, faults: list) -> Amendment:
    """The files' amendment for ``faults`` of ``run``'s diagnosis of the files ``sources`` (one, or each run's),
    without its header."""
    contents = read_runs(sources)
    recording = to_recording(contents)
    if list(recording.sensor_labels) != list(run.recording.sensor_labels) or list(recording.exciter_labels) != list(
        run.recording.exciter_labels
    ):
        raise MasslineError("the files given are not those diagnosed (their channels differ): give the files read")
    factor, rows = row_operation(recording, faults)
    fixed = corrected(recording, faults)
    sign = np.where(flipped(factor), -1.0, 1.0)
    channels = {("response", i): (label, fixed.sensors.points[i], sign[i] * fixed.sensors.directions[i])
                for i, label in enumerate(recording.sensor_labels)}  # fmt: skip
    channels |= {("reference", j): (label, fixed.exciters.points[j], fixed.exciters.directions[j])
                 for j, label in enumerate(recording.exciter_labels)}  # fmt: skip
    placement = placed(contents.node_ids, contents.node_points, contents.node_frames, contents.node_systems,
                       list(contents.systems), channels)  # fmt: skip
    return Amendment(recording.frequencies, factor * sign[:, None], rows, placement, recording.sensor_labels,
                     recording.exciter_labels)  # fmt: skip


def changes(run, finding, placement) -> str:
    """What undoing ``finding`` changes in the file: the rows it scales, exchanges or turns, and the channels
    whose labels or nodes change (``placement``: the corrected file's, keyed as :func:`amendment` keys them)."""
    labels = placement.labels
    recording = run.recording
    factor, sources = row_operation(recording, [finding])
    fixed = corrected(recording, [finding])
    said = []
    names = recording.sensor_channels
    for t in np.flatnonzero(sources != np.arange(len(sources))):
        if t < sources[t]:
            said.append(f"the FRFs recorded as {names[t]} and {names[sources[t]]} exchanged")
    for t in np.flatnonzero(np.abs(factor - 1).max(axis=1) > EXACT):
        a = factor[t]
        if flipped(factor)[t] and np.allclose(a, -1):
            continue
        if np.allclose(a, a[0], rtol=EXACT) and abs(a[0].imag) <= EXACT * abs(a[0]):
            said.append(f"the FRFs of {names[t]} divided by {abs(1 / a[0].real):.6g}")
        else:
            said.append(f"the FRFs of {names[t]} divided by the factor of frequency found")
    for key, old, new in moved_lines(recording, fixed):
        said.append(f"{old} {new}: written as {labels[key]}{node_change(placement, labels[key].node)}")
    for t in np.flatnonzero(flipped(factor)):
        said.append(f"{names[t]} written as {labels[('response', int(t))]} (its sign)")
    return "; ".join(dict.fromkeys(said)) or "nothing in the file"


def node_change(placement, node: int) -> str:
    """How the corrected file holds ``node``: moved, given a coordinate system, or added."""
    place = placement.moved.get(node) or next((p for p in placement.added if p.node == node), None)
    if place is None:
        return ""
    how = "a node added" if node not in placement.moved else "its node written again"
    system = f" in coordinate system {place.system}" if place.system in placement.systems else ""
    x, y, z = 1e3 * np.asarray(place.point)
    return f" ({how} at ({x:.3f}, {y:.3f}, {z:.3f}) mm{system})"


def moved_lines(recording, fixed) -> list:
    """(key, old label, what moved) of each line ``fixed`` moves or turns."""
    out = []
    roles = (("response", recording.sensors, fixed.sensors, recording.sensor_channels),
             ("reference", recording.exciters, fixed.exciters, recording.exciter_channels))  # fmt: skip
    for role, old, new, names in roles:
        for i in range(len(old)):
            shift = 1e3 * np.linalg.norm(new.points[i] - old.points[i])
            turn = np.degrees(2 * np.arcsin(min(1.0, np.linalg.norm(new.directions[i] - old.directions[i]) / 2)))
            what = ", ".join(w for w, x in ((f"moved {shift:.3g} mm", shift > 1e-9),
                                             (f"turned {turn:.3g} deg", turn > 1e-9)) if x)  # fmt: skip
            if what:
                out.append(((role, i), names[i], what))
    return out


def not_corrected(finding) -> str:
    """Why a finding is not in the file, and how it is undone instead."""
    if finding.kind == "unexplained":
        return "not corrected (no effect of the library explains it)"
    if finding.kind == "test_physics":
        return "not corrected: test physics, modelled by identify in every band fit"
    effect = named(finding.effect)
    if effect.undone_on == "identify":
        option = effect.identify_option.replace("_", "-")
        return f"not in the file: give identify --{option} {effect.option_value(finding):.6g}"
    return "not in the file: undone on the body (the properties after take it off)"


def header(run, faults: list, placement) -> list[tuple[str, str]]:
    """The header's entries: each correction (its sentence with ±, what changed in the file), then each finding
    not corrected and why."""
    sensors, hits = run.sensors, run.hits
    entries = [(f"massline: correction {k} of {len(faults)}, {f.effect}",
                f"{finding_note(f, sensors, hits)}. In this file: {changes(run, f, placement)}.")
               for k, f in enumerate(faults, 1)]  # fmt: skip
    rest = [f for f in run.findings if f not in faults]
    entries += [(f"massline: not corrected {k} of {len(rest)}, {f.effect}",
                 f"{finding_note(f, sensors, hits)}. {not_corrected(f)}.")
                for k, f in enumerate(rest, 1)]  # fmt: skip
    return entries or [("massline: no finding", "the recording as it came: nothing to correct")]


def corrected_paths(path, sources) -> list[Path]:
    """Where the corrected recording of ``sources`` (files or folders of a test's runs) goes: ``path`` for one
    file; for several runs' files, one file beside ``path`` per run, ``STEM.RUN.uff`` (RUN the run's file stem)."""
    files, path = run_paths(sources if isinstance(sources, (list, tuple)) else [sources]), Path(path)
    if len(files) == 1:
        return [path]
    return [path.with_name(f"{path.stem}.{f.stem}{path.suffix or '.uff'}") for f in files]


def write_corrected(run, source, path, *, force: bool = False) -> list[Path]:
    """Write the file ``source`` (or the runs' files and folders of a list) that ``run`` diagnosed with the faults
    it names undone to ``path`` (several runs: :func:`corrected_paths`), each an existing file only with ``force``;
    a header lists each correction with its ± and each finding not corrected. Returns the files written."""
    sources = run_paths(source if isinstance(source, (list, tuple)) else [source])
    faults = written_faults(run.findings)
    first = amendment(run, sources, faults)
    entries = header(run, faults, first.placement)
    paths = corrected_paths(path, sources)
    return write_amended(sources, paths, replace(first, header=tuple(entries)), force=force)

