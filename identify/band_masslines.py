"""A recording's massline band and the masslines its band fits give: what the estimator weighs.

The band is the engineer's (lo, hi) or the one the model chooses (:func:`.band_choice.choose_band`), with the
support's top mode and the first elastic mode the record shows around it (:func:`.resonances.bounding_modes`).
Each FRF's band fit (:func:`.massline_fit.fit_band`) gives its massline and 1-σ; a richer fit, with each
tail's next term, says how far the truncated tails can move it (:func:`.uncertainty.seen_truncation`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from massline.core.band import Band
from massline.core.lines import Lines
from massline.core.masslines import Masslines
from massline.identify.band_choice import choose_band
from massline.identify.massline_fit import BandFit, fit_band
from massline.identify.recording_noise import RecordingNoise, recording_noise, stated_averages
from massline.identify.resonances import bounding_modes
from massline.identify.uncertainty import seen_truncation
from massline.identify.zones import given_band
from massline.uff.recording import Recording
from massline.uff.runs import coherence_weights

SIGMA_FLOOR = 1e-9  # a massline's 1-σ is at least this fraction of the largest massline (a noiseless fit's is 0)


def recording_band(recording: Recording, band, planar: bool) -> tuple[Band, Band]:
    """The massline band as chosen, and as used: with the resonances the record shows around it.

    Parameters
    ----------
    recording : Recording
        The FRFs (n_s, n_e, n_f) over frequencies above 0 Hz, with their coherence.
    band : (lo, hi) or None
        The engineer's band edges, Hz; None: the band the model chooses, each line weighted by its coherence.
    planar : bool
        Plate data (§2.3): every line along z.

    Returns
    -------
    chosen : Band
        The band given or found (what the recording's own warnings judge).
    used : Band
        ``chosen`` with ``suspension_top`` and ``first_elastic`` the record's modes around it, Hz (nan: none).
    """
    f, frf, sensors, exciters = recording.frequencies, recording.frf, recording.sensors, recording.exciters
    if band:
        chosen = given_band(f, *band)
    else:
        chosen = choose_band(f, frf, sensors, exciters, planar=planar, weights=coherence_weights(recording.coherence))
    suspension_top, first_elastic = bounding_modes(f, frf, chosen, sensors, exciters, planar)
    return chosen, replace(chosen, suspension_top=suspension_top, first_elastic=first_elastic)


def band_residual(fit: BandFit, noise: RecordingNoise) -> float:
    """The band fits' RMS residual relative to the FRFs over the band, √(Σ_ij Σ_lines |r|² / Σ_ij Σ_lines |H|²)
    (``fit.quality`` is each FRF's per real part, relative to |A|): comparable with ``noise.relative()``."""
    squares = 2 * noise.lines * (fit.quality * fit.values) ** 2
    ok = np.isfinite(squares)
    return float(np.sqrt(np.sum(squares[ok]) / np.sum((noise.lines * noise.mean_square)[ok])))


@dataclass(frozen=True, eq=False)
class BandMasslines:
    """Each FRF's band fit, and the masslines and 1-σ the estimator takes from it.

    Attributes
    ----------
    fit : BandFit
        Massline A + tails B/ω², Cω², Dω⁴ of every FRF over the band (NaN: a pair with no massline).
    richer : BandFit
        The same with each tail's next term, B₂/ω⁴ and D₂ω⁶, fitted too.
    sensors, exciters : Lines
        The recording's sensor and exciter lines (rows and columns).
    noise : RecordingNoise
        Each FRF's noise over the band, from the recording alone (:mod:`.recording_noise`): what the fit is
        measured against.
    """

    fit: BandFit
    richer: BandFit
    sensors: Lines
    exciters: Lines
    noise: RecordingNoise

    @classmethod
    def of(cls, recording: Recording, band: Band) -> BandMasslines:
        """The band fits of ``recording``'s FRFs over ``band``, each line weighted by its coherence."""
        f, frf, weights = recording.frequencies, recording.frf, coherence_weights(recording.coherence)
        fit = fit_band(f, frf, band.low, band.high, weights)
        richer = fit_band(f, frf, band.low, band.high, weights, richer=True)
        averages = stated_averages(recording.description)
        noise = recording_noise(f, frf, recording.coherence, band.low, band.high, averages)
        return cls(fit, richer, recording.sensors, recording.exciters, noise)

    @property
    def residual(self) -> float:
        """The band fits' relative RMS residual (:func:`band_residual`)."""
        return band_residual(self.fit, self.noise)

    @cached_property
    def present(self) -> np.ndarray:
        """(n_s, n_e) bool: the pairs with a massline (not a pair with no FRF, or too few lines in the band)."""
        return np.isfinite(self.fit.values)

    @property
    def missing(self) -> int:
        """How many pairs have no massline."""
        return int((~self.present).sum())

    @cached_property
    def data(self) -> Masslines:
        """The masslines A_ij (n_s, n_e), (m/s²)/N; 0 at a missing pair."""
        return Masslines(np.where(self.present, self.fit.values, 0.0), self.sensors, self.exciters)

    @cached_property
    def sigma(self) -> np.ndarray:
        """1-σ of each A_ij (n_s, n_e), (m/s²)/N, at least ``SIGMA_FLOOR`` of the largest |A|; inf at a missing
        pair (no weight)."""
        floor = SIGMA_FLOOR * np.nanmax(np.abs(self.fit.values))
        return np.where(self.present, np.maximum(self.fit.std, floor), np.inf)

    @cached_property
    def truncation(self) -> np.ndarray:
        """Each A_ij's shift by its tails' next term (n_s, n_e), (m/s²)/N, no larger than the richer fit shows
        it (:func:`.uncertainty.seen_truncation`); 0 at a missing pair."""
        return np.where(self.present, seen_truncation(self.fit.truncation, self.fit, self.richer), 0.0)
