"""Diagnosability of a layout: can one faulty channel or one faulty hit be located?

A rigid body's masslines at the sensors lie in the column space of S (n_s × q, the
sensor lines' coordinates, q = 6 or 3 for a plate). A fault on channel i (its gain,
polarity or direction) adds δ e_i a_iᵀ to the masslines; after the rigid fit what is
left of it is (I − P) e_i, P = S S⁺ the kinematic hat matrix. The fault shows only
when its leverage h_ii = P_ii is below 1 (h_ii = 1: leaving the channel out loses a
rigid motion, and the others cannot predict it), and it can be told from a fault on
channel k only when the two residual signatures are not parallel:

    r_ik = |(I − P)_ik| / √((1 − h_ii)(1 − h_kk)) < 1.

With n_s = q + 1 every signature is the same line (r_ik = 1): the fault is seen,
never located — ``massline diagnose``'s "no redundancy". A hit's fault changes its
FRF column; the others must still determine the parameters: the block leverage
λ_max(A_j F⁻¹ A_jᵀ) of hit j's weighted sensitivities A_j (n_s × p) in the Fisher
information F = Σ_j A_jᵀ A_j is below 1 exactly when leaving hit j out keeps F
regular. A layout is *diagnosable* when every channel and every hit has leverage at
most ``H_MAX`` and no two channels' signatures are closer than ``R_MAX``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.core.errors import MasslineError
from massline.core.information import NoiseModel, weighted_sensitivities
from massline.core.lines import Lines
from massline.core.model import RigidModel

H_MAX = 0.9  # a channel's or a hit's leverage beyond which its fault is mostly absorbed by the fit
R_MAX = 0.99  # two channels' residual signatures this parallel (8°) cannot be told apart
HIDDEN = ("sensor_gain", "sensor_polarity", "sensor_direction")  # what a channel of high leverage can hide


class UndiagnosableError(MasslineError):
    """The planner found no diagnosable layout of the budget (a larger budget may have one)."""


@dataclass(frozen=True, eq=False)
class Diagnosability:
    """Per-channel and per-hit leverage of a layout and what fails.

    Attributes
    ----------
    channel_leverage : ndarray (n_s,)
        h_ii of the kinematic hat matrix (1: leaving the channel out loses a rigid motion).
    channel_confusion : ndarray (n_s,)
        Each channel's largest r_ik with another channel (1: some other channel's fault looks the same).
    hit_leverage : ndarray (n_e,)
        λ_max of each hit's block of the information hat matrix (1: without it the parameters are unidentified).
    motions : int
        Rigid motions (6, or 3 for a plate).
    """

    channel_leverage: np.ndarray
    channel_confusion: np.ndarray
    hit_leverage: np.ndarray
    motions: int

    @property
    def weak_channels(self) -> list[int]:
        """Channels (0-based) whose fault cannot be located: high leverage or a twin signature."""
        bad = (self.channel_leverage > H_MAX) | (self.channel_confusion > R_MAX)
        return np.flatnonzero(bad).tolist()

    @property
    def weak_hits(self) -> list[int]:
        """Hits (0-based) whose fault cannot be located."""
        return np.flatnonzero(self.hit_leverage > H_MAX).tolist()

    @property
    def diagnosable(self) -> bool:
        return not self.weak_channels and not self.weak_hits

    @property
    def excess(self) -> float:
        """How far from diagnosable: the leverages and confusions beyond their limits, summed (0: diagnosable)."""
        return float(excess(self.channel_leverage, self.channel_confusion, self.hit_leverage))

    @property
    def failures(self) -> list[str]:
        """What fails, in sentences (empty when diagnosable)."""
        out = []
        n = len(self.channel_leverage)
        if n <= self.motions + 1:
            out.append(
                f"{n} channels for {self.motions} rigid motions leave no redundancy: a faulty channel cannot be "
                f"located (diagnosis needs {self.motions + 2})"
            )
        elif self.weak_channels:
            out.append(f"channels {_listed(self.weak_channels)} cannot be checked by the others")
        if self.weak_hits:
            out.append(f"hits {_listed(self.weak_hits)} cannot be checked by the others")
        return out

    def hidden(self, channel: int) -> tuple[str, ...]:
        """The faults channel ``channel`` (0-based) could hide: gain, polarity, direction, or none."""
        return HIDDEN if channel in self.weak_channels else ()

    def as_dict(self) -> dict:
        """JSON-ready: the verdict, the leverages and what each channel could hide."""
        return {
            "diagnosable": self.diagnosable,
            "h_max": H_MAX,
            "r_max": R_MAX,
            "channel_leverage": self.channel_leverage.tolist(),
            "channel_confusion": self.channel_confusion.tolist(),
            "hit_leverage": self.hit_leverage.tolist(),
            "hidden": [list(self.hidden(k)) for k in range(len(self.channel_leverage))],
            "failures": self.failures,
        }


def _listed(indices: list[int]) -> str:
    return ", ".join(str(k + 1) for k in indices)


def hat_matrix(S: np.ndarray, motions: int) -> np.ndarray:
    """P = S S⁺ (..., n, n) of sensor line coordinates S (..., n, q), one per layout of a stack; the identity
    where S sees fewer than ``motions`` motions (nothing is predicted)."""
    n = S.shape[-2]
    U, s, _ = np.linalg.svd(S, full_matrices=False)
    if s.shape[-1] < motions:
        return np.broadcast_to(np.eye(n), S.shape[:-2] + (n, n)).copy()
    seen = s[..., motions - 1] > 1e-10 * s[..., 0]
    Um = U[..., :motions]
    return np.where(seen[..., None, None], Um @ np.swapaxes(Um, -1, -2), np.eye(n))


def confusion(P: np.ndarray) -> np.ndarray:
    """Each channel's largest |(I − P)_ik| / √((1 − h_ii)(1 − h_kk)) over k ≠ i (1 at leverage 1), of hat
    matrices P (..., n, n)."""
    n = P.shape[-1]
    R = np.eye(n) - P
    d = np.sqrt(np.clip(np.diagonal(R, axis1=-2, axis2=-1), 0, None))
    dd = d[..., :, None] * d[..., None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        C = np.where(dd > 1e-9, np.abs(R) / dd, 1.0)
    C[..., np.arange(n), np.arange(n)] = 0.0
    return C.max(axis=-1) if n > 1 else np.ones(P.shape[:-1])


def hit_leverages(A: np.ndarray) -> np.ndarray:
    """λ_max(A_j F⁻¹ A_jᵀ) per hit, A (..., n_s, n_e, p) the weighted sensitivities; 1 where F is singular."""
    n_s, n_e, p = A.shape[-3:]
    flat = A.reshape(A.shape[:-3] + (n_s * n_e, p))
    F = np.swapaxes(flat, -1, -2) @ flat
    w = np.linalg.eigvalsh(F)
    singular = w[..., 0] <= 1e-12 * w[..., -1]
    L = np.linalg.cholesky(np.where(singular[..., None, None], np.eye(p), F))
    B = np.linalg.solve(L, np.swapaxes(flat, -1, -2)).reshape(A.shape[:-3] + (p, n_s, n_e))
    Bj = np.moveaxis(B, -1, -3)  # (..., n_e, p, n_s): hit j's block of L⁻¹ Aᵀ
    K = np.swapaxes(Bj, -1, -2) @ Bj  # A_j F⁻¹ A_jᵀ (..., n_e, n_s, n_s)
    return np.where(singular[..., None], 1.0, np.linalg.eigvalsh(K)[..., -1])


def excess(channel_leverage: np.ndarray, channel_confusion: np.ndarray, hit_leverage: np.ndarray) -> np.ndarray:
    """How far from diagnosable (0: diagnosable): the leverages and confusions beyond their limits summed over
    the last axis (one value per layout of a stack)."""
    over = [channel_leverage - H_MAX, channel_confusion - R_MAX, hit_leverage - H_MAX]
    return sum(np.clip(x, 0, None).sum(axis=-1) for x in over)


def _measures(model: RigidModel, S: np.ndarray, W: np.ndarray, noise: NoiseModel) -> tuple:
    """Channel leverages, channel confusions and hit leverages of sensor and exciter line coordinates
    S (..., n_s, q), W (..., n_e, q)."""
    P = hat_matrix(S, S.shape[-1])
    return (
        np.clip(np.diagonal(P, axis1=-2, axis2=-1), 0.0, 1.0),
        confusion(P),
        np.clip(hit_leverages(weighted_sensitivities(model, S, W, noise)), 0.0, 1.0),
    )


def of_coordinates(model: RigidModel, S: np.ndarray, W: np.ndarray, noise: NoiseModel) -> Diagnosability:
    """The diagnosability of sensor and exciter line coordinates S (n_s, q), W (n_e, q) at the nominal body."""
    return Diagnosability(*_measures(model, S, W, noise), S.shape[1])


def excesses(model: RigidModel, S: np.ndarray, W: np.ndarray, noise: NoiseModel) -> np.ndarray:
    """The excess (:attr:`Diagnosability.excess`) of each layout of a stack, S (T, n_s, q), W (T, n_e, q): the
    planner's trials evaluated together, each as :func:`of_coordinates` would."""
    return excess(*_measures(model, S, W, noise))


def diagnosability(
    model: RigidModel, sensors: Lines, exciters: Lines, noise: NoiseModel = NoiseModel()
) -> Diagnosability:
    """The diagnosability of the layout at the model's nominal body."""
    return of_coordinates(model, model.coordinates(sensors), model.coordinates(exciters), noise)
