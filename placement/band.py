"""The massline band: Appendix A's zone B, between the support modes (zone A) and the elastic modes (zone C).

One type for the band wherever it comes from: predicted before the test from the model
(:func:`massline.virtual.band.predict_band`), found in a recording
(:func:`massline.identify.band.find_band`) or given by the engineer (``--band LO HI``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Band:
    """The massline band and the resonances that bound it.

    Attributes
    ----------
    low, high : float
        Band edges, Hz (nan when no frequency qualifies; ``high`` inf for a rigid model, which has no zone C).
    suspension_top : float
        Highest support resonance below the band, Hz (nan when none is known).
    first_elastic : float
        Lowest elastic resonance above the band, Hz (nan when none is known, inf for a rigid model).
    rule : str
        How the band was chosen: "predicted", "found" or "given".
    tolerance : float
        Relative deviation from the massline allowed inside a predicted band (nan otherwise).
    """

    low: float
    high: float
    suspension_top: float = np.nan
    first_elastic: float = np.nan
    rule: str = "given"
    tolerance: float = np.nan

    @property
    def exists(self) -> bool:
        return bool(np.isfinite(self.low) and self.high > self.low)

    @property
    def ratio(self) -> float:
        """high/low: how many times wider than a point the band is (nan if none)."""
        return self.high / self.low if self.exists else np.nan

    def wider_than(self, other: "Band") -> bool:
        """Wider in log frequency; between two bands open at the top, the one starting lower."""
        if not self.exists:
            return False
        if not other.exists:
            return True
        if np.isinf(self.high) and np.isinf(other.high):
            return self.low < other.low
        return self.ratio > other.ratio
