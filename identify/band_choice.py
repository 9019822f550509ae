"""The massline band chosen by the model: the candidate band whose masslines give the smallest predicted
error of the properties, their scatter and the bias their truncated tails may carry.

The resonance-free stretch (:func:`.band.stretch`) bounds the search: from ``MARGIN`` above where the
support's resonances leave the massline to ``MARGIN`` below where the elastic modes do. Inside it, candidate
bands start at 1–5 × their lower margin and end at 1–5 × below their upper one. For each, every FRF is fitted
with its massline and tails (:func:`.massline_fit.solve`, the fit :func:`.massline_fit.fit_band` makes, from
sums over the runs of lines between candidate edges, which the candidates share), and the predicted mean
squared error of the scaled parameters is

    trace F⁻¹ + ‖F⁻¹ Σ g_ij δA_ij/σ_ij²‖²,     F = Σ g_ij g_ijᵀ/σ_ij²,

with g_ij the sensitivity of massline ij at the start body, σ_ij its band-fit 1-σ and δA_ij the shift that
each tail's next term may carry into it (:func:`.massline_fit.truncation_shift`). A wide band has many lines
but reaches where the tails are large; a narrow one keeps clear of them but sees few: the score weighs both.
The widest candidate gives the start body; the one farthest from both resonances is the fallback when
that body cannot be found.

Each FRF is fitted on the lines it has (:mod:`.missing_lines`): the criterion sums over the pairs a candidate
fits (a pair with no FRF, or too few lines in it, weighs 0 in F and the bias), and the start body is found from
the masslines present, the missing ones filled from a body that fits them (:func:`.missing_pairs.completed`).
"""

from __future__ import annotations

import numpy as np

from massline.identify.zones import MIN_LINES, stretch
from massline.identify.massline_fit import (
    LineSums,
    Solution,
    band_lines,
    fitted,
    line_sums,
    line_weights,
    solve,
    truncation_shift,
)
from massline.identify.missing_lines import pair_norm, present
from massline.identify.missing_pairs import completed
from massline.identify.resonances import RIGID, rigid_misfit
from massline.core.band import Band, GIVE_BAND
from massline.core.errors import MasslineError
from massline.core.information import sensitivities
from massline.core.lines import Lines
from massline.core.masslines import Masslines
from massline.core.methods import starting_body
from massline.core.model import RigidModel
from massline.core.plate import plate_coordinates

STEPS = (1.0, 1.5, 2.0, 3.0, 5.0)  # candidate edges: these factors inside the stretch's margins
GAPS = 3  # flat gaps tried, from the widest up the axis, before the fallback
MARGIN = 1.25  # the search keeps this factor clear of the resonances that bound the stretch


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
        real, imag, has = band_lines(frf, keep, weights)
        runs.append(line_sums(omega2[keep] / reference, real, imag, line_weights(weights, keep, has), has))
    sums = {}
    for lo, hi in pairs:
        first, last = cuts.index(lo), cuts.index(np.nextafter(hi, np.inf))
        kept = 2 * np.pi * f[(f >= lo) & (f <= hi)]
        sums[lo, hi] = sum(runs[first + 1 : last], runs[first]).rescaled(reference / (kept[0] * kept[-1]))
    return sums


def predicted_spread(fit: Solution, truncation: np.ndarray, G: np.ndarray) -> float:
    """Predicted mean squared error of the scaled parameters: trace F⁻¹ + ‖F⁻¹ Σ g_ij δA_ij/σ_ij²‖².

    F = Σ g_ij g_ijᵀ / σ_ij² is the information of the band's masslines (their variance, trace F⁻¹), and
    δA_ij the shift the truncation of their tails may carry (``truncation``, :func:`.truncation_shift`): the
    bias it moves the properties by. ``fit`` the band's fits of the n_fr FRFs, ``G`` (n_fr, p) the g_ij; the sums
    run over the FRFs fitted (a pair with no FRF or too few lines, NaN in ``fit``, weighs 0).
    inf when F is singular.
    """
    used = np.isfinite(fit.std)
    sigma = np.maximum(fit.std[used], 1e-12 * np.abs(fit.real[used, 0]).max(initial=0.0))
    weighted = G[used] / sigma[:, None]
    F = weighted.T @ weighted
    try:
        covariance = np.linalg.inv(F)
    except np.linalg.LinAlgError:
        return np.inf
    bias = covariance @ (weighted.T @ (truncation[used] / sigma))
    return float(np.trace(covariance) + bias @ bias)


def choose_band(
    frequencies: np.ndarray, frf: np.ndarray, sensors: Lines, exciters: Lines, planar: bool, weights=None
) -> Band:
    """The candidate band with the smallest predicted error of the properties.

    ``frequencies`` (Hz), ``frf`` (n_s, n_e, n_f) accelerance, ``weights`` the lines' coherence weights or
    None. Raises MasslineError when the stretch holds no candidate of MIN_LINES lines.
    """
    above, fallback = np.ones(len(frequencies), dtype=bool), None
    for _ in range(GAPS):
        free = stretch(frequencies[above], frf[:, :, above])
        pairs = candidates(frequencies, free)
        if not pairs:
            break
        chosen = best_candidate(frequencies, frf, pairs, sensors, exciters, planar=planar, weights=weights)
        if chosen is not None and not closed_by_support(frequencies, frf, free, sensors, exciters, planar=planar):
            return Band(*chosen, free.suspension_top, free.first_elastic, "chosen")
        fallback = fallback or Band(*(chosen or conservative(pairs)), free.suspension_top, free.first_elastic, "chosen")
        above = frequencies > free.high  # a gap below a stiff bounce: its FRFs follow a spring, not the mass
        if not np.isfinite(free.high) or np.count_nonzero(above) < MIN_LINES:
            break
    if fallback is None:
        raise MasslineError(
            f"no massline band found: the widest resonance-free stretch, {free.low:.3g}–{free.high:.3g} Hz, "
            f"holds fewer than {MIN_LINES} lines clear of its resonances; soften the support, record more "
            f"lines, or give {GIVE_BAND}"
        )
    return fallback


def closed_by_support(frequencies, frf, free: Band, sensors: Lines, exciters: Lines, *, planar: bool) -> bool:
    """Whether the resonance closing the gap ``free`` at its top is a support mode: the body moving rigidly.

    At the strongest line of Im H within 1.5 × the top, a resonance stands out of the gap's massline level
    (‖Im H‖ above ‖Re H‖ at the gap's middle; a notch in the force spectrum does not), and one rigid motion
    explains its shape at the sensors and at the hits (:func:`.resonances.rigid_misfit`, on the pairs present at
    that line). It can only tell with more sensor lines than q.
    """
    S = plate_coordinates(sensors) if planar else sensors.coordinates
    E = plate_coordinates(exciters) if planar else exciters.coordinates
    near = np.flatnonzero((frequencies >= free.high) & (frequencies <= 1.5 * free.high))
    if not np.isfinite(free.high) or len(sensors) <= S.shape[1] or not len(near):
        return False
    has = present(frf)
    imaginary = pair_norm(frf[:, :, near].imag, has[:, :, near])
    peak = near[np.argmax(imaginary)]
    middle = np.argmin(np.abs(frequencies - np.sqrt(free.low * free.high)))
    if imaginary.max() < pair_norm(frf[:, :, [middle]].real, has[:, :, [middle]])[0]:
        return False
    return rigid_misfit(frf[:, :, peak], S, E) < RIGID


def best_candidate(frequencies, frf, pairs, sensors, exciters, *, planar, weights) -> tuple[float, float] | None:
    """The candidate of least predicted error, scored at the widest candidate's body (from the masslines it fits,
    the missing ones filled); None when that body is none (no positive mass: the FRFs of the gap follow a
    spring, not a mass)."""
    widest = pairs[0]  # every other candidate lies inside it
    sums = candidate_sums(frequencies, frf, weights, pairs)
    reference = solve(sums[widest])
    values = reference.real[:, 0].reshape(frf.shape[:2])
    measured = fitted(sums[widest]).reshape(values.shape)
    if not np.isfinite(values[measured]).all():
        raise MasslineError(f"a band fit failed (overflow in the FRFs?): check the recording or give {GIVE_BAND}")
    data = Masslines(np.where(measured, values, 0.0), sensors, exciters)
    try:
        start = data if measured.all() else completed(data, measured, planar)
        model = RigidModel(starting_body(start, planar), planar)
    except (MasslineError, np.linalg.LinAlgError):
        return None
    if not model.nominal.mass > 0:
        return None
    G = sensitivities(model, model.coordinates(sensors), model.coordinates(exciters))[0]
    G = G.reshape(-1, G.shape[-1])
    fits = {pair: reference if pair == widest else solve(sums[pair]) for pair in pairs}
    return min(pairs, key=lambda pair: predicted_spread(fits[pair], truncation_shift(sums[pair], fits[pair]), G))
