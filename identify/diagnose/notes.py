"""A diagnosis finding as an engineer would write it: one sentence (each effect's own, :mod:`.effects`)."""

from __future__ import annotations

from massline.identify.diagnose.effects import named
from massline.identify.diagnose.finding import UNEXPLAINED, Finding
from massline.identify.diagnose.signature import phrase
from massline.identify.diagnose.unexplained import sentence as unexplained_sentence
from massline.core.numbers import formatted


def finding_note(finding: Finding, sensors: list, hits: list) -> str:
    """One sentence: what is wrong, where, how large, and what was done about it.

    ``sensors``, ``hits``: the channels' labels (:class:`massline.uff.recording.Channel`), indexed as the finding's.
    """
    if finding.kind == UNEXPLAINED:
        return unexplained_sentence(finding, sensors, hits)
    e = finding.evidence
    names = [sensors[c] for c in finding.channels]
    if len(names) == 3 and names[0].node is not None and len({n.node for n in names}) == 1:
        who = f"the triaxial sensor at node {names[0].node}"
    else:
        who = " and ".join(f"sensor {n}" for n in names)
    hit = None if finding.exciter is None else f"hit {hits[finding.exciter]}"
    also = e.get("alternatives") or []
    tail = f" (the data fit {' or '.join(also)} there as well)" if also else ""
    moved = e.get("moved")
    shift = f"; undoing it moves identify's mass by {formatted(moved['mass_percent'], '+.3f')} %" if moved else ""
    signature = finding.parameters.get("signature")
    shape = f"; its misfit in frequency: {phrase(signature)}" if signature else ""
    return named(finding.effect).sentence(finding, who, hit) + tail + shift + shape


def fit_sentence(chi2: dict, before: float, after: float, noise: float) -> str:
    """The fit before and after as one sentence: identify's reduced χ² of the masslines (``chi2``: the run's
    ``chi2``; the one χ² of identify, diagnose and the reports) and every line's relative RMS residual ``before``
    and ``after`` in the ``noise`` (the recording's; a noiseless recording's residuals are given as they are)."""
    if noise > 0:
        lines = f"every line's RMS residual {before / noise:.2f}× → {after / noise:.2f}× the noise of {noise:.2%}"
    else:
        lines = f"every line's RMS residual {before:.2%} → {after:.2%} of the FRFs, on a noiseless recording"
    if chi2["before"] is None:
        return f"fit: {lines}"
    return (
        f"fit: identify's reduced χ² of the masslines {chi2['before']:.3g} before, {chi2['after']:.3g} after "
        f"(chance: 1 ± {(2 / chi2['dof']) ** 0.5:.2f}); {lines}"
    )


def verdict(findings: list, chi2: dict) -> str | None:
    """The "no fault" verdict and why, when no finding is a fault or unexplained; None otherwise."""
    if any(f.kind in ("fault", UNEXPLAINED) for f in findings):
        return None
    within = f" (identify's reduced χ² {chi2['after']:.3g})" if chi2["after"] is not None else ""
    return f"no fault: the rigid model with the test's physics fits the masslines within the noise{within}"
