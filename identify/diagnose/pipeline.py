"""Diagnosis of a recording, as ``massline diagnose`` runs it: bands, layout, screens, the diagnosis.

``diagnose_recording`` is the pipeline a script calls; ``DiagnosisRun`` holds what it found with what
it ran on, and serialises itself as DESIGN.md's diagnose JSON (``document``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.identify.band import estimation_band, find_band, given_band
from massline.identify.diagnose.diagnosis import Diagnosis, diagnose, fit_std, relative_noise, roomy
from massline.identify.diagnose.effect_model import Layout
from massline.identify.diagnose.finding import finding_payload
from massline.identify.diagnose.screens import kinematic_matrix, rigid_subspace_residual, screen
from massline.identify.estimator import TRANSVERSE
from massline.identify.pipeline import is_planar, properties_payload, usable_lines
from massline.identify.tails import BandData
from massline.placement.band import Band
from massline.placement.degeneracy import unseen_motion
from massline.placement.errors import MasslineError
from massline.placement.rigid_body import RigidBody
from massline.uff.recording import Recording


@dataclass(frozen=True, eq=False)
class DiagnosisRun:
    """A diagnosis of a recording with what it was run on.

    Attributes
    ----------
    recording : Recording
    band : Band
        The diagnosis band (the plan's, given, or found).
    estimation_band : Band
        The band the properties are estimated on: identify's.
    data : BandData
        The recorded FRFs inside the diagnosis band.
    layout : Layout
    planar : bool
    sensors, hits : list of Channel (or Numbered)
        The channels as the file labels them ('12:+Y'; 'sensor 3' without labels), as the findings name them.
    noise : float
        Relative RMS noise of the FRFs over the band.
    screens : dict
        The model-free screens.
    result : Diagnosis
    notes : tuple of str
        What was set aside before the diagnosis (an exporter's 0 Hz line).
    """

    recording: Recording
    band: Band
    estimation_band: Band
    data: BandData
    layout: Layout
    planar: bool
    sensors: list
    hits: list
    noise: float
    screens: dict
    result: Diagnosis
    notes: tuple = ()

    def off_rigid(self) -> np.ndarray | None:
        """How far each recorded channel sits from the rigid motions at every band line (None without redundancy)."""
        if not roomy(self.layout):
            return None
        S = kinematic_matrix(self.layout.sensors, self.layout.planar)
        return np.linalg.norm(rigid_subspace_residual(self.data.frf, S), axis=1)

    @property
    def document(self) -> dict:
        """DESIGN.md's diagnose JSON (and the per-channel fit and screens)."""
        result, band = self.result, (self.estimation_band.low, self.estimation_band.high)
        bodies = (result.estimates[0].body, result.corrected)

        def properties(body: RigidBody | None, estimate) -> dict | None:
            return None if body is None else properties_payload(body, fit_std(estimate), band, self.planar)

        return {
            "findings": [finding_payload(x, self.recording) for x in result.findings],
            "fit": {
                "before": result.relative_rms("before"),
                "after": result.relative_rms("after"),
                "noise": result.noise,
            },
            "fit_per_channel": {
                "before": result.relative_rms("before", axis=1).tolist(),
                "after": result.relative_rms("after", axis=1).tolist(),
            },
            "properties": {
                "before": properties(bodies[0], result.estimates[0]),
                "after": properties(bodies[1], result.estimates[1]),
            },
            "band_hz": [self.band.low, self.band.high],
            "screens": self.screens,
        }


def check_seen(layout: Layout) -> None:
    """Refuse sensor lines that cannot see every rigid motion (identify refuses them too): nothing to diagnose."""
    need = 3 if layout.planar else 6
    rank = np.linalg.matrix_rank(kinematic_matrix(layout.sensors, layout.planar))
    if rank < need:
        why = f"the sensor lines see {rank} of a plate's 3 rigid motions" if layout.planar else None
        raise MasslineError(
            f"{why or unseen_motion(layout.sensors)}: the body can be neither identified nor diagnosed; "
            "measure more responses"
        )


def diagnose_recording(recording: Recording, band=None, nominal=None, transverse: float = TRANSVERSE) -> DiagnosisRun:
    """The diagnosis on ``band`` (lo, hi) Hz, the plan's, or the found one; properties on identify's band.

    Lines at or below 0 Hz are set aside, as identify does (``recording`` of the run is the one diagnosed).
    """
    recording, notes = usable_lines(recording)
    f = recording.frequencies
    used = given_band(f, *band) if band else find_band(f, recording.frf)
    estimation = estimation_band(f, recording.frf, used)
    data = BandData.from_recording(f, recording.frf, used.low, used.high)
    wide = BandData.from_recording(f, recording.frf, estimation.low, estimation.high)
    planar = is_planar(recording.sensors, recording.exciters)
    layout = Layout.of(recording.sensors, recording.exciters, planar)
    check_seen(layout)
    screens = screen(data, layout)
    result = diagnose(data, layout, nominal, transverse, wide)
    return DiagnosisRun(
        recording,
        used,
        estimation,
        data,
        layout,
        planar,
        recording.sensor_channels,
        recording.exciter_channels,
        relative_noise(data),
        screens,
        result,
        notes,
    )
