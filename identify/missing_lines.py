"""Lines an FRF does not have: NaN in a recording's FRFs, where the runs it was assembled from did not measure.

A recording assembled from several test runs holds NaN (complex NaN) at every line of a response–reference pair
that was not measured, and at the lines of its axis (the union of the runs' axes) that an FRF measured on a
coarser or shorter axis lacks; its coherence is NaN at the same places. Identify reads each FRF on its own
lines: a missing line weighs 0 in every sum, a reduction over FRFs or lines takes the values present, and
nothing is concluded from a NaN. These are those reductions; on a recording with every line each gives what
its plain numpy counterpart gives, to the bit.
"""

from __future__ import annotations

import warnings

import numpy as np


def present(frf: np.ndarray, weights: np.ndarray | None = None) -> np.ndarray:
    """Where each FRF has a line (bool, ``frf``'s shape): H finite, and its weight finite when ``weights`` are
    given (a coherence weight is NaN where the coherence is). A complex NaN's imaginary part reads 0: only H
    itself tells."""
    has = np.isfinite(frf)
    return has if weights is None else has & np.isfinite(weights)


def missing_as_nan(values: np.ndarray, has: np.ndarray) -> np.ndarray:
    """``values`` (a part of H, a coherence) with NaN where the FRF has no line (``has`` False)."""
    return np.where(has, values, np.nan)


def pair_norm(values: np.ndarray, has: np.ndarray) -> np.ndarray:
    """‖values(f)‖_F over the FRFs (axes 0 and 1) at each line, over those present (``has``) scaled to all of
    them, √(n_pairs / n_present · Σ |v|²): comparable from line to line whichever FRFs a line holds; 0 at a
    line none holds."""
    v = np.where(has, values, 0)
    squares = np.add.reduce((v.conj() * v).real, axis=(0, 1))
    count = np.count_nonzero(has, axis=(0, 1))
    scale = np.divide(has.shape[0] * has.shape[1], count, out=np.zeros(np.shape(count)), where=count > 0)
    return np.sqrt(squares * scale)


def median_present(values: np.ndarray, axis=None) -> np.ndarray:
    """The median over ``axis`` of the values that are not NaN; NaN where there is none."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # an all-NaN slice: an FRF with no line there
        return np.nanmedian(values, axis=axis)


def mean_present(values: np.ndarray, axis=None) -> np.ndarray:
    """The mean over ``axis`` of the values that are not NaN; NaN where there is none."""
    kept = ~np.isnan(values)
    count = np.count_nonzero(kept, axis=axis)
    total = np.where(kept, values, 0.0).sum(axis=axis)
    return np.divide(total, count, out=np.full(np.shape(total), np.nan), where=count > 0)
