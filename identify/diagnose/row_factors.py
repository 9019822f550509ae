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

quadratic in k, profiled over p on a grid and finer grids about its least (:func:`profile`). p's 1-σ comes from
the curvature, scaled by √(χ²/dof) where the fit leaves more than the noise (correlated lines, elastic tails). The effect is
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

from massline.identify.diagnose.criterion import EVIDENCE  # the diagnosis's one criterion, on a channel's factor
from massline.identify.diagnose.effect_model import Layout
from massline.identify.diagnose.corrections import corrected
from massline.identify.diagnose.effects import modelled, named
from massline.identify.diagnose.finding import Finding
from massline.identify.diagnose.screens import kinematic_matrix
from massline.identify.diagnose.signature import FREQUENCY_SHAPES
from massline.identify.tails import BandData

GRID = 61  # values of p tried before polishing
ZOOM, ZOOMS = 21, 3  # each polish's values between the best's neighbours, and how many polishes (step ÷ 1000)
SIZED = 2.0  # a factor named must depart from 1 at the band's top by this many of its 1-σ (``with_spread``'s)
MOST_ROWS = 3  # channels one recording's chains are corrected on before the rest is left to the other stages
SWEEPS = 6  # refits of several rows, each with the others undone
ALIKE = 0.9  # |cos| between two channels' residual directions beyond which a factor on one reads as on the other


def line_noise(frf: np.ndarray) -> np.ndarray:
    """σ_ij (n_s, n_e): the noise of one real component of one line, from second differences along the lines,
    E|Δ²n|² = 6 E|n|² for white noise, where a smooth trend (a tail, a delay, a mount) cancels. Read from their
    median (|Δ²n|² of complex normal noise is exponential: median = ln 2 × mean), so that the few lines a hum
    leaves beside those set aside, or a resonance's, do not lift it."""
    second = frf[..., :-2] - 2 * frf[..., 1:-1] + frf[..., 2:]
    return np.sqrt(np.median(np.abs(second) ** 2, axis=-1) / np.log(2) / 12)


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

    def cost(self, i: int, inverse: np.ndarray, hits=slice(None)) -> tuple[np.ndarray, np.ndarray]:
        """min over k of χ²(k) with row ``i`` times k / F (``inverse`` (…, n_f): 1/F at the lines, for any number of
        factors at once), and that k; over the columns ``hits`` (default all). With c = k z − y, z = y/F, and the
        sums over the hits done first (F is the row's, the same for every hit):
        χ² = χ²₀ + k²Σ_f |1/F|² w + 2k Σ_f Re((1/F)* (v − w)) + Σ(α|y|² − 2 Re ȳr),
        w_f = Σ_j α_j |y_jf|², v_f = Σ_j ȳ_jf r_jf."""
        y, r, a = self.y[i, hits], self.r[i, hits], self.alpha[i, hits][:, None]
        w = np.sum(a * np.abs(y) ** 2, axis=0)
        v = np.sum(np.conj(y) * r, axis=0)
        inverse = np.asarray(inverse)
        zz = np.abs(inverse) ** 2 @ w
        cross = np.real(np.conj(inverse) @ (w - v))
        k = cross / np.maximum(zz, 1e-300)
        rest = np.sum(np.abs(self.r[:, hits]) ** 2) + np.sum(w) - 2 * np.sum(np.real(v))
        return rest + k**2 * zz - 2 * k * cross, k

    def scale(self, chi2: float, values: int) -> float:
        """max(χ²/dof, 1) of a fit with ``values`` more values: the noise as the fit leaves it."""
        return max(chi2 / max(self.dof - values, 1), 1.0)


@dataclass(frozen=True)
class RowFit:
    """One effect's factor fitted on one channel's row: p and its 1-σ, the gain k profiled with it, the χ² it
    removes scaled by the fit's reduced χ² (``gain``), and the band's top and lowest lines (Hz)."""

    effect: str
    channel: int
    value: float
    sigma: float
    factor: float
    gain: float
    top: float
    low: float

    def finding(self, before: float, after: float) -> Finding:
        """The finding, its evidence the scaled χ² removed and the channel's rigid misfit in the noise's units
        (reduced χ² of its row) ``before`` and ``after`` the factor is undone."""
        effect = named(self.effect)
        shape = {"signature": effect.signature, "frequencies_hz": [float(self.low), self.top],
                 "delay_s" if effect.signature == "phase_linear" else "resonance_hz": self.value}  # fmt: skip
        parameters = {**effect.row_parameters(self.value, self.sigma), "top_hz": self.top, "signature": shape}
        evidence = {"delta_chi2_lines": self.gain, "values": 1, "row_chi2_reduced": {"before": before, "after": after}}
        return Finding(self.effect, (self.channel,), None, parameters, evidence)


def least(rows: Rows, i: int, effect, grid: np.ndarray, to_p, hits=slice(None)) -> tuple[float, float]:
    """(t, χ²) at the least χ² over the search variable t (p = ``to_p``(t)) on the columns ``hits``: the best of
    ``grid``, then ``ZOOMS`` finer grids between its neighbours."""
    f = rows.frequencies

    def costs(ts: np.ndarray) -> np.ndarray:
        return rows.cost(i, 1 / effect.factor(f[None], to_p(ts)[:, None]), hits)[0]

    ts = grid
    for _ in range(ZOOMS + 1):
        chi2 = costs(ts)
        k = int(np.argmin(chi2))
        best = (float(ts[k]), float(chi2[k]))
        ts = np.linspace(ts[max(k - 1, 0)], ts[min(k + 1, len(ts) - 1)], ZOOM)
    return best


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

    around = rows.cost(i, 1 / effect.factor(f[None], to_p(np.array([t - h, t + h]))[:, None]))[0]
    curvature = (around.sum() - 2 * chi2) / h**2
    sigma_t = np.sqrt(2 * spread / curvature) if curvature > 0 else np.nan
    value = float(to_p(t))
    sigma = float(value * sigma_t if to_p is np.exp else sigma_t)
    factor = float(rows.cost(i, 1 / effect.factor(f, value))[1])
    return RowFit(effect.name, i, value, sigma, factor, float(none - chi2) / spread, float(f[-1]), float(f[0]))


def with_spread(rows: Rows, fit: RowFit) -> RowFit:
    """``fit`` with its 1-σ grown by the hits' disagreement (Birge's ratio): p fitted on each hit's FRFs alone, each
    with its curvature's 1-σ; where they differ by more than those allow, χ² over n_e − 1 degrees of freedom, the
    lines' other misfits lend p something (an elastic tail on that row: a 146 Hz mount on the plate read 156 ± 1.4
    Hz from the curvature alone), and the 1-σ of p from all hits grows by √(χ²/dof). A hit that barely sees the row
    weighs little: leaving out the one hit that does (a jackknife) had read the structure's channel 8 as 230 ± 114
    Hz, and left it unnamed."""
    effect, f = model_of(fit.effect), rows.frequencies
    grid, to_p = search_grid(rows, effect)
    log = to_p is np.exp
    h = 1e-3 * (grid[1] - grid[0])
    ts, weights = [], []
    for j in range(rows.y.shape[1]):
        t, chi2 = least(rows, fit.channel, effect, grid, to_p, [j])
        around = rows.cost(fit.channel, 1 / effect.factor(f[None], to_p(np.array([t - h, t + h]))[:, None]), [j])[0]
        curvature = (around.sum() - 2 * chi2) / h**2
        if curvature > 0:
            ts.append(t), weights.append(curvature / 2)
    if len(ts) < 2:
        return fit
    ts, weights = np.array(ts), np.array(weights)
    mean = np.sum(weights * ts) / np.sum(weights)
    birge = np.sqrt(max(np.sum(weights * (ts - mean) ** 2) / (len(ts) - 1), 1.0) / np.sum(weights))
    sigma_t = max(fit.sigma / fit.value if log else fit.sigma, birge)
    return replace(fit, sigma=float(fit.value * sigma_t if log else sigma_t))


def checked(band: BandData, layout: Layout) -> bool:
    """Whether the rows can be checked: every FRF on every line, and more channels than rigid motions plus one."""
    return bool(np.isfinite(band.frf).all()) and len(layout.sensors) > (3 if layout.planar else 6) + 1


def accepted(fit: RowFit, n_values: int) -> bool:
    """The diagnosis's criterion: the scaled χ² removed beyond ``EVIDENCE`` + ln n, p finite with a finite 1-σ."""
    return fit.gain > EVIDENCE + np.log(n_values) and np.isfinite(fit.sigma) and fit.sigma > 0


def constant_evidence(rows: Rows, i: int) -> float:
    """The scaled χ² a constant factor k on channel ``i`` removes (a gain, a calibration, a sign)."""
    none, _ = rows.cost(i, np.ones(len(rows.frequencies)))
    return float(rows.chi2 - none) / rows.scale(none, 1)


def a_gain_first(rows: Rows, passing: list) -> bool:
    """Whether a constant factor on some channel is more evident, by ``EVIDENCE``, than every factor of frequency
    with its own constant (:attr:`RowFit.gain` is beyond the constant): the misfit is first a gain's, which the
    block search names. While it is in the lines, it bends the rigid motion every other row is read against by
    the FRFs' own shape (the elastic tails' rise): the demo's 10.9 % gain on the structure's channel 12 lent
    channel 7 a "750 ± 50 Hz mount" (its row 11.32× → 11.25× the noise) and channel 2 an "18 ± 2 µs delay"."""
    constant = [constant_evidence(rows, i) for i in range(rows.y.shape[0])]
    shaped = [constant[f.channel] + f.gain for f in passing]
    return max(constant) > max(shaped, default=0.0) + EVIDENCE


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


def model_of(name: str):
    """The factor a fit was made with: a row effect of the registry, or a library-free shape."""
    shapes = {shape.name: shape for shape in FREQUENCY_SHAPES}
    return shapes[name] if name in shapes else named(name)


def sized(fit: RowFit) -> bool:
    """Whether the factor's own departure at the band's top — a rise's magnitude, ln|F|, or a delay's phase, arg F —
    lies ``SIZED`` of its 1-σ from none (p ± σ propagated on the scale p was searched on). The plate's elastic tails
    lent a "mount at 456 ± 1170 Hz" a rise of 0.3 % there; a mount far above the band is all phase (−2ζf/f_m) and
    no rise, a delay's likeness, and is no mount named (a 73 µs delay, the delay out of the registry, had been
    named a 306 ± 100 Hz mount); the concealed 55 Hz mount read 55.5 ± 4.0."""
    model, top = model_of(fit.effect), np.array([fit.top])
    searched = model.search_range(fit.top)
    high, low = (fit.value * np.exp(fit.sigma / fit.value * np.array([1, -1])) if searched[2]
                 else fit.value + fit.sigma * np.array([1, -1]))  # fmt: skip
    part = np.imag if getattr(model, "signature", model.name) == "phase_linear" else np.real

    def departure(p: float) -> float:
        return float(part(np.log(model.factor(top, p)[0])))

    spread = abs(departure(high) - departure(low)) / 2
    return bool(np.isfinite(spread) and abs(departure(fit.value)) > SIZED * spread)


def alike(layout: Layout) -> np.ndarray:
    """(n_s, n_s) bool: channels whose residual directions (I − SS⁺)e_i are within ``ALIKE`` of parallel — a factor
    on one is read nearly as well as the opposite factor on the other (the plate's channels 2–4: 0.96–0.99)."""
    S = kinematic_matrix(layout.sensors, layout.planar)
    residual = np.eye(len(S)) - S @ np.linalg.pinv(S)
    unit = residual / np.sqrt(np.maximum(np.diag(residual), 1e-300))[None]
    return np.abs(unit.T @ unit) > ALIKE


def chosen(rows: Rows, passing: list, layout: Layout) -> RowFit | None:
    """Of the fits that pass the criterion, channel by channel from the most evident: those within ``EVIDENCE`` of
    the channel's best (the data cannot tell them apart), the effects of the library first, then the library-free
    shapes, each in order of evidence; the first whose size its 1-σ (:func:`with_spread`) proves (:func:`sized`). A channel
    with none is undecided, and so is every channel whose residual direction is like its (:func:`alike`): no less
    evident name is given where the misfit may be the undecided channel's (a 146 Hz mount read 143 ± 27 Hz beside a
    delay elsewhere, and a delay a third as evident had been named there; a plate's 80 µs delay on channel 3,
    unsized beside the body's elastic tail, left a −49 µs "delay" on channel 2). A 64 µs delay's row is fitted as
    well by a "362 ± 130 Hz mount", the body's elastic tail lending it its rise: within ``EVIDENCE``, the delay,
    sized, is chosen."""
    shapes, similar = {shape.name for shape in FREQUENCY_SHAPES}, alike(layout)
    while passing:
        channel = max(passing, key=lambda f: f.gain).channel
        here = sorted((f for f in passing if f.channel == channel), key=lambda f: -f.gain)
        close = [f for f in here if f.gain > here[0].gain - EVIDENCE]
        for pick in [f for f in close if f.effect not in shapes] + [f for f in close if f.effect in shapes]:
            fit = with_spread(rows, pick)
            if sized(fit):
                return fit
        passing = [f for f in passing if not similar[channel, f.channel]]
    return None


def undone_rows(band: BandData, fits: list) -> BandData:
    """The band with each fit's factor undone on its row."""
    frf = band.frf.copy()
    for fit in fits:
        frf[fit.channel] /= model_of(fit.effect).factor(band.frequencies, fit.value)
    return BandData(band.frequencies, frf)


def settled(band: BandData, layout: Layout, fits: list) -> list:
    """The fits, each taken out in turn and chosen again (:func:`chosen`) on the band with the others undone, until
    none changes its channel, its effect or its value by a tenth of its 1-σ (``SWEEPS`` at most); a fit nothing
    replaces is dropped. The first of two faulty rows is chosen while the second still bends the rigid motion the
    others see: on the bracket delays of 172 and 141 µs on channels 8 and 1 were first read as −91 µs on channel 2
    (whose residual direction is much like channel 1's), 88 µs on 8 and −30 µs on 5; two mounts at 83 and 94 Hz on
    the plate as 118 ± 14 and 112 Hz."""
    n_values = 2 * band.frf.size
    for _ in range(SWEEPS):
        changed, k = False, 0
        while k < len(fits):
            rest = fits[:k] + fits[k + 1 :]
            rows = Rows.of(undone_rows(band, rest), layout)
            again = chosen(rows, [f for f in trials(rows, layout, {f.channel for f in rest}) if accepted(f, n_values)],
                           layout)
            if again is None:
                fits, changed = rest, True
                continue
            same = (again.channel, again.effect) == (fits[k].channel, fits[k].effect)
            changed = changed or not same or abs(again.value - fits[k].value) > 0.1 * fits[k].sigma
            fits, k = rest[:k] + [again] + rest[k:], k + 1
        if not changed:
            break
    return fits


def trials(rows: Rows, layout: Layout, done: set) -> list:
    """Every row effect of the registry and every library-free shape fitted at every channel not in ``done``."""
    return [profile(rows, i, e) for i in range(len(layout.sensors)) if i not in done
            for e in modelled("row") + FREQUENCY_SHAPES]  # fmt: skip


def row_findings(band: BandData, layout: Layout) -> tuple[list, list]:
    """The row effects of the registry the band's lines prove, one channel at a time, the most evident first (each
    channel's best, then the others again on the band with it undone; when several, :func:`settled`), and the rows a library-free shape (:data:`.signature.FREQUENCY_SHAPES`) explains better than
    any effect by more than ``EVIDENCE``: those are ``unexplained``, with the shape's signature (a delay's phase is
    no mount's rise)."""
    if not checked(band, layout):
        return [], []
    n_values, fits = 2 * band.frf.size, []
    for _ in range(MOST_ROWS):
        rows = Rows.of(undone_rows(band, fits), layout)
        passing = [f for f in trials(rows, layout, {f.channel for f in fits}) if accepted(f, n_values)]
        best = None if a_gain_first(rows, passing) else chosen(rows, passing, layout)
        if best is None:
            break
        fits.append(best)
    fits = settled(band, layout, fits) if len(fits) > 1 else fits
    found, left, shapes = [], [], {shape.name for shape in FREQUENCY_SHAPES}
    for fit in fits:
        rows = Rows.of(undone_rows(band, [f for f in fits if f is not fit]), layout)
        before, after = row_misfit(rows, fit.channel), row_misfit(Rows.of(undone_rows(band, fits), layout), fit.channel)
        if fit.effect in shapes:
            left.append(unexplained_row(fit, rows, before))
        else:
            found.append(fit.finding(before, after))
    return found, left


def chains_undone(recording, low: float, high: float, layout: Layout) -> tuple[list, list, object]:
    """The row effects the lines of ``recording`` between ``low`` and ``high`` Hz prove and the rows no effect
    explains (:func:`row_findings`), and the recording with the effects undone, on which the rest of the diagnosis
    searches."""
    f = recording.frequencies
    found, left = row_findings(BandData.from_recording(f, recording.frf, low, high), layout)
    return found, left, corrected(recording, found)
