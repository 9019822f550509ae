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
from pathlib import Path

import numpy as np

from massline.identify.zones import given_band
from massline.identify.band_choice import choose_band
from massline.identify.diagnose.corrected_file import write_corrected, written_faults
from massline.identify.diagnose.corrections import corrected
from massline.identify.diagnose.diagnosis import Diagnosis, diagnose
from massline.identify.diagnose.effect_model import Layout
from massline.identify.diagnose.effects import held
from massline.identify.diagnose.effects.excitation_mass_loading import ExcitationMassLoading
from massline.identify.diagnose.effects.mains_interference import MainsInterference
from massline.identify.diagnose.finding import faults_first, finding_payload, mains_finding
from massline.identify.diagnose.gauge_mass import GaugeMass, gauge_mass, gauge_pattern
from massline.identify.diagnose.mass_loading import MassLoading, mass_loading, weighed
from massline.identify.diagnose.screens import kinematic_matrix, rigid_subspace_residual, roomy, screen
from massline.identify.diagnose.targeted import at_place
from massline.identify.diagnose.misfit_signatures import signed
from massline.identify.diagnose.row_factors import chains_undone
from massline.identify.diagnose.placed import beside_a_spread_misfit, at_the_misfit, same_place, where_the_misfit_is
from massline.identify.diagnose.undone import best_undone, identified, identified_after
from massline.identify.suspicions import beyond_chance
from massline.identify.diagnose.unexplained import excess_over_mesh, refused_misfit, unexplained
from massline.identify.estimator import TRANSVERSE
from massline.identify.pipeline import (
    NONE_TAKEN_OFF,
    Identification,
    against_nominal,
    as_recording,
    fit_note,
    is_planar,
    properties_payload,
    support_corrected,
    usable_lines,
    without_mains,
)
from massline.identify.missing_lines import mean_present
from massline.identify.missing_pairs import unmeasured_notes
from massline.identify.recording_noise import RecordingNoise, below_noise, recording_noise, stated_averages
from massline.identify.tails import BandData
from massline.identify.warning_codes import CodedWarning
from massline.core.band import Band
from massline.core.degeneracy import unseen_motion
from massline.core.errors import MasslineError
from massline.core.housing_masses import HousingMasses
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


def diagnose_recording(
    recording: Recording | str | Path,
    band=None,
    nominal=None,
    transverse: float = TRANSVERSE,
    *,
    sensor_mass: float | HousingMasses = 0.0,
    exciter_mass: float = 0.0,
    support=None,
) -> DiagnosisRun:
    """identify, then the diagnosis on ``band`` (lo, hi) Hz or identify's, then identify on the recording
    with the faults undone; ``nominal`` (the mesh's body) lets the accelerometers' mass loading be found.
    ``sensor_mass`` and ``exciter_mass``: the instrumentation's masses the engineer knows, as identify takes
    them (every identify run of the diagnosis is given them; a gauge given is not searched for).

    ``band`` is the band the diagnosis examines (the plan's); the properties are identify's, on the band it
    chooses, as ``massline identify FILE`` gives them (on ``band`` only when identify finds none).

    Lines at or below 0 Hz are set aside, as identify does (``recording`` of the run is the one diagnosed), and
    the lines of any mains interference: identify sets them aside itself, the band data are taken without them,
    and the mains interference is a test-physics finding. ``recording`` may be the path of a Universal File, or
    several (one per run: pairs not measured and FRFs on a coarser axis are NaN, and the diagnosis reads each FRF
    on its own lines, :mod:`massline.identify.tails`).

    ``support``: the support and the elastic modes as the mesh's FE model gives them, whose departure from the
    masslines is taken off the recording first, as identify takes it off (:func:`.support_corrected`); the
    recording diagnosed is the corrected one.
    """
    recording, modelled = as_recording(recording), ()
    if support is not None:
        recording, fit = support_corrected(recording, band, support, transverse=transverse, sensor_mass=sensor_mass,
                                           exciter_mass=exciter_mass)  # fmt: skip
        modelled = (CodedWarning("support_modelled", fit.note),)
    recording, notes = usable_lines(recording)
    notes = modelled + notes + unmeasured_notes(recording.unmeasured_nodes)
    cleaned, mains, aside = without_mains(recording) if held(MainsInterference.name) else (recording, None, ())
    notes += aside
    planar = is_planar(recording.sensors, recording.exciters)
    layout = Layout.of(recording.sensors, recording.exciters, planar)
    check_seen(layout)
    known = {"sensor_mass": sensor_mass, "exciter_mass": exciter_mass}
    before, refused = identified(recording, band, transverse, known)
    if before is not None:
        before = against_nominal(before, nominal)  # the mesh's mass checked as identify --mesh checks it
    identify_band = band if before is not None and before.band.rule == "given" else None
    f = cleaned.frequencies
    if band:
        used = given_band(f, *band)
    else:
        used = before.band if before else choose_band(f, cleaned.frf, cleaned.sensors, cleaned.exciters, planar)
    estimation = used if before is None else before.band
    gauge = None
    if before is not None and not exciter_mass and held(ExcitationMassLoading.name):
        gauge = gauge_mass(before.data, before.sigma, planar, transverse, before.best)
    searched = cleaned if gauge is None else shifted(cleaned, gauge)  # the other effects, on the bare body
    chains, in_frequency, searched = chains_undone(searched, used.low, used.high, layout)  # the chains' factors
    data = BandData.from_recording(f, searched.frf, used.low, used.high)
    wide = BandData.from_recording(f, searched.frf, estimation.low, estimation.high)
    screens = screen(data, layout)
    record = BandData.from_recording(f, searched.frf, f[0], f[-1])
    averages = stated_averages(recording.description)  # measured as recorded, relative to the FRFs searched
    noise = recording_noise(f, cleaned.frf, cleaned.coherence, used.low, used.high, averages)
    noise = noise.on(f, searched.frf, used.low, used.high)
    result = diagnose(data, layout, transverse, wide, record, noise.relative())
    found = ([] if gauge is None else [gauge.finding()]) + chains + result.findings
    found, set_aside = where_the_misfit_is(found, None if before is None else unexplained(before))

    def proven(faults: list) -> tuple:
        """identify with ``faults`` undone, the findings it keeps, the faults withdrawn (with those set aside) and
        what it leaves unexplained."""
        after, findings, withdrawn = identified_after(recording, faults, identify_band, transverse, before, known)
        withdrawn = set_aside + withdrawn
        return after, findings, withdrawn, None if after is None else unexplained(after, withdrawn)

    after, findings, withdrawn, left = proven(found)
    if left is not None and left.parameters["shape"] != "spread":  # the place is known: the library tried there
        p = left.parameters
        candidates = at_place(result, (*left.channels, *p.get("also_channels", ())), p["hits"] + p.get("also_hits", []))
        placed = best_undone(recording, found, candidates, identify_band, transverse, known)
        if placed:
            tried = proven(found + placed)
            if any(same_place(f, placed[0]) for f in tried[1]):
                found, (after, findings, withdrawn, left) = found + placed, tried
    partial = at_the_misfit(findings, left) or beside_a_spread_misfit(findings, left)
    if partial:  # named where the misfit still is: part of it fitted, the place's misfit not explained
        found = [f for f in found if not any(same_place(f, p) for p in partial)]
        set_aside = set_aside + partial
        after, findings, withdrawn, left = proven(found)
    loading = None if not measures_a_body(after, nominal) else weighed_loading(after, result, nominal, transverse)
    if loading is not None and not held(loading.finding().effect):  # the mesh's excess, its effect not in the library
        stand_ins = [f for f in found if f.kind == "fault" and f.exciter is not None]
        if loading.side == "excitation" and stand_ins:  # located before any hit's fault that absorbs part of it
            found = [f for f in found if f not in stand_ins]
            after, findings, withdrawn, _ = proven(found)
            withdrawn = withdrawn + stand_ins
        left, loading = excess_over_mesh(loading, withdrawn), None
    if loading is not None and loading.side == "excitation":  # undone by identify, column by column
        after, findings, withdrawn, left = proven(found + [loading.finding()])
        findings, loading = faults_first(findings), None
    elif loading is not None:
        findings = faults_first(findings + [loading.finding()])
    if mains is not None:
        findings = findings + [mains_finding(mains)]
    if before is None and not any(f.kind == "fault" for f in findings):  # refused, and no fault named undoes it
        left = refused_misfit(screens, withdrawn)
    findings = faults_first(findings + in_frequency + ([] if left is None else [left]))
    findings = signed(findings, BandData.from_recording(f, cleaned.frf, used.low, used.high), layout)
    return DiagnosisRun(
        recording=recording,
        band=used,
        estimation_band=estimation,
        data=data,
        layout=layout,
        planar=planar,
        sensors=recording.sensor_channels,
        hits=recording.exciter_channels,
        noise=noise,
        screens=screens,
        result=result,
        before=before,
        after=after,
        findings=findings,
        loading=loading,
        notes=notes + refused + tuple(below_noise(noise, result.relative_rms("after"), "the diagnosis's fit")),
    )


def measures_a_body(after: Identification | None, nominal: RigidBody | None) -> bool:
    """Whether identify's body after can be weighed against the mesh's: a mesh was given and the rigid model fits
    the masslines within chance. Beyond it the body is the misfit's (an 8 mm sensor offset left χ² 150× the
    noise and a body 3 % heavy, which the mesh would have called a gauge's mass at the drive points)."""
    return nominal is not None and after is not None and not beyond_chance(after.best.chi2, after.best.dof)


def weighed_loading(after: Identification, result: Diagnosis, nominal: RigidBody, transverse: float):
    """The mass loading θ̂ − θ_mesh shows: at the housings, or (when identify fitted no gauge) at the drive points
    (not when the body with gauges riding there fits no rigid body: the estimate diverged)."""
    excitation = None
    if not after.exciter_mass and len(after.recording.exciters) > 1:
        try:
            pattern = gauge_pattern(after.data, after.sigma, after.planar, transverse, after.best)  # a difference
            excitation = (after.recording.exciters.points, pattern)
        except MasslineError:  # no rigid body fits with gauges riding: the drive points cannot be weighed
            excitation = None
    theta, covariance, planar = weighed(after.best, result.after)
    bare = theta - after.housings.theta(planar)  # the housings the engineer gave are no loading
    return mass_loading(bare, covariance, planar, after.recording.sensors, nominal, excitation)


def shifted(recording: Recording, gauge: GaugeMass) -> Recording:
    """The recording moved column by column onto the masslines of the bare body the gauge fit found."""
    shift = gauge.column_shift(recording.sensors, recording.exciters)
    return replace(recording, frf=recording.frf + shift[:, :, None])
