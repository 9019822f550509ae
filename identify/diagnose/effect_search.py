"""The continuous effects' search: every effect of the registry at every place and the test physics' tail laws,
examined in one loop on the band's lines (the procedure's steps 3 and 4, :mod:`.diagnosis`).

Each pass ranks every block by its score at the current fit, refits the tail laws and the best-scored blocks,
and accepts the best that passes the one criterion (:mod:`.criterion`: the BIC drops by more than ``EVIDENCE``)
with materiality and plausibility; the residual is scored again after each acceptance. A backward pass drops
what the others made redundant.
"""

from __future__ import annotations

import numpy as np

from massline.identify.diagnose.criterion import EVIDENCE
from massline.identify.diagnose.effect_fit import Fit, penalty, plausible, refit, score
from massline.identify.diagnose.effect_model import Block
from massline.identify.diagnose.effects import held, named
from massline.identify.tails import TAIL_LAWS, BandData

MATERIAL = 0.1  # share of the noise variance an effect must explain to be worth a finding
AMBIGUOUS = 6.0  # effects at one place within this ΔBIC of the best are reported together
REFITS = 3  # score-ranked candidates refitted in full at a time
MOST_EFFECTS = 4  # a search adding this many effects is fitting the tails' misfit, not faults


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
