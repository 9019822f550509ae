"""The warnings an identification carries, in the order identify lists them: what the fit, the scale, the
band, the coherence, the tails' truncation, the recording itself, the density, the missing pairs, the
repeated runs and the recording's noise say against its result (:mod:`.suspicions` and the modules beside it).
"""

from __future__ import annotations

import numpy as np

from massline.core.band import Band
from massline.core.rigid_body import RigidBody
from massline.identify.band_masslines import BandMasslines
from massline.identify.estimator import Estimate
from massline.identify.missing_pairs import missing_warnings
from massline.identify.plausibility import units_warnings
from massline.identify.recording_noise import above_coherence, below_noise
from massline.identify.repeats import repeat_warnings
from massline.identify.sensor_mass import Housings
from massline.identify.suspicions import (
    band_warnings,
    coherence_warnings,
    fit_warnings,
    recording_warnings,
    truncation_warnings,
    weighing_warnings,
)
from massline.identify.uncertainty import Spread
from massline.identify.warning_codes import CodedWarning
from massline.identify.weighing import WeighedMass
from massline.uff.recording import Recording
from massline.uff.runs import coherence_weights


def absent(recording: Recording, present: np.ndarray) -> list:
    """The (response, reference) labels of the pairs without a massline (``present`` (n_s, n_e) False)."""
    rows, columns = np.nonzero(~present)
    return [(recording.sensor_channels[i], recording.exciter_channels[j]) for i, j in zip(rows, columns)]


def identification_warnings(
    recording: Recording,
    bands: tuple[Band, Band],
    masslines: BandMasslines,
    best: Estimate,
    spread: Spread,
    *,
    weighed: WeighedMass | None,
    housings: Housings,
    bare: RigidBody,
    tested: RigidBody,
) -> tuple[CodedWarning, ...]:
    """Every warning on an identification of ``recording``.

    Parameters
    ----------
    recording : Recording
        The recording identified (its lines above 0 Hz, any mains interference set aside).
    bands : (Band, Band)
        The band as chosen and as used (:func:`.band_masslines.recording_band`), Hz.
    masslines : BandMasslines
        The band fits: which pairs have a massline.
    best : Estimate
        The weighted estimate of the body as tested: its reduced χ², its degrees of freedom, the scale's
        studentised residual.
    spread : Spread
        The 1-σ: the tails' truncation against the statistical 1-σ of the bare body.
    weighed : WeighedMass or None
        The scale's reading of the bare body, kg.
    housings : Housings
        The accelerometer housings taken off the body as tested (their total, kg).
    bare : RigidBody
        The estimate's body with the housings taken off (SI).
    tested : RigidBody
        The reported body as tested: the estimate's or a paper method's (SI).
    """
    chosen, used = bands
    f, frf, coherence, present = recording.frequencies, recording.frf, recording.coherence, masslines.present
    in_band = (f >= used.low) & (f <= used.high)
    channels = [f"{s} / {e}" for s in recording.sensor_channels for e in recording.exciter_channels]
    points = np.vstack([recording.sensors.points, recording.exciters.points])
    repeated = [coherence_weights(r.coherence) for r in recording.repeats]
    return tuple(
        fit_warnings(best.chi2, best.dof, spread.explained, spread.draws)
        + weighing_warnings(best.weighed_z, weighed, housings.total)
        + band_warnings(used, int(in_band.sum()))
        + coherence_warnings(frf, coherence, in_band, channels)
        + truncation_warnings(spread.truncation, spread.statistical, bare)
        + recording_warnings(f, frf, coherence, chosen, recording.exponential_window)
        + units_warnings(tested, points, best.model.planar)
        + missing_warnings(absent(recording, present), present.size)
        + repeat_warnings(recording, used.low, used.high, repeated)
        + below_noise(masslines.noise, masslines.residual, "identify's band fit")
        + above_coherence(masslines.noise)
    )
