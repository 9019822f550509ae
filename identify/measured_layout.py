"""What a recording measured, as the next run's plan takes it: its lines and each massline's 1-σ over the band.

The same band and band fits identify uses (:func:`.band_masslines.recording_band`, :class:`.band_masslines.
BandMasslines`), without the estimate: a first run that lost a channel, and so identifies nothing, still says
what it measured and how well.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from massline.core.band import Band
from massline.identify.band_masslines import BandMasslines, recording_band
from massline.identify.estimator import TRANSVERSE
from massline.identify.pipeline import as_recording, is_planar, usable_lines, without_mains
from massline.uff.recording import Recording


@dataclass(frozen=True, eq=False, kw_only=True)
class MeasuredLayout:
    """A recording's lines (m, its frame), its band, each massline's |A_ij| and 1-σ ((m/s²)/N; inf: not
    measured), the noise it shows (relative RMS) and the transverse-sensitivity prior identify weighs it with."""

    recording: Recording
    band: Band
    magnitude: np.ndarray
    sigma: np.ndarray
    noise_relative: float
    transverse: float = TRANSVERSE

    @property
    def planar(self) -> bool:
        return is_planar(self.recording.sensors, self.recording.exciters)


def measured_layout(recording: Recording | str | Path | list, band=None) -> MeasuredLayout:
    """The layout ``recording`` (a Recording, a file, or the files of its runs) measured, with identify's band
    (``band`` (lo, hi) Hz, or found) and band fits."""
    recording, _ = usable_lines(as_recording(recording))
    recording, _, _ = without_mains(recording)
    _, used = recording_band(recording, band, is_planar(recording.sensors, recording.exciters))
    fitted = BandMasslines.of(recording, used)
    return MeasuredLayout(
        recording=recording, band=used, magnitude=np.abs(fitted.data.values), sigma=fitted.sigma,
        noise_relative=fitted.noise.relative(),
    )  # fmt: skip
