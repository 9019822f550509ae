"""massline.identify.diagnose — where a recording departs from the rigid body, and which physics was left out.

:func:`~.pipeline.diagnose_recording` is what ``massline diagnose`` runs: model-free screens
(:mod:`.screens`), the massline model with the effects of the registry (:mod:`.effects`, one class per
effect: its simulation, model, correction and sentence) (:mod:`.effect_model`) fitted
(:mod:`.effect_fit`), effects added while the evidence says so (:mod:`.diagnosis`), mass loading
against the mesh (:mod:`.mass_loading`); each accepted effect is a :class:`~.finding.Finding`,
written as an engineer would (:mod:`.notes`).
"""

from massline.identify.diagnose.finding import Finding
from massline.identify.diagnose.pipeline import DiagnosisRun, diagnose_recording

__all__ = ["DiagnosisRun", "Finding", "diagnose_recording"]
