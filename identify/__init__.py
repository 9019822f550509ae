"""massline.identify — post-test: a recording → its masslines → the properties with their 1-σ.

:func:`~.pipeline.identify_recording` is what ``massline identify`` runs: the band
(:mod:`.band`), each FRF's massline with its tails removed (:mod:`.massline_fit`, :mod:`.tails`),
the weighted, physically consistent estimate (:mod:`.estimator`) and its uncertainty
(:mod:`.uncertainty`). :mod:`massline.identify.diagnose` says which physics the model left out.
"""

from massline.identify.pipeline import Identification, identify_recording

__all__ = ["Identification", "identify_recording"]
