"""How much less than its count of lines a band's noise is worth: the lag-1 correlation of a fit's residual.

A massline's 1-σ from the scatter of n lines assumes each line's noise its own. An impact test's H1 estimate
is smoothed by its windows (the exponential window's decay spreads each line over its neighbours), and a tail
law that does not quite follow the recorded tail leaves a slow residual: in both the residual of neighbouring
lines is alike, and the massline is known only as well as n_eff ≈ n (1 − ρ)/(1 + ρ) independent lines would
give it, n_eff = n/τ with τ = 1 + 2 Σ_k ρ_k the integrated autocorrelation time of the residual (ρ_k its
lag-k correlation; Bartlett 1946, Sokal 1997). One impact test of the bracket: ρ₁ ≈ 0.7 and ρ_k decaying
slowly, τ ≈ 9, the white-noise 1-σ 3× too small, and a clean file's reduced χ² 14.6 where chance gives 1.

identify's band fits (:mod:`.massline_fit`) and the diagnosis's (:mod:`.tails`) scale their noise by the same
factor, so that every χ² of a file is measured against one noise.
"""

from __future__ import annotations

import numpy as np

LONGEST = 40.0  # the factor is capped here: a residual smoother than this is a misfit, not noise
LAGS = 0.25  # correlations are summed over at most this share of the lines


def own_lines(series: np.ndarray, present: np.ndarray) -> np.ndarray:
    """Each series (…, n) on its own lines: the values ``present`` (…, n) marks first, in their order, then 0
    (``series`` itself when it marks every value)."""
    if present.all():
        return series
    order = np.argsort(~present, axis=-1, kind="stable")
    return np.where(np.take_along_axis(present, order, axis=-1), np.take_along_axis(series, order, axis=-1), 0.0)


def autocorrelation(residual: np.ndarray, lags: np.ndarray, lines: np.ndarray) -> np.ndarray:
    """ρ_k, k = 1 … the largest of ``lags``, of each series of ``residual`` (…, n) over its first ``lines`` (…,)
    values (…, lags): 0 past its own ``lags`` (…,), and for a flat one."""
    n = residual.shape[-1]
    mean = residual.sum(axis=-1, keepdims=True) / np.maximum(lines, 1)[..., None]
    centred = np.where(np.arange(n) < lines[..., None], residual - mean, 0.0)
    spectrum = np.fft.rfft(centred, 2 * n, axis=-1)
    covariance = np.fft.irfft(np.abs(spectrum) ** 2, axis=-1)[..., : lags.max(initial=1) + 1]
    power = covariance[..., :1]
    within = np.arange(1, covariance.shape[-1]) <= lags[..., None]
    return np.divide(covariance[..., 1:], power, out=np.zeros_like(covariance[..., 1:]), where=(power > 0) & within)


def variance_inflation(*parts: np.ndarray, present: np.ndarray | None = None) -> np.ndarray:
    """τ = 1 + 2 Σ_k ρ_k for residual series (…, n) over lines: ρ_k the mean of ``parts``' lag-k correlations (the
    real and imaginary residuals of one FRF), summed while positive (the initial positive sequence: past it the
    estimates are noise; Geyer 1992), over at most ``LAGS`` of the lines, capped at ``LONGEST``: the factor a
    massline's white-noise variance is short of (1 for white noise). ``present`` (…, n): the lines each series
    has (all when None); it is read on those alone, in their order (an FRF on a coarser axis, on its own)."""
    present = np.ones(parts[0].shape, dtype=bool) if present is None else present
    lines = np.count_nonzero(present, axis=-1)
    lags = np.maximum((LAGS * lines).astype(int), 1)
    rho = np.mean([autocorrelation(own_lines(p, present), lags, lines) for p in parts], axis=0)
    positive = np.cumprod(rho > 0, axis=-1)  # 1 up to the first lag that is not positive
    return np.minimum(1 + 2 * np.sum(rho * positive, axis=-1), LONGEST)
