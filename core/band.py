"""The massline band: Appendix A's zone B, between the support modes (zone A) and the elastic modes (zone C).

One type for the band wherever it comes from: predicted before the test from the model
(:func:`massline.virtual.band_prediction.predict_band`), chosen in a recording
(:func:`massline.identify.band_choice.choose_band`) or given by the engineer (``--band LO HI``).

One rule for a predicted band (:func:`held_band`): the widest run of frequencies where every single FRF
stays within the tolerance of its massline's scale, |H_ij(f) − A_ij| ≤ tol·s_ij — not the norm of the
matrix, which lets the weak FRFs stray far while the strong ones hold. The scale s_ij = √(a_i b_j) is the
geometric mean of the largest massline sensor i reads (a_i, its channel's level, which sets its noise) and
the largest hit j drives (b_j): a strong FRF is judged against itself, a weak one (a sensor nearly square to
the motion a hit drives, |A_ij| ≈ 10⁻³ s_ij) against the level its own channel and hit work at, not against
a near-zero massline that no frequency holds to within a few per cent.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.core.errors import MasslineError, param

NULL = 1e-9  # a scale this small against the largest is none
GIVE_BAND = param("band", "(lo, hi)", cli="LO HI")  # 'give band=(lo, hi)': an error's remedy


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
        Deviation of every FRF from its massline allowed inside a predicted band, relative to its scale
        (:func:`frf_scales`; nan otherwise).
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


def frf_scales(massline: np.ndarray) -> np.ndarray:
    """s_ij = √(max_l |A_il| · max_k |A_kj|) (n_s, n_e), (m/s²)/N: the level FRF ij is judged on, its sensor's
    largest massline times its hit's, square-rooted. |A_ij| ≤ s_ij, with equality for the strongest FRF of a
    row and column."""
    size = np.abs(massline)
    return np.sqrt(size.max(axis=1)[:, None] * size.max(axis=0)[None, :])


def stray(frf: np.ndarray, massline: np.ndarray) -> np.ndarray:
    """max_ij |H_ij(f) − A_ij| / s_ij at each frequency: the FRF farthest from its massline, against its scale.

    A sensor or hit with no massline at all (s_ij ≤ NULL × the largest) has none to hold.

    Parameters
    ----------
    frf : (n_s, n_e, n_f) complex array
        Accelerance, (m/s²)/N.
    massline : (n_s, n_e) array
        The masslines A_ij, (m/s²)/N.
    """
    scale = frf_scales(massline)
    kept = scale > NULL * scale.max()
    return np.max(np.abs(frf[kept] - massline[kept][:, None]) / scale[kept][:, None], axis=0)


def held_band(frequencies: np.ndarray, strays: np.ndarray, tolerance: float) -> tuple[float, float]:
    """First and last frequency (Hz) of the widest run, in log frequency, where ``strays`` ≤ ``tolerance``;
    (nan, nan) when no frequency holds."""
    good = np.asarray(strays) <= tolerance
    if not good.any():
        return np.nan, np.nan
    runs = np.flatnonzero(np.diff(np.concatenate([[0], good.astype(int), [0]]))).reshape(-1, 2)
    start, stop = runs[np.argmax(np.log(frequencies[runs[:, 1] - 1]) - np.log(frequencies[runs[:, 0]]))]
    return float(frequencies[start]), float(frequencies[stop - 1])


def band_to_dict(band: Band) -> dict:
    """A predicted band as plan.json keeps it (Hz)."""
    return {
        "low_hz": band.low,
        "high_hz": band.high,
        "tolerance": band.tolerance,
        "suspension_top_hz": band.suspension_top,
        "first_elastic_hz": band.first_elastic,
    }


def band_from_dict(doc: dict | None) -> Band | None:
    """The band ``band_to_dict`` wrote (null edges: no band held), or None for a plan that keeps none."""
    if not isinstance(doc, dict):
        return None
    try:
        low, high, top, elastic, tolerance = (
            np.nan if doc.get(k) is None else float(doc[k])
            for k in ("low_hz", "high_hz", "suspension_top_hz", "first_elastic_hz", "tolerance")
        )
    except (TypeError, ValueError):
        raise MasslineError("plan file: its 'band' needs numbers (Hz): write it again with 'massline plan'") from None
    return Band(low=low, high=high, suspension_top=top, first_elastic=elastic, rule="predicted", tolerance=tolerance)
