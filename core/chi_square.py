"""The χ² distribution's tails, for the tests of chance the identification and the diagnosis make.

With k degrees of freedom, P(χ² > x) = Q(k/2, x/2), the regularised upper incomplete gamma function, and the
value exceeded with probability q is 2 Q⁻¹(k/2, q). Taken from :mod:`scipy.special` rather than
``scipy.stats.chi2``: the same functions underneath, without the second it takes to load ``scipy.stats`` on
every command.
"""

from __future__ import annotations

import numpy as np
from scipy.special import gammaincc, gammainccinv


def chi2_sf(x, dof):
    """P(χ²_dof > x): the chance that a χ² of ``dof`` degrees of freedom exceeds ``x``."""
    return gammaincc(np.divide(dof, 2.0), np.divide(x, 2.0))


def chi2_isf(q, dof):
    """The value a χ² of ``dof`` degrees of freedom exceeds with probability ``q``."""
    return 2.0 * gammainccinv(np.divide(dof, 2.0), q)
