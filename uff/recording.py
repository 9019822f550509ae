"""What a modal test system stores: FRFs between sensor and exciter lines."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from massline.placement.lines import Lines


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
    sensor_labels, exciter_labels : tuple of (node, direction code) or None
        The channels as the file names them (UFF node and ±1..±3), when read from a file.
    """

    frequencies: np.ndarray
    frf: np.ndarray
    sensors: Lines
    exciters: Lines
    coherence: np.ndarray | None = None
    description: str = ""
    sensor_labels: tuple | None = None
    exciter_labels: tuple | None = None

    def __post_init__(self):
        f = np.asarray(self.frequencies, dtype=float)
        h = np.asarray(self.frf, dtype=complex)
        if h.shape != (len(self.sensors), len(self.exciters), len(f)):
            raise ValueError(f"frf has shape {h.shape}, expected {(len(self.sensors), len(self.exciters), len(f))}")
        object.__setattr__(self, "frequencies", f)
        object.__setattr__(self, "frf", h)
