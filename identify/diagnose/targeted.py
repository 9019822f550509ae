"""The library's effects tried at the one channel or hit where identify's misfit sits.

The forward search ranks every effect at every place by its score at the current fit, and the tails' misfit can
outscore a fault (on the bracket's default plan a 10 % gain on channel 5 lost to spurious tilts elsewhere, the
search stopped at its limit and named nothing). When identify's masslines, leaving one channel or one hit out,
fit within chance (:mod:`.unexplained`), the place is known: each effect of the library at that place is
refitted on the diagnosis's final model, and the best that passes the diagnosis's evidence and plausibility is
proposed, to be proven on identify's χ² as every fault is (:mod:`.undone`).
"""

from __future__ import annotations

from massline.identify.diagnose.criterion import EVIDENCE
from massline.identify.diagnose.diagnosis import Diagnosis
from massline.identify.diagnose.effect_fit import plausible, refit
from massline.identify.diagnose.effects import named
from massline.identify.diagnose.finding import Finding, accepted_finding


def at_place(result: Diagnosis, channels: tuple, hits: list) -> list[Finding]:
    """Every effect at sensor ``channels`` or exciters ``hits`` (0-based) that lowers the final model's BIC by
    ``EVIDENCE`` with plausible values, as findings, the lowest BIC first (identify's χ² chooses among them:
    the lines' BIC can prefer a sensor moved to the gain that scales it, :func:`.undone.best_undone`)."""
    current = result.after
    layout, data = current.problem.layout, current.problem.data
    taken = set(current.blocks)

    def here(block) -> bool:
        if named(block.effect).perturbs == "sensor":
            return bool(set(layout.channels(block)) & set(channels))
        return block.target in hits

    trials = [
        (refit(current, result.band, data.laws, current.blocks + (b,), data.shared), b)
        for b in layout.candidates()
        if here(b) and b not in taken
    ]
    passing = [(t, b) for t, b in trials if current.bic - t.bic > EVIDENCE and plausible(t, b)]
    placed = "identify's misfit, one channel or hit left out"
    return [
        accepted_finding(
            t, result.band, b, {"delta_bic": current.bic - t.bic, "placed_by": placed}
        )
        for t, b in sorted(passing, key=lambda tb: tb[0].bic)
    ]
