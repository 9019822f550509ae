"""The noise a band is worth when neighbouring lines' noise is alike (identify.line_correlation).

The factor τ = 1 + 2 Σ ρ_k: 1 for white noise, (1 + ρ)/(1 − ρ) for a first-order autoregressive series; and
a massline's 1-σ from the band fit, scaled by it, is the scatter of the massline over repeated tests when the
noise is smoothed across lines as an impact test's windows smooth it.
"""

from __future__ import annotations

import numpy as np
import pytest

from massline.identify.line_correlation import LONGEST, variance_inflation
from massline.identify.massline_fit import fit_band


def autoregressive(rng, rho: float, shape: tuple) -> np.ndarray:
    """Series x_k = ρ x_(k−1) + √(1 − ρ²) e_k over the last axis, unit variance."""
    e = rng.normal(size=shape)
    x = np.empty(shape)
    x[..., 0] = e[..., 0]
    for k in range(1, shape[-1]):
        x[..., k] = rho * x[..., k - 1] + np.sqrt(1 - rho**2) * e[..., k]
    return x


def test_white_noise_is_worth_every_line():
    rng = np.random.default_rng(0)
    tau = variance_inflation(rng.normal(size=(400, 500)))
    assert abs(np.mean(tau) - 1) < 0.1 and np.all(tau >= 1)


@pytest.mark.parametrize("rho", [0.5, 0.8])
def test_an_autoregressive_series_is_worth_its_effective_lines(rho):
    rng = np.random.default_rng(1)
    tau = variance_inflation(autoregressive(rng, rho, (200, 2000)))
    assert np.median(tau) == pytest.approx((1 + rho) / (1 - rho), rel=0.2)


def test_the_factor_is_capped():
    ramp = np.linspace(-1, 1, 300)[None, :] ** 3  # a smooth misfit, not noise
    assert variance_inflation(ramp)[0] == LONGEST


def test_the_massline_one_sigma_covers_smoothed_noise():
    """300 tests of one FRF (massline 1, tails, noise smoothed over ~8 lines): the band fit's 1-σ with τ is the
    masslines' scatter within 25 %; the white-noise 1-σ (τ taken back out) is 2.5× or more too small."""
    rng = np.random.default_rng(2)
    f = np.linspace(1.0, 200.0, 800)
    omega = 2 * np.pi * f
    clean = 1.0 + 40 / omega**2 - 1e-7 * omega**2
    kernel = np.exp(-np.abs(np.arange(-20, 21)) / 4.0)
    kernel /= np.sqrt(np.sum(kernel**2))
    values, sigmas, white = [], [], []
    for _ in range(300):
        noise = [np.convolve(rng.normal(size=f.size + 40), kernel, "valid") * 1e-3 for _ in range(2)]
        H = (clean + noise[0] + 1j * noise[1])[None, None, :]
        fit = fit_band(f, H, 10.0, 190.0)
        values.append(fit.values[0, 0])
        sigmas.append(fit.std[0, 0])
        white.append(fit.std[0, 0] / np.sqrt(fit.inflation[0, 0]))
    scatter = np.std(values)
    assert np.mean(sigmas) == pytest.approx(scatter, rel=0.25)
    assert scatter / np.mean(white) > 2.5
