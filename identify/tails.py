"""The band's spectral lines, reduced to one massline per FRF for any set of tail laws.

Over the massline band each FRF is the rigid body's massline A plus, when the
model admits them, the tails of its neighbours (mismatch notes A1, A3):

    suspension             B/ω² + B₂/ω⁴   (B complex: the support's damping; B₂ its second order)
    residual_flexibility   Cω² + Dω⁴      (C complex: the modes' damping; D the next term)

For a given set of laws the tail coefficients of each FRF enter linearly and
are projected out (variable projection). The residual sum of squares of FRF
ij over all its lines is then a parabola in its massline,

    RSS_ij(A) = rss_ij + κ (A − â_ij)²,

so a rigid-body model is fitted to the n_s × n_e numbers â_ij with weights
κ/σ_ij², while every χ², BIC and relative residual still counts each spectral
line. σ_ij, the noise of one real component of one line, comes from the fullest
fit (massline and both tails), whose residual is the measurement scatter.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from massline.placement.errors import MasslineError

TAIL_LAWS = ("suspension", "residual_flexibility")
MIN_LINES = 12


def tail_columns(omega: np.ndarray, laws: frozenset) -> np.ndarray:
    """Columns (2n, k) of the tail laws over [Re; Im] of n lines; x = ω²/ω_mid² keeps them O(1)."""
    x = (omega / np.sqrt(omega[0] * omega[-1])) ** 2
    zero = np.zeros_like(x)
    columns = []
    if "suspension" in laws:
        columns += [(1 / x, zero), (zero, 1 / x), (1 / x**2, zero)]
    if "residual_flexibility" in laws:
        columns += [(x, zero), (zero, x), (x**2, zero)]
    return np.array([np.concatenate(c) for c in columns]).reshape(-1, 2 * len(x)).T


@dataclass(frozen=True, eq=False)
class Reduced:
    """The band reduced for one set of tail laws.

    Attributes
    ----------
    massline : (n_s, n_e) array
        â_ij, the massline that best fits FRF ij with those tails, (m/s²)/N.
    kappa : float
        Curvature of every RSS_ij in A (lines' worth of information on a massline).
    rss : (n_s, n_e) array
        RSS_ij at â_ij, ((m/s²)/N)².
    tails : (n_s, n_e, k) array
        The tail coefficients at â_ij (scaled laws of ``tail_columns``).
    laws : frozenset
        The tail laws admitted.
    """

    massline: np.ndarray
    kappa: float
    rss: np.ndarray
    tails: np.ndarray
    laws: frozenset

    def rss_at(self, A: np.ndarray) -> np.ndarray:
        """RSS_ij of every FRF with masslines A (n_s, n_e)."""
        return self.rss + self.kappa * (A - self.massline) ** 2


@dataclass(frozen=True, eq=False)
class BandData:
    """The recorded FRFs inside the band.

    Attributes
    ----------
    frequencies : (n,) array
        Lines inside the band, Hz.
    frf : (n_s, n_e, n) complex array
        Accelerance, (m/s²)/N.
    """

    frequencies: np.ndarray
    frf: np.ndarray

    @classmethod
    def from_recording(cls, frequencies: np.ndarray, frf: np.ndarray, low: float, high: float) -> "BandData":
        keep = (frequencies >= low) & (frequencies <= high)
        if keep.sum() < MIN_LINES:
            raise MasslineError(
                f"the band {low:g}–{high:g} Hz holds {keep.sum()} spectral lines; diagnosis needs {MIN_LINES}: "
                "widen it with --band LO HI"
            )
        return cls(frequencies[keep], frf[:, :, keep])

    @cached_property
    def values(self) -> np.ndarray:
        """[Re; Im] of every FRF, (n_s, n_e, 2n)."""
        return np.concatenate([self.frf.real, self.frf.imag], axis=2)

    @property
    def n_values(self) -> int:
        return self.values.size

    @cached_property
    def noise(self) -> np.ndarray:
        """σ_ij (n_s, n_e): scatter of one real component of one line, from the fullest fit's residual."""
        full = self.reduced(frozenset(TAIL_LAWS))
        dof = self.values.shape[2] - 1 - full.tails.shape[2]
        return np.sqrt(np.maximum(full.rss / dof, 1e-300))

    @cached_property
    def energy(self) -> np.ndarray:
        """Σ over lines of |H_ij|², per FRF: the scale of the relative residuals."""
        return np.sum(self.values**2, axis=2)

    def reduced(self, laws: frozenset) -> Reduced:
        """Project the tails of ``laws`` out of every FRF (one QR, shared by all FRFs)."""
        omega = 2 * np.pi * self.frequencies
        n = len(omega)
        u = np.concatenate([np.ones(n), np.zeros(n)])
        X = tail_columns(omega, laws)
        Y = self.values
        if X.shape[1]:
            Q, _ = np.linalg.qr(X)
            project = lambda v: v - (v @ Q) @ Q.T  # noqa: E731  (I − QQᵀ) v, on the last axis
        else:
            project = lambda v: v  # noqa: E731
        Pu, PY = project(u), project(Y)
        kappa = float(Pu @ Pu)
        massline = PY @ Pu / kappa
        rss = np.sum(PY**2, axis=2) - kappa * massline**2
        tails = np.linalg.lstsq(X, np.moveaxis(Y - massline[..., None] * u, 2, 0).reshape(2 * n, -1), rcond=None)[0]
        tails = tails.T.reshape(*massline.shape, X.shape[1]) if X.shape[1] else np.zeros((*massline.shape, 0))
        return Reduced(massline, kappa, np.maximum(rss, 0.0), tails, laws)

    def tail_size(self, reduced: Reduced, law: str) -> np.ndarray:
        """Each FRF's fitted ``law`` tail at the band edge where it is largest, relative to its massline."""
        omega = 2 * np.pi * self.frequencies
        n = len(omega)
        line = 0 if law == "suspension" else n - 1
        X = tail_columns(omega, reduced.laws)[[line, n + line]]  # Re and Im rows of the edge line
        k = sorted(reduced.laws, key=TAIL_LAWS.index).index(law)
        value = np.einsum("rk,ijk->ijr", X[:, 3 * k : 3 * k + 3], reduced.tails[..., 3 * k : 3 * k + 3])
        return np.hypot(value[..., 0], value[..., 1]) / np.maximum(np.abs(reduced.massline), 1e-300)
