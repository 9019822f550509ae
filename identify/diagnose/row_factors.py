"""A channel's chain in frequency: one factor F(f; p) on every FRF of its row, fitted on the band's lines.

A delay or a mount's resonance leaves a channel's masslines nearly as they are (F → 1 as f → 0, and each FRF's
own Cω² + Dω⁴ tail takes up a smooth rise), but not its lines: a rigid body's FRF columns lie, at every line, in
the span of the sensors' line coordinates S (n_s, q) — the massline and the support's tail alike. Row i read
through F breaks that, line by line. With each column j whitened by its lines' noise σ_ij (W_j = diag(1/σ_·j),
read from the lines' second differences, where a smooth trend cancels: :func:`line_noise`), the rigid motion at
every line estimated, and row i divided by k F(f; p) (k a real constant, a gain's or a sign's, profiled out),

    χ²(k, p) = Σ_jf ‖(I − P_j)(y_jf + e_i c_jf)‖²,   c_jf = (k / F(f; p) − 1) y_ijf,   P_j = W_jS (W_jS)⁺,

which, r_jf = (I − P_j) y_jf being the rigid misfit now and α_j = (I − P_j)_ii, is

    χ²(k, p) = χ²₀ + Σ_jf 2 Re(c̄_jf r_ijf) + α_j |c_jf|²,

quadratic in k, profiled over p on a grid and polished (:func:`profile`). p's 1-σ comes from the curvature,
scaled by √(χ²/dof) where the fit leaves more than the noise (correlated lines, elastic tails). The effect is
accepted by the diagnosis's criterion: the χ² it removes, so scaled, beyond ``EVIDENCE`` + ln n (Schwarz's
price of its one value). Proven on the lines, not on identify's masslines, which do not show it
(:func:`massline.identify.diagnose.undone.proven_apart`). The signatures' shapes in frequency, a phase ∝ f and a
magnitude rising towards a resonance (:mod:`.signature`), are the library-free accounts of a row: a row one of
them explains by more than ``EVIDENCE`` beyond every effect of the library is a misfit the library cannot name
(a smooth polynomial factor was tried instead: the plate's elastic tails gave it χ² 80 on clean files).
Needs every FRF on every line and more channels than rigid motions plus one (else no row is checked).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import minimize_scalar

from massline.identify.diagnose.effect_model import Layout
from massline.identify.diagnose.corrections import corrected
from massline.identify.diagnose.effects import modelled, named
from massline.identify.diagnose.finding import Finding
from massline.identify.diagnose.screens import kinematic_matrix
from massline.identify.diagnose.signature import FREQUENCY_SHAPES
from massline.identify.tails import BandData

EVIDENCE = 10.0  # ΔBIC of very strong evidence, as the diagnosis's (Kass & Raftery 1995)
GRID = 61  # values of p tried before polishing
MOST_ROWS = 3  # channels one recording's chains are corrected on before the rest is left to the other stages


def line_noise(frf: np.ndarray) -> np.ndarray:
    """σ_ij (n_s, n_e): the noise of one real component of one line, from second differences along the lines,
    E|Δ²n|² = 6 E|n|² for white noise, where a smooth trend (a tail, a delay, a mount) cancels."""
    second = frf[..., :-2] - 2 * frf[..., 1:-1] + frf[..., 2:]
    return np.sqrt(np.mean(np.abs(second) ** 2, axis=-1) / 12)


@dataclass(frozen=True, eq=False)
class Rows:
    """The band's FRFs whitened column by column, their rigid misfit and each channel's share of it.

    ``y`` (n_s, n_e, n_f) whitened FRFs, ``r`` their misfit (I − P_j) y, ``alpha`` (n_s, n_e) = (I − P_j)_ii,
    ``chi2`` the misfit's Σ|r|², ``dof`` its degrees of freedom, ``frequencies`` Hz."""

    y: np.ndarray
    r: np.ndarray
    alpha: np.ndarray
    chi2: float
    dof: int
    frequencies: np.ndarray

    @classmethod
    def of(cls, band: BandData, layout: Layout) -> "Rows":
        S = kinematic_matrix(layout.sensors, layout.planar)
        y = band.frf / line_noise(band.frf)[..., None]
        weights = 1 / line_noise(band.frf)
        r, alpha = np.empty_like(y), np.empty(weights.shape)
        for j in range(y.shape[1]):
            WS = weights[:, j, None] * S
            residual = np.eye(len(S)) - WS @ np.linalg.pinv(WS)
            r[:, j] = residual @ y[:, j]
            alpha[:, j] = np.diag(residual)
        dof = 2 * y.shape[1] * y.shape[2] * (len(S) - S.shape[1])
        return cls(y, r, alpha, float(np.sum(np.abs(r) ** 2)), dof, band.frequencies)

    def cost(self, i: int, inverse: np.ndarray, hits=slice(None)) -> tuple[float, float]:
        """min over k of χ²(k) with row ``i`` times k / F (``inverse`` 1/F at the lines), and that k; over the
        columns ``hits`` (default all)."""
        y, r, a = self.y[i, hits], self.r[i, hits], self.alpha[i, hits][:, None]
        z = y * inverse
        k = np.sum(a * np.real(np.conj(z) * y) - np.real(np.conj(z) * r)) / max(np.sum(a * np.abs(z) ** 2), 1e-300)
        c = k * z - y
        chi2 = np.sum(np.abs(self.r[:, hits]) ** 2)
        return float(chi2 + np.sum(2 * np.real(np.conj(c) * r) + a * np.abs(c) ** 2)), float(k)

    def scale(self, chi2: float, values: int) -> float:
        """max(χ²/dof, 1) of a fit with ``values`` more values: the noise as the fit leaves it."""
        return max(chi2 / max(self.dof - values, 1), 1.0)


@dataclass(frozen=True)
class RowFit:
    """One effect's factor fitted on one channel's row: p and its 1-σ, the gain k profiled with it, and the χ² it
    removes scaled by the fit's reduced χ² (``gain``)."""

    effect: str
    channel: int
    value: float
    sigma: float
    factor: float
    gain: float
    top: float

    def finding(self, before: float, after: float) -> Finding:
        """The finding, its evidence the scaled χ² removed and the channel's rigid misfit in the noise's units
        (reduced χ² of its row) ``before`` and ``after`` the factor is undone."""
        effect = named(self.effect)
        parameters = {**effect.row_parameters(self.value, self.sigma), "top_hz": self.top}
        evidence = {"delta_chi2_lines": self.gain, "values": 1, "row_chi2_reduced": {"before": before, "after": after}}
        return Finding(self.effect, (self.channel,), None, parameters, evidence)


def least(rows: Rows, i: int, effect, grid: np.ndarray, to_p, hits=slice(None)) -> tuple[float, float]:
    """(t, χ²) at the least χ² over the search variable t (p = ``to_p``(t)) on the columns ``hits``: the best of
    ``grid``, polished by bounded Brent between its neighbours."""
    f = rows.frequencies

    def cost(t: float) -> float:
        return rows.cost(i, 1 / effect.factor(f, float(to_p(t))), hits)[0]

    k = int(np.argmin([cost(t) for t in grid]))
    best = minimize_scalar(cost, bounds=(grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]), method="bounded",
                           options={"xatol": 1e-10 * max(abs(grid[k]), 1e-12)})  # fmt: skip
    return float(best.x), float(best.fun)


def search_grid(rows: Rows, effect) -> tuple[np.ndarray, object]:
    """The grid of the search variable t over ``effect``'s range on this band, and t → p."""
    low, high, log = effect.search_range(float(rows.frequencies[-1]))
    return np.linspace(*(np.log([low, high]) if log else (low, high)), GRID), (np.exp if log else (lambda t: t))


def profile(rows: Rows, i: int, effect) -> RowFit:
    """``effect``'s p on channel ``i`` (grid over its ``search_range``, then bounded Brent) and the χ² it removes
    against none (F = 1), both with k profiled; p's 1-σ from χ²'s curvature, scaled by the fit's reduced χ²."""
    f = rows.frequencies
    grid, to_p = search_grid(rows, effect)
    t, chi2 = least(rows, i, effect, grid, to_p)
    none, _ = rows.cost(i, np.ones(len(f)))
    spread = rows.scale(chi2, 1)
    h = 1e-3 * (grid[1] - grid[0])

    def cost(t: float) -> float:
        return rows.cost(i, 1 / effect.factor(f, float(to_p(t))))[0]

    curvature = (cost(t + h) - 2 * chi2 + cost(t - h)) / h**2
    sigma_t = np.sqrt(2 * spread / curvature) if curvature > 0 else np.nan
    value = float(to_p(t))
    sigma = float(value * sigma_t if to_p is np.exp else sigma_t)
    factor = rows.cost(i, 1 / effect.factor(f, value))[1]
    return RowFit(effect.name, i, value, sigma, factor, (none - chi2) / spread, float(f[-1]))


def with_jackknife(rows: Rows, fit: RowFit) -> RowFit:
    """``fit`` with the spread of p leaving each hit out in turn (jackknife) added to its 1-σ: what the lines'
    other misfits lend p (an elastic tail on that row: a 146 Hz mount on the plate read 156 ± 1.4 Hz from the
    curvature alone, ± 13 Hz with the jackknife)."""
    n_e = rows.y.shape[1]
    if n_e < 3:
        return fit
    effect = named(fit.effect)
    grid, to_p = search_grid(rows, effect)
    left = np.array([least(rows, fit.channel, effect, grid, to_p, np.arange(n_e) != j)[0] for j in range(n_e)])
    log = to_p is np.exp
    t = np.log(fit.value) if log else fit.value
    sigma_t = fit.sigma / fit.value if log else fit.sigma
    sigma_t = np.sqrt(sigma_t**2 + (n_e - 1) / n_e * np.sum((left - left.mean()) ** 2))
    return replace(fit, sigma=float(np.exp(t) * sigma_t if log else sigma_t))


def checked(band: BandData, layout: Layout) -> bool:
    """Whether the rows can be checked: every FRF on every line, and more channels than rigid motions plus one."""
    return bool(np.isfinite(band.frf).all()) and len(layout.sensors) > (3 if layout.planar else 6) + 1


def accepted(fit: RowFit, n_values: int) -> bool:
    """The diagnosis's criterion: the scaled χ² removed beyond ``EVIDENCE`` + ln n, p finite with a finite 1-σ."""
    return fit.gain > EVIDENCE + np.log(n_values) and np.isfinite(fit.sigma) and fit.sigma > 0


def row_misfit(rows: Rows, i: int) -> float:
    """Channel ``i``'s rigid misfit over the band's lines in the noise's units: Σ_jf |r_ijf|²/α_j over its 2 n_e n_f
    values (the leave-one-out residual's reduced χ²; ≈ 1 for a channel that reads its point as the others do)."""
    return float(np.sum(np.abs(rows.r[i]) ** 2 / rows.alpha[i][:, None]) / (2 * rows.r[i].size))


def loco_ratio(rows: Rows, i: int) -> np.ndarray:
    """ρ_i(f) (n_f,): channel ``i``'s row against the rigid motion the other channels see at each line (the
    leave-one-out prediction y − r/α), weighted over the hits."""
    y, r, a = rows.y[i], rows.r[i], rows.alpha[i][:, None]
    predicted = y - r / a
    return np.sum(np.conj(predicted) * y, axis=0) / np.sum(np.abs(predicted) ** 2, axis=0)


def unexplained_row(fit: RowFit, rows: Rows, before: float) -> Finding:
    """The ``unexplained`` finding of a row a library-free shape explains and no effect of the library does:
    its channel, the shape's signature and the lines' evidence."""
    f = rows.frequencies
    signature = {"signature": fit.effect, "frequencies_hz": [float(f[0]), float(f[-1])],
                 "delay_s" if fit.effect == "phase_linear" else "resonance_hz": fit.value}  # fmt: skip
    parameters = {"hits": [], "shape": "in_frequency", "also_channels": [], "also_hits": [], "signature": signature}
    evidence = {"chi2_reduced": before, "dof": float(2 * rows.r[fit.channel].size), "withdrawn": [], "outfitted": [],
                "delta_chi2_lines": fit.gain}  # fmt: skip
    return Finding("unexplained", (fit.channel,), None, parameters, evidence)


def row_findings(band: BandData, layout: Layout) -> tuple[list, list]:
    """The row effects of the registry the band's lines prove, one channel at a time, the most evident first (each
    channel's best, then the others again on the band with it undone), and the rows a library-free shape
    (:data:`.signature.FREQUENCY_SHAPES`) explains better than any effect by more than ``EVIDENCE``: those are
    ``unexplained``, with the shape's signature (a delay's phase is no mount's rise)."""
    found, left = [], []
    if not checked(band, layout):
        return found, left
    n_values = 2 * band.frf.size
    for _ in range(MOST_ROWS):
        rows = Rows.of(band, layout)
        done = {c for f in found + left for c in f.channels}
        fits = [profile(rows, i, e) for i in range(len(layout.sensors)) if i not in done
                for e in modelled("row") + FREQUENCY_SHAPES]  # fmt: skip
        passing = [f for f in fits if accepted(f, n_values)]
        if not passing:
            break
        channel = max(passing, key=lambda f: f.gain).channel
        here = sorted((f for f in passing if f.channel == channel), key=lambda f: -f.gain)
        effects = [f for f in here if f.effect not in {s.name for s in FREQUENCY_SHAPES}]
        best = effects[0] if effects and effects[0].gain > here[0].gain - EVIDENCE else here[0]
        factor = named(best.effect) if best in effects else next(s for s in FREQUENCY_SHAPES if s.name == best.effect)
        before = row_misfit(rows, channel)
        band = BandData(band.frequencies, band.frf.copy())
        band.frf[channel] /= factor.factor(band.frequencies, best.value)
        if best not in effects:
            left.append(unexplained_row(best, rows, before))
            continue
        found.append(with_jackknife(rows, best).finding(before, row_misfit(Rows.of(band, layout), channel)))
    return found, left


def chains_undone(recording, low: float, high: float, layout: Layout) -> tuple[list, list, object]:
    """The row effects the lines of ``recording`` between ``low`` and ``high`` Hz prove and the rows no effect
    explains (:func:`row_findings`), and the recording with the effects undone, on which the rest of the diagnosis
    searches."""
    f = recording.frequencies
    found, left = row_findings(BandData.from_recording(f, recording.frf, low, high), layout)
    return found, left, corrected(recording, found)
