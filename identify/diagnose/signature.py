"""The misfit's signature in frequency: what a place's complex residual ratio over the band's lines looks like.

A place (a channel's row, a hit's column) reads ρ(f) times what the rigid body predicts there. The physics
that makes each signature:

* ``constant``: ρ = c, one factor at every line — a gain, a calibration, a sign, a moved or tilted line (the
  rigid body's own massline, read otherwise);
* ``phase_linear``: ρ = c e^{−2πifτ}, a phase growing in proportion to f — a delay or an anti-alias filter
  that differs (a massline is real: a phase ∝ f is the acquisition chain's);
* ``rising``: ρ = c / (1 − (f/f_b)² + 2iζf/f_b), a magnitude rising towards a resonance above the band, its
  phase lagging — a mount (wax, a magnet, adhesive) resonating, not the body (whose elastic tails are real);
* ``narrow``: the misfit held by a few lines around f₀ — a resonance that is not the body's (something attached
  or loose), a tone;
* ``column_ripple``: ρ = c (1 + a cos 2πfT + b sin 2πfT) along one hit's column — a ripple in that hit's force
  record (a double hit, a ringing tip, a window that cuts the force);
* ``spread``: no one place holds it, or no shape above fits it.

:func:`classify` fits each shape to ρ by weighted least squares (σ of ρ from its lines' second differences,
where a smooth trend cancels) and keeps the least BIC (χ² + k ln n); ``narrow`` when most of what the best
smooth shape leaves sits within a tenth of the band. (A ratio alone carries the body's own elastic tails too:
rows are weighed on their rigid misfit instead, :mod:`.misfit_signatures`.) Pure functions of arrays: the places'
ratios are taken in
:mod:`.row_factors` (a row against the others' rigid motion) and in the pipeline (a column against identify's
masslines).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.core.numbers import formatted

GRID = 61  # values of τ, f_b or T tried
NARROW = 0.1  # share of the band's lines a narrow misfit sits within
HELD = 0.6  # share of the excess χ² those lines must hold
DAMPED = 0.05  # ζ of the rising shape a row is fitted with: a resonance of an attachment, which lags in phase (the
# body's elastic tails, lightly damped, are real: undamped, the shape took the plate's clean rows at χ² 26)
CHANCE = 3.0  # a shape fits within chance when its χ² is within this many of its standard deviations of the dof


@dataclass(frozen=True)
class Shape:
    """A signature's factor of frequency F(f; p), as the row fit takes an effect's (:mod:`.row_factors`)."""

    name: str

    def factor(self, frequencies: np.ndarray, value: float) -> np.ndarray:
        f = np.asarray(frequencies, dtype=float)
        if self.name == "phase_linear":
            return np.exp(-2j * np.pi * f * value)
        u = f / value
        return 1 / (1 - u**2 + 2j * DAMPED * u)

    def search_range(self, top: float) -> tuple[float, float, bool]:
        """(low, high, logarithmic) of p on a band whose top line is ``top`` Hz: a delay to a quarter period there,
        a resonance from just above it to a hundred times it."""
        return (-0.25 / top, 0.25 / top, False) if self.name == "phase_linear" else (1.05 * top, 100 * top, True)


FREQUENCY_SHAPES = (Shape("phase_linear"), Shape("rising"))
"""The library-free shapes a channel's chain can read its row through (no effect's physics claimed)."""


def ratio_noise(ratio: np.ndarray) -> float:
    """σ of one real component of ρ at one line, from its second differences (E|Δ²n|² = 6 E|n|²)."""
    second = ratio[:-2] - 2 * ratio[1:-1] + ratio[2:]
    return float(np.sqrt(np.mean(np.abs(second) ** 2) / 12))


def residual(design: np.ndarray, ratio: np.ndarray) -> np.ndarray:
    """ρ − D a at the complex least-squares a (design (n, k))."""
    return ratio - design @ np.linalg.lstsq(design, ratio, rcond=None)[0]


def best_over(grid: np.ndarray, design, ratio: np.ndarray) -> tuple[np.ndarray, float, float]:
    """(residual, complex values, p) of the least Σ|ρ − D(p) a|² over ``grid`` (p itself: half a complex value)."""
    left = [residual(design(p), ratio) for p in grid]
    k = int(np.argmin([np.sum(np.abs(r) ** 2) for r in left]))
    return left[k], design(grid[k]).shape[1] + 0.5, float(grid[k])


def shape_costs(f: np.ndarray, ratio: np.ndarray, column: bool) -> dict:
    """Each shape's (residual (n,), complex values it is fitted with, p) fitted to ρ (a constant factor c in each)."""
    one = np.ones((len(f), 1))
    top, span = f[-1], f[-1] - f[0]
    costs = {"constant": (residual(one, ratio), 1, np.nan)}
    delays = np.linspace(-0.25 / top, 0.25 / top, GRID)
    costs["phase_linear"] = (*best_over(delays, lambda t: np.exp(-2j * np.pi * f * t)[:, None], ratio), )
    poles = np.exp(np.linspace(np.log(1.05 * top), np.log(100 * top), GRID))
    costs["rising"] = best_over(poles, lambda p: (1 / (1 - (f / p) ** 2))[:, None], ratio)
    if column:
        periods = span / np.linspace(1.5, max(len(f) / 8, 2.0), GRID)

        def ripple(T):
            return np.column_stack([one[:, 0], np.cos(2 * np.pi * f / T), np.sin(2 * np.pi * f / T)])

        left, k, period = best_over(periods, ripple, ratio)
        costs["column_ripple"] = (left, k, period)
    return costs


def narrow_at(f: np.ndarray, residual2: np.ndarray, excess: float) -> float | None:
    """f₀ (Hz) of the window of ``NARROW`` of the lines holding at least ``HELD`` of the ``excess`` χ² (None)."""
    width = max(3, int(NARROW * len(f)))
    held = np.convolve(residual2 - 2.0, np.ones(width), mode="valid")
    k = int(np.argmax(held))
    return float(f[k + width // 2]) if excess > 0 and held[k] >= HELD * excess else None


def classify(frequencies: np.ndarray, ratio: np.ndarray, column: bool = False) -> dict:
    """The signature of a place's complex ratio ``ratio`` (n,) over ``frequencies`` (Hz): {"signature": name,
    "frequencies_hz": [lo, hi]} with the shape's parameter (``delay_s``, ``resonance_hz``, ``period_hz``) or, when
    narrow, its ``hz``; ``column``: the place is a hit's column (a ripple may be its force record's)."""
    f = np.asarray(frequencies, dtype=float)
    ratio = np.asarray(ratio, dtype=complex)
    sigma2 = max(ratio_noise(ratio), 1e-300) ** 2
    n = 2 * len(f)
    costs = shape_costs(f, ratio, column)
    bic = {name: np.sum(np.abs(r) ** 2) / sigma2 + 2 * k * np.log(n) for name, (r, k, _) in costs.items()}
    name = min(bic, key=bic.get)
    out = {"signature": name, "frequencies_hz": [float(f[0]), float(f[-1])]}
    left = np.abs(costs[name][0]) ** 2 / sigma2
    dof = n - 2 * costs[name][1]
    if left.sum() > dof + CHANCE * np.sqrt(2 * dof):  # the best shape leaves more than chance: narrow?
        f0 = narrow_at(f, left, left.sum() - dof)
        if f0 is not None:
            return {**out, "signature": "narrow", "hz": f0}
    key = {"phase_linear": "delay_s", "rising": "resonance_hz", "column_ripple": "period_hz"}.get(name)
    return {**out, key: costs[name][2]} if key else out


def phrase(signature: dict) -> str:
    """The signature as an engineer reads it."""
    lo, hi = signature["frequencies_hz"]
    name = signature["signature"]
    if name == "phase_linear":
        degrees = formatted(-360 * hi * signature["delay_s"], "+.1f")
        return f"a phase growing with frequency ({degrees}° at {hi:.0f} Hz: a delay or a filter)"
    if name == "rising":
        near = signature["resonance_hz"]
        return f"a magnitude rising towards a resonance near {near:.0f} Hz above the band (a mount)"
    if name == "narrow":
        return f"a narrow band around {signature['hz']:.1f} Hz (a resonance that is not the body's)"
    if name == "column_ripple":
        return f"a ripple along the hit's column every {signature['period_hz']:.1f} Hz (its force record)"
    if name == "constant":
        return f"one constant factor over {lo:.3g}–{hi:.3g} Hz (a gain, a calibration, a sign)"
    return f"a misfit spread over {lo:.3g}–{hi:.3g} Hz"
