"""The identification's fast formulas against the straightforward ones they replace, on small cases."""

import numpy as np
import pytest

from massline.identify.band_choice import candidate_sums
from massline.identify.estimator import WeightedSystem
from massline.identify.massline_fit import fit_band, solve


def lstsq_fit(frequencies, frf, low, high, weights, richer=False):
    """Per-FRF lstsq on the design over [Re; Im] of A + B/x + Cx + Dx² (+ B₂/x², D₂x³): masslines and 1-σ."""
    keep = (frequencies >= low) & (frequencies <= high)
    omega = 2 * np.pi * frequencies[keep]
    x = omega**2 / (omega[0] * omega[-1])
    zero = np.zeros_like(x)
    real = [np.ones_like(x), 1 / x, zero, x, zero, x**2] + ([1 / x**2, x**3] if richer else [])
    imag = [zero, zero, 1 / x, zero, x, zero] + ([zero, zero] if richer else [])
    X = np.vstack([np.column_stack(real), np.column_stack(imag)])
    values, std = np.empty(frf.shape[:2]), np.empty(frf.shape[:2])
    for i, j in np.ndindex(*frf.shape[:2]):
        w = np.sqrt(np.concatenate([weights[i, j, keep]] * 2))
        Xw, yw = X * w[:, None], np.concatenate([frf[i, j, keep].real, frf[i, j, keep].imag]) * w
        c, *_ = np.linalg.lstsq(Xw, yw, rcond=None)
        r = yw - Xw @ c
        values[i, j] = c[0]
        std[i, j] = np.sqrt(r @ r / (len(yw) - X.shape[1]) * np.linalg.pinv(Xw.T @ Xw)[0, 0])
    return values, std


@pytest.fixture(scope="module")
def noisy():
    """Frequencies (Hz), FRFs (3, 2, n) with tails and noise, and line weights."""
    rng = np.random.default_rng(3)
    f = np.linspace(0.5, 120.0, 600)
    omega = 2 * np.pi * f[None, None, :]
    A = rng.normal(size=(3, 2, 1))
    H = A + 300 * (1 + 0.03j) / omega**2 - 4e-7 * (1 + 0.01j) * omega**2 + 2e-13 * omega**4
    H = H + 1e-3 * (rng.normal(size=H.shape) + 1j * rng.normal(size=H.shape))
    return f, H, rng.uniform(20, 400, size=H.shape)


@pytest.mark.parametrize("richer", [False, True])
def test_band_fit_from_sums_is_the_least_squares_fit(noisy, richer):
    f, H, weights = noisy
    values, std = lstsq_fit(f, H, 3.0, 100.0, weights, richer)
    fit = fit_band(f, H, 3.0, 100.0, weights, richer)
    np.testing.assert_allclose(fit.values, values, rtol=1e-10)
    np.testing.assert_allclose(fit.std, std, rtol=1e-10)


def test_candidate_bands_from_shared_runs_are_their_own_fits(noisy):
    f, H, weights = noisy
    pairs = [(2.0, 110.0), (3.0, 110.0), (2.0, 60.0), (6.0, 60.0), (6.0, 110.0)]
    sums = candidate_sums(f, H, weights, pairs)
    for pair in pairs:
        for richer in (False, True):
            values, std = lstsq_fit(f, H, *pair, weights, richer)
            found = solve(sums[pair], richer)
            np.testing.assert_allclose(found.real[:, 0], values.ravel(), rtol=1e-9)
            np.testing.assert_allclose(found.std, std.ravel(), rtol=1e-8)  # Σ w²|H|² − cᵀXᵀW²y cancels


@pytest.mark.parametrize("transverse", [0.03, 0.0])
def test_paid_parameters_are_the_hat_matrix_trace(transverse):
    """p_eff from the Schur blocks equals tr(J_d (JᵀJ)⁻¹ J_dᵀ) of the dense Jacobian."""
    rng = np.random.default_rng(5)
    n_s, n_e, p = 7, 3, 10
    D = rng.normal(size=(n_s, n_e, 2)) * 30 if transverse else None
    system = WeightedSystem(
        rng.normal(size=(n_s, n_e, p)), D, rng.normal(size=(n_s, n_e)), np.zeros((n_s, 2)), transverse
    )
    J, _ = system.dense()
    n = n_s * n_e
    hat = J[:n] @ np.linalg.solve(J.T @ J, J[:n].T)
    assert system.paid_parameters() == pytest.approx(np.trace(hat), rel=1e-10)
