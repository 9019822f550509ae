"""Diagnosis: which physics the rigid-body model left out, modelled, refitted and shown to improve the fit.

The procedure of the mismatch notes (§6), on the band's spectral lines:

1. The nominal model: the rigid body's masslines, every accelerometer's transverse
   reading under the datasheet prior, no tails, no effects (:mod:`.effect_model`, :mod:`.effect_fit`).
2. Discrete faults first (they break any linearisation): polarity flips and swapped
   channels, proposed by the rigid-subspace screen (:mod:`.screens`) and kept when
   the refit's BIC drops by more than ``EVIDENCE`` (:mod:`.discrete_stage`, :mod:`.criterion`).
3. Continuous effects, forward: every block of the library is ranked by its score
   statistic at the current fit; the two tail laws and the three best-scored blocks
   (then, while none is accepted, the next best-scored tilts) are refitted in full,
   and the best is kept when (a) BIC drops by more than ``EVIDENCE``, (b) it
   explains at least ``MATERIAL`` of the noise variance over the band, in the residual
   or, for an effect, in the masslines it moves (a law the data show but that changes
   nothing worth a line is not a finding), and (c) its fitted
   values are physically plausible. Effects at the same place whose BIC is within
   ``AMBIGUOUS`` of the best cannot be told apart by the data and are reported with it.
4. A backward pass drops any effect that the others made redundant (steps 3 and 4: :mod:`.effect_search`).
5. When the support's tail is found, steps 3–4 again with that tail the rigid body's,
   s_iᵀ X e_j shared by every FRF (:mod:`massline.identify.tails`): a fault on a line
   changes it as it changes the massline, so it cannot hide in free per-FRF tails. The
   model with the lower BIC is kept (per-FRF tails stay for tails no rigid support makes).

Faults come first among the findings, then the test physics (DESIGN.md). The properties before and
after, and mass loading against a mesh, are identify's on the recording as it came and as corrected
(:mod:`.pipeline`, :mod:`.corrections`, :mod:`.mass_loading`): one estimator.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.identify.diagnose.discrete_stage import discrete_stage
from massline.identify.diagnose.effect_fit import Fit, base_fit, refit, rigid_tail, with_model_form
from massline.identify.diagnose.effect_model import Layout
from massline.identify.diagnose.effect_search import search
from massline.identify.diagnose.finding import accepted_finding, faults_first
from massline.identify.diagnose.screens import corrected_band, kinematic_matrix
from massline.identify.estimator import TRANSVERSE
from massline.identify.recording_noise import recording_noise
from massline.identify.resonances import support_and_elastic
from massline.identify.tails import TAIL_LAWS, BandData
from massline.core.band import Band


@dataclass(frozen=True, eq=False, kw_only=True)
class Diagnosis:
    """Findings, faults first, with the fit before and after.

    ``before`` and ``after`` are the nominal and the final model on the diagnosis band (the fit
    shown); ``estimates`` the same two models on the estimation band with identify's per-FRF tails.
    ``fixes`` are the discrete corrections applied to the recording: (effect name, channels), e.g. a
    flipped polarity or a swap. ``noise`` is the recording's relative RMS noise over the band
    (:mod:`massline.identify.recording_noise`), what both fits are measured against.
    """

    findings: list
    before: Fit
    after: Fit
    estimates: tuple
    band: BandData
    noise: float
    fixes: tuple

    def relative_rms(self, which: str, axis=None) -> np.ndarray:
        """Relative RMS residual over every band line: overall, or per channel (``axis=1``)."""
        result = self.before if which == "before" else self.after
        energy = result.problem.energy
        return np.sqrt(np.sum(result.rss, axis=axis) / np.sum(energy, axis=axis))


def band_noise(band: BandData) -> float:
    """The band's noise as a relative RMS from its FRFs' line differences alone (:mod:`.recording_noise`): the
    recording's noise where no coherence comes with the band."""
    f = band.frequencies
    return recording_noise(f, band.frf, None, f[0], f[-1]).relative()


def weighted_noise(band: BandData) -> float:
    """The noise in the units the fits' weights measure an effect in, as a relative RMS over the band: √(Σ 2n_ij
    σ_ij² / Σ |H|²) of the lines' σ (``band.noise``, n_ij each FRF's lines). What an effect explains is counted in
    those weights, so its materiality is judged on this scale; the noise stated is the recording's."""
    lines = np.count_nonzero(band.lines, axis=2)
    return float(np.sqrt(np.sum(lines * np.where(band.present, band.noise, 0.0) ** 2) / np.sum(band.energy)))



def test_physics_modes(record: BandData, band: BandData, layout: Layout) -> dict:
    """The support's top mode and the first elastic mode (law → Hz, nan where the record does not resolve
    them) around ``band``, on the recording with the discrete faults undone: a flipped or swapped channel
    makes every mode's shape look elastic."""
    edges = Band(float(band.frequencies[0]), float(band.frequencies[-1]), np.nan, np.nan, "found")
    S, E = kinematic_matrix(layout.sensors, layout.planar), kinematic_matrix(layout.exciters, layout.planar)
    return dict(zip(TAIL_LAWS, support_and_elastic(record.frequencies, record.frf, edges, S, E)))


def covers(wide: BandData, band: BandData) -> bool:
    """Whether ``wide`` spans ``band``'s lines (to a line's width)."""
    step = np.diff(band.frequencies).max()
    return wide.frequencies[0] <= band.frequencies[0] + step and wide.frequencies[-1] >= band.frequencies[-1] - step


def diagnose(
    band: BandData,
    layout: Layout,
    transverse: float = TRANSVERSE,
    estimation: BandData | None = None,
    record: BandData | None = None,
    noise: float | None = None,
) -> Diagnosis:
    """The whole procedure on the band's FRFs.

    ``estimation``: the band identify uses; when it holds the diagnosis band, the final model is refitted
    there with identify's per-FRF tails (more lines, every small tail modelled). ``record``: every line of the
    recording, where the test physics' frequencies are read (:func:`test_physics_modes`). ``noise``: the
    recording's relative RMS noise over the band (:mod:`massline.identify.recording_noise`), what every fit is
    measured against (None: from the band's line differences, :func:`band_noise`).
    """
    noise = band_noise(band) if noise is None else noise
    before = base_fit(band, layout, frozenset(), transverse)
    discrete = discrete_stage(before, band)
    fixed, start, findings = discrete.band, discrete.fit, list(discrete.findings)
    resonances = None
    if record is not None:
        resonances = test_physics_modes(corrected_band(record, discrete.fixes), estimation or band, layout)
    weighted = weighted_noise(fixed)
    result, laws, accepted = search(fixed, start, weighted, shared=False)
    if rigid_tail(laws):
        rigid = search(fixed, start, weighted, shared=True)
        result, laws, accepted = min((result, laws, accepted), rigid, key=lambda r: r[0].bic)
    findings += [accepted_finding(result, fixed, what, evidence, resonances) for what, evidence in accepted]
    estimates = (before, with_model_form(result, refit(result, fixed, "free", result.blocks)) if laws else result)
    if estimation is not None and covers(estimation, band):
        estimates = (
            refit(before, estimation, "free", ()),
            refit(result, corrected_band(estimation, discrete.fixes), "free", result.blocks),
        )
    return Diagnosis(
        findings=faults_first(findings),
        before=before,
        after=result,
        estimates=estimates,
        band=fixed,
        noise=noise,
        fixes=discrete.fixes,
    )
