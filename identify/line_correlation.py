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


def autocorrelation(residual: np.ndarray, lags: int) -> np.ndarray:
    """ρ_k, k = 1 … ``lags``, of each series of ``residual`` (…, n) over its last axis (…, lags); 0 for a flat one."""
    n = residual.shape[-1]
    centred = residual - residual.mean(axis=-1, keepdims=True)
    spectrum = np.fft.rfft(centred, 2 * n, axis=-1)
    covariance = np.fft.irfft(np.abs(spectrum) ** 2, axis=-1)[..., : lags + 1]
    power = covariance[..., :1]
    return np.divide(covariance[..., 1:], power, out=np.zeros_like(covariance[..., 1:]), where=power > 0)


def variance_inflation(*parts: np.ndarray) -> np.ndarray:
    """τ = 1 + 2 Σ_k ρ_k for residual series (…, n) over lines: ρ_k the mean of ``parts``' lag-k correlations (the
    real and imaginary residuals of one FRF), summed while positive (the initial positive sequence: past it the
    estimates are noise; Geyer 1992), over at most ``LAGS`` of the lines, capped at ``LONGEST``: the factor a
    massline's white-noise variance is short of (1 for white noise)."""
    n = parts[0].shape[-1]
    rho = np.mean([autocorrelation(p, max(int(LAGS * n), 1)) for p in parts], axis=0)
    positive = np.cumprod(rho > 0, axis=-1)  # 1 up to the first lag that is not positive
    return np.minimum(1 + 2 * np.sum(rho * positive, axis=-1), LONGEST)
