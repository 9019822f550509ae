"""What a diagnosis of a recording found, with what it was run on: the report object of ``massline diagnose``.

``DiagnosisRun`` holds the recording, the bands, the line-level diagnosis, identify's properties before and after,
and the findings; it serialises itself as DESIGN.md's diagnose JSON (``document``), exports the body after, and
writes the recording with the faults named undone (:mod:`.corrected_file`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from massline.identify.diagnose.corrected_file import write_corrected, written_faults
from massline.identify.diagnose.corrections import corrected
from massline.identify.diagnose.diagnosis import Diagnosis
from massline.identify.diagnose.effect_model import Layout
from massline.identify.diagnose.finding import finding_payload
from massline.identify.diagnose.mass_loading import MassLoading
from massline.identify.diagnose.screens import kinematic_matrix, rigid_subspace_residual, roomy
from massline.identify.missing_lines import mean_present
from massline.identify.pipeline import NONE_TAKEN_OFF, Identification, fit_note, properties_payload
from massline.identify.recording_noise import RecordingNoise
from massline.identify.tails import BandData
from massline.core.band import Band
from massline.core.errors import MasslineError
from massline.core.files import to_json
from massline.core.properties import JSON_UNITS, reported_values
from massline.core.rigid_body import RigidBody
from massline.export.body import Body
from massline.export.units import SI, Units
from massline.uff.recording import Recording


@dataclass(frozen=True, eq=False, kw_only=True)
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
    noise : RecordingNoise
        Each FRF's noise over the diagnosis band as the recording shows it (its coherence, else its line
        differences: :mod:`massline.identify.recording_noise`), what every fit is measured against.
    screens : dict
        The model-free screens.
    result : Diagnosis
    before, after : Identification
        identify on the file as it came, and on the recording with the faults undone (``after.body`` is
        the bare body when a mass loading was found; ``after`` is ``before`` when there is no fault).
    findings : list of Finding
        The diagnosis's findings and the mass loading, faults first, each fault's ``moved`` evidence from
        identify.
    loading : MassLoading or None
    notes : tuple of CodedWarning
        What was set aside before the diagnosis (an exporter's 0 Hz line, the lines of mains interference), why
        identify refused the file, and a diagnosis's fit that leaves less than the noise.
    """

    recording: Recording
    band: Band
    estimation_band: Band
    data: BandData
    layout: Layout
    planar: bool
    sensors: list
    hits: list
    noise: RecordingNoise
    screens: dict
    result: Diagnosis
    before: Identification | None
    after: Identification | None
    findings: list
    loading: MassLoading | None = None
    notes: tuple = ()

    @property
    def after_body(self) -> RigidBody | None:
        """The body after: identify's on the corrected recording, less any loading masses (None: no body)."""
        if self.after is None:
            return None
        return self.after.body if self.loading is None else self.loading.bare(self.after.body)

    def off_rigid(self) -> np.ndarray | None:
        """How far each recorded channel sits from the rigid motions at every band line (None without redundancy):
        the norm over the hits it has there, scaled to all of them (NaN where it has none)."""
        if not roomy(self.layout):
            return None
        S = kinematic_matrix(self.layout.sensors, self.layout.planar)
        off = rigid_subspace_residual(self.data.frf, S)
        return np.sqrt(mean_present(off**2, axis=1) * off.shape[1])

    @property
    def document(self) -> dict:
        """DESIGN.md's diagnose JSON (and the per-channel fit and screens)."""
        result = self.result
        return {
            "findings": [finding_payload(x, self.recording) for x in self.findings],
            "fit": {
                "before": result.relative_rms("before"),
                "after": result.relative_rms("after"),
                "noise": result.noise,
                "noise_method": self.noise.method,
                "chi2_reduced": self.chi2,
            },
            "fit_per_channel": {
                "before": result.relative_rms("before", axis=1).tolist(),
                "after": result.relative_rms("after", axis=1).tolist(),
            },
            "properties": {
                "before": None if self.before is None else self.before.payload,
                "after": None
                if self.after is None
                else {**self.after.payload, **reported(self.after_body, self.after, self.planar)},
            },
            "band_hz": [self.band.low, self.band.high],
            "screens": self.screens,
            "warnings": [w.as_json() for w in self.warnings],
            "units": JSON_UNITS,
        }

    @property
    def chi2(self) -> dict:
        """identify's reduced χ² of the masslines on the file as it came and with the named faults undone, and its
        degrees of freedom (None where identify refused the file or no redundancy checks it): the one χ² of
        identify, diagnose and the reports."""
        if self.before is None or not np.isfinite(self.before.best.chi2):
            return {"before": None, "after": None, "dof": None}
        after = self.after or self.before
        return {"before": self.before.best.chi2, "after": after.best.chi2, "dof": self.before.best.dof}

    @property
    def warnings(self) -> tuple:
        """What was set aside before the diagnosis and identify's warnings on the file as it came."""
        return self.notes + (() if self.before is None else self.before.warnings)

    @property
    def mass(self) -> float | None:
        """The body's mass after the diagnosis, kg (None: no body)."""
        return None if self.after is None else self.after_body.mass

    @property
    def cog(self) -> np.ndarray | None:
        """The body's CoG after the diagnosis, m, frame of the recording (a plate's z_G NaN; None: no body)."""
        return None if self.after is None else np.asarray(reported_values(self.after_body, self.planar)["cog"])

    @property
    def inertia(self) -> np.ndarray | None:
        """The body's inertia tensor about the CoG after the diagnosis, kg·m², tensor sign, frame of the recording
        (a plate's z row and column NaN; None: no body)."""
        if self.after is None:
            return None
        return np.asarray(reported_values(self.after_body, self.planar)["inertia_cog"])

    @property
    def std(self) -> dict | None:
        """The 1-σ of the properties after, as identify gives them (None: no body)."""
        return None if self.after is None else self.after.std

    def to_json(self) -> str:
        """DESIGN.md's diagnose JSON (``document``) as text, NaN as null."""
        return to_json(self.document)

    def measured(self, as_tested: bool = False, source: str = "") -> Body:
        """The body after the diagnosis as measured, with its 1-σ and what was measured (``source``: the
        recording's name): less the accelerometers' loading masses when found, or with ``as_tested`` with them."""
        if self.after is None:
            why = "; ".join(self.notes) or "identify refuses the recording"
            raise MasslineError(f"{source or 'the recording'}: the diagnosis leaves no body to export ({why})")
        body = self.after.body if as_tested or self.loading is None else self.after_body
        values = reported_values(body, self.planar)
        undone = [f.effect for f in self.findings if f.kind == "fault" and f.effect != "sensor_mass_loading"]
        which = NONE_TAKEN_OFF
        if self.loading is not None:
            grams = f"{self.loading.housings.describe()} of loading".replace("×", "x")  # exports are ASCII
            which = f"the body as tested, {grams} on" if as_tested else f"the bare body, {grams} taken off"
        note = (
            f"{source or 'a recording'}, massline diagnose (faults undone: {', '.join(undone) or 'none'}; then "
            f"identify: {fit_note(self.after)}); {which}"
        )
        return Body(mass=body.mass, cog=values["cog"], inertia=values["inertia_cog"], std=self.after.std, note=note,
                    warnings=self.warnings)  # fmt: skip

    def corrected(self) -> Recording:
        """The recording with the faults named undone, as the properties after were identified on it
        (:func:`.corrections.corrected`)."""
        return corrected(self.recording, written_faults(self.findings))

    def write_corrected(self, source, path: str | Path, *, force: bool = False) -> list[Path]:
        """Write the file ``source`` this diagnosis read (or its runs' files, a list) with the faults named undone,
        and a header listing each correction and each finding not corrected, to ``path`` (several runs: one file
        per run beside it); the files written (:mod:`.corrected_file`)."""
        return write_corrected(self, source, path, force=force)

    def export(self, path: str | Path, units: str | Units = SI, *, as_tested: bool = False, force: bool = False,
               source: str = "") -> Path:  # fmt: skip
        """Write the body after the diagnosis (``measured``) to ``path`` in the format its suffix names, in
        ``units``; an existing file only with ``force``."""
        return self.measured(as_tested, source).export(path, units, force)


def reported(body: RigidBody, found: Identification, planar: bool) -> dict:
    """identify's value keys of ``body`` with ``found``'s 1-σ and band."""
    return properties_payload(body, found.std, (found.band.low, found.band.high), planar)
