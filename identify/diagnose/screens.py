"""Screens that need no inertia model: where a recording cannot be a rigid body's (mismatch notes §5.2).

Whatever the mass matrix, a rigid body's response to exciter j at the
sensors is S q_j, with S (n_s × 6) the sensors' line coordinates and q_j the
body's motion: every FRF column lies in the column space of S. How far a
column sits from it, channel by channel and line by line, locates sensor
faults before any fit; leaving one channel out and predicting it from the
others (LOCO) names the channel, and the sign of that prediction tells a
flipped polarity from a gain.

A pair not measured, or a line an FRF lacks, is NaN (:mod:`massline.identify.missing_lines`: a recording
assembled from several test runs need not hold every pair on every line): each column is fitted on the rows it
has, a column with fewer rows than rigid motions checks nothing (no residual, no LOCO prediction), and σ₇ is
read only at the lines where the whole matrix is measured.
"""

from __future__ import annotations

import numpy as np

from massline.identify.diagnose.effect_model import Layout, line_coordinates
from massline.identify.diagnose.effects import EFFECTS, modelled, named
from massline.identify.missing_lines import median_present
from massline.identify.tails import BandData, Reduced
from massline.core.lines import Lines


def kinematic_matrix(sensors: Lines, planar: bool) -> np.ndarray:
    """S (n_s, q): the nominal sensor lines' coordinates."""
    return line_coordinates(sensors.points, sensors.directions, planar)


def with_gaps(reduced: Reduced) -> np.ndarray:
    """The masslines (n_s, n_e), NaN for the pairs with none."""
    return np.where(reduced.present, reduced.massline, np.nan)


def rigid_motions(S: np.ndarray, columns: np.ndarray, has: np.ndarray) -> np.ndarray:
    """The rigid motion q (q, k) of each column of ``columns`` (n_s, k) by least squares on its rows ``has``
    (n_s, k), one solve per set of rows; NaN for a column whose rows are fewer than the motions."""
    q = np.full((S.shape[1], columns.shape[1]), np.nan, dtype=np.result_type(S, columns))
    masks, which = np.unique(has.T, axis=0, return_inverse=True)
    for k, rows in enumerate(masks):
        if rows.sum() >= S.shape[1]:
            kept = which.ravel() == k
            q[:, kept] = np.linalg.lstsq(S[rows], columns[rows][:, kept], rcond=None)[0]
    return q


def off_subspace(S: np.ndarray, columns: np.ndarray) -> np.ndarray:
    """(I − S S⁺) applied to columns (n_s, ...), each on the rows it has (not NaN): the part no rigid motion
    explains; 0 where the column has no value or too few rows to be checked."""
    flat = columns.reshape(len(S), -1)
    has = np.isfinite(flat)
    fitted = S @ rigid_motions(S, np.where(has, flat, 0.0), has)
    return np.where(has & np.isfinite(fitted), flat - fitted, 0.0).reshape(columns.shape)


def rigid_subspace_residual(frf: np.ndarray, S: np.ndarray) -> np.ndarray:
    """|(I − SS⁺) H(f)| relative to each FRF column's norm over the rows it has: (n_s, n_e, n_f), 0 for a rigid
    body, NaN at the lines an FRF lacks."""
    has = np.isfinite(frf)
    residual = off_subspace(S, frf)
    norm = np.linalg.norm(np.where(has, frf, 0.0), axis=0, keepdims=True)
    return np.where(has, np.abs(residual) / np.maximum(norm, 1e-300), np.nan)


def leave_one_out(A: np.ndarray, S: np.ndarray) -> np.ndarray:
    """Each channel's masslines predicted from the others' present ones (n_s, n_e): the rigid motion seen by the
    n_s − 1 other channels; NaN where A is or where the others are too few to see it."""
    predicted = np.empty_like(A)
    for k in range(len(S)):
        has = np.isfinite(A) & (np.arange(len(S)) != k)[:, None]
        predicted[k] = S[k] @ rigid_motions(S, np.where(has, A, 0.0), has)
    return np.where(np.isfinite(A), predicted, np.nan)


def channel_consistency(A: np.ndarray, S: np.ndarray) -> np.ndarray:
    """‖a_k − â_k‖ / ‖â_k‖ of the LOCO predictions (n_s,) over the pairs predicted: large for a channel that
    breaks rigidity (A NaN for a pair with no massline)."""
    predicted = leave_one_out(A, S)
    checked = np.isfinite(predicted)
    miss = np.linalg.norm(np.where(checked, A - predicted, 0.0), axis=1)
    return miss / np.maximum(np.linalg.norm(np.where(checked, predicted, 0.0), axis=1), 1e-300)


def singular_values(frf: np.ndarray) -> np.ndarray:
    """σ_k(H(f)) / σ_1(H(f)) for every line (n_f, min(n_s, n_e)): a 7th that rises marks physics beyond rigid.
    NaN at a line where a pair is missing: the singular values are the whole matrix's."""
    complete = np.isfinite(frf).all(axis=(0, 1))
    s = np.linalg.svd(np.moveaxis(np.where(complete, frf, 0.0), 2, 0), compute_uv=False)
    return np.where(complete[:, None], s / np.maximum(s[:, :1], 1e-300), np.nan)


def discrete_fixes(A: np.ndarray, S: np.ndarray) -> list[tuple[float, str, tuple]]:
    """The registry's discrete effects (polarity flips, channel swaps) ranked by the rigid-subspace misfit
    their undoing leaves (relative to now); A (n_s, n_e) NaN for a pair with no massline (undone with its row).

    Returns (misfit after / misfit now, effect, channels), best first; needs n_s > q + 1 channels.
    """

    def misfit(B):
        return float(np.sum(off_subspace(S, B) ** 2))

    now = max(misfit(A), 1e-300)
    ranked = []
    for effect in modelled("discrete"):
        for channels in effect.proposals(len(A)):
            B = A.copy()
            effect.undo_rows(B, channels)
            ranked.append((misfit(B) / now, effect.name, channels))
    return sorted(ranked)


def corrected_band(band: BandData, fixes) -> BandData:
    """The recording with the discrete faults ``fixes`` ((effect name, channels)) undone on its rows, effect by
    effect in the registry's order (every flip, then every swap), each effect's in the order found."""
    frf = band.frf.copy()
    order = [cls.name for cls in EFFECTS]
    for name, channels in sorted(fixes, key=lambda fix: order.index(fix[0])):
        named(name).undo_rows(frf, channels)
    return BandData(band.frequencies, frf)


def driving_points(sensors: Lines, exciters: Lines, tolerance: float = 1e-3) -> list[tuple[int, int]]:
    """(i, j) pairs where sensor and hit share point and direction: their massline must be positive."""
    pairs = []
    for i in range(len(sensors)):
        for j in range(len(exciters)):
            same_point = np.linalg.norm(sensors.points[i] - exciters.points[j]) < tolerance
            same_axis = abs(sensors.directions[i] @ exciters.directions[j]) > 1 - 1e-6
            if same_point and same_axis:
                pairs.append((i, j))
    return pairs


def screen(band: BandData, layout: Layout) -> dict:
    """The model-free screens of a recording's band, JSON-ready.

    ``channel_consistency``: each channel's LOCO misfit (None without redundancy);
    ``negative_driving_points``: (sensor, hit) pairs, 1-based, whose massline is not positive;
    ``off_rigid``: each channel's median distance from the rigid motions over the band (relative), over its lines;
    ``tails_low`` / ``tails_high``: median over FRFs of the free fit's 1/ω² tail at the lower edge and
    ω² tail at the upper edge, relative to the massline (the per-FRF trends, summarised);
    ``seventh_singular_value``: σ₇/σ₁ of the FRF matrix at every line of the band, which a rigid body keeps
    at the noise (None with fewer than 7 sensors or hits: then ``off_rigid`` is the rank test; NaN at a line where a
    pair is missing). A pair with no massline is in none of them.
    """
    S = kinematic_matrix(layout.sensors, layout.planar)
    free = band.free
    A = with_gaps(free)
    redundant = len(S) > S.shape[1] + 1
    off = rigid_subspace_residual(band.frf, S) if redundant else np.full(band.frf.shape, np.nan)
    x = (band.omega[[0, -1]] / np.sqrt(band.omega[0] * band.omega[-1])) ** 2
    scale = np.maximum(np.abs(A), 1e-300)
    low = np.abs(free.tails[..., 0] / x[0] + free.tails[..., 2] / x[0] ** 2) / scale
    high = np.abs(free.tails[..., 3] * x[1] + free.tails[..., 5] * x[1] ** 2) / scale
    return {
        "channel_consistency": channel_consistency(A, S).tolist() if redundant else None,
        "negative_driving_points": [
            [i + 1, j + 1] for i, j in driving_points(layout.sensors, layout.exciters) if A[i, j] <= 0
        ],
        "off_rigid": median_present(off, axis=(1, 2)).tolist(),
        "tails_low": float(median_present(low)),
        "tails_high": float(median_present(high)),
        "seventh_singular_value": singular_values(band.frf)[:, 6].tolist() if min(band.frf.shape[:2]) >= 7 else None,
    }


def roomy(layout: Layout) -> bool:
    """More channels than rigid motions plus one: only then can one channel be checked against the others."""
    return len(layout.sensors) > (3 if layout.planar else 6) + 1
