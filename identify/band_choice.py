"""The massline band chosen by the model: the candidate band whose masslines give the smallest predicted
uncertainty of the properties, among those that the band fit explains.

The resonance-free stretch (:func:`.band.stretch`) bounds the search: from ``MARGIN`` above where the
support's resonances leave the massline to ``MARGIN`` below where the elastic modes do. Inside it, candidate bands start at 1–5 × their lower margin and
end at 1–5 × below their upper one. For each, every FRF is fitted with its massline and tails
(:func:`.massline_fit.solve`, from sums over the runs of lines between candidate edges, which the
candidates share), and

* the predicted covariance of the properties is the inverse information Σ g_ij g_ijᵀ/σ_ij², with g_ij the
  sensitivity of massline ij at the start body and σ_ij its band-fit 1-σ (DESIGN.md, "Information"); the
  score is its trace in scaled parameters;
* the band is *explained* when each tail's next term (B₂/ω⁴, D₂ω⁶) leaves its masslines in place to the
  noise: the mean over FRFs of (A_ij − A⁺_ij)²/(σ⁺_ij² − σ_ij²) at most ``AGREEMENT``, A⁺ and σ⁺ from the
  richer fit. A band reaching so close to a resonance that the fitted tails are truncated moves its
  masslines when the next term is let in, and is passed over.

The most conservative candidate (farthest from both resonances) is the fallback when none is explained,
and gives the start body whose sensitivities score the others.
"""

from __future__ import annotations

import numpy as np

from massline.identify.band import MIN_LINES, stretch
from massline.identify.massline_fit import LineSums, Solution, line_sums, line_weights, solve
from massline.placement.band import Band
from massline.placement.errors import MasslineError
from massline.placement.information import sensitivities
from massline.placement.lines import Lines
from massline.placement.masslines import Masslines
from massline.placement.methods import starting_body
from massline.placement.model import RigidModel

STEPS = (1.0, 1.5, 2.0, 3.0, 5.0)  # candidate edges: these factors inside the stretch's margins
MARGIN = 1.25  # the search keeps this factor clear of the resonances that bound the stretch
AGREEMENT = 2.0  # mean normalised squared shift of the masslines when each tail's next term is fitted


def candidates(frequencies: np.ndarray, stretch: Band) -> list[tuple[float, float]]:
    """(low, high) Hz of every candidate band inside the stretch, each with at least MIN_LINES lines."""
    f = frequencies
    bottom = max(stretch.suspension_top * MARGIN if np.isfinite(stretch.suspension_top) else f[0], f[0])
    top = min(stretch.first_elastic / MARGIN if np.isfinite(stretch.first_elastic) else f[-1], f[-1])
    pairs = [(bottom * a, top / b) for a in STEPS for b in STEPS]
    return [(lo, hi) for lo, hi in pairs if hi > 1.2 * lo and np.count_nonzero((f >= lo) & (f <= hi)) >= MIN_LINES]


def conservative(pairs: list[tuple[float, float]]) -> tuple[float, float]:
    """The candidate farthest from both resonances: the largest of its two margins' smaller one."""
    low0, high0 = min(p[0] for p in pairs), max(p[1] for p in pairs)
    return max(pairs, key=lambda p: (min(p[0] / low0, high0 / p[1]), np.log(p[1] / p[0])))


def candidate_sums(
    frequencies: np.ndarray, frf: np.ndarray, weights, pairs: list[tuple[float, float]]
) -> dict[tuple[float, float], LineSums]:
    """Every candidate band's sums in its own x = ω²/ω_mid² (ω_mid² = ω_first ω_last of its lines), added up
    from the runs of lines between consecutive candidate edges (low ≤ f ≤ high)."""
    f = frequencies
    cuts = sorted({lo for lo, _ in pairs} | {np.nextafter(hi, np.inf) for _, hi in pairs})
    omega2 = (2 * np.pi * f) ** 2
    reference = np.sqrt(omega2[f >= cuts[0]].min() * omega2[f < cuts[-1]].max())
    runs = []
    for lo, hi in zip(cuts[:-1], cuts[1:]):
        keep = (f >= lo) & (f < hi)
        H = frf[:, :, keep].reshape(-1, int(keep.sum()))
        runs.append(line_sums(omega2[keep] / reference, H, line_weights(weights, keep, H.shape)))
    sums = {}
    for lo, hi in pairs:
        first, last = cuts.index(lo), cuts.index(np.nextafter(hi, np.inf))
        kept = 2 * np.pi * f[(f >= lo) & (f <= hi)]
        sums[lo, hi] = sum(runs[first + 1 : last], runs[first]).rescaled(reference / (kept[0] * kept[-1]))
    return sums


def predicted_spread(fit: Solution, G: np.ndarray) -> float:
    """trace F⁻¹ in scaled parameters, F = Σ g_ij g_ijᵀ / σ_ij² (inf when singular); G (n_fr, p) the g_ij."""
    sigma = np.maximum(fit.std, 1e-12 * np.abs(fit.real[:, 0]).max())
    F = (G / sigma[:, None]).T @ (G / sigma[:, None])
    try:
        return float(np.trace(np.linalg.inv(F)))
    except np.linalg.LinAlgError:
        return np.inf


def agreement(fit: Solution, richer: Solution) -> float:
    """Mean over FRFs of (A − A⁺)²/(σ⁺² − σ²): how far each tail's next term moves the masslines, against
    what noise alone moves them by (the variance of a difference between nested least-squares fits)."""
    variance = np.maximum(richer.std**2 - fit.std**2, 0.05 * richer.std**2)
    return float(np.mean((fit.real[:, 0] - richer.real[:, 0]) ** 2 / np.maximum(variance, 1e-300)))


def choose_band(
    frequencies: np.ndarray, frf: np.ndarray, sensors: Lines, exciters: Lines, planar: bool, weights=None
) -> Band:
    """The band with the smallest predicted spread of the properties among the explained candidates.

    ``frequencies`` (Hz), ``frf`` (n_s, n_e, n_f) accelerance, ``weights`` the lines' coherence weights or
    None. Raises MasslineError when the stretch holds no candidate of MIN_LINES lines.
    """
    free = stretch(frequencies, frf)
    pairs = candidates(frequencies, free)
    if not pairs:
        raise MasslineError(
            f"no massline band found: the widest resonance-free stretch, {free.low:.3g}–{free.high:.3g} Hz, "
            f"holds fewer than {MIN_LINES} lines clear of its resonances; soften the support, record more lines, "
            "or give --band LO HI"
        )
    safe = conservative(pairs)
    sums = candidate_sums(frequencies, frf, weights, pairs)
    reference = solve(sums[safe])
    try:
        values = reference.real[:, 0].reshape(frf.shape[:2])
        model = RigidModel(starting_body(Masslines(values, sensors, exciters), planar), planar)
    except (MasslineError, np.linalg.LinAlgError):
        return Band(*safe, free.suspension_top, free.first_elastic, "chosen")
    G = sensitivities(model, model.coordinates(sensors), model.coordinates(exciters))[0]
    G = G.reshape(-1, G.shape[-1])
    best, best_spread = safe, np.inf
    for pair in pairs:
        fit = reference if pair == safe else solve(sums[pair])
        spread = predicted_spread(fit, G)
        if spread < best_spread and agreement(fit, solve(sums[pair], richer=True)) <= AGREEMENT:
            best, best_spread = pair, spread
    return Band(*best, free.suspension_top, free.first_elastic, "chosen")
