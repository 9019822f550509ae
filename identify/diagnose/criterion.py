"""The one criterion a candidate explanation of a recording is accepted by, and its false-alarm rate.

Every candidate (an effect of the registry at a place, a tail law of the test physics, a discrete fix, a fault's
undoing on identify's masslines) is accepted only when it lowers the objective it is scored on by more than
``EVIDENCE``: the lines' BIC, χ² + k ln n, in the line-level search (:mod:`.effect_search`,
:mod:`.discrete_stage`, :mod:`.row_factors`), identify's χ² of the masslines in the proof (:mod:`.undone`). On
noise alone a χ² drops by more than 10 for one added value, per candidate, with probability P(χ²₁ > 10) = 0.16 %
(0.67 % for two values, 1.9 % for three); the BIC's k ln n only lowers it.
"""

EVIDENCE = 10.0  # ΔBIC (or Δχ²) of very strong evidence (Kass & Raftery 1995): 0.16 % false alarms per value
