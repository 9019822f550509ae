"""Diagnosis of a recording, as ``massline diagnose`` runs it: identify, bands, screens, the diagnosis,
identify again on the recording with the faults undone.

One estimator: the properties before are identify's on the file with the same options, those after are
identify's on the recording with every fault the diagnosis found undone (:mod:`.corrections`) and, with a
mesh, the accelerometers' loading masses taken off (:mod:`.mass_loading`). With no fault, after = before.
How far a fault moved the properties is identify's result with it undone against without.

``diagnose_recording`` is the pipeline a script calls; ``DiagnosisRun`` holds what it found with what
it ran on, and serialises itself as DESIGN.md's diagnose JSON (``document``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from massline.identify.zones import given_band
from massline.identify.band_choice import choose_band
from massline.identify.diagnose.corrections import corrected
from massline.identify.diagnose.diagnosis import Diagnosis, diagnose, relative_noise, roomy
from massline.identify.diagnose.effect_model import Layout
from massline.identify.diagnose.effects import named
from massline.identify.diagnose.finding import faults_first, finding_payload
from massline.identify.diagnose.mass_loading import MassLoading, mass_loading, weighed
from massline.identify.diagnose.screens import kinematic_matrix, rigid_subspace_residual, screen
from massline.identify.estimator import TRANSVERSE
from massline.identify.pipeline import (
    Identification,
    against_nominal,
    identify_recording,
    is_planar,
    properties_payload,
    usable_lines,
)
from massline.identify.tails import BandData
from massline.identify.warning_codes import CodedWarning
from massline.core.band import Band
from massline.core.degeneracy import unseen_motion
from massline.core.errors import MasslineError
from massline.core.properties import JSON_UNITS
from massline.core.rigid_body import RigidBody
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
    noise : float
        Relative RMS noise of the FRFs over the band.
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
        What was set aside before the diagnosis (an exporter's 0 Hz line), and why identify refused the file.
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
        """How far each recorded channel sits from the rigid motions at every band line (None without redundancy)."""
        if not roomy(self.layout):
            return None
        S = kinematic_matrix(self.layout.sensors, self.layout.planar)
        return np.linalg.norm(rigid_subspace_residual(self.data.frf, S), axis=1)

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
            "warnings": [w.as_json() for w in self.notes + (() if self.before is None else self.before.warnings)],
            "units": JSON_UNITS,
        }


def reported(body: RigidBody, found: Identification, planar: bool) -> dict:
    """identify's value keys of ``body`` with ``found``'s 1-σ and band."""
    return properties_payload(body, found.std, (found.band.low, found.band.high), planar)


def moved(without: RigidBody, with_: RigidBody) -> dict:
    """How far undoing a fault moves identify's properties: mass %, CoG mm, principal moments %."""
    return {
        "mass_percent": 100 * (with_.mass / without.mass - 1),
        "cog_mm": (1e3 * (with_.cog - without.cog)).tolist(),
        "principal_moments_percent": (100 * (with_.principal_moments / without.principal_moments - 1)).tolist(),
    }


def identified_after(recording, findings: list, band, transverse: float, before: Identification):
    """identify (on ``band``: None, its own) on the recording with every fault undone, and each fault's finding with how far undoing it
    moved the properties (identify with all faults undone against with all but that one; no bootstrap).

    When identify refuses the corrected recording, the properties stay ``before`` (and no finding says it moved them).
    """
    faults = [f for f in findings if f.kind == "fault" and named(f.effect).undone_on == "recording"]
    if not faults:
        return before, findings
    after = attempt(corrected(recording, faults), band, transverse, 100)
    if after is None:
        return before, findings
    marked = []
    for finding in findings:
        if finding in faults and before is not None:
            rest = [f for f in faults if f is not finding]
            without = attempt(corrected(recording, rest), band, transverse, 0)
            if without is not None:
                finding = replace(finding, evidence={**finding.evidence, "moved": moved(without.body, after.body)})
        marked.append(finding)
    return after, marked


def attempt(recording, band, transverse: float, draws: int) -> Identification | None:
    """identify on ``recording``, or None when it refuses it or its solve fails."""
    try:
        return identify_recording(recording, band, transverse, draws=draws)
    except (MasslineError, np.linalg.LinAlgError, ValueError):
        return None


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
    """identify, then the diagnosis on ``band`` (lo, hi) Hz or identify's, then identify on the recording
    with the faults undone; ``nominal`` (the mesh's body) lets the accelerometers' mass loading be found.

    ``band`` is the band the diagnosis examines (the plan's); the properties are identify's, on the band it
    chooses, as ``massline identify FILE`` gives them (on ``band`` only when identify finds none).

    Lines at or below 0 Hz are set aside, as identify does (``recording`` of the run is the one diagnosed).
    """
    recording, notes = usable_lines(recording)
    planar = is_planar(recording.sensors, recording.exciters)
    layout = Layout.of(recording.sensors, recording.exciters, planar)
    check_seen(layout)
    before, refused = identified(recording, band, transverse)
    if before is not None:
        before = against_nominal(before, nominal)  # the mesh's mass checked as identify --mesh checks it
    identify_band = band if before is not None and before.band.rule == "given" else None
    f = recording.frequencies
    if band:
        used = given_band(f, *band)
    else:
        used = before.band if before else choose_band(f, recording.frf, recording.sensors, recording.exciters, planar)
    estimation = used if before is None else before.band
    data = BandData.from_recording(f, recording.frf, used.low, used.high)
    wide = BandData.from_recording(f, recording.frf, estimation.low, estimation.high)
    screens = screen(data, layout)
    record = BandData.from_recording(f, recording.frf, f[0], f[-1])
    result = diagnose(data, layout, transverse, wide, record)
    after, findings = identified_after(recording, result.findings, identify_band, transverse, before)
    if nominal is None or after is None:
        loading = None
    else:
        loading = mass_loading(*weighed(after.best, result.after), recording.sensors, nominal)
    if loading is not None:
        findings = faults_first(findings + [loading.finding()])
    return DiagnosisRun(
        recording=recording,
        band=used,
        estimation_band=estimation,
        data=data,
        layout=layout,
        planar=planar,
        sensors=recording.sensor_channels,
        hits=recording.exciter_channels,
        noise=relative_noise(data),
        screens=screens,
        result=result,
        before=before,
        after=after,
        findings=findings,
        loading=loading,
        notes=notes + refused,
    )


def identified(recording, band, transverse: float) -> tuple[Identification | None, tuple]:
    """identify's result on the file as it came (its own band; the diagnosis band ``band`` only when identify
    finds none), or None and a note saying why identify refuses it (a gross fault can leave the masslines
    fitting no body: the diagnosis is what finds it)."""
    try:
        return identify_recording(recording, None, transverse), ()
    except MasslineError as reason:
        if band:
            try:
                return identify_recording(recording, band, transverse), (
                    CodedWarning(
                        "identify_no_band", f"identify finds no band ({reason}): the properties are on the given band"
                    ),
                )
            except MasslineError as again:
                reason = again
        return None, (CodedWarning("identify_refused", f"identify refuses the file as it came ({reason})"),)
