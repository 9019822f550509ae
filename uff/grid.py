"""The FRFs of a Universal File on one sensor × exciter grid: the :class:`~.recording.Recording` the
estimators read, from what :func:`.reader.read_uff` found.

Rows are the response channels in file order, columns the reference channels in file order; a node's three
response channels along its three axes form a triaxial accelerometer. Every FRF must be at nodes with
coordinates, along translations: anything else is refused with the FRF, its line in the file and what to export
instead. Pairs not measured, FRFs on other axes and pairs measured twice are kept as they are (NaN where nothing
was measured, repeats combined): what the estimators make of them is theirs to say. A 1858 qualifier of window
type 4 or 6 marks the recording as windowed exponentially (an impact test's window).
"""

from __future__ import annotations

import numpy as np

from massline.core.errors import MasslineError
from massline.core.lines import Lines
from massline.uff.reader import Frf, UffContents
from massline.uff.recording import Channel, Recording, Repeat, code_direction
from massline.uff.runs import coherence_weights, combined, lines_in, union_axis

EXPONENTIAL = {4, 6}  # dataset 1858 window types with an exponential window: exponential, impact and exponential


def _no_frfs(contents: UffContents) -> MasslineError:
    found = ", ".join(str(n) for n in dict.fromkeys(contents.datasets))
    if contents.functions:
        counts = ", ".join(f"{kind} ×{contents.functions.count(kind)}" for kind in dict.fromkeys(contents.functions))
        return MasslineError(
            f"file {contents.path} holds no FRFs (datasets found: {found}; functions: {counts}): export the "
            "frequency response functions (dataset 58, function type 4)"
        )
    what = "it is a geometry file" if len(contents.node_ids) or contents.systems else "it holds no measurement"
    return MasslineError(
        f"file {contents.path} holds no FRFs (datasets found: {found}): {what}; give the measurement export"
    )


def _check_channels(frf: Frf, contents: UffContents) -> None:
    """Every channel a translation (code ±1..±3) at a node with coordinates, and values."""
    where = f"file {contents.path}: {frf.name}"
    for role, (node, code) in (("response", frf.response), ("reference", frf.reference)):
        if code == 0:
            raise MasslineError(
                f"{where} has {role} direction code 0 (a scalar or unknown direction): the method needs "
                "translations along ±X, ±Y or ±Z of a node; give every channel its node and direction and export again"
            )
        if abs(code) > 3:
            raise MasslineError(
                f"{where} has {role} {Channel(node, code)}, not a translation: the method needs translational "
                "responses and forces; leave rotational channels out of the export"
            )
        if node not in contents.node_ids:
            raise MasslineError(
                f"{where} names {role} node {node}, which has no coordinates in dataset 15/2411: "
                "export the geometry with the FRFs"
            )
    if not len(frf.accelerance):
        raise MasslineError(f"{where} holds no values: export it again or leave it out")


def _lines(contents: UffContents, channels: list[tuple[int, int]], triaxials: bool) -> Lines:
    """Lines of (node, code) channels; a node's three channels along its three axes form a triaxial group."""
    index = {int(n): k for k, n in enumerate(contents.node_ids)}
    points = contents.node_points[[index[node] for node, _ in channels]]
    axes = [code_direction(contents.node_frames[index[node]], code) for node, code in channels]
    group = np.full(len(channels), -1)
    for node in dict.fromkeys(node for node, _ in channels) if triaxials else ():
        members = [i for i, (n, _) in enumerate(channels) if n == node]
        if sorted(abs(channels[i][1]) for i in members) == [1, 2, 3]:
            group[members] = group.max() + 1
    return Lines(points, np.array(axes), group)


def _table(contents: UffContents) -> dict:
    """{(response, reference): [Frf, ...]}: each pair's measurements in file (and run) order."""
    table: dict = {}
    for frf in contents.frfs:
        table.setdefault((frf.response, frf.reference), []).append(frf)
    return table


def _on_axis(frfs: list, frequencies: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
    """Measurements of one pair (k, n_f) on the union axis ``frequencies`` and their coherence (NaN off each
    FRF's own lines)."""
    index = [lines_in(frequencies, frf.frequencies) for frf in frfs]
    values = np.full((len(frfs), len(frequencies)), np.nan, dtype=complex)
    weighted = all(frf.coherence is not None for frf in frfs)
    coherence = np.full(values.shape, np.nan) if weighted else None
    for k, (frf, lines) in enumerate(zip(frfs, index)):
        values[k, lines] = frf.accelerance
        if weighted:
            coherence[k, lines] = frf.coherence
    return values, coherence


def _grid(contents: UffContents, sensors: list, exciters: list, frequencies: np.ndarray, weighted: bool):
    """The FRF (n_s, n_e, n_f) and coherence grids, NaN where a pair or a line was not measured, and the
    :class:`Repeat` of every pair measured more than once."""
    table = _table(contents)
    frf = np.full((len(sensors), len(exciters), len(frequencies)), np.nan, dtype=complex)
    coherence = np.full(frf.shape, np.nan) if weighted else None
    repeats = []
    for i, s in enumerate(sensors):
        for j, e in enumerate(exciters):
            if (s, e) not in table:
                continue
            values, gamma2 = _on_axis(table[s, e], frequencies)
            if len(values) == 1:
                frf[i, j], joined = values[0], None if gamma2 is None else gamma2[0]
            else:
                frf[i, j], joined = combined(values, coherence_weights(gamma2))
                runs = tuple(frf_.run or f"FRF {frf_.number}" for frf_ in table[s, e])
                repeats.append(Repeat(i, j, runs, values, gamma2))
            if weighted:
                coherence[i, j] = joined
    return frf, coherence, tuple(repeats)


def to_recording(contents: UffContents) -> Recording:
    """The FRFs of a file (or of several runs' files, :func:`.runs.read_runs`) on one grid: unique responses in
    file order × unique references in file order, on the union of the FRFs' frequency axes.

    Sensor lines are the response channels (point: the node, m; direction: the code's axis of the node's
    displacement frame, global); a node's channels along its three axes form a triaxial accelerometer.
    Exciter lines are the reference channels. A pair no FRF measures is NaN at every line; an FRF on another
    axis is NaN at the lines of the union it lacks; a pair measured more than once is their combination
    (:func:`.runs.combined`), each measurement kept in ``repeats``.

    Raises
    ------
    MasslineError (a ValueError)
        No FRFs; a scalar or rotational channel; a node without coordinates; NaN or infinite values; fewer
        than 3 exciters or 3 sensors.
    """
    frfs = contents.frfs
    if not frfs:
        raise _no_frfs(contents)
    for frf in frfs:
        _check_channels(frf, contents)
    sensors = list(dict.fromkeys(frf.response for frf in frfs))
    exciters = list(dict.fromkeys(frf.reference for frf in frfs))
    needs = {
        "reference (exciter)": (
            exciters,
            "3 excitations, in non-parallel directions for a 3-D body (out-of-plane"
            " at 3 points not in a row for a plate); measure more references",
        ),
        "response (sensor)": (
            sensors,
            "6 sensor lines for a 3-D body (3 along z for a plate), so that every rigid "
            "motion is seen; measure more responses",
        ),
    }
    for role, (channels, need) in needs.items():
        if len(channels) < 3:
            raise MasslineError(
                f"file {contents.path}: the FRFs have {len(channels)} {role} channel(s) "
                f"({', '.join(map(str, channels))}): the method needs at least {need}"
            )
    frequencies, _ = union_axis([frf.frequencies for frf in frfs])
    weighted = all(frf.coherence is not None for frf in frfs)
    frf, coherence, repeats = _grid(contents, sensors, exciters, frequencies, weighted)
    return Recording(
        frequencies=frequencies,
        frf=frf,
        sensors=_lines(contents, sensors, True),
        exciters=_lines(contents, exciters, False),
        coherence=coherence,
        description=contents.description,
        sensor_labels=tuple(sensors),
        exciter_labels=tuple(exciters),
        exponential_window=bool(EXPONENTIAL & set(contents.windows)),
        runs=contents.runs,
        repeats=repeats,
        unmeasured_nodes=unmeasured_nodes(contents),
    )


def unmeasured_nodes(contents: UffContents) -> tuple[int, ...]:
    """The geometry's node numbers, in file order, that no FRF has as its response or its reference."""
    used = {frf.response.node for frf in contents.frfs} | {frf.reference.node for frf in contents.frfs}
    return tuple(int(n) for n in contents.node_ids if int(n) not in used)
