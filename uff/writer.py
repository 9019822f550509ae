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

Nodes and direction codes: :mod:`.node_layout`. :func:`write_geometry` writes the geometry alone (151, 164,
2420/18, 2411/15 and a wireframe's 82): the setup test software loads before a test.

pyuff 2.5 writes 151, 164, 15, 18, 2411, 2420 and 82 as the format says, so those go through
`pyuff.UFF.write_sets`; dataset 58 and its 1858 qualifiers are formatted by :mod:`.function_records`.

Precision: 15 and 18 are E13.5 (6 significant digits: node coordinates and frames to ~5e-6), 2411 and 2420 are
D25.16 (exact), ascii 58 values are E20.12 (13 digits), 58b values are IEEE doubles (exact); the abscissa minimum
and increment are E13.5 in both.
"""

from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import pyuff

from massline.core.errors import MasslineError
from massline.core.files import atomic_file
from massline.uff.function_records import SILENT, ascii_line, dataset_58, qualifiers_1858
from massline.uff.node_layout import UffLayout, setup_layout, uff_layout
from massline.uff.recording import Recording, code_name
from massline.uff.units import ACCELERATIONS, UNITS, AccelerationUnits, Characteristic, UnitSystem, accelerance_units

COLOR = 8
FRF, COHERENCE = 4, 6  # UFF 58 function types
IMPACT_AND_EXPONENTIAL = 6  # dataset 1858's window type of an impact test's force and exponential windows
SETUP = "massline test setup"  # the model and part name of a setup's geometry


def _stamp() -> str:
    """Date and time as UFF writes them: 'DD-Mon-YY HH:MM:SS'."""
    return time.strftime("%d-%b-%y %H:%M:%S")


def _header_151(description: str, stamp: str, model: str = "massline virtual test") -> dict:
    date, clock = stamp.split()
    dataset = pyuff.prepare_151(
        model_name=model,
        description=ascii_line(description),
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


def _systems(
    layout: UffLayout, nodes_dataset: int, units: UnitSystem, part: str = "massline virtual test"
) -> list[dict]:
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
                Part_Name=part,
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
                yield qualifiers_1858(number, IMPACT_AND_EXPONENTIAL)
            lines = np.isfinite(recording.frf[i, j])
            yield dataset_58(
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
    setup_systems: bool = False,
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
    setup_systems : bool
        Every node in a system of its own, each lone line its +Z (:func:`.node_layout.setup_layout`: the systems
        ``massline setup`` gives the test software), instead of the global system where it serves.

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
    lines = (recording.sensors, recording.exciters)
    layout = setup_layout(*lines) if setup_systems else uff_layout(*lines, node_systems)
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


def _with_wireframe(layout: UffLayout, wireframe) -> tuple[UffLayout, list[dict]]:
    """The layout with the wireframe's nodes added (global system), and its dataset 82 (none without one)."""
    if wireframe is None:
        return layout, []
    ids, points, trace = (np.asarray(a) for a in wireframe)
    added = replace(
        layout,
        node_ids=np.concatenate([layout.node_ids, ids]).astype(int),
        node_points=np.vstack([layout.node_points, points]),
        node_frames=np.concatenate([layout.node_frames, np.broadcast_to(np.eye(3), (len(ids), 3, 3))]),
        node_systems=np.concatenate([layout.node_systems, np.zeros(len(ids), dtype=int)]),
    )
    line = pyuff.prepare_82(trace_num=1, n_nodes=len(trace), color=COLOR, id="the part's edges", nodes=trace)
    return added, [line]


def write_geometry(
    path,
    layout: UffLayout,
    *,
    description: str,
    nodes_dataset: int = 2411,
    units: str = "SI",
    wireframe=None,
    force: bool = False,
) -> None:
    """Write a test's geometry as test software imports it: 151, 164, 2420 (or 18), 2411 (or 15) and 82, no
    functions.

    Parameters
    ----------
    path : str or Path
        The file to write; written whole or not at all.
    layout : UffLayout
        The nodes (m, test frame) and their coordinate systems (:func:`.node_layout.setup_layout`).
    description : str
        Dataset 151's description (one line).
    nodes_dataset : {2411, 15}
        Nodes in 2411 with coordinate systems in 2420 (D25.16: exact), or in 15 with 18 (E13.5: 6 digits).
    units : {"SI", "MM", "IN"}
        Dataset 164's unit system; coordinates in its length unit.
    wireframe : (ids (k,), points (k, 3) m, trace (n,)) or None
        The part's outline: nodes (global system) and one traceline (dataset 82) through them, 0 lifting the pen.
    force : bool
        Overwrite an existing file.
    """
    path = Path(path)
    if path.exists() and not force:
        raise FileExistsError(f"{path} already exists: pass force=True to overwrite it")
    if nodes_dataset not in (15, 2411):
        raise MasslineError(f"nodes_dataset must be 15 or 2411, got {nodes_dataset!r}")
    system, stamp = UNITS[units], _stamp()
    nodes, lines = _with_wireframe(layout, wireframe)
    datasets = [
        _header_151(description, stamp, SETUP),
        _units_164(system),
        *_systems(layout, nodes_dataset, system, SETUP),
        _nodes(nodes, nodes_dataset, system),
        *lines,
    ]
    _write(path, datasets, ())


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
