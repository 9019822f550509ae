"""The misfit's shape, read without the library: a constant factor on one channel's row or one hit's column.

A named fault is a claim about physics; the shape of the misfit it removes is a claim about the data only. The
simplest shapes need no effect at all: every FRF of channel i off by one factor g_i (a gain, a calibration, a
flipped sign, a cable), or every FRF of hit j by one factor (the force's calibration, a hit's direction on a
plate). identify's rigid model with the place's row (or column) scaled by its best factor,

    A_ij ≈ g_i Â_ij(θ),   g_i = Σ_j A_ij Â_ij / σ_ij²  /  Σ_j Â_ij² / σ_ij²   (θ fixed),

then polished with θ estimated again (:func:`scaled`), is the library-free account of a misfit at one place.
A named effect that fits no better than it, counting the values each is fitted with, is not proven by the
data: on the bracket's channel 9 a 10 % gain is fitted to 0.70× the noise by a 9.0 ± 0.6 mm sensor offset as
well, so with the gain out of the library the offset would be named. The comparison is Schwarz's (BIC):
χ² + k ln n, k the free values, n the masslines (:func:`outfits`).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import minimize

from massline.core.masslines import Masslines
from massline.identify.diagnose.unexplained import estimated, tilts
from massline.identify.estimator import Estimate

MAX_TRIALS = 200  # estimates Nelder–Mead may try (each trial is one estimate of θ)
CURVATURE_STEP = 1e-3  # relative step of the factor's second difference


def objective(best: Estimate) -> float:
    """identify's objective of an estimate: Σ z² of the masslines plus its transverse prior's Σ |τ_i|²/t²."""
    return float(best.chi2 * best.dof + np.sum(tilts(best)))


def _scaling(found, places: list):
    """identify's objective on ``found``'s masslines with each place ((0, channel) or (1, hit)) scaled by its
    factor: a function of the factors (inf where the rest cannot be estimated)."""
    data, sigma, best = found.data, found.sigma, found.best

    def cost(factors: np.ndarray) -> float:
        scale = np.ones_like(data.values)
        for (axis, k), g in zip(places, factors):
            if axis == 0:
                scale[k] *= g
            else:
                scale[:, k] *= g
        if not np.all(np.isfinite(scale)) or np.any(scale == 0):
            return np.inf
        fit = estimated(found, Masslines(data.values / scale, data.sensors, data.exciters), sigma / np.abs(scale),
                        best.riding)  # fmt: skip
        return np.inf if fit is None else objective(fit)

    return cost


def scaled(found, rows: tuple = (), columns: tuple = ()) -> tuple[float, np.ndarray]:
    """identify's objective on ``found``'s masslines (an ``Identification``) with each of ``rows`` (channels)
    and ``columns`` (hits, 0-based) scaled by its own best factor, and the factors (rows', then columns');
    (inf, nan) where the rest cannot be estimated.

    The factors start at the closed form above with θ fixed at identify's, or at ±1 (its signs, or their
    opposite) where that costs less, and are then polished by Nelder–Mead on the objective, θ estimated again at
    each trial: θ takes up part of a faulty channel's misfit, so alternating the two creeps (a 10 % gain read as
    5 % after twelve rounds), and a flipped channel bends θ so far that the closed form starts Nelder–Mead off it
    (a factor of 7.8e5 where −1 fits)."""
    data, sigma, best = found.data, found.sigma, found.best
    places = [(0, i) for i in rows] + [(1, j) for j in columns]
    cost = _scaling(found, places)
    model = data.values - best.residual
    start = []
    for axis, k in places:
        a, m, s = (data.values[k], model[k], sigma[k]) if axis == 0 else (data.values[:, k], model[:, k], sigma[:, k])
        denominator = np.sum(m**2 / s**2)
        start.append(np.sum(a * m / s**2) / denominator if denominator > 0 else 1.0)
    start = np.array(start)
    unit = np.where(start < 0, -1.0, 1.0)  # no fault, or a flipped sign: the closed form is bent by θ taking it up
    start = min((start, unit, -unit), key=lambda x: cost(x))
    simplex = np.vstack([start] + [start + 0.05 * np.abs(start).clip(0.1) * e for e in np.eye(len(start))])
    with np.errstate(invalid="ignore"):  # trials no body fits cost inf: the simplex's spread is then nan
        options = {"initial_simplex": simplex, "xatol": 1e-6, "fatol": 1e-6, "maxfev": MAX_TRIALS}
        found_min = minimize(cost, start, method="Nelder-Mead", options=options)
    if not np.isfinite(found_min.fun):
        return np.inf, np.full(len(places), np.nan)
    return float(found_min.fun), np.asarray(found_min.x)


def channel_factor(found, channel: int, step: float | None = None) -> tuple[float, float]:
    """One channel's factor by identify's objective (:func:`scaled`) and its 1-σ from the objective's curvature
    along it, θ estimated again at each point (a profile: σ² = 2 / ∂²f/∂g²), scaled by √(χ²/dof) where the fit
    leaves more than the noise; the second difference steps by ``step`` (about the factor's 1-σ, so that the
    estimate's tolerance does not swamp it; default a thousandth of the factor). (nan, nan) where the rest
    cannot be estimated, (g, nan) where the objective is not convex along the factor."""
    least, (g,) = scaled(found, (channel,))
    if not np.isfinite(least):
        return np.nan, np.nan
    h = max(CURVATURE_STEP * max(abs(g), 1e-3), step or 0.0)
    cost = _scaling(found, [(0, channel)])
    curvature = (cost(np.array([g + h])) - 2 * least + cost(np.array([g - h]))) / h**2
    dof = found.best.dof - 1  # the factor is fitted too
    spread = np.sqrt(max(least / dof, 1.0)) if dof > 0 else 1.0
    convex = np.isfinite(curvature) and curvature > 0
    return float(g), float(np.sqrt(2 / curvature) * spread) if convex else np.nan


def place_of(finding) -> tuple[tuple, tuple]:
    """(rows, columns) a fault's misfit sits at: a sensor effect's channels, an excitation effect's hit."""
    if finding.exciter is not None:
        return (), (finding.exciter,)
    return tuple(finding.channels), ()


def outfits(without, after, finding) -> dict | None:
    """The library-free account of ``finding``'s place when it explains the misfit as well as the named effect
    with the values each has paid for (BIC, module docstring), else None. ``without``: identify with every
    other fault undone (an ``Identification``); ``after``: with ``finding`` undone too. Its factor's own effects
    (a gain, a flipped sign) are that shape, and never outfitted."""
    rows, columns = place_of(finding)
    if not rows and not columns or finding.effect in SCALE_EFFECTS:
        return None
    shape, factors = scaled(without, rows, columns)
    n = np.count_nonzero(np.isfinite(without.sigma))  # the masslines present (σ = ∞: a pair with none)
    named_cost = objective(after.best) + finding.evidence.get("values", 0) * np.log(n)
    shape_cost = shape + len(factors) * np.log(n)
    if not shape_cost <= named_cost:
        return None
    return {"rows": list(rows), "columns": list(columns), "factors": factors.tolist(), "chi2": shape,
            "named_chi2": objective(after.best)}  # fmt: skip


SCALE_EFFECTS = ("sensor_gain", "sensor_polarity")  # a factor on one channel's row: the shape itself
