"""The identification's fast formulas against the straightforward ones they replace, on small cases."""

import numpy as np
import pytest

from massline.identify.band_choice import candidate_sums
from massline.identify.estimator import reduced_chi2
from massline.identify.massline_fit import fit_band, solve, truncation_shift
from massline.identify.weighted_system import WeightedSystem


def design(frequencies, low, high, richer=False):
    """The band's lines and its unweighted design over [Re; Im] of A + B/x + Cx + Dx² (+ B₂/x², D₂x³),
    columns (A, Re B, Im B, Re C, Im C, D (, B₂, D₂)), x = ω²/(ω_first ω_last)."""
    keep = (frequencies >= low) & (frequencies <= high)
    omega = 2 * np.pi * frequencies[keep]
    x = omega**2 / (omega[0] * omega[-1])
    zero = np.zeros_like(x)
    real = [np.ones_like(x), 1 / x, zero, x, zero, x**2] + ([1 / x**2, x**3] if richer else [])
    imag = [zero, zero, 1 / x, zero, x, zero] + ([zero, zero] if richer else [])
    return keep, x, np.vstack([np.column_stack(real), np.column_stack(imag)])


def lstsq_coefficients(frequencies, frf, low, high, weights, richer=False):
    """Per-FRF lstsq on the design: its coefficients (n_s, n_e, k) and each A's 1-σ."""
    keep, _, X = design(frequencies, low, high, richer)
    coef, std = np.empty(frf.shape[:2] + (X.shape[1],)), np.empty(frf.shape[:2])
    for i, j in np.ndindex(*frf.shape[:2]):
        w = np.sqrt(np.concatenate([weights[i, j, keep]] * 2))
        Xw, yw = X * w[:, None], np.concatenate([frf[i, j, keep].real, frf[i, j, keep].imag]) * w
        c, *_ = np.linalg.lstsq(Xw, yw, rcond=None)
        r = yw - Xw @ c
        coef[i, j] = c
        # (XᵀX)⁻¹₀₀ as the squared norm of R⁻¹'s first row (Xw = QR): the normal matrix's pinv loses
        # cond(X)² ≈ 1e9 of the digits with the richer tails (1.2e-10 relative, against 1e-13 here)
        r_inverse = np.linalg.solve(np.linalg.qr(Xw, mode="r"), np.eye(X.shape[1]))
        std[i, j] = np.sqrt(r @ r / (len(yw) - X.shape[1]) * (r_inverse[0] @ r_inverse[0]))
    return coef, std


def lstsq_fit(frequencies, frf, low, high, weights, richer=False):
    """Per-FRF lstsq on the design: masslines and their 1-σ."""
    coef, std = lstsq_coefficients(frequencies, frf, low, high, weights, richer)
    return coef[..., 0], std


def straight_truncation(frequencies, coef, low, high, richer=False):
    """The truncation shift as first written: the row of X⁺ (X the band's unweighted design) that gives A,
    applied to the next terms' columns 1/x² and x³ (Re rows), times B₂ = B²/A and D₂ = D²/C."""
    _, x, X = design(frequencies, low, high, richer)
    zero = np.zeros_like(x)
    row = np.linalg.pinv(X)[0]
    into_suspension, into_flexibility = row @ np.concatenate([1 / x**2, zero]), row @ np.concatenate([x**3, zero])
    A, B, C, D = coef[..., 0], coef[..., 1], coef[..., 3], coef[..., 5]
    return into_suspension * B**2 / A + into_flexibility * D**2 / C


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
    np.testing.assert_allclose(fit.std / np.sqrt(fit.inflation), std, rtol=1e-10)  # white noise's 1-σ, then τ


@pytest.mark.parametrize("band", [(3.0, 100.0), (1.0, 118.0), (20.0, 40.0)])
def test_tails_and_truncation_shift_are_the_least_squares_ones(noisy, band):
    """The tails' coefficients (refined once from the residuals) and the truncation shift from the sums equal
    lstsq's and the row of X⁺ applied to the next terms, as main first computed them."""
    f, H, weights = noisy
    coef, _ = lstsq_coefficients(f, H, *band, weights)
    fit = fit_band(f, H, *band, weights)
    keep = (f >= band[0]) & (f <= band[1])
    mid2 = (2 * np.pi) ** 2 * f[keep][0] * f[keep][-1]
    np.testing.assert_allclose(fit.suspension, (coef[..., 1] + 1j * coef[..., 2]) * mid2, rtol=1e-10)
    np.testing.assert_allclose(fit.flexibility, (coef[..., 3] + 1j * coef[..., 4]) / mid2, rtol=1e-10)
    np.testing.assert_allclose(fit.truncation, straight_truncation(f, coef, *band), rtol=1e-9)
    assert np.abs(fit.truncation).max() > 0
    richer = fit_band(f, H, *band, weights, richer=True)  # the next terms in the design: nothing left over
    assert np.abs(richer.truncation).max() < 1e-6 * np.abs(fit.truncation).max()


def test_candidate_truncation_from_shared_runs_is_its_own(noisy):
    f, H, weights = noisy
    pairs = [(2.0, 110.0), (3.0, 110.0), (6.0, 60.0)]
    sums = candidate_sums(f, H, weights, pairs)
    for pair in pairs:
        coef, _ = lstsq_coefficients(f, H, *pair, weights)
        found = truncation_shift(sums[pair], solve(sums[pair]))
        np.testing.assert_allclose(found, straight_truncation(f, coef, *pair).ravel(), rtol=1e-7)  # unrefined C, D


def test_an_frf_without_coherence_in_the_band_is_fitted_unweighted(noisy):
    """Coherence 0 on every line of an FRF's band: its fit is the unweighted one (its 1-σ from its own
    scatter), not a singular system; the other FRFs keep their weights."""
    f, H, weights = noisy
    dead = weights.copy()
    dead[1, 0] = 0.0
    fit = fit_band(f, H, 3.0, 100.0, dead)
    plain = fit_band(f, H, 3.0, 100.0)
    weighted = fit_band(f, H, 3.0, 100.0, weights)
    assert np.isfinite(fit.values).all() and np.isfinite(fit.std).all()
    assert fit.values[1, 0] == pytest.approx(plain.values[1, 0], rel=1e-9)
    assert fit.std[1, 0] == pytest.approx(plain.std[1, 0], rel=1e-6)
    mask = np.ones(H.shape[:2], dtype=bool)
    mask[1, 0] = False
    np.testing.assert_allclose(fit.values[mask], weighted.values[mask], rtol=1e-12)
    sums = candidate_sums(f, H, dead, [(3.0, 100.0), (6.0, 60.0)])
    assert np.isfinite(solve(sums[3.0, 100.0]).std).all()


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


def random_system(transverse, weighed, seed=5, n_s=7, n_e=3, p=10):
    rng = np.random.default_rng(seed)
    D = rng.normal(size=(n_s, n_e, 2)) * 30 if transverse else None
    prior = rng.normal(size=(n_s, 2 if transverse else 0))
    scale = {"scale_row": np.eye(p)[0] * 40.0, "scale_r": 0.7} if weighed else {}
    return WeightedSystem(rng.normal(size=(n_s, n_e, p)), D, rng.normal(size=(n_s, n_e)), prior, transverse, **scale)


@pytest.mark.parametrize("weighed", [False, True])
@pytest.mark.parametrize("transverse", [0.03, 0.0])
def test_paid_parameters_are_the_hat_matrix_trace(transverse, weighed):
    """p_eff from the eliminated blocks equals tr(J_d (JᵀJ)⁻¹ J_dᵀ) of the dense Jacobian over the measured
    rows (the masslines and the scale's), and the scale row's leverage is its diagonal entry."""
    system = random_system(transverse, weighed)
    J, _ = system.dense()
    n = system.measured.size
    leverage = np.einsum("ij,ji->i", J[:n], np.linalg.solve(J.T @ J, J[:n].T))
    assert system.paid_parameters() == pytest.approx(leverage.sum(), rel=1e-10)
    chi2, dof, scale = reduced_chi2(system)
    assert dof == pytest.approx(n - leverage.sum(), rel=1e-9)
    assert chi2 == pytest.approx(np.sum(system.measured**2) / (n - leverage.sum()), rel=1e-9)
    if weighed:
        assert scale == pytest.approx(leverage[-1], rel=1e-10)
    else:
        assert np.isnan(scale)


@pytest.mark.parametrize("weighed", [False, True])
@pytest.mark.parametrize("transverse", [0.03, 0.0])
def test_eliminated_step_is_the_dense_least_squares_step(transverse, weighed):
    """The step (θ̃, τ) and S from the eliminated blocks: the dense lstsq step and the Schur complement
    Σ AᵢᵀAᵢ + aaᵀ − Eᵢ Cᵢ⁻¹ Eᵢᵀ of the normal equations."""
    system = random_system(transverse, weighed)
    J, residual = system.dense()
    x, tau, S = system.step()
    dense = np.linalg.lstsq(J, residual, rcond=None)[0]
    p = system.A.shape[2]
    np.testing.assert_allclose(np.concatenate([x, tau.ravel()]), dense, rtol=1e-10, atol=1e-12)
    N = J.T @ J
    schur = N[:p, :p] - N[:p, p:] @ np.linalg.solve(N[p:, p:], N[p:, :p]) if transverse else N
    np.testing.assert_allclose(S, schur, rtol=1e-10, atol=1e-10 * np.abs(S).max())


def test_candidate_edges_with_no_line_between_them(noisy):
    """Two candidate edges closer than a line spacing leave an empty run of lines: the sums still add up."""
    f, H, weights = noisy
    pairs = [(2.01, 110.0), (2.02, 60.0)]
    assert not np.any((f >= 2.01) & (f < 2.02))
    sums = candidate_sums(f, H, weights, pairs)
    for pair in pairs:
        values, _ = lstsq_fit(f, H, *pair, weights)
        np.testing.assert_allclose(solve(sums[pair]).real[:, 0], values.ravel(), rtol=1e-9)
