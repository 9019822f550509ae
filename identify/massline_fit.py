"""Each FRF's massline from its band: a fit that removes the suspension and residual-flexibility tails.

Inside zone B the accelerance of the suspended elastic body is, to the
first order in each neighbour (Appendix A, eq. 14; mismatch notes A1, A3),

    H(ω) = A + B/ω² + C ω² + D ω⁴,

with A the massline (real), B the tail of the suspension modes (K/ω², complex
with the suspension's damping), C the residual flexibility of the elastic
modes above (−ω² Σ φφᵀ/ω_r², complex with their damping) and D its next term
(−ω⁴ Σ φφᵀ/ω_r⁴, real): without it a band reaching f₁/3 leaves ~2σ of bias
in the CoG and products of inertia. The fit is linear in (A, Re B, Im B,
Re C, Im C, D); the scatter of its residual gives each massline's standard
deviation, from the data and not from an assumed noise.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.identify.tails import scaled_frequency
from massline.placement.errors import MasslineError


@dataclass(frozen=True, eq=False)
class BandFit:
    """Masslines fitted over a band.

    Attributes
    ----------
    values : (n_s, n_e) array
        The masslines A, (m/s²)/N.
    std : (n_s, n_e) array
        1-σ of each A from the fit's residual scatter, (m/s²)/N.
    suspension, flexibility : (n_s, n_e) complex arrays
        B ((m/s²)/N·(rad/s)²) and C ((m/s²)/N·(rad/s)⁻²): the tails removed.
    quality : (n_s, n_e) array
        RMS residual of each fit relative to |A|.
    bias : (n_s, n_e) array
        How far the plain band average of Re H sits from A, relative to |A|.
    truncation : (n_s, n_e) array
        How far A moves when each tail's next term is taken out (:func:`truncation_shift`), (m/s²)/N.
    """

    values: np.ndarray
    std: np.ndarray
    suspension: np.ndarray
    flexibility: np.ndarray
    quality: np.ndarray
    bias: np.ndarray
    truncation: np.ndarray


def design_matrix(omega: np.ndarray, richer: bool = False) -> np.ndarray:
    """Rows of Re and Im parts of H(ω) = A + B/ω² + Cω² + Dω⁴ in (A, Re B, Im B, Re C, Im C, D), scaled to O(1).

    ``richer`` adds each tail's next term, B₂/ω⁴ and D₂ω⁶ (real): the model a band is checked against.
    """
    x = scaled_frequency(omega)  # ω²/ω_mid²: keeps the columns comparable
    zero = np.zeros_like(x)
    real = [np.ones_like(x), 1 / x, zero, x, zero, x**2] + ([1 / x**2, x**3] if richer else [])
    imag = [zero, zero, 1 / x, zero, x, zero] + ([zero, zero] if richer else [])
    return np.vstack([np.column_stack(real), np.column_stack(imag)])


def truncation_shift(X: np.ndarray, coef: np.ndarray) -> np.ndarray:
    """The change of each massline when each tail's next term is removed from the data, (n_s, n_e).

    A single mode below the band gives the real tail A (x_s/x + x_s²/x² + …) and one above it
    R (x/x_r + x²/x_r² + x³/x_r³ + …), so the first terms the fit leaves out are B₂/x² with B₂ = B²/A and
    D₂x³ with D₂ = D²/C (scaled coefficients ``coef`` of :func:`design_matrix`'s columns). The band's
    design ``X`` carries a part of each into A: that part, the row of X⁺ that gives A applied to them,
    is what the truncation of the tails may bias the massline by. Several modes make the next terms larger
    than a single one does when they are far apart, so this is a size, not a correction.
    """
    n = X.shape[0] // 2
    x = X[:n, 3]  # the Cω² column: x = ω²/ω_mid²
    zero = np.zeros(n)
    row = np.linalg.pinv(X)[0]
    into_suspension = row @ np.concatenate([1 / x**2, zero])
    into_flexibility = row @ np.concatenate([x**3, zero])
    A, B, C, D = coef[..., 0], coef[..., 1], coef[..., 3], coef[..., 5]
    with np.errstate(divide="ignore", invalid="ignore"):
        B2 = np.where(A != 0, B**2 / A, 0.0)
        D2 = np.where(C != 0, D**2 / C, 0.0)
    return into_suspension * B2 + into_flexibility * D2


def fit_band(
    frequencies: np.ndarray, frf: np.ndarray, low: float, high: float, weights=None, richer: bool = False
) -> BandFit:
    """Least-squares fit of A + B/ω² + Cω² + Dω⁴ to every FRF (n_s, n_e, n_f) over low ≤ f ≤ high (Hz).

    ``weights`` (n_s, n_e, n_f), e.g. the coherence γ²/(1 − γ²), weight the lines of each FRF;
    ``richer`` fits each tail's next term too (:func:`design_matrix`).
    """
    keep = (frequencies >= low) & (frequencies <= high)
    n = int(keep.sum())
    if n < 8:
        raise MasslineError(f"the band {low:g}–{high:g} Hz holds {n} spectral lines; at least 8 are needed")
    omega = 2 * np.pi * frequencies[keep]
    X = design_matrix(omega, richer)
    mid2 = omega[0] * omega[-1]
    H = frf[:, :, keep]
    Y = np.concatenate([H.real, H.imag], axis=2)  # (n_s, n_e, 2n)
    w = np.ones_like(Y) if weights is None else np.sqrt(np.concatenate([weights[:, :, keep]] * 2, axis=2))
    coef = np.empty(Y.shape[:2] + (X.shape[1],))
    std = np.empty(Y.shape[:2])
    rms = np.empty(Y.shape[:2])
    for i, j in np.ndindex(*Y.shape[:2]):
        Xw, yw = X * w[i, j, :, None], Y[i, j] * w[i, j]
        c, *_ = np.linalg.lstsq(Xw, yw, rcond=None)
        r = yw - Xw @ c
        sigma2 = r @ r / max(len(yw) - X.shape[1], 1)
        cov = sigma2 * np.linalg.pinv(Xw.T @ Xw)
        coef[i, j], std[i, j] = c, np.sqrt(cov[0, 0])
        rms[i, j] = np.sqrt(np.mean((Y[i, j] - X @ c) ** 2))
    A = coef[..., 0]
    if not np.isfinite(A).all():
        raise MasslineError("a band fit failed (NaN in the FRFs?): check the recording or give --band LO HI")
    B = (coef[..., 1] + 1j * coef[..., 2]) * mid2
    C = (coef[..., 3] + 1j * coef[..., 4]) / mid2
    scale = np.maximum(np.abs(A), 1e-300)
    plain = H.real.mean(axis=2)
    return BandFit(A, std, B, C, rms / scale, np.abs(plain - A) / scale, truncation_shift(X, coef))
