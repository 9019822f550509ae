"""massline.identify — post-test: a recording → its masslines → the properties with their 1-σ.

:func:`~.pipeline.identify_recording` is what ``massline identify`` runs: the band
(:mod:`.band`), each FRF's massline with its tails removed (:mod:`.massline_fit`, :mod:`.tails`),
the weighted, physically consistent estimate (:mod:`.estimator`) and its uncertainty
(:mod:`.uncertainty`). :mod:`massline.identify.diagnose` says which physics the model left out.

``from massline.identify import identify_recording`` loads the pipeline when first asked for (PEP 562), so
that importing one of this package's modules loads nothing else.
"""

from __future__ import annotations

from importlib import import_module

PUBLIC = {"Identification": "massline.identify.pipeline", "identify_recording": "massline.identify.pipeline"}

__all__ = sorted(PUBLIC)


def __getattr__(name: str):
    """The public name ``name``, imported from its module on first use and kept."""
    if name not in PUBLIC:
        raise AttributeError(f"module 'massline.identify' has no attribute {name!r}")
    value = getattr(import_module(PUBLIC[name]), name)
    globals()[name] = value
    return value
