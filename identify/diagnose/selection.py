"""Model selection on identify's χ²: which of the candidate explanations the lines named the recording proves.

The third stage of :func:`.pipeline.diagnose_recording`. The candidates come from one loop on the band's lines
(:mod:`.line_level`: every effect of the registry at every place and the test physics' tails, scored on the lines'
BIC, each accepted by the one criterion of :mod:`.criterion`, the residual scored again after each acceptance).
Here each is proven on identify's objective, the χ² of the masslines, by the same criterion: undone, it must
lower that χ² by ``EVIDENCE`` with the others undone, and a factor at its place, the misfit's library-free shape
(:mod:`.shapes`), must not explain as much (:func:`.undone.identified_after`, which withdraws the rest and proves
again). What identify's misfit with the proven faults undone still holds is ``unexplained`` (:mod:`.unexplained`),
with its place and shape. Three rules stand beside the loop, each saying why the loop alone is not enough.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

from massline.identify.diagnose.diagnosis import Diagnosis
from massline.identify.diagnose.placed import beside_a_spread_misfit, at_the_misfit, same_place, where_the_misfit_is
from massline.identify.diagnose.targeted import at_place
from massline.identify.diagnose.undone import best_undone, identified_after
from massline.identify.diagnose.unexplained import unexplained
from massline.identify.pipeline import Identification


class Proven(NamedTuple):
    """identify with the faults undone (None: no body), the findings it keeps, the faults withdrawn (with those set
    aside before the proof) and what it leaves unexplained (None: within chance, or no body)."""

    after: Identification | None
    findings: list
    withdrawn: list
    left: object


@dataclass(frozen=True, eq=False)
class Prover:
    """The proof of faults on identify's χ²: identify run on ``recording`` with them undone, on ``band`` (None:
    its own), against ``before``, with the masses the engineer gave (``known``)."""

    recording: object
    band: tuple | None
    transverse: float
    before: Identification | None
    known: dict

    def __call__(self, faults: list, set_aside: list) -> Proven:
        """identify with ``faults`` undone, the findings it keeps, the faults withdrawn (``set_aside`` first) and
        what it leaves unexplained."""
        after, findings, withdrawn = identified_after(self.recording, faults, self.band, self.transverse,
                                                      self.before, self.known)  # fmt: skip
        withdrawn = set_aside + withdrawn
        return Proven(after, findings, withdrawn, None if after is None else unexplained(after, withdrawn))


@dataclass(frozen=True, eq=False)
class Selection:
    """The candidates kept (``found``), those set aside before the proof, and the proof of the kept ones."""

    found: list
    set_aside: list
    proven: Proven


def select(found: list, result: Diagnosis, prove: Prover) -> Selection:
    """The candidates ``found`` on the lines (``result``: the line-level diagnosis) proven on identify's χ²: the
    stand-ins away from identify's misfit set aside, the rest proven, an effect tried where the misfit is still
    held, and the faults that explained only part of a place's misfit withdrawn."""
    before = prove.before
    # rule: on the lines a hit's fault can absorb a channel's gain; only identify's leave-one-out places the misfit
    found, set_aside = where_the_misfit_is(found, None if before is None else unexplained(before))
    chosen = Selection(found, set_aside, prove(found, set_aside))
    return partial(placed(chosen, result, prove), prove)


def placed(chosen: Selection, result: Diagnosis, prove: Prover) -> Selection:
    """Rule: the lines' loop ranks effects by their score, and the tails' misfit can outscore a fault (the
    bracket's 10 % gain on channel 5 lost to spurious tilts elsewhere); where identify's misfit is still at one
    place, every effect of the registry there is tried (:func:`.targeted.at_place`) and the best on identify's
    objective kept when its proof keeps it."""
    left = chosen.proven.left
    if left is None or left.parameters["shape"] == "spread":
        return chosen
    p = left.parameters
    candidates = at_place(result, (*left.channels, *p.get("also_channels", ())), p["hits"] + p.get("also_hits", []))
    best = best_undone(prove.recording, chosen.found, candidates, prove.band, prove.transverse, prove.known)
    if not best:
        return chosen
    tried = prove(chosen.found + best, chosen.set_aside)
    if any(same_place(f, best[0]) for f in tried.findings):
        return Selection(chosen.found + best, chosen.set_aside, tried)
    return chosen


def partial(chosen: Selection, prove: Prover) -> Selection:
    """Rule: an effect that explains part of a place's misfit passes the criterion all the same; a misfit left
    beyond chance at its place, or spread, says the name is not what the data prove
    (:func:`.placed.at_the_misfit`, :func:`.placed.beside_a_spread_misfit`): those faults are withdrawn and the
    rest proven again."""
    findings, left = chosen.proven.findings, chosen.proven.left
    named = at_the_misfit(findings, left) or beside_a_spread_misfit(findings, left)
    if not named:
        return chosen
    found = [f for f in chosen.found if not any(same_place(f, p) for p in named)]
    set_aside = chosen.set_aside + named
    return Selection(found, set_aside, prove(found, set_aside))
