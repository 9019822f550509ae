"""Read the FRFs of a test from a Universal File (UFF/UNV) as modal test software exports it.

`read_uff` places what the file holds (DESIGN.md, "Recordings") in one global frame and in SI:

- dataset 164's factors are file units per SI unit: coordinates are divided by the length factor (a file in mm
  has 1000); FRFs are scaled and turned into accelerance as `frf_kind` decides;
- coordinate systems of dataset 18 (origin, a point on +x, a point in the +xz plane, in a reference system) and
  2420 (rows 1-3: the local x, y, z axes in the global frame; row 4: the origin) place the nodes of 15/2411:
  coordinates in their definition system, direction codes in their displacement system;
- FRFs (58, function type 4) get the coherence (function type 6) of the same channels;
- the window types of the 1858 qualifiers say whether the records were windowed as an impact test's are.

A direction code c (±1..±3) at a node is the global unit vector sign(c)·R[:, |c|−1] of the node's displacement
frame R (columns: its local axes in the global frame); a node's local +Z may be a global −Z.
:func:`.grid.to_recording` puts the FRFs on one sensor × exciter grid.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from massline.core.errors import MasslineError
from massline.uff.datasets import Function, function_name, parse, split
from massline.uff.frf_kind import check_accelerance, decide, to_accelerance
from massline.uff.recording import Channel

FRF_TYPE, COHERENCE_TYPE = 4, 6


@dataclass(frozen=True, eq=False)
class Frf:
    """One FRF record, as accelerance in SI.

    Attributes
    ----------
    number, line : int
        Its place among the file's FRFs (from 1) and the line where its record starts.
    response, reference : Channel
        (node, direction code) of the response (sensor) and the reference (exciter).
    frequencies : (n,) array
        Hz.
    accelerance : (n,) complex array
        (m/s²)/N.
    kind, rule : str
        What the record stored ("accelerance", "mobility", "receptance") and the rule that decided it
        ("type field", "unit label", "physics"; see `frf_kind`).
    coherence : (n,) array or None
        Its ordinary coherence, when the file holds one for the same channels and frequencies.
    run : str
        The file it was read from, when several were (:mod:`.runs`); empty for one file.
    """

    number: int
    line: int
    response: Channel
    reference: Channel
    frequencies: np.ndarray
    accelerance: np.ndarray
    kind: str
    rule: str
    coherence: np.ndarray | None = None
    run: str = ""

    @property
    def name(self) -> str:
        """'FRF 12 (line 3456)', with its file when several were read."""
        return f"{self.run + ': ' if self.run else ''}FRF {self.number} (line {self.line})"


@dataclass(frozen=True, eq=False)
class UffContents:
    """What a Universal File holds for this project.

    Attributes
    ----------
    path : Path
    datasets : tuple of int
        Dataset numbers in file order (58 for 58b too).
    functions : tuple of str
        The function type of each 58 record, in file order ("FRF", "coherence", "time response", ...).
    node_ids : (n,) int array
    node_points : (n, 3) array
        Node coordinates, m, global frame.
    node_frames : (n, 3, 3) array
        Each node's displacement frame: columns are its local x, y, z axes in the global frame.
    node_systems : (n,) int array
        Each node's displacement coordinate system (0: global).
    systems : dict of int to (4, 3) array
        Coordinate systems of datasets 18 and 2420 in the global frame: rows 1-3 the local axes, row 4 the
        origin (m).
    frfs : tuple of Frf
    description : str
        Dataset 151's model name and description.
    windows : tuple of int
        The window type of every dataset 1858 (the 58 qualifiers), in file order: 4 exponential, 5 impact,
        6 impact and exponential (record 2, field 2); empty when the file has none.
    warnings : list of str
        Anything odd that was tolerated.
    runs : tuple of str
        The files merged into these contents (:func:`.runs.read_runs`); empty for one file.
    """

    path: Path
    datasets: tuple[int, ...]
    functions: tuple[str, ...]
    node_ids: np.ndarray
    node_points: np.ndarray
    node_frames: np.ndarray
    node_systems: np.ndarray
    systems: dict[int, np.ndarray]
    frfs: tuple[Frf, ...]
    description: str
    warnings: list[str]
    windows: tuple[int, ...] = ()
    runs: tuple[str, ...] = ()


def _resolve(definitions: dict, name: str) -> dict:
    """{label: (type, origin, axes)} in the global frame (file units), each system placed in its reference."""
    placed = {0: (0, np.zeros(3), np.eye(3))}

    def place(label: int, chain: tuple[int, ...]):
        if label in placed:
            return placed[label]
        if label in chain or label not in definitions:
            problem = "is its own reference" if label in chain else "is not defined"
            raise MasslineError(
                f"file {name}: coordinate system {chain[-1]} is defined in system {label}, which {problem}: "
                "export every coordinate system (dataset 18 or 2420) with the geometry"
            )
        kind, reference, origin, axes = definitions[label]
        reference_kind, o, r = place(reference, (*chain, label))
        if reference_kind:
            raise MasslineError(
                f"file {name}: coordinate system {label} is defined in system {reference}, which is not Cartesian: "
                "export the coordinate systems in Cartesian form"
            )
        placed[label] = (kind, o + r @ origin, r @ axes)
        return placed[label]

    for label in definitions:
        place(label, ())
    return placed


def _node_system(systems: dict, label: int, name: str, assumed: set) -> tuple[np.ndarray, np.ndarray]:
    """Origin and axes of a node's system; an undefined system 1 is the global frame (I-DEAS numbers it 1)."""
    if label not in systems:
        if label != 1:
            raise MasslineError(
                f"file {name}: nodes use coordinate system {label}, which no dataset 18 or 2420 defines: "
                "export the coordinate systems with the nodes"
            )
        assumed.add(label)
        return np.zeros(3), np.eye(3)
    kind, origin, axes = systems[label]
    if kind != 0:
        raise MasslineError(
            f"file {name}: nodes use coordinate system {label}, which is not Cartesian (type {kind}): "
            "export the geometry in Cartesian coordinate systems"
        )
    return origin, axes


def _place_nodes(rows: np.ndarray, systems: dict, length: float, name: str):
    """Node labels, global points (m), displacement frames and displacement systems; and what was odd."""
    unique = {int(row[0]): row for row in rows}
    notes = (
        [f"{len(rows) - len(unique)} node(s) defined twice: the last definition is used"]
        if len(unique) < len(rows)
        else []
    )
    assumed, points, frames = set(), np.zeros((len(unique), 3)), np.zeros((len(unique), 3, 3))
    for k, (_, definition, displacement, _, *xyz) in enumerate(unique.values()):
        origin, axes = _node_system(systems, int(definition), name, assumed)
        points[k] = (origin + axes @ np.array(xyz)) / length
        frames[k] = _node_system(systems, int(displacement), name, assumed)[1]
    if assumed:
        notes.append("nodes use coordinate system 1, which the file does not define: taken as the global frame")
    systems_of = np.array([int(row[2]) for row in unique.values()], dtype=int)
    return np.array(list(unique), dtype=int), points, frames, systems_of, notes


def same_axis(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two frequency axes (Hz) are the same lines, to rounding."""
    return a.shape == b.shape and np.allclose(a, b, rtol=1e-6, atol=1e-9 * max(1.0, np.abs(a).max(initial=0.0)))


def _frfs(functions: list[Function], length: float, force: float, notes: list[str], name: str) -> tuple[Frf, ...]:
    """The FRF records as accelerance in SI, each with its coherence; exact repeats dropped."""
    coherences = {(f.response, f.reference): f for f in functions if f.type == COHERENCE_TYPE}
    frfs, seen = [], {}
    for number, f in enumerate((f for f in functions if f.type == FRF_TYPE), 1):
        label = f"FRF {number} (line {f.line}, {f.response} / {f.reference})"
        decision = decide(f.ordinate, f.frequencies, f.values, length, force, label)
        notes += decision.warnings
        if not np.iscomplexobj(f.values):
            notes.append(f"{label}: real values, read with a zero imaginary part")
        coherence = coherences.pop((f.response, f.reference), None)
        if coherence is not None and not same_axis(coherence.frequencies, f.frequencies):
            notes.append(f"{label}: its coherence is on other frequencies: ignored")
            coherence = None
        with np.errstate(all="ignore"):  # overflow of absurd values is refused just below
            accelerance = to_accelerance(decision.kind, f.frequencies, f.values * decision.scale)
        check_accelerance(accelerance, f"file {name}: FRF {number} (line {f.line})")
        if coherence is not None and not np.isfinite(coherence.values).all():
            notes.append(f"{label}: its coherence has NaN or infinite values: ignored")
            coherence = None
        weights = None if coherence is None else coherence.values.real
        frf = Frf(
            number, f.line, f.response, f.reference, f.frequencies, accelerance, decision.kind, decision.rule, weights
        )
        twin = seen.setdefault((f.response, f.reference), frf)
        if (
            twin is not frf
            and np.array_equal(twin.frequencies, frf.frequencies)
            and np.array_equal(twin.accelerance, frf.accelerance)
        ):
            notes.append(f"{label} repeats FRF {twin.number} exactly: ignored")
            continue
        frfs.append(frf)
    notes += [f"coherence at line {c.line} ({c.response}) has no FRF: ignored" for c in coherences.values()]
    weighted = sum(frf.coherence is not None for frf in frfs)
    if 0 < weighted < len(frfs):
        notes.append(f"only {weighted} of {len(frfs)} FRFs have a coherence: none is used")
    return tuple(frfs)


def _read_bytes(path: Path) -> bytes:
    try:
        return path.read_bytes()
    except FileNotFoundError:
        raise MasslineError(f"file {path} does not exist: check the path") from None
    except IsADirectoryError:
        raise MasslineError(f"{path} is a folder: give the UFF file inside it") from None
    except OSError as error:
        raise MasslineError(f"file {path} cannot be read ({error.strerror}): check its permissions") from None


def read_uff(path) -> UffContents:
    """Nodes, coordinate systems and FRFs (as accelerance in SI) of a Universal File.

    Parameters
    ----------
    path : str or Path
        A UFF/UNV file as test software exports it (ascii or with binary 58b records).

    Raises
    ------
    MasslineError (a ValueError)
        A missing, truncated or unreadable file, a coordinate system or node that cannot be placed.
    """
    path = Path(path)
    name = str(path)
    blocks = split(_read_bytes(path), name)
    if not blocks:
        raise MasslineError(
            f"file {name} holds no Universal File datasets (no '    -1' delimiter lines): give a UFF or UNV export"
        )
    parsed = [(block.number, parse(block, name)) for block in blocks]
    notes = [f"the file holds a single dataset ({blocks[0].number})"] if len(blocks) == 1 else []
    length, force = next((p for n, p in parsed if n == 164), (1.0, 1.0))
    definitions = {label: s for n, p in parsed if n in (18, 2420) for label, s in p.items()}
    systems = _resolve(definitions, name)
    rows = [p for n, p in parsed if n in (15, 2411)]
    ids, points, frames, node_systems, node_notes = _place_nodes(
        np.vstack(rows) if rows else np.zeros((0, 7)), systems, length, name
    )
    functions = [p[0] for n, p in parsed if n == 58]
    notes += node_notes + [note for n, p in parsed if n == 58 for note in p[1]]
    return UffContents(
        path=path,
        datasets=tuple(n for n, _ in parsed),
        functions=tuple(function_name(f.type) for f in functions),
        node_ids=ids,
        node_points=points,
        node_frames=frames,
        node_systems=node_systems,
        systems={label: np.vstack([axes.T, origin / length]) for label, (_, origin, axes) in systems.items() if label},
        frfs=_frfs(functions, length, force, notes, name),
        description=next((p for n, p in parsed if n == 151), ""),
        warnings=notes,
        windows=tuple(p for n, p in parsed if n == 1858),
    )
