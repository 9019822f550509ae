"""Pairs measured in more than one run: their masslines must agree within their noise.

The recording joins the runs' measurements of a pair (:func:`massline.uff.runs.combined`). Here each run's FRF
is fitted on the band on its own (:func:`.massline_fit.fit_band`), and the k masslines A_r with their 1-σ s_r
give χ² = Σ ((A_r − Ā)/s_r)², Ā their weighted mean, on k − 1 degrees of freedom. A pair beyond chance (at
``FALSE_ALARM`` over all repeats) changed between runs: a re-mounted sensor, a moved support, a changed
calibration. It is warned with the runs named; within noise the join is used silently.
"""

from __future__ import annotations

import numpy as np

from massline.core.chi_square import chi2_sf
from massline.identify.massline_fit import fit_band
from massline.identify.warning_codes import CodedWarning

FALSE_ALARM = 1e-3  # chance that some consistent repeat is warned, over all the recording's repeats


def disagreement(frequencies, frf: np.ndarray, low: float, high: float, weights) -> tuple[float, float, float]:
    """χ², its degrees of freedom and the spread (max − min)/min |A_r| of k runs' masslines (``frf`` (k, n_f))."""
    fit = fit_band(frequencies, frf[None], low, high, None if weights is None else weights[None])
    A, s = fit.values[0], fit.std[0]
    ok = np.isfinite(A) & np.isfinite(s) & (s > 0)
    if ok.sum() < 2:
        return 0.0, 0.0, 0.0
    A, s = A[ok], s[ok]
    mean = np.sum(A / s**2) / np.sum(1 / s**2)
    return float(np.sum(((A - mean) / s) ** 2)), float(ok.sum() - 1), float(np.ptp(A) / np.abs(A).min())


def repeat_warnings(recording, low: float, high: float, weights: list) -> list[CodedWarning]:
    """A warning for each repeated pair whose runs disagree beyond chance in the band [low, high] Hz
    (``weights``: each repeat's coherence weights (k, n_f) or None)."""
    repeats = recording.repeats
    found = []
    for repeat, w in zip(repeats, weights):
        chi2, dof, spread = disagreement(recording.frequencies, repeat.frf, low, high, w)
        if dof and chi2_sf(chi2, dof) < FALSE_ALARM / len(repeats):
            pair = f"{recording.sensor_channels[repeat.sensor]} / {recording.exciter_channels[repeat.exciter]}"
            found.append(CodedWarning(
                "repeat_disagrees",
                f"response-reference pair {pair} measured in {' and '.join(repeat.runs)} differs by "
                f"{100 * spread:.3g} % between them (χ² {chi2:.3g} on {dof:g} dof): something changed between the "
                "runs (a re-mounted sensor, a moved support, a calibration); their mean is used",
            ))  # fmt: skip
    return found
