"""massline.identify.diagnose — where a recording departs from the rigid body, and which physics was left out.

:func:`~.pipeline.diagnose_recording` is what ``massline diagnose`` runs: model-free screens
(:mod:`.screens`), the massline model with the effects of the registry (:mod:`.effects`, one class per
effect: its simulation, model, correction and sentence) (:mod:`.effect_model`) fitted
(:mod:`.effect_fit`), effects added while the evidence says so (:mod:`.diagnosis`, :mod:`.effect_search`),
proven on identify's χ² (:mod:`.selection`), mass loading against the mesh (:mod:`.mass_loading`,
:mod:`.against_mesh`); each accepted effect is a :class:`~.finding.Finding`, written as an engineer would
(:mod:`.notes`).
"""

from massline.identify.diagnose.finding import Finding
from massline.identify.diagnose.diagnosis_run import DiagnosisRun
from massline.identify.diagnose.pipeline import diagnose_recording

__all__ = ["DiagnosisRun", "Finding", "diagnose_recording"]
