"""Diagnosis of a recording, as ``massline diagnose`` runs it: read and weigh the recording, fit the rigid body on the
band's lines, select the explanations on identify's χ², weigh the body against the mesh, report.

One estimator: the properties before are identify's on the file with the same options, those after are
identify's on the recording with every fault the diagnosis found undone (:mod:`.corrections`) and, with a
mesh, the accelerometers' loading masses taken off (:mod:`.mass_loading`). With no fault, after = before.
How far a fault moved the properties is identify's result with it undone against without.

``diagnose_recording`` is the pipeline a script calls, one stage a line, each in the module of its concept:
:mod:`.reading`, :mod:`.line_level`, :mod:`.selection`, :mod:`.against_mesh`; ``DiagnosisRun``
(:mod:`.diagnosis_run`) holds what it found with what it ran on, and serialises itself as DESIGN.md's diagnose
JSON.
"""

from __future__ import annotations

from pathlib import Path

from massline.identify.diagnose.against_mesh import weighed_against_mesh
from massline.identify.diagnose.diagnosis_run import DiagnosisRun
from massline.identify.diagnose.finding import faults_first, mains_finding
from massline.identify.diagnose.line_level import LineLevel, line_level
from massline.identify.diagnose.misfit_signatures import signed
from massline.identify.diagnose.reading import Reading, read
from massline.identify.diagnose.selection import Proven, Prover, select
from massline.identify.diagnose.unexplained import refused_misfit
from massline.identify.estimator import TRANSVERSE
from massline.identify.recording_noise import below_noise
from massline.identify.tails import BandData
from massline.core.housing_masses import HousingMasses
from massline.uff.recording import Recording


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
    known = {"sensor_mass": sensor_mass, "exciter_mass": exciter_mass}
    reading = read(recording, band, nominal, transverse, known, support)
    line = line_level(reading, transverse)
    prove = Prover(reading.recording, reading.identify_band, transverse, reading.before, known)
    chosen = select(line.found, line.result, prove)
    proven, loading = weighed_against_mesh(chosen, prove, line.result, nominal, transverse)
    return report(reading, line, proven, loading)


def reported_findings(reading: Reading, line: LineLevel, proven: Proven) -> list:
    """The findings proven with the rules' findings beside them, faults first, each place's misfit signed with its
    shape in frequency (:mod:`.misfit_signatures`)."""
    findings, left = proven.findings, proven.left
    if reading.mains is not None:  # rule: its lines are set aside before any fit, so no candidate models them
        findings = findings + [mains_finding(reading.mains)]
    # rule: identify refuses the file and no named fault mends it: no χ² to select on, the screen places the misfit
    if reading.before is None and not any(f.kind == "fault" for f in findings):
        left = refused_misfit(line.screens, proven.withdrawn)
    findings = faults_first(findings + line.in_frequency + ([] if left is None else [left]))
    cleaned, used = reading.cleaned, reading.band
    return signed(findings, BandData.from_recording(cleaned.frequencies, cleaned.frf, used.low, used.high),
                  reading.layout)  # fmt: skip


def report(reading: Reading, line: LineLevel, proven: Proven, loading) -> DiagnosisRun:
    """The report object: what the diagnosis found with what it ran on, and a fit that leaves less than the noise
    noted."""
    recording, result = reading.recording, line.result
    below = tuple(below_noise(line.noise, result.relative_rms("after"), "the diagnosis's fit"))
    return DiagnosisRun(
        recording=recording,
        band=reading.band,
        estimation_band=reading.estimation,
        data=line.data,
        layout=reading.layout,
        planar=reading.planar,
        sensors=recording.sensor_channels,
        hits=recording.exciter_channels,
        noise=line.noise,
        screens=line.screens,
        result=result,
        before=reading.before,
        after=proven.after,
        findings=reported_findings(reading, line, proven),
        loading=loading,
        notes=reading.notes + reading.refused + below,
    )
