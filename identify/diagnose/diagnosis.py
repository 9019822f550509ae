"""Diagnosis: which physics the rigid-body model left out, modelled, refitted and shown to improve the fit.

The procedure of the mismatch notes (§6), on the band's spectral lines:

1. The nominal model: the rigid body's masslines, every accelerometer's transverse
   reading under the datasheet prior, no tails, no effects (:mod:`.effect_model`).
2. Discrete faults first (they break any linearisation): polarity flips and swapped
   channels, proposed by the rigid-subspace screen (:mod:`.screens`) and kept when
   the refit's BIC drops by more than ``EVIDENCE``.
3. Continuous effects, forward: every block of the library is ranked by its score
   statistic at the current fit; the two tail laws and the three best-scored blocks
   (then, while none is accepted, the next best-scored tilts) are refitted in full,
   and the best is kept when (a) BIC drops by more than ``EVIDENCE``, (b) it
   explains at least ``MATERIAL`` of the noise variance over the band, in the residual
   or, for an effect, in the masslines it moves (a law the data show but that changes
   nothing worth a line is not a finding), and (c) its fitted
   values are physically plausible. Effects at the same place whose BIC is within
   ``AMBIGUOUS`` of the best cannot be told apart by the data and are reported with it.
4. A backward pass drops any effect that the others made redundant.
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

from massline.identify.diagnose.effect_fit import Fit, fit, is_body, penalty, score, with_model_form
from massline.identify.diagnose.effect_model import Block, Layout, Problem
from massline.identify.diagnose.effects import held, named
from massline.identify.diagnose.finding import Finding, accepted_finding, faults_first
from massline.identify.diagnose.screens import (
    channel_consistency,
    corrected_band,
    discrete_fixes,
    kinematic_matrix,
    with_gaps,
)
from massline.identify.estimator import TRANSVERSE, estimate
from massline.identify.recording_noise import recording_noise
from massline.identify.resonances import support_and_elastic
from massline.identify.tails import TAIL_LAWS, BandData
from massline.core.band import Band
from massline.core.errors import MasslineError, solver_errors
from massline.core.masslines import Masslines
from massline.core.methods import starting_body
from massline.core.model import RigidModel
from massline.core.rigid_body import RigidBody

EVIDENCE = 10.0  # ΔBIC that counts as very strong evidence (Kass & Raftery 1995)
MATERIAL = 0.1  # share of the noise variance an effect must explain to be worth a finding
AMBIGUOUS = 6.0  # effects at one place within this ΔBIC of the best are reported together
REFITS = 3  # score-ranked candidates refitted in full at a time
MOST_EFFECTS = 4  # a search adding this many effects is fitting the tails' misfit, not faults
PROPOSALS = 0.5  # a discrete fix is tried when it leaves at most this share of the rigid-subspace misfit


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


def rigid_tail(laws) -> bool:
    """Whether one of the tail ``laws`` can be the rigid body's own, s_iᵀ X e_j (the support's)."""
    return any(named(law).rigid_tail for law in laws)


def problem_for(band: BandData, layout: Layout, laws, model: RigidModel, transverse: float, shared=False) -> Problem:
    """The fit problem on ``band`` with the tail ``laws`` (or "free": identify's per-FRF tails); ``shared``: the
    support's tail is the rigid body's, s_iᵀ X e_j, on the model's lines (:mod:`massline.identify.tails`)."""
    if laws == "free":
        data = band.free
    else:
        data = band.shared_support(laws) if shared and rigid_tail(laws) else band.reduced(laws)
    return Problem(layout, data, band.noise, model, transverse, band.n_values, band.energy)


def starting_point(masslines: Masslines, sigma: np.ndarray, layout: Layout, transverse: float) -> RigidBody:
    """A body to start the fit from: the weighted estimate, else the paper's, else one of the data's scale
    (data with a gross fault may admit no body at all)."""
    for attempt in (
        lambda: estimate(masslines, sigma, layout.planar, 0.0 if layout.planar else transverse).body,
        lambda: starting_body(masslines, layout.planar),
    ):
        try:
            with np.errstate(invalid="ignore"):  # data with a gross fault can drive the estimate through no-bodies
                body = attempt()
            if is_body(body):
                return body
        except (np.linalg.LinAlgError, MasslineError, *solver_errors()):
            continue
    mass = 1 / np.median(np.abs(masslines.values))
    return RigidBody(mass, layout.sensors.points.mean(axis=0), mass * layout.extent**2 * np.eye(3))


def base_fit(band: BandData, layout: Layout, laws: frozenset, transverse: float) -> Fit:
    """The nominal model fitted (no effects), started from ``starting_point``."""
    data = band.reduced(laws)
    masslines = Masslines(data.massline, layout.sensors, layout.exciters)
    start = starting_point(masslines, band.noise / np.sqrt(data.kappa), layout, transverse)
    return fit(problem_for(band, layout, laws, RigidModel(start, layout.planar), transverse))


def refit(current: Fit, band: BandData, laws: frozenset, blocks, shared: bool = False) -> Fit:
    """The model with ``laws`` and ``blocks`` (the support's tail ``shared`` or per FRF), started from ``current``."""
    lay, model, transverse = current.problem.layout, current.problem.model, current.problem.transverse
    return fit(problem_for(band, lay, laws, model, transverse, shared), blocks, current)


def plausible(result: Fit, block: Block) -> bool:
    """Fitted values a technician could have produced (notes §6: angles, gains, offsets within reason), as
    the block's effect judges them."""
    theta, tau, values = result.parts
    return named(block.effect).plausible(result, block, values[result.blocks.index(block)], tau)


def roomy(layout: Layout) -> bool:
    """More channels than rigid motions plus one: only then can one channel be checked against the others."""
    return len(layout.sensors) > (3 if layout.planar else 6) + 1


@dataclass(frozen=True, eq=False)
class DiscreteStage:
    """What the discrete stage did: the fixes ((effect name, channels)), the band with them undone, its fit and
    the findings."""

    fixes: tuple
    band: BandData
    fit: Fit
    findings: list


def discrete_stage(before: Fit, band: BandData) -> DiscreteStage:
    """Undo the discrete effects the rigid-subspace screen proposes (flips, swaps) while the BIC says so."""
    fixes, findings = [], []
    laws, layout, transverse = frozenset(), before.problem.layout, before.problem.transverse
    current = before
    S = kinematic_matrix(layout.sensors, layout.planar)
    if not roomy(layout):
        return DiscreteStage((), band, current, findings)
    for _ in range(len(layout.sensors)):
        corrected = corrected_band(band, fixes)
        A = with_gaps(corrected.reduced(laws))
        ranked = discrete_fixes(A, S)
        proposals = [r for r in ranked if r[0] < PROPOSALS][:3]
        best = None
        for _, effect, channels in proposals:
            trial_fixes = fixes + [(effect, channels)]
            trial = base_fit(corrected_band(band, trial_fixes), layout, laws, transverse)
            fixed_bic = trial.bic + np.log(current.problem.n_values)  # with the discrete fix's cost
            if len(channels) > 1 and moved_instead(current, corrected, channels, fixed_bic):  # a swap's rival
                continue
            gain = current.bic - fixed_bic
            if gain > EVIDENCE and (best is None or gain > best[0]):
                best = (gain, effect, channels, trial, trial_fixes)
        if best is None:
            break
        gain, effect, channels, current, fixes = best
        evidence = {"delta_bic": gain, "loco_misfit": float(channel_consistency(A, S)[list(channels)].max())}
        findings.append(Finding(effect, tuple(channels), None, {}, evidence))
    return DiscreteStage(tuple(fixes), corrected_band(band, fixes), current, findings)


def moved_instead(current: Fit, band: BandData, channels, bic: float) -> bool:
    """Whether one of two channels' accelerometers, moved on its face, explains the data at least as well as
    swapping the two (BIC ``bic`` with the swap's cost): a sensor placed off its label leaves a misfit a swap
    with a neighbour can halve, but only a swap makes the two rows exact."""
    layout = current.problem.layout
    moved = [b for b in layout.candidates() if moves_sensor(b) and set(layout.channels(b)) & set(channels)]
    return any(refit(current, band, frozenset(), current.blocks + (b,)).bic <= bic for b in moved)


def moves_sensor(block: Block) -> bool:
    """Whether the block moves an accelerometer on its face (``sensor_location``)."""
    effect = named(block.effect)
    return effect.perturbs == "sensor" and effect.moves == "point"


def forward_stage(band: BandData, start: Fit, noise: float, shared: bool) -> tuple[Fit, frozenset, list]:
    """Add the best-supported continuous effect while it passes evidence, materiality and plausibility (the
    support's tail ``shared`` or per FRF).

    The tail laws and the ``REFITS`` best-scored candidates are refitted; when none passes, the next
    best-scored tilts, ``REFITS`` at a time, down to a score of ``EVIDENCE``. A tilt is judged by its prior,
    not by the energy it moves, so it can pass where better-scored effects were immaterial: a weak FRF's
    support tail, huge in χ² and immaterial, and the hit effects it lends scores to stood before the
    structure's 11° tilts (9th and 19th by score: they were never refitted). Going down every effect's
    ranking instead took a foam case 147 s and found nothing more.

    A search that has added ``MOST_EFFECTS`` effects is fitting a misfit no fault explains (a stiff cord's
    tail beside residual flexibility: one spurious effect after another passed, for minutes, and moved the
    properties 13σ from identify's): its effects are dropped and only the tails it accepted are kept."""
    current, laws, accepted = start, frozenset(), []
    layout = start.problem.layout
    while len(current.blocks) < MOST_EFFECTS:
        J = current.problem.jacobian(current.x, current.blocks)
        taken = set(current.blocks)
        scored = [(score(current, b, J) - penalty(current.problem, b), b) for b in layout.candidates()]
        ranked = sorted((s for s in scored if s[1] not in taken), key=lambda s: -s[0])
        options = [
            (refit(current, band, laws | {law}, current.blocks, shared), law, laws | {law})
            for law in TAIL_LAWS
            if law not in laws and held(law)  # a law taken out of the registry is physics the search does not know
        ]
        tilts = [s for s in ranked[REFITS:] if named(s[1].effect).widens_prior and s[0] > EVIDENCE]
        ranked = ranked[:REFITS] + tilts
        for first in range(0, max(len(ranked), 1), REFITS):  # the next tilts while none is accepted
            batch = ranked[first : first + REFITS]
            options += [(refit(current, band, laws, current.blocks + (b,), shared), b, laws) for _, b in batch]
            chosen = first_accepted(current, options, band, noise)
            if chosen is not None:
                break
        if chosen is None:
            return current, laws, accepted
        trial, what, laws, evidence = chosen
        alternatives = [] if isinstance(what, str) else _alternatives(current, band, laws, what, trial, shared)
        accepted.append((what, {**evidence, "alternatives": alternatives}))
        current = trial
    tails = [(what, evidence) for what, evidence in accepted if isinstance(what, str)]
    return refit(current, band, laws, (), shared), laws, tails


def first_accepted(current: Fit, options: list, band: BandData, noise: float) -> tuple | None:
    """Of the options (trial fit, block or tail law, laws), the one of lowest BIC that passes evidence,
    materiality and plausibility, with its evidence; None when none does."""
    energy = float(np.sum(band.energy))
    for trial, what, trial_laws in sorted(options, key=lambda o: o[0].bic):
        gain = current.bic - trial.bic
        explained = (np.sum(current.rss) - np.sum(trial.rss)) / energy
        ok = isinstance(what, str) or plausible(trial, what)
        by_prior = not isinstance(what, str) and named(what.effect).widens_prior  # judged by its prior
        moved = 0.0 if isinstance(what, str) else massline_change(current, trial, band)
        material = max(explained, moved) > MATERIAL * noise**2 or by_prior
        if gain > EVIDENCE and material and ok and (isinstance(what, str) or seen_per_frf(current, trial, band)):
            return trial, what, trial_laws, {"delta_bic": gain, "explained": explained, "massline_change": moved}
    return None


def seen_per_frf(current: Fit, trial: Fit, band: BandData) -> bool:
    """Whether an effect fitted with the support's tail shared also lowers the BIC by ``EVIDENCE`` with each
    FRF's own tail: a fault is in the data whatever the tail's form, while what the shared form's small
    misfits (a support of several modes, the elastic tail's shape) lend an effect is not."""
    if not current.problem.data.shared:
        return True
    laws = current.problem.data.laws
    without = refit(current, band, laws, current.blocks)
    return without.bic - refit(trial, band, laws, trial.blocks).bic > EVIDENCE


def massline_change(current: Fit, trial: Fit, band: BandData) -> float:
    """How far an effect moves the masslines, as a share of the band's energy: Σ_ij n_ij (ΔA_ij)² / Σ_ij |H_ij|²
    over the n_ij lines of each FRF with a massline. Tails that are nearly collinear with the massline over a
    narrow band can mimic most of an effect in the residual; what it changes in the rigid body's lines is its size
    all the same."""
    lines = np.count_nonzero(band.lines, axis=2) // 2
    change = np.sum(lines * (trial.masslines - current.masslines) ** 2)
    return float(change / np.sum(band.energy))


def _alternatives(current: Fit, band: BandData, laws: frozenset, chosen: Block, best: Fit, shared: bool) -> list[str]:
    """Other effects at the same place (sharing a channel, or the same exciter) that fit within
    ``AMBIGUOUS`` of the chosen one: the data cannot tell them apart."""
    layout = current.problem.layout

    def place(block):
        if named(block.effect).perturbs == "sensor":
            return {("s", c) for c in layout.channels(block)}
        return {("e", block.target)}

    same = [b for b in layout.candidates() if b != chosen and place(b) & place(chosen)]
    close = []
    for b in same:
        trial = refit(current, band, laws, current.blocks + (b,), shared)
        if trial.bic - best.bic < AMBIGUOUS and b.effect != chosen.effect:
            close.append(b.effect)
    return sorted(set(close))


def backward_stage(
    band: BandData, result: Fit, laws: frozenset, accepted: list, shared: bool
) -> tuple[Fit, frozenset, list]:
    """Drop an accepted effect when the model without it is within ``EVIDENCE`` of the model with it."""
    kept = []
    for what, evidence in accepted:
        if isinstance(what, str):
            trial_laws, blocks = laws - {what}, result.blocks
        else:
            trial_laws, blocks = laws, tuple(b for b in result.blocks if b != what)
        trial = refit(result, band, trial_laws, blocks, shared)
        if trial.bic - result.bic < EVIDENCE:
            result, laws = trial, trial_laws
        else:
            kept.append((what, evidence))
    return result, laws, kept


def search(band: BandData, start: Fit, noise: float, shared: bool) -> tuple[Fit, frozenset, list]:
    """The forward then the backward stage, the support's tail ``shared`` (the rigid body's) or per FRF.

    A support acts on the rigid body: its tail s_iᵀ X e_j changes with a fault on line i or j as the massline
    does, so a fault cannot hide in it as it can in free per-FRF tails; the per-FRF form stays for tails no
    rigid support makes (``diagnose`` keeps the form with the lower BIC).
    """
    result, laws, accepted = forward_stage(band, start, noise, shared)
    return backward_stage(band, result, laws, accepted, shared)


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
