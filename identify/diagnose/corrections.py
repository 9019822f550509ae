"""The recording with the faults a diagnosis found undone, for identify to estimate the properties again.

One estimator: the diagnosis says what is wrong; the properties before and after are identify's, on the
recording as it came and as corrected. Each fault is undone where it entered, by its effect's ``correct``
(:mod:`.effects`): a flipped polarity or a swap on the channels' FRFs, a gain by dividing them by it, a tilted
axis, a moved sensor or hit on the lines' directions and points.

Test physics (the support, the elastic modes) is no correction: identify models both in every band fit.
Mass loading is undone on the body, not the recording (:func:`.mass_loading.mass_loading`).
"""

from __future__ import annotations

from dataclasses import replace

from massline.identify.diagnose.effects import named
from massline.identify.diagnose.finding import Finding


def undone(recording, finding: Finding):
    """The recording with one fault undone (test physics and mass loading: unchanged)."""
    effect = named(finding.effect)
    frf, sensors, exciters = effect.correct(recording.frf.copy(), recording.sensors, recording.exciters, finding)
    frf = effect.correct_lines(recording.frequencies, frf, finding)
    return replace(recording, frf=frf, sensors=sensors, exciters=exciters)


def corrected(recording, findings: list):
    """The recording with every fault among ``findings`` undone, in their order."""
    for finding in findings:
        recording = undone(recording, finding)
    return recording
