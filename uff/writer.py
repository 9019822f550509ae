"""Write a virtual test's FRFs as a Universal File, the way modal test software exports them.

Units (164, and the labels of 58: SI, mm or inches; accelerance in length/s² or g per force unit): :mod:`.units`.

The file holds, in this order (DESIGN.md, "Recordings"):

- 151 header (the recording's description) and 164 units;
- 18 (with nodes in 15) or 2420 (with nodes in 2411): one Cartesian displacement coordinate system per node
  whose lines are not all along ± global axes, numbered like its node (0 is the global system);
- 15 or 2411 nodes;
- one 58 (ascii) or 58b (binary) record per sensor-exciter pair: function type 4, complex accelerance, response
  node and direction code, reference (exciter) node and direction code; then, when the recording has coherence,
  one record of function type 6 (coherence, UFF's code for it) per pair. A recording windowed exponentially
  (an impact test's) has a 1858 qualifier before each FRF record, window type 6 (impact and exponential).

Nodes and direction codes: :mod:`.layout`.

pyuff 2.5 writes 151, 164, 15, 18, 2411 and 2420 as the format says, so those go through `pyuff.UFF.write_sets`.
Dataset 58 is formatted here: pyuff's 58b header states 8 bytes per point for complex data (16 are written), it
stores an uneven abscissa of 58b in double precision where the format and real exporters use single, and it
rereads the whole file after every record.

Precision: 15 and 18 are E13.5 (6 significant digits: node coordinates and frames to ~5e-6), 2411 and 2420 are
D25.16 (exact), ascii 58 values are E20.12 (13 digits), 58b values are IEEE doubles (exact); the abscissa minimum
and increment are E13.5 in both.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pyuff

from massline.core.errors import MasslineError
from massline.core.files import atomic_file
from massline.uff.node_layout import UffLayout, uff_layout
from massline.uff.recording import Recording, code_name
from massline.uff.units import ACCELERATIONS, UNITS, AccelerationUnits, Characteristic, UnitSystem, accelerance_units

COLOR = 8
FRF, COHERENCE = 4, 6  # UFF 58 function types
IMPACT_AND_EXPONENTIAL = 6  # dataset 1858's window type of an impact test's force and exponential windows
ABSCISSA = Characteristic(18, (0, 0, 0), "Frequency", "Hz")
SILENT = Characteristic(0, (0, 0, 0), "NONE", "NONE")


def _text(text: str) -> str:
    """One ascii line of at most 80 characters ('NONE' when empty), as UFF id lines need."""
    line = " ".join(text.split()).encode("ascii", "replace").decode()[:80]
    return line or "NONE"


def _stamp() -> str:
    """Date and time as UFF writes them: 'DD-Mon-YY HH:MM:SS'."""
    return time.strftime("%d-%b-%y %H:%M:%S")


def _header_151(description: str, stamp: str) -> dict:
    date, clock = stamp.split()
    dataset = pyuff.prepare_151(
        model_name="massline virtual test",
        description=_text(description),
        db_app="massline",
        date_db_created=date,
        time_db_created=clock,
        date_db_saved=date,
        time_db_saved=clock,
        program="massline",
    )
    return dataset | {"date_file_written": date, "time_file_written": clock}


def _units_164(units: UnitSystem) -> dict:
    return pyuff.prepare_164(
        units_code=units.code,
        units_description=units.description,
        temp_mode=2,
        length=units.length,
        force=units.force,
        temp=1.0,
        temp_offset=273.15,
    )


def _systems(layout: UffLayout, nodes_dataset: int, units: UnitSystem) -> list[dict]:
    """Dataset 18 (origin, point on +x, point on the +xz plane, 1 m apart) or 2420 (rows: local axes, origin)."""
    local = layout.node_systems > 0
    if not local.any():
        return []
    labels, frames = layout.node_systems[local], layout.node_frames[local]
    origins = layout.node_points[local] * units.length
    names = [f"NODE {n}" for n in labels]
    if nodes_dataset == 2411:
        return [
            pyuff.prepare_2420(
                Part_UID=1,
                Part_Name="massline virtual test",
                CS_sys_labels=[int(n) for n in labels],
                CS_types=[0] * len(labels),
                CS_colors=[COLOR] * len(labels),
                CS_names=names,
                CS_matrices=[np.vstack([r.T, o]) for r, o in zip(frames, origins)],
            )
        ]
    x_points = origins + frames[:, :, 0] * units.length
    return [
        pyuff.prepare_18(
            cs_num=labels,
            cs_type=np.zeros(len(labels), dtype=int),
            ref_cs_num=np.zeros(len(labels), dtype=int),
            color=np.full(len(labels), COLOR),
            method=np.ones(len(labels), dtype=int),
            cs_name=names,
            ref_o=origins,
            x_point=x_points,
            xz_point=x_points + frames[:, :, 2] * units.length,
        )
    ]


def _nodes(layout: UffLayout, nodes_dataset: int, units: UnitSystem) -> dict:
    """Dataset 15 or 2411: node coordinates in the global system (0), displacement in each node's system."""
    x, y, z = (layout.node_points * units.length).T
    prepare = pyuff.prepare_2411 if nodes_dataset == 2411 else pyuff.prepare_15
    n = len(layout.node_ids)
    return prepare(
        node_nums=layout.node_ids,
        def_cs=np.zeros(n, dtype=int),
        disp_cs=layout.node_systems,
        color=np.full(n, COLOR),
        x=x,
        y=y,
        z=z,
    )


def _even_step(frequencies: np.ndarray) -> float | None:
    """Increment (Hz) of an evenly spaced axis, None for an uneven one (or a single line)."""
    steps = np.diff(frequencies)
    if len(steps) == 0 or not np.allclose(steps, steps[0], rtol=1e-9, atol=0.0):
        return None
    return float((frequencies[-1] - frequencies[0]) / len(steps))


def _characteristics(c: Characteristic) -> str:
    """Records 8-11: specific data type, length/force/temperature exponents, axis label and unit label."""
    (a, b, t), label, unit = c.exponents, c.axis_label, c.unit_label
    return f"{c.data_type:10d}{a:5d}{b:5d}{t:5d} {label:<20.20s} {unit:<20.20s}\n"


def ascii_values(x: np.ndarray, parts: list[np.ndarray], even: bool) -> bytes:
    """Record 12 in ascii: 4E20.12 (even), E13.5,2E20.12 (uneven complex), 2(E13.5,E20.12) (uneven real)."""
    columns = parts if even else [x, *parts]
    formats = ["%20.12E"] * len(parts) if even else ["%13.5E"] + ["%20.12E"] * len(parts)
    fields = [form % value for row in zip(*columns) for form, value in zip(formats, row)]
    per_line = 3 if len(columns) == 3 else 4
    return "".join("".join(fields[i : i + per_line]) + "\n" for i in range(0, len(fields), per_line)).encode()


def binary_values(x: np.ndarray, parts: list[np.ndarray], even: bool) -> bytes:
    """Record 12 in binary, little-endian: ordinates as doubles, an uneven abscissa as singles before each point."""
    fields = ([] if even else [("x", "<f4")]) + [(f"y{i}", "<f8") for i in range(len(parts))]
    packed = np.empty(len(parts[0]), dtype=fields)
    for (name, _), column in zip(fields, ([] if even else [x]) + parts):
        packed[name] = column
    return packed.tobytes()


def _dataset_58(
    number: int,
    kind: int,
    ids: list[str],
    response: tuple[int, int],
    reference: tuple[int, int],
    frequencies: np.ndarray,
    values: np.ndarray,
    ordinate: tuple[Characteristic, Characteristic],
    binary: bool,
) -> bytes:
    """One function at nodal DOF, with the record layout of Addendum B (complex or real, double precision).

    ``ordinate`` holds records 9 and 10 (numerator and denominator characteristics).
    """
    step = _even_step(frequencies)
    even = step is not None
    minimum, increment = (frequencies[0], step) if even else (0.0, 0.0)
    parts = [values.real, values.imag] if np.iscomplexobj(values) else [values]
    body = (binary_values if binary else ascii_values)(frequencies, parts, even)
    opening = f"{58:6d}b{1:6d}{2:6d}{11:12d}{len(body):12d}{0:6d}{0:6d}{0:12d}{0:12d}\n" if binary else f"{58:6d}\n"
    header = "".join(
        [
            f"{-1:6d}\n",
            opening,
            *(f"{_text(line):<80s}\n" for line in ids),
            f"{kind:5d}{number:10d}{1:5d}{0:10d} {'NONE':<10s}{response[0]:10d}{response[1]:4d}"
            f" {'NONE':<10s}{reference[0]:10d}{reference[1]:4d}\n",
            f"{6 if len(parts) == 2 else 4:10d}{len(frequencies):10d}{int(even):10d}"
            f"{minimum:13.5E}{increment:13.5E}{0.0:13.5E}\n",
            _characteristics(ABSCISSA),
            *map(_characteristics, ordinate),
            _characteristics(SILENT),
        ]
    )
    return header.encode("ascii") + body + f"{-1:6d}\n".encode()


def _qualifiers_1858(number: int, window: int) -> bytes:
    """Dataset 1858, the qualifiers of the 58 record that follows: its set record ``number`` and ``window``
    type; everything else unknown (0)."""
    zeros = f"{0.0:15.7E}" * 5 + "\n"
    records = [f"{number:12d}" + f"{0:12d}" * 5 + "\n", f"{0:6d}{window:6d}" + f"{0:6d}" * 10 + "\n"]
    records += [zeros] * 3 + [f"{'NONE':<4s}  {'NONE':<4s}\n", f"{'NONE':<80s}\n"]
    return f"{-1:6d}\n{1858:6d}\n".encode() + "".join(records).encode() + f"{-1:6d}\n".encode()


def _functions(
    recording: Recording, layout: UffLayout, units: AccelerationUnits, binary: bool, stamp: str, columns=None
):
    """The 58 records: every FRF (accelerance, in the file's units) of the exciters ``columns`` (all: None), then
    every coherence. Each FRF on its own lines (those not NaN); a pair NaN at every line is not written."""
    accelerance = (units.numerator, units.denominator)
    dimensionless = (Characteristic(1, (0, 0, 0), "Coherence", "NONE"), SILENT)
    functions = [("Frequency Response Function", FRF, recording.frf * units.factor, accelerance)]
    if recording.coherence is not None:
        functions.append(("Coherence", COHERENCE, np.asarray(recording.coherence, dtype=float), dimensionless))
    present = recording.present
    chosen = range(len(recording.exciters)) if columns is None else columns
    pairs = [(i, j) for i in range(len(recording.sensors)) for j in chosen if present[i, j]]
    for k, (title, kind, data, ordinate) in enumerate(functions):
        for n, (i, j) in enumerate(pairs):
            response = (int(layout.sensor_nodes[i]), int(layout.sensor_codes[i]))
            reference = (int(layout.exciter_nodes[j]), int(layout.exciter_codes[j]))
            channel = f"S{i + 1} {code_name(response[1])} / E{j + 1} {code_name(reference[1])}"
            ids = [title, "massline virtual test", stamp, channel, "NONE"]
            number = k * len(pairs) + n + 1
            if kind == FRF and recording.exponential_window:
                yield _qualifiers_1858(number, IMPACT_AND_EXPONENTIAL)
            lines = np.isfinite(recording.frf[i, j])
            yield _dataset_58(
                number, kind, ids, response, reference, recording.frequencies[lines], data[i, j, lines], ordinate,
                binary,
            )  # fmt: skip


def _write(path: Path, datasets: list[dict], records) -> None:
    """The file, whole or not at all: pyuff's datasets, then the 58 records (:func:`~massline.core.files.atomic_file`)."""
    with atomic_file(path) as temporary:
        pyuff.UFF(str(temporary)).write_sets(datasets, mode="add")
        with open(temporary, "ab") as handle:
            for record in records:
                handle.write(record)


def write_uff(
    path,
    recording: Recording,
    *,
    binary: bool = False,
    nodes_dataset: int = 15,
    node_systems: bool = True,
    units: str = "SI",
    acceleration: str = "length",
    force: bool = False,
    columns=None,
) -> UffLayout:
    """Write a recording as a Universal File: 151, 164, 18/2420, 15/2411, then 58 or 58b records.

    Parameters
    ----------
    path : str or Path
        The file to write; written whole or not at all.
    recording : Recording
        Accelerance FRFs ((m/s²)/N) between sensor and exciter lines (m, test frame), frequencies in Hz.
    binary : bool
        58b records (IEEE little-endian doubles) instead of ascii 58 (E20.12).
    nodes_dataset : {15, 2411}
        Nodes in dataset 15 with coordinate systems in 18, or in 2411 with coordinate systems in 2420.
    node_systems : bool
        Give each node with lines off the global axes its own displacement coordinate system; if False,
        every line must be along a ± global axis.
    units : {"SI", "MM", "IN"}
        Dataset 164 unit system (:mod:`.units`): m and N (code 1), mm and mN (code 5; accelerance (mm/s²)/mN,
        the same numbers as (m/s²)/N) or in and lbf (code 7; accelerance (in/s²)/lbf); coordinates in its
        length unit.
    acceleration : {"length", "g"}
        Accelerance as length/s² per force in the system's units, or as exporters show it to test engineers:
        g/N (SI, MM) or g/lbf (IN), said by the unit labels.
    force : bool
        Overwrite an existing file.
    columns : sequence of int or None
        The exciters whose FRFs the file holds (one run of a test that moved the shaker, :func:`write_runs`);
        every node is written all the same, so that each run's file numbers them alike. None: every exciter.

    A recording's NaN lines are left out: each FRF is written on its own lines, a pair NaN at every line not at
    all (the files a test with missing FRFs or runs at other resolutions leaves).

    Returns
    -------
    UffLayout
        The nodes and direction codes written.

    Raises
    ------
    FileExistsError
        ``path`` exists and ``force`` is False.
    MasslineError (a ValueError)
        A layout or option the file cannot represent (see `uff_layout`).
    """
    path = Path(path)
    if path.exists() and not force:
        raise FileExistsError(f"{path} already exists: pass force=True to overwrite it")
    if nodes_dataset not in (15, 2411):
        raise MasslineError(f"nodes_dataset must be 15 or 2411, got {nodes_dataset!r}")
    if units not in UNITS:
        raise MasslineError(f"units must be one of {', '.join(UNITS)}, got {units!r}")
    if acceleration not in ACCELERATIONS:
        raise MasslineError(f"acceleration must be one of {', '.join(ACCELERATIONS)}, got {acceleration!r}")
    if np.any(np.diff(recording.frequencies) <= 0):
        raise MasslineError("the frequencies of a recording must increase")
    layout = uff_layout(recording.sensors, recording.exciters, node_systems)
    system, stamp = UNITS[units], _stamp()
    datasets = [
        _header_151(recording.description, stamp),
        _units_164(system),
        *_systems(layout, nodes_dataset, system),
        _nodes(layout, nodes_dataset, system),
    ]
    frf_units = accelerance_units(system, acceleration)
    _write(path, datasets, _functions(recording, layout, frf_units, binary, stamp, columns))
    return layout


def run_files(path, count: int) -> list[Path]:
    """The files :func:`write_runs` writes for ``path``: ``STEM.run1.uff`` … ``STEM.run{count}.uff`` beside it."""
    path = Path(path)
    return [path.with_name(f"{path.stem}.run{j + 1}{path.suffix or '.uff'}") for j in range(count)]


def write_runs(path, recording: Recording, *, force: bool = False, **options) -> list[Path]:
    """The recording as a test that moved its exciter between runs leaves it: one Universal File per exciter
    (:func:`run_files`), each with every node and that exciter's FRFs; ``options`` as :func:`write_uff`'s.
    Every file is refused before any is written when one exists and ``force`` is False."""
    paths = run_files(path, len(recording.exciters))
    if not force and (there := [p for p in paths if p.exists()]):
        raise FileExistsError(f"{there[0]} already exists: pass force=True to overwrite it")
    for j, run in enumerate(paths):
        write_uff(run, recording, force=force, columns=[j], **options)
    return paths
