"""A moved accelerometer's offset as identify's masslines read it.

An accelerometer glued δ from its labelled point p reads along s = (d, (p + δ) × d): its masslines are linear
in δ at a given body, A_ij = s_iᵀ M⁻¹ ℓ_j. The line-level search fits δ together with the body, the tails and
every other effect, and where the offset is large against the channel's leverage the two trade (on the
bracket's default plan an 8 mm offset on channel 8 was fitted as 11.7 mm in another direction, its Δ(p × d)
uncorrelated with the truth's, and identify's χ² left 80 % of the misfit). Here the body is identify's
estimate from the other channels (the faulty one left out, so it does not bend the body), and δ is the
weighted least-squares offset of the channel's own masslines on that body, in the plane ⊥ d (along d an offset
cannot be seen), or in 3-D for a triaxial's channels, which move as one.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from massline.core.information import sensitivities
from massline.core.lines import Lines
from massline.core.masslines import Masslines
from massline.identify.diagnose.effects.base import offset_parameters
from massline.identify.diagnose.unexplained import estimated

STEP = 1e-3  # m: the difference step (the masslines are linear in δ: any step is exact to rounding)


def offset_basis(directions: np.ndarray) -> np.ndarray:
    """(k, 3) unit vectors an offset of these channels is fitted along: the plane ⊥ the one channel's axis,
    or every axis for a triaxial's channels."""
    if len(directions) > 1:
        return np.eye(3)
    d = directions[0] / np.linalg.norm(directions[0])
    u = np.linalg.svd(d[None, :])[2][1:]  # the two unit vectors ⊥ d
    return u


def masslines_at(model, sensors: Lines, exciters: Lines, riding) -> np.ndarray:
    """A_ij (n_s, n_e), (m/s²)/N: the masslines of ``model``'s body for these lines."""
    return sensitivities(model, model.coordinates(sensors), model.coordinates(exciters), riding)[1]


def read_offset(finding, without):
    """``finding`` (a ``sensor_location``) with its offset, and the offset's 1-σ, read on identify's estimate
    ``without`` (identify with every other fault undone): the body from the other channels, δ by weighted least
    squares on the finding's channels; the finding unchanged where the rest cannot be estimated."""
    data, sigma, riding = without.data, without.sigma, without.best.riding
    channels = list(finding.channels)
    rest = [i for i in range(len(data.sensors)) if i not in channels]
    others = estimated(without, Masslines(data.values[rest], data.sensors[rest], data.exciters), sigma[rest], riding)
    if others is None:
        return finding
    lines = data.sensors[channels]
    base = masslines_at(others.model, lines, data.exciters, riding)
    basis = offset_basis(lines.directions)
    columns = [
        (masslines_at(others.model, Lines(lines.points + STEP * b, lines.directions), data.exciters, riding) - base)
        / STEP
        for b in basis
    ]
    w = 1 / sigma[channels]
    seen = np.isfinite(w) & np.isfinite(data.values[channels])
    A = np.stack([c[seen] * w[seen] for c in columns], axis=1)
    r = (data.values[channels] - base)[seen] * w[seen]
    if A.shape[0] <= A.shape[1] or np.linalg.matrix_rank(A) < A.shape[1]:
        return finding
    v, *_ = np.linalg.lstsq(A, r, rcond=None)
    dof = A.shape[0] - A.shape[1]
    spread = max(float(np.sum((r - A @ v) ** 2)) / dof, 1.0)  # the rows' misfit left, in the noise's units
    std = np.sqrt(np.diag(np.linalg.inv(A.T @ A)) * spread)
    offset = basis.T @ v
    return replace(finding, parameters={**finding.parameters, **offset_parameters(offset, np.linalg.norm(offset), std)})
