"""The discrete stage of the diagnosis: polarity flips and swapped channels undone before any continuous effect.

Discrete faults break any linearisation, so they come first (the procedure's step 2, :mod:`.diagnosis`): the
rigid-subspace screen (:mod:`.screens`) proposes them, and each is kept when the refit's BIC, with the fix's
cost, drops by more than ``EVIDENCE`` (:mod:`.criterion`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.identify.diagnose.criterion import EVIDENCE
from massline.identify.diagnose.effect_fit import Fit, base_fit, refit
from massline.identify.diagnose.effect_model import Block
from massline.identify.diagnose.effects import named
from massline.identify.diagnose.finding import Finding
from massline.identify.diagnose.screens import (
    channel_consistency,
    corrected_band,
    discrete_fixes,
    kinematic_matrix,
    roomy,
    with_gaps,
)
from massline.identify.tails import BandData

PROPOSALS = 0.5  # a discrete fix is tried when it leaves at most this share of the rigid-subspace misfit


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
