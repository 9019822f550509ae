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

In x = ω²/ω_mid² every column is a power of x, and the real and imaginary parts have
their own coefficients: Re H = A + B_r x⁻¹ + C_r x + D x², Im H = B_i x⁻¹ + C_i x. The
weighted least squares of every FRF thus needs only its sums over the band's lines
(:class:`LineSums`): Σ w² xᵐ, Σ w² Re H xᵐ, Σ w² Im H xᵐ and Σ w² |H|², and the
unweighted Σ xᵐ give the truncation shift of each massline (:func:`truncation_shift`). Sums
over adjacent runs of lines add, so the candidate bands of :mod:`.band_choice` share them;
:func:`fit_band` refines its fits once from their residuals, to a QR fit's accuracy.

Each FRF is fitted on its own lines (:mod:`.missing_lines`): a line it does not have (NaN in the FRF, or in
its weight) is in none of its sums, its degrees of freedom count its own lines, and a pair with no more
lines in the band than the fit has coefficients has no fit (NaN).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from massline.core.band import GIVE_BAND
from massline.identify.line_correlation import variance_inflation
from massline.identify.missing_lines import present
from massline.core.errors import MasslineError

REAL = (0, -1, 1, 2)  # powers of x in Re H: A, Re B, Re C, D
RICHER = (-2, 3)  # each tail's next term, B₂/ω⁴ and D₂ω⁶ (real): what the truncation shift carries into A
IMAG = (-1, 1)  # powers of x in Im H: Im B, Im C
WEIGHT_POWERS = np.arange(-4, 7)  # every product of two columns' powers
REAL_POWERS = np.arange(-2, 4)  # every real column's power
WEIGHT_FLOOR = 1e-12  # a line's least weight γ²/(1 − γ²): a coherence of 0 weighs as 1e-12


@dataclass(frozen=True, eq=False, kw_only=True)
class BandFit:
    """Masslines fitted over a band; each attribute NaN (complex NaN) where the pair has no FRF or too few lines
    in the band (no more than the fit's coefficients).

    Attributes
    ----------
    values : (n_s, n_e) array
        The masslines A, (m/s²)/N.
    std : (n_s, n_e) array
        1-σ of each A from the fit's residual scatter, (m/s²)/N, its variance scaled by how alike neighbouring
        lines' residuals are (:mod:`.line_correlation`).
    suspension, flexibility : (n_s, n_e) complex arrays
        B ((m/s²)/N·(rad/s)²) and C ((m/s²)/N·(rad/s)⁻²): the tails removed.
    quality : (n_s, n_e) array
        RMS residual of each fit relative to |A|.
    bias : (n_s, n_e) array
        How far the plain band average of Re H sits from A, relative to |A|.
    truncation : (n_s, n_e) array
        How far A moves when each tail's next term is taken out (:func:`truncation_shift`), (m/s²)/N.
    inflation : (n_s, n_e) array
        τ, the factor each A's white-noise variance was scaled by (1 for white noise).
    """

    values: np.ndarray
    std: np.ndarray
    suspension: np.ndarray
    flexibility: np.ndarray
    quality: np.ndarray
    bias: np.ndarray
    truncation: np.ndarray
    inflation: np.ndarray


@dataclass(frozen=True, eq=False, kw_only=True)
class LineSums:
    """Each FRF's weighted sums over a run of lines, in x = ω²/ω_ref².

    Attributes
    ----------
    weight : (n_fr, 11) array
        Σ w² xᵐ, m = −4 … 6 (w² the line's weight, dimensionless).
    real : (n_fr, 6) array
        Σ w² Re H xᵐ, m = −2 … 3, (m/s²)/N.
    imag : (n_fr, 2) array
        Σ w² Im H xᵐ, m = ±1, (m/s²)/N.
    square : (n_fr,) array
        Σ w² |H|², ((m/s²)/N)².
    lines : (n_fr,) int array
        How many lines of each FRF were summed (the lines it has).
    plain : (n_fr, 11) array
        Σ xᵐ, m = −4 … 6, unweighted over each FRF's lines: the gram of its own design (:func:`truncation_shift`).
    """

    weight: np.ndarray
    real: np.ndarray
    imag: np.ndarray
    square: np.ndarray
    lines: int
    plain: np.ndarray

    def __add__(self, other: LineSums) -> LineSums:
        return LineSums(
            weight=self.weight + other.weight,
            real=self.real + other.real,
            imag=self.imag + other.imag,
            square=self.square + other.square,
            lines=self.lines + other.lines,
            plain=self.plain + other.plain,
        )

    def rescaled(self, s: float) -> LineSums:
        """The same sums in x' = s x."""
        s = float(s)
        return LineSums(
            weight=self.weight * s**WEIGHT_POWERS,
            real=self.real * s**REAL_POWERS,
            imag=self.imag * s ** np.array(IMAG),
            square=self.square,
            lines=self.lines,
            plain=self.plain * s**WEIGHT_POWERS,
        )


def line_sums(x: np.ndarray, real: np.ndarray, imag: np.ndarray, w2: np.ndarray, has: np.ndarray) -> LineSums:
    """The sums of FRFs Re H, Im H (n_fr, n) at x (n,) with line weights w2 (n_fr, n) or (1, n), each over the
    lines it has (``has`` (n_fr, n), :func:`band_lines`; w2 is 0 at the others)."""
    powers = x[:, None] ** WEIGHT_POWERS
    weight = np.broadcast_to(w2 @ powers, (len(real), len(WEIGHT_POWERS)))
    weighted_real, weighted_imag = w2 * real, w2 * imag
    square = np.einsum("fn,fn->f", weighted_real, real) + np.einsum("fn,fn->f", weighted_imag, imag)
    sums_real = weighted_real @ powers[:, 2:8]  # x⁻² … x³
    sums_imag = weighted_imag @ powers[:, [3, 5]]  # x⁻¹, x
    plain = (has[:, :, None] * powers).sum(axis=1)
    return LineSums(
        weight=weight, real=sums_real, imag=sums_imag, square=square, lines=has.sum(axis=1), plain=plain
    )


def band_lines(frf: np.ndarray, keep: np.ndarray, weights=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Re H and Im H (n_fr, n) of the kept lines, each contiguous, and the lines each FRF has (n_fr, n) bool: H
    finite, and its weight when ``weights`` (n_s, n_e, n_f) are given; Re H and Im H are 0 at the others."""
    shape = (frf.shape[0] * frf.shape[1], int(np.count_nonzero(keep)))  # a run may hold no line
    has = present(frf[:, :, keep], None if weights is None else weights[:, :, keep]).reshape(shape)
    real, imag = (np.where(has, part[:, :, keep].reshape(shape), 0.0) for part in (frf.real, frf.imag))
    return real, imag, has


@dataclass(frozen=True, eq=False)
class Solution:
    """Every FRF's weighted least-squares fit from its sums (x = ω²/ω_mid²).

    Attributes
    ----------
    real : (n_fr, 4 or 6) array
        A, Re B, Re C, D (and B₂, D₂): the coefficients of Re H on the powers REAL (+ RICHER) of x, (m/s²)/N.
    imag : (n_fr, 2) array
        Im B, Im C: the coefficients of Im H on x⁻¹ and x, (m/s²)/N.
    variance : (n_fr,) array
        [(XᵀW²X)⁻¹]₀₀: A's variance per unit variance of a weighted line, dimensionless.
    rss : (n_fr,) array
        Weighted residual sum of squares Σ w² |H − fit|², ((m/s²)/N)².
    dof : (n_fr,) int array
        Each FRF's lines' real and imaginary parts less the coefficients.

    ``real``, ``imag`` and ``rss`` are NaN for an FRF with too few lines (:func:`fitted`).
    """

    real: np.ndarray
    imag: np.ndarray
    variance: np.ndarray
    rss: np.ndarray
    dof: np.ndarray

    @property
    def std(self) -> np.ndarray:
        """1-σ of each A from the residual scatter, (m/s²)/N."""
        return np.sqrt(np.maximum(self.rss, 0.0) / self.dof * self.variance)


def fitted(sums: LineSums, richer: bool = False) -> np.ndarray:
    """(n_fr,) bool: the FRFs with more lines than the fit has coefficients; the others have no fit (NaN)."""
    return sums.lines > len(REAL + (RICHER if richer else ())) + len(IMAG)


def gram(weight: np.ndarray, powers: tuple, usable: np.ndarray) -> np.ndarray:
    """Σ w² x^(a+b) over the columns' powers a, b: (n_fr, k, k); the identity for the FRFs not ``usable``
    (:func:`fitted`), whose fits are set NaN."""
    return np.where(usable[:, None, None], weight[:, np.add.outer(powers, powers) + 4], np.eye(len(powers)))


def solve(sums: LineSums, richer: bool = False) -> Solution:
    """Every FRF's fit from its sums; the weighted RSS as Σ w²|H|² − cᵀXᵀW²y (exact to ~1e-10, cancellation)."""
    powers = REAL + (RICHER if richer else ())
    usable = fitted(sums, richer)
    G = gram(sums.weight, powers, usable)
    g = sums.real[:, np.array(powers) + 2]
    real = np.linalg.solve(G, g[..., None])[..., 0]
    imag = np.linalg.solve(gram(sums.weight, IMAG, usable), sums.imag[..., None])[..., 0]
    real, imag = (np.where(usable[:, None], c, np.nan) for c in (real, imag))
    rss = sums.square - np.einsum("fk,fk->f", real, g) - np.einsum("fk,fk->f", imag, sums.imag)
    dof = np.maximum(2 * sums.lines - len(powers) - len(IMAG), 1)
    return Solution(real, imag, np.linalg.inv(G)[:, 0, 0], rss, dof)


def columns(x: np.ndarray, powers) -> np.ndarray:
    """xᵐ (k, n) for each power m."""
    return x[None, :] ** np.array(powers, dtype=float)[:, None]


def truncation_shift(sums: LineSums, fit: Solution, richer: bool = False) -> np.ndarray:
    """The change of each massline when each tail's next term is removed from the data, (n_fr,).

    A single mode below the band gives the real tail A (x_s/x + x_s²/x² + …) and one above it
    R (x/x_r + x²/x_r² + x³/x_r³ + …), so the first terms the fit leaves out are B₂/x² with B₂ = B²/A and
    D₂x³ with D₂ = D²/C (the scaled coefficients of ``fit``). The band's design X, unweighted, carries a part
    of each into A: that part, the row of X⁺ that gives A applied to them, is what the truncation of the
    tails may bias the massline by. Several modes make the next terms larger than a single one does when
    they are far apart, so this is a size, not a correction.

    X is block-diagonal in (Re H: the powers REAL of x) and (Im H: IMAG), and the next terms are real, so
    the row of X⁺ = (XᵀX)⁻¹Xᵀ applied to a column xᵏ is [G⁻¹ h]₀ with G = Σ x^(a+b) over the real
    columns' powers a, b and h_a = Σ x^(a+k): the unweighted sums ``sums.plain`` give both, over each FRF's own
    lines.
    """
    powers = REAL + (RICHER if richer else ())
    G = gram(sums.plain, powers, fitted(sums, richer))
    h = sums.plain[:, np.add.outer(powers, RICHER) + 4]  # (n_fr, k, 2): Σ x^(a−2), Σ x^(a+3)
    into_suspension, into_flexibility = np.linalg.solve(G, h)[:, 0].T
    A, B, C, D = (fit.real[:, k] for k in range(4))
    with np.errstate(divide="ignore", invalid="ignore"):
        B2 = np.where(A != 0, B**2 / A, 0.0)
        D2 = np.where(C != 0, D**2 / C, 0.0)
    return into_suspension * B2 + into_flexibility * D2


def fit_band(
    frequencies: np.ndarray, frf: np.ndarray, low: float, high: float, weights=None, richer: bool = False
) -> BandFit:
    """Least-squares fit of A + B/ω² + Cω² + Dω⁴ to every FRF (n_s, n_e, n_f) over low ≤ f ≤ high (Hz).

    ``weights`` (n_s, n_e, n_f), e.g. the coherence γ²/(1 − γ²), weight the lines of each FRF (floored at
    WEIGHT_FLOOR: an FRF with coherence 0 on every line of the band is fitted unweighted, not left singular);
    ``richer`` fits each tail's next term too, B₂/ω⁴ and D₂ω⁶. Each FRF is fitted on the lines it has (NaN in
    ``frf`` or ``weights``: a line it lacks); a pair with too few of them in the band has NaN in every attribute.
    """
    keep = (frequencies >= low) & (frequencies <= high)
    n = int(keep.sum())
    if n < 8:
        raise MasslineError(f"the band {low:g}–{high:g} Hz holds {n} spectral lines; at least 8 are needed")
    omega = 2 * np.pi * frequencies[keep]
    mid2 = omega[0] * omega[-1]
    x = omega**2 / mid2
    real, imag, has = band_lines(frf, keep, weights)
    w2 = line_weights(weights, keep, has)
    sums = line_sums(x, real, imag, w2, has)
    usable = fitted(sums, richer)
    fit = solve(sums, richer)
    powers = REAL + (RICHER if richer else ())
    real_columns, imag_columns = columns(x, powers), columns(x, IMAG)
    lines = np.maximum(sums.lines, 1)  # a pair with no line is not fitted
    plain = real.sum(axis=1) / lines
    model_real, model_imag = fit.real @ real_columns, fit.imag @ imag_columns
    real = np.subtract(real, model_real, out=model_real)  # the residuals, in the model's arrays
    imag = np.subtract(imag, model_imag, out=model_imag)
    # one step of iterative refinement from the residuals: the tails' coefficients to a QR fit's accuracy
    # (the normal equations alone leave C and D ~1e-9 off, and the truncation shift with them)
    weighted = (w2 * real, w2 * imag)
    g_real, g_imag = weighted[0] @ real_columns.T, weighted[1] @ imag_columns.T
    step_real = np.linalg.solve(gram(sums.weight, powers, usable), g_real[..., None])[..., 0]
    step_imag = np.linalg.solve(gram(sums.weight, IMAG, usable), g_imag[..., None])[..., 0]
    # the weighted RSS from the residuals (no cancellation), less the step's δᵀg = δᵀGδ (≥ 0, tiny)
    rss = np.einsum("fn,fn->f", weighted[0], real) + np.einsum("fn,fn->f", weighted[1], imag)
    rss -= np.einsum("fk,fk->f", step_real, g_real) + np.einsum("fk,fk->f", step_imag, g_imag)
    real -= step_real @ real_columns
    imag -= step_imag @ imag_columns
    real[~has] = imag[~has] = 0.0  # no residual at a line the FRF does not have
    squares = np.einsum("fn,fn->f", real, real) + np.einsum("fn,fn->f", imag, imag)
    w = np.sqrt(w2)
    inflation = variance_inflation(w * real, w * imag, present=has)  # neighbouring lines' noise alike
    fit = replace(fit, real=fit.real + step_real, imag=fit.imag + step_imag, rss=rss)
    shape = frf.shape[:2]

    def pairs(values: np.ndarray) -> np.ndarray:
        """(n_s, n_e): each FRF's ``values``, NaN where it has too few lines."""
        return np.where(usable, values, np.nan).reshape(shape)

    A = pairs(fit.real[:, 0])
    if not np.isfinite(A[usable.reshape(shape)]).all():
        raise MasslineError(f"a band fit failed (overflow in the FRFs?): check the recording or give {GIVE_BAND}")
    scale = np.maximum(np.abs(A), 1e-300)
    return BandFit(
        values=A,
        std=pairs(fit.std * np.sqrt(inflation)),
        suspension=pairs((fit.real[:, 1] + 1j * fit.imag[:, 0]) * mid2),
        flexibility=pairs((fit.real[:, 2] + 1j * fit.imag[:, 1]) / mid2),
        quality=pairs(np.sqrt(squares / (2 * lines))) / scale,
        bias=np.abs(pairs(plain) - A) / scale,
        truncation=pairs(truncation_shift(sums, fit, richer)),
        inflation=pairs(inflation),
    )


def line_weights(weights, keep: np.ndarray, has: np.ndarray) -> np.ndarray:
    """The lines' weights w² (n_fr, n) over the kept lines, 0 at those an FRF does not have (``has``, from
    :func:`band_lines`); without weights, ones (1, n) when every FRF has every line.

    Weights below WEIGHT_FLOOR count as it: an FRF whose coherence is 0 on every line of the band is fitted
    with equal weights, as it would be without coherence, its 1-σ from its own scatter (and the pipeline's
    coherence warning names it), where zero weights would leave its fit undetermined.
    """
    if weights is None:
        return np.ones((1, has.shape[1])) if has.all() else has.astype(float)
    return np.where(has, np.maximum(weights[:, :, keep].reshape(has.shape), WEIGHT_FLOOR), 0.0)
