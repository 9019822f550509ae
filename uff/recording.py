"""What a modal test system stores: FRFs between sensor and exciter lines, and the channels' names."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np

from massline.core.errors import MasslineError
from massline.core.lines import Lines

AXIS_NAMES = ("X", "Y", "Z", "RX", "RY", "RZ")


def code_name(code: int) -> str:
    """'+X', '-Z', '-RX' for a UFF direction code (±1..±6); 'scalar' for 0."""
    if code == 0 or abs(code) > 6:
        return "scalar" if code == 0 else f"code {code}"
    return ("+" if code > 0 else "-") + AXIS_NAMES[abs(code) - 1]


def code_direction(frame, code: int) -> np.ndarray:
    """Global unit direction sign(c)·R[:, |c|−1] of a translation code c (±1..±3) in a node's Cartesian frame R.

    Parameters
    ----------
    frame : (3, 3) array
        Columns: the node's local x, y, z axes in the test frame.
    code : int
        1, 2, 3 for +x, +y, +z of the frame; negative for the opposite direction.
    """
    if code not in (-3, -2, -1, 1, 2, 3):
        raise MasslineError(f"direction code {code} is not a translation (±1..±3)")
    return np.sign(code) * np.asarray(frame, dtype=float)[:, abs(code) - 1]


class Channel(NamedTuple):
    """A channel as a Universal File names it: a node and a direction code along the node's frame.

    It unpacks as ``node, code`` and prints as the file names it: ``57:+Z``, ``3:-X``.
    """

    node: int
    code: int

    def __str__(self) -> str:
        return f"{self.node}:{code_name(self.code)}"


class Numbered(NamedTuple):
    """A channel of a recording that carries no labels: 'sensor 3', 'hit 2' (1-based); it has no node."""

    role: str
    number: int
    node = None

    def __str__(self) -> str:
        return f"{self.role} {self.number}"


@dataclass(frozen=True, eq=False)
class Repeat:
    """A response–reference pair measured in several runs.

    Attributes
    ----------
    sensor, exciter : int
        Its row and column in the recording.
    runs : tuple of str
        The run (file) of each measurement.
    frf : (k, n_f) complex array
        Each run's accelerance on the recording's lines, (m/s²)/N (NaN off the run's axis).
    coherence : (k, n_f) array or None
    """

    sensor: int
    exciter: int
    runs: tuple
    frf: np.ndarray
    coherence: np.ndarray | None = None

    def kept(self, keep: np.ndarray) -> "Repeat":
        """The repeat on the lines ``keep`` marks."""
        coherence = None if self.coherence is None else self.coherence[:, keep]
        return replace(self, frf=self.frf[:, keep], coherence=coherence)


@dataclass(frozen=True, eq=False)
class Recording:
    """Accelerance FRFs of one test.

    Attributes
    ----------
    frequencies : (n_f,) array
        Frequency axis, Hz.
    frf : (n_s, n_e, n_f) complex array
        Accelerance H_ij(f), (m/s²)/N, sensor i along its line, force j along its line.
    sensors, exciters : Lines
        The nominal lines (m, test frame), as the engineer labelled them.
    coherence : (n_s, n_e, n_f) array or None
        Ordinary coherence of each FRF, when it was estimated from averages.
    description : str
        Free text carried into the file header.
    sensor_labels, exciter_labels : tuple of Channel or None
        The channels as the file names them (UFF node and ±1..±3), when read from a file.
    exponential_window : bool
        The responses were windowed exponentially, as an impact test's are (a file's dataset 1858 says so:
        window type 4 or 6). The window adds σ_w = ln(1/end)/T to every pole; False when nothing says so.
    runs : tuple of str
        The files (test runs) the FRFs were read from, when more than one.
    repeats : tuple of Repeat
        The pairs measured in more than one run, each run's FRF on the recording's lines; ``frf`` holds their
        combination (:func:`massline.uff.runs.combined`).
    unmeasured_nodes : tuple of int
        The geometry's nodes (datasets 15, 2411) that no FRF has as its response or its reference: points planned
        and not measured (a channel lost, a file cut short), or a wireframe's.

    ``frf`` (and ``coherence``) hold NaN at the lines an FRF was not measured on: a pair no run measured
    (NaN at every line, :attr:`present` False), or an FRF on a coarser or shorter axis than the union of the
    runs' axes (``frequencies``).
    """

    frequencies: np.ndarray
    frf: np.ndarray
    sensors: Lines
    exciters: Lines
    coherence: np.ndarray | None = None
    description: str = ""
    sensor_labels: tuple | None = None
    exciter_labels: tuple | None = None
    exponential_window: bool = False
    runs: tuple = ()
    repeats: tuple = ()
    unmeasured_nodes: tuple = ()

    def __post_init__(self):
        f = np.asarray(self.frequencies, dtype=float)
        h = np.asarray(self.frf, dtype=complex)
        if h.shape != (len(self.sensors), len(self.exciters), len(f)):
            raise ValueError(f"frf has shape {h.shape}, expected {(len(self.sensors), len(self.exciters), len(f))}")
        object.__setattr__(self, "frequencies", f)
        object.__setattr__(self, "frf", h)
        for name in ("sensor_labels", "exciter_labels"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, tuple(Channel(int(n), int(c)) for n, c in getattr(self, name)))

    def above_zero(self) -> "Recording":
        """The recording without its lines at or below 0 Hz: exporters start the axis at 0 Hz, where an FRF
        holds noise or window residue and no massline (a massline is ω²-weighted receptance: nothing at DC)."""
        return self.kept(self.frequencies > 0)

    def kept(self, keep: np.ndarray) -> "Recording":
        """The recording on the lines ``keep`` (n_f,) bool marks (itself when it marks every line)."""
        if keep.all():
            return self
        return replace(
            self,
            frequencies=self.frequencies[keep],
            frf=self.frf[:, :, keep],
            coherence=None if self.coherence is None else self.coherence[:, :, keep],
            repeats=tuple(repeat.kept(keep) for repeat in self.repeats),
        )

    @property
    def present(self) -> np.ndarray:
        """(n_s, n_e) bool: the pairs measured (an FRF with at least one line)."""
        return np.isfinite(self.frf).any(axis=2)

    @property
    def sensor_channels(self) -> list:
        """Every sensor channel's label: its Channel ('12:+Y') or, in a recording without labels, 'sensor k'."""
        return list(self.sensor_labels or (Numbered("sensor", i + 1) for i in range(len(self.sensors))))

    @property
    def exciter_channels(self) -> list:
        """Every exciter channel's label: its Channel ('3:-Z') or, in a recording without labels, 'hit k'."""
        return list(self.exciter_labels or (Numbered("hit", j + 1) for j in range(len(self.exciters))))
