"""The FRFs of a Universal File on one sensor × exciter grid: the :class:`~.recording.Recording` the
estimators read, from what :func:`.reader.read_uff` found.

Rows are the response channels in file order, columns the reference channels in file order; a node's three
response channels along its three axes form a triaxial accelerometer. Every pair must be measured once, on
one frequency axis, at nodes with coordinates, along translations: anything else is refused with the FRF,
its line in the file and what to export instead. A 1858 qualifier of window type 4 or 6 marks the recording
as windowed exponentially (an impact test's window).
"""

from __future__ import annotations

import numpy as np

from massline.core.errors import MasslineError
from massline.core.lines import Lines
from massline.uff.reader import Frf, UffContents, same_axis
from massline.uff.recording import Channel, Recording, code_direction

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
    where = f"file {contents.path}: FRF {frf.number} (line {frf.line})"
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


def _table(contents: UffContents, sensors: list, exciters: list) -> dict:
    """{(response, reference): Frf}, every pair once."""
    table = {}
    for frf in contents.frfs:
        twin = table.setdefault((frf.response, frf.reference), frf)
        if twin is not frf:
            raise MasslineError(
                f"file {contents.path}: FRFs {twin.number} and {frf.number} both give response "
                f"{frf.response} against reference {frf.reference}, with different "
                "data: keep one measurement per pair"
            )
    missing = [(s, e) for s in sensors for e in exciters if (s, e) not in table]
    if missing:
        (s, e), n = missing[0], len(sensors) * len(exciters)
        raise MasslineError(
            f"file {contents.path}: no FRF between response {s} and reference {e} "
            f"({len(missing)} of {n} response-reference pairs missing): measure every response against every "
            "reference and export them all"
        )
    return table


def to_recording(contents: UffContents) -> Recording:
    """The FRFs of a file on one grid: unique responses in file order × unique references in file order.

    Sensor lines are the response channels (point: the node, m; direction: the code's axis of the node's
    displacement frame, global); a node's channels along its three axes form a triaxial accelerometer.
    Exciter lines are the reference channels.

    Raises
    ------
    MasslineError (a ValueError)
        No FRFs; a scalar or rotational channel; a node without coordinates; NaN or infinite values; fewer
        than 3 exciters or 3 sensors; FRFs on different frequency axes; a pair measured twice with different
        data, or missing.
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
    first = frfs[0]
    for frf in frfs:
        if not same_axis(frf.frequencies, first.frequencies):
            raise MasslineError(
                f"file {contents.path}: FRF {frf.number} has {_describe(frf.frequencies)}, FRF {first.number} "
                f"{_describe(first.frequencies)}: export all FRFs on one frequency axis"
            )
    table = _table(contents, sensors, exciters)
    grid = [[table[s, e] for e in exciters] for s in sensors]
    weighted = all(frf.coherence is not None for frf in frfs)
    return Recording(
        frequencies=first.frequencies,
        frf=np.array([[frf.accelerance for frf in row] for row in grid]),
        sensors=_lines(contents, sensors, True),
        exciters=_lines(contents, exciters, False),
        coherence=np.array([[frf.coherence for frf in row] for row in grid]) if weighted else None,
        description=contents.description,
        sensor_labels=tuple(sensors),
        exciter_labels=tuple(exciters),
        exponential_window=bool(EXPONENTIAL & set(contents.windows)),
    )


def _describe(frequencies: np.ndarray) -> str:
    return f"{len(frequencies)} frequencies {frequencies[0]:g}-{frequencies[-1]:g} Hz"
