"""massline.identify.diagnose — where a recording departs from the rigid body, and which physics was left out.

:func:`~.pipeline.diagnose_recording` is what ``massline diagnose`` runs: model-free screens
(:mod:`.screens`), the massline model with the effects of the registry (:mod:`.effects`, one class per
effect: its simulation, model, correction and sentence) (:mod:`.effect_model`) fitted
(:mod:`.effect_fit`), effects added while the evidence says so (:mod:`.diagnosis`), mass loading
against the mesh (:mod:`.mass_loading`); each accepted effect is a :class:`~.finding.Finding`,
written as an engineer would (:mod:`.notes`).

The names below load their modules when first asked for (PEP 562): importing the registry
(:mod:`.effects`) loads no pipeline.
"""

from __future__ import annotations

from importlib import import_module

PUBLIC = {
    "DiagnosisRun": "massline.identify.diagnose.pipeline",
    "Finding": "massline.identify.diagnose.finding",
    "diagnose_recording": "massline.identify.diagnose.pipeline",
}

__all__ = sorted(PUBLIC)


def __getattr__(name: str):
    """The public name ``name``, imported from its module on first use and kept."""
    if name not in PUBLIC:
        raise AttributeError(f"module 'massline.identify.diagnose' has no attribute {name!r}")
    value = getattr(import_module(PUBLIC[name]), name)
    globals()[name] = value
    return value
