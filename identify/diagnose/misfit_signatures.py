"""Every placed finding's signature in frequency, read on the band's lines of the recording as it came.

A channel's row, where the layout has the redundancy, is weighed by the χ² each shape removes from its rigid
misfit at every line (:mod:`.row_factors`: the support's tail, which is rigid, is no misfit there): a phase ∝ f or
a damped rise (:data:`.signature.FREQUENCY_SHAPES`) when one passes the diagnosis's criterion, else one constant
factor when it does, else ``spread``. The row's ratio against the others' rigid motion cannot be classified
alone: the body's own elastic tails rise on it too (on the plate's default plan a 98 µs delay's row read as
rising). A hit's column, and a row without redundancy, against each FRF's massline (the per-FRF band fit,
:attr:`.tails.BandData.free`), divided by the other columns' (rows') ratio so that what every FRF shares
cancels, classified by :func:`.signature.classify`. A misfit no one place holds is ``spread``.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from massline.identify.diagnose.effect_model import Layout
from massline.identify.diagnose.finding import UNEXPLAINED
from massline.identify.diagnose.row_factors import EVIDENCE, Rows, checked, line_noise, profile
from massline.identify.diagnose.signature import FREQUENCY_SHAPES, classify
from massline.identify.tails import MIN_LINES, BandData


def massline_ratio(band: BandData, axis: int, k: int) -> np.ndarray:
    """ρ(f) of row (``axis`` 0) or column (``axis`` 1) ``k`` against each FRF's massline â, weighted by 1/σ², over
    the same ratio of every other row or column."""
    a = np.where(band.free.present, band.free.massline, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        w = np.where(np.isfinite(band.frf).all(axis=2), a / line_noise(band.frf) ** 2, 0.0)
    H = np.nan_to_num(band.frf)

    def ratio(mask):
        weights = np.moveaxis(w, axis, 0)[mask]
        with np.errstate(invalid="ignore", divide="ignore"):  # no FRF of the place measured: no ratio
            return np.einsum("ab,abf->f", weights, np.moveaxis(H, axis, 0)[mask]) / np.sum(
                weights * np.moveaxis(a, axis, 0)[mask])

    place = np.arange(band.frf.shape[axis]) == k
    return ratio(place) / ratio(~place)


def row_signature(rows: Rows, i: int) -> dict:
    """Channel ``i``'s signature from the χ² each shape removes from its row's rigid misfit (module docstring)."""
    f = rows.frequencies
    threshold = EVIDENCE + np.log(2 * rows.y.size)
    out = {"signature": "spread", "frequencies_hz": [float(f[0]), float(f[-1])]}
    fits = [profile(rows, i, shape) for shape in FREQUENCY_SHAPES]
    best = max(fits, key=lambda fit: fit.gain)
    if best.gain > threshold:
        key = "delay_s" if best.effect == "phase_linear" else "resonance_hz"
        return {**out, "signature": best.effect, key: best.value}
    least = rows.cost(i, np.ones(len(f)))[0]
    constant = (rows.chi2 - least) / rows.scale(least, 1)
    return {**out, "signature": "constant"} if constant > threshold else out


def place_signature(band: BandData, layout: Layout, rows: Rows | None, finding) -> dict | None:
    """The signature of ``finding``'s place (its first channel's row, else its hit's column, else the unexplained
    finding's first hit); None for a finding with no place."""
    hits = finding.parameters.get("hits", []) if finding.effect == UNEXPLAINED else []
    if finding.effect == UNEXPLAINED and finding.parameters.get("shape") == "spread":
        return {"signature": "spread", "frequencies_hz": [float(band.frequencies[0]), float(band.frequencies[-1])]}
    if finding.channels and rows is not None:
        return row_signature(rows, finding.channels[0])
    j = finding.exciter if finding.exciter is not None else (hits[0] if hits else None)
    axis, k = (0, finding.channels[0]) if finding.channels else (1, j)
    return None if k is None else classified(band.frequencies, massline_ratio(band, axis, k), axis == 1)


def classified(frequencies: np.ndarray, ratio: np.ndarray, column: bool) -> dict | None:
    """:func:`.signature.classify` on the lines where the ratio is defined (a pair not measured leaves lines
    without it); None with fewer than ``MIN_LINES``."""
    kept = np.isfinite(ratio)
    return classify(frequencies[kept], ratio[kept], column) if kept.sum() >= MIN_LINES else None


def signed(findings: list, band: BandData, layout: Layout) -> list:
    """The findings, each placed one with ``signature`` in its parameters (a row's library-free shape keeps the
    one it was found by)."""
    rows = Rows.of(band, layout) if checked(band, layout) else None
    out = []
    for finding in findings:
        signature = finding.parameters.get("signature") or place_signature(band, layout, rows, finding)
        out.append(finding if signature is None else replace(finding, parameters={**finding.parameters,
                                                                                  "signature": signature}))
    return out
