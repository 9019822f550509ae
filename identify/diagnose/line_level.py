"""The diagnosis on the band's lines, as the pipeline runs it: the rigid body fitted with what the lines show.

The second stage of :func:`.pipeline.diagnose_recording`, on the recording :mod:`.reading` read. A force gauge's
mass at every drive point is found first, in identify's masslines (:mod:`.gauge_mass`), and the recording shifted
onto the bare body's; the acquisition chains' factors of frequency are found on the lines and undone
(:mod:`.row_factors`); the noise is the recording's own (:mod:`massline.identify.recording_noise`); then the
line-level procedure (:mod:`.diagnosis`): the nominal rigid model, the discrete fixes, and the search over every
effect of the registry at every place and the test physics' tails.
"""

from __future__ import annotations

from dataclasses import dataclass

from massline.identify.diagnose.diagnosis import Diagnosis, diagnose
from massline.identify.diagnose.effects import held
from massline.identify.diagnose.effects.excitation_mass_loading import ExcitationMassLoading
from massline.identify.diagnose.gauge_mass import GaugeMass, gauge_mass, shifted
from massline.identify.diagnose.reading import Reading
from massline.identify.diagnose.row_factors import chains_undone
from massline.identify.diagnose.screens import screen
from massline.identify.recording_noise import RecordingNoise, recording_noise, stated_averages
from massline.identify.tails import BandData


@dataclass(frozen=True, eq=False, kw_only=True)
class LineLevel:
    """What the band's lines show.

    Attributes
    ----------
    gauge : GaugeMass or None
        A force gauge's mass found at every drive point.
    chains : list of Finding
        The acquisition chains' factors of frequency found on the lines (undone for the rest).
    in_frequency : list of Finding
        The rows whose lines depart in frequency as no effect of the registry explains.
    data : BandData
        The recorded FRFs inside the diagnosis band, the gauge and the chains undone.
    screens : dict
        The model-free screens on ``data``.
    noise : RecordingNoise
        Each FRF's noise over the diagnosis band as the recording shows it.
    result : Diagnosis
        The line-level diagnosis.
    """

    gauge: GaugeMass | None
    chains: list
    in_frequency: list
    data: BandData
    screens: dict
    noise: RecordingNoise
    result: Diagnosis

    @property
    def found(self) -> list:
        """The faults and test physics the lines name: the gauge, the chains, then the line-level diagnosis's."""
        return ([] if self.gauge is None else [self.gauge.finding()]) + self.chains + self.result.findings


def line_level(reading: Reading, transverse: float) -> LineLevel:
    """The gauge, the chains' factors, the noise and the line-level diagnosis of ``reading`` on its band (the final
    model refitted on identify's band, the test physics read on every line of the record)."""
    before, cleaned, used, layout = reading.before, reading.cleaned, reading.band, reading.layout
    gauge = None
    if before is not None and not reading.known["exciter_mass"] and held(ExcitationMassLoading.name):
        gauge = gauge_mass(before.data, before.sigma, reading.planar, transverse, before.best)
    searched = cleaned if gauge is None else shifted(cleaned, gauge)  # the other effects, on the bare body
    chains, in_frequency, searched = chains_undone(searched, used.low, used.high, layout)  # the chains' factors
    f, estimation = cleaned.frequencies, reading.estimation
    data = BandData.from_recording(f, searched.frf, used.low, used.high)
    wide = BandData.from_recording(f, searched.frf, estimation.low, estimation.high)
    record = BandData.from_recording(f, searched.frf, f[0], f[-1])
    averages = stated_averages(reading.recording.description)  # measured as recorded, relative to the FRFs searched
    noise = recording_noise(f, cleaned.frf, cleaned.coherence, used.low, used.high, averages)
    noise = noise.on(f, searched.frf, used.low, used.high)
    result = diagnose(data, layout, transverse, wide, record, noise.relative())
    return LineLevel(gauge=gauge, chains=chains, in_frequency=in_frequency, data=data, screens=screen(data, layout),
                     noise=noise, result=result)  # fmt: skip
