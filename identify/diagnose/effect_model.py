"""The massline model with the instrumentation effects of the mismatch catalogue.

The rigid body's masslines (eq. 14 in the band) are H_ij = s_iᵀ M(θ)⁻¹ e_j. The
effects change the lines (mismatch notes §3 B, C), each a block of parameters
that is zero in the nominal model:

    s_i = (1 + g_i) (d_i', p_i' × d_i')    sensor reading, 6-vector at O
        d_i' = unit(d_i + T_i τ_i)         effective axis (B1): misalignment and transverse sensitivity
        p_i' = p_i + T_i δ_i               sensing point (B2; a triaxial moves as one: δ in 3-D)
    e_j = (f_j, r_j' × f_j)                force line
        f_j = unit(d_j + T_j β_j)          hit direction (C1)
        r_j' = r_j + T_j γ_j               hit point (C2)

Each block's effect is a class of the registry (:mod:`.effects`): where it can sit (``blocks``), its values
and how they move the lines (``displace``); this module holds the algebra they share.

On a support of stiffness K the FRFs carry its tail s_iᵀ X e_j/(x − x_s) on the same lines, X = M⁻¹KM⁻¹/ω_mid²
(:mod:`massline.identify.tails`); when the data's support is *shared*, X (symmetric) is fitted with θ, and
every effect changes the tail on its line as it changes the massline.

T_i holds two unit vectors ⊥ d_i: what lies along the line is unobservable. Every
τ_i is estimated under the datasheet's prior (transverse sensitivity, 3 %);
the ``sensor_direction`` effect widens that prior for one accelerometer to a
mounting error's (``MISALIGNMENT``), and pays the Laplace evidence's Occam factor
for it, 2 ln(σ_wide/σ_datasheet) per component, instead of BIC's ln n. The
fit weighs every massline by the spectral lines behind it (:mod:`massline.identify.tails`), so its
χ² counts every line.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from massline.identify.diagnose.effects import modelled, named
from massline.identify.diagnose.effects.base import MISALIGNMENT, Block, MeasuredLines
from massline.core.lines import perpendicular_bases
from massline.identify.tails import Reduced
from massline.core.lines import Lines, cross
from massline.core.model import RigidModel

__all__ = ["MISALIGNMENT", "Block", "Layout", "Problem", "jacobian", "line_coordinates"]


@dataclass(frozen=True, eq=False)
class Layout:
    """The nominal lines as labelled, with the accelerometers they belong to.

    Attributes
    ----------
    sensors, exciters : Lines
        Nominal lines (m, test frame).
    groups : tuple of tuple of int
        Channels of each accelerometer (one for a uniaxial, three for a triaxial).
    planar : bool
        Plate data (§2.3): out-of-plane lines, 6 parameters, no transverse readings.
    """

    sensors: Lines
    exciters: Lines
    groups: tuple
    planar: bool

    @classmethod
    def of(cls, sensors: Lines, exciters: Lines, planar: bool) -> "Layout":
        groups = {}
        for i, g in enumerate(sensors.triaxial):
            groups.setdefault(i if g < 0 else f"t{g}", []).append(i)
        return cls(sensors, exciters, tuple(tuple(v) for v in groups.values()), planar)

    @cached_property
    def sensor_bases(self) -> np.ndarray:
        """T_i (n_s, 3, 2): the axes each sensor's transverse reading lies on (computed once per layout)."""
        return perpendicular_bases(self.sensors.directions)

    @cached_property
    def exciter_bases(self) -> np.ndarray:
        """U_j (n_e, 3, 2): the axes ⊥ each hit's direction."""
        return perpendicular_bases(self.exciters.directions)

    def size(self, block: Block) -> int:
        """Number of values the block adds to x (a widened prior adds none: its τ are estimated anyway)."""
        return named(block.effect).values(self, block.target)

    @property
    def extent(self) -> float:
        """The largest distance of a sensor from the sensors' centroid, m: the layout's size."""
        points = self.sensors.points
        return float(np.linalg.norm(points - points.mean(axis=0), axis=1).max())

    def candidates(self) -> list[Block]:
        """Every block effect of the registry at every place it can sit (:meth:`Effect.blocks`): the sensors'
        effects first, each effect's places together, then the hits', exciter by exciter (in ``rank``)."""
        effects = sorted(modelled("block"), key=lambda cls: cls.rank)
        sensors = [b for cls in effects if cls.perturbs == "sensor" for b in cls.blocks(self)]
        hits = [b for cls in effects if cls.perturbs == "exciter" for b in cls.blocks(self)]
        return sensors + sorted(hits, key=lambda b: b.target)

    def channels(self, block: Block) -> list[int]:
        """The sensor channels a sensor block acts on (a gain: its channel; else the accelerometer's)."""
        return named(block.effect).channels(self, block.target)


def line_coordinates(points: np.ndarray, vectors: np.ndarray, planar: bool) -> np.ndarray:
    """(d, r × d) of unnormalised vectors d (a gain stays a gain); the plate's (d_z, y d_z, −x d_z)."""
    if planar:
        return np.column_stack([vectors[:, 2], points[:, 1] * vectors[:, 2], -points[:, 0] * vectors[:, 2]])
    return np.hstack([vectors, cross(points, vectors)])


@dataclass(frozen=True, eq=False)
class Problem:
    """What stays fixed while effects are tried: the layout, the reduced data, noise and prior.

    ``data`` holds the masslines with the discrete corrections (polarity, swaps) applied;
    ``sigma`` (n_s, n_e) the per-line noise σ_ij (∞ for a pair with no massline); ``transverse`` the prior 1-σ
    of τ; ``n_values`` the real numbers behind the fit (2 × each FRF's lines), BIC's n; ``energy`` (n_s, n_e)
    Σ|H|² over each FRF's lines, the scale of relative residuals.
    """

    layout: Layout
    data: Reduced
    sigma: np.ndarray
    model: RigidModel
    transverse: float
    n_values: int
    energy: np.ndarray

    @property
    def n_tau(self) -> int:
        """Transverse components estimated: none for a plate or when the axes are taken as exact."""
        return 0 if self.layout.planar or self.transverse <= 0 else 2 * len(self.layout.sensors)

    @property
    def n_support(self) -> int:
        """Entries of the shared support's symmetric X (6×6, a plate's 3×3); none for per-FRF tails."""
        q = 3 if self.layout.planar else 6
        return q * (q + 1) // 2 if self.data.shared else 0

    @property
    def head(self) -> int:
        """Where the effect blocks' values start in x: after θ̃, τ and X."""
        return self.model.p + self.n_tau + self.n_support

    @cached_property
    def support_rank(self) -> int:
        """X's entries the FRFs with a massline determine: s_iᵀ X e_j sees X only on the lines' span (four hits: not
        all 21)."""
        if not self.n_support:
            return 0
        s, e = self.line_vectors(np.zeros((len(self.layout.sensors), 2)), (), ())
        return int(
            np.linalg.matrix_rank(np.einsum("ia,abk,jb->ijk", s, self.support_basis(), e)[self.data.present])
        )

    def support_basis(self) -> np.ndarray:
        """(q, q, n_support): the symmetric unit matrices of X's upper-triangle entries."""
        q = 3 if self.layout.planar else 6
        rows, cols = np.triu_indices(q)
        basis = np.zeros((q, q, len(rows)))
        basis[rows, cols, np.arange(len(rows))] = 1.0
        basis[cols, rows, np.arange(len(rows))] = 1.0
        return basis

    def support_matrix(self, x: np.ndarray) -> np.ndarray:
        """X (q, q): the support's tail b_ij = s_iᵀ X e_j, M⁻¹KM⁻¹/ω_mid² for a support of stiffness K, kg⁻²·N/m."""
        return self.support_basis() @ x[self.model.p + self.n_tau : self.head]

    def lines(self, tau: np.ndarray, blocks, values):
        """The lines as measured: sensor points, unit axes, their norms before normalising, gains; hit
        directions and points."""
        lay = self.layout
        T, U = lay.sensor_bases, lay.exciter_bases
        d = lay.sensors.directions + (np.einsum("nak,nk->na", T, tau) if tau.size else 0.0)
        norm = np.linalg.norm(d, axis=1)
        d = d / norm[:, None]  # a tilted axis, not a gain
        moved = MeasuredLines(
            points=lay.sensors.points.copy(),
            gains=np.ones(len(d)),
            forces=lay.exciters.directions.copy(),
            hits=lay.exciters.points.copy(),
            T=T,
            U=U,
        )
        for block, v in zip(blocks, values):
            named(block.effect).displace(moved, lay, block.target, v)
        return moved.points, d, norm, moved.gains, moved.forces, moved.hits

    def line_vectors(self, tau: np.ndarray, blocks, values) -> tuple[np.ndarray, np.ndarray]:
        """The sensors' line coordinates with their gains (n_s, q) and the hits' (n_e, q), as measured."""
        p, d, _, gain, f, r = self.lines(tau, blocks, values)
        return line_coordinates(p, d * gain[:, None], self.layout.planar), line_coordinates(r, f, self.layout.planar)

    def predicted(self, x: np.ndarray, blocks) -> np.ndarray:
        """(n_s, n_e, m): the masslines, and when the support is shared its tails s_iᵀ X e_j on the same lines
        (an effect on a line changes both)."""
        theta, tau, values = self.unpack(x, blocks)
        s, e = self.line_vectors(tau, blocks, values)
        A = s @ np.linalg.solve(self.model.mass_matrix(self.model.scale * theta), e.T)
        return np.stack([A] + ([s @ self.support_matrix(x) @ e.T] if self.n_support else []), axis=-1)

    def whitened(self, deviation: np.ndarray) -> np.ndarray:
        """L d / σ_ij of deviations d (n_s, n_e, m, …) from the targets, on the FRFs with a massline (``data.present``;
        the model predicts every pair, only the comparison leaves the others out): rows of the weighted residual,
        (k, m, …)."""
        rule = "ijab,ijb...->ija..." if self.data.per_frf else "ab,ijb...->ija..."
        rows = np.einsum(rule, self.data.whitening, deviation)
        return (rows / self.sigma.reshape(self.sigma.shape + (1,) * (deviation.ndim - 2)))[self.data.present]

    def jacobian(self, x: np.ndarray, blocks) -> np.ndarray:
        """∂r/∂x: analytic in θ̃ (∂M⁻¹ = −M⁻¹ B_k M⁻¹), τ (∂d'/∂τ = (I − d'd'ᵀ) T / ‖d + Tτ‖) and X (linear),
        central differences in the few effect values."""
        theta, tau, values = self.unpack(x, blocks)
        p, d, norm, gain, f, r = self.lines(tau, blocks, values)
        s = line_coordinates(p, d * gain[:, None], self.layout.planar)
        e = line_coordinates(r, f, self.layout.planar)
        M_inv = np.linalg.inv(self.model.mass_matrix(self.model.scale * theta))
        U, V = s @ M_inv, e @ M_inv
        n_s, n_e = len(s), len(e)
        m = 2 if self.n_support else 1
        dP = np.zeros((n_s, n_e, m, self.head))
        dP[:, :, 0, : self.model.p] = -np.einsum("ia,kab,jb->ijk", U, self.model.basis, V)
        if self.n_tau:
            projector = np.eye(3) - np.einsum("na,nb->nab", d, d)
            delta = np.einsum("nab,nbc->nac", projector, self.layout.sensor_bases) / norm[:, None, None]
            ds = gain[:, None, None] * np.concatenate([delta, cross(p[:, :, None], delta, axis=1)], axis=1)
            W = np.stack([V] + ([e @ self.support_matrix(x)] if self.n_support else []))  # ∂(A, b)/∂s_i
            tau_columns = self.model.p + 2 * np.arange(n_s)
            for c in range(2):
                dP[np.arange(n_s), :, :, tau_columns + c] = np.einsum("ia,mja->ijm", ds[:, :, c], W)
        if self.n_support:
            dP[:, :, 1, self.model.p + self.n_tau :] = np.einsum("ia,abk,jb->ijk", s, self.support_basis(), e)
        J = -self.whitened(dP).reshape(-1, self.head)
        if self.n_tau:
            scale = np.where(self.released(blocks), MISALIGNMENT, self.transverse)
            prior = np.zeros((self.n_tau, self.head))
            prior[:, self.model.p : self.model.p + self.n_tau] = np.diag(np.repeat(1 / scale, 2))
            J = np.vstack([J, prior])
        extra = range(self.head, len(x))
        return np.hstack([J, jacobian(self, x, blocks, extra)]) if len(extra) else J

    def released(self, blocks) -> np.ndarray:
        """Channels whose transverse prior is released by a block that widens it (``sensor_direction``)."""
        mask = np.zeros(len(self.layout.sensors), dtype=bool)
        for block in blocks:
            if named(block.effect).widens_prior:
                mask[list(self.layout.groups[block.target])] = True
        return mask

    def residual(self, x: np.ndarray, blocks) -> np.ndarray:
        """Weighted residual: L(â − A, b̂ − b)/σ per FRF (√κ(â − A)/σ with per-FRF tails), then the prior rows
        τ/t (t widened where released)."""
        _, tau, _ = self.unpack(x, blocks)
        rows = [self.whitened(self.data.targets - self.predicted(x, blocks)).ravel()]
        if self.n_tau:
            scale = np.where(self.released(blocks), MISALIGNMENT, self.transverse)
            rows.append((tau / scale[:, None]).ravel())
        return np.concatenate(rows)

    def unpack(self, x: np.ndarray, blocks):
        p, n_tau = self.model.p, self.n_tau
        tau = x[p : p + n_tau].reshape(-1, 2)
        values, k = [], self.head
        for block in blocks:
            n = self.layout.size(block)
            values.append(x[k : k + n])
            k += n
        return x[:p], tau, values

    def start(self, previous, blocks) -> np.ndarray:
        """Parameters to start from: the previous fit's where it had them, zeros for new blocks, and a shared
        support's X the previous fit's or the least-squares one of the b̂_ij on the lines.

        ``previous``: an earlier fit of this problem (its ``parts`` and ``blocks``), or None.
        """
        if previous is None:
            theta, tau, old = self.model.theta / self.model.scale, np.zeros(self.n_tau), {}
        else:
            theta, tau, values = previous.parts
            old = dict(zip(previous.blocks, values))
        sizes = [self.layout.size(b) for b in blocks]
        values = [old.get(b, np.zeros(n)) for b, n in zip(blocks, sizes)]
        if not self.n_support:
            X = np.zeros(0)
        elif previous is not None and previous.problem.n_support == self.n_support:
            X = previous.x[previous.problem.model.p + previous.problem.n_tau : previous.problem.head]
        else:
            X = self.support_fit(tau.reshape(-1, 2), blocks, values)
        return np.concatenate([theta, np.ravel(tau), X, *values])

    def support_fit(self, tau: np.ndarray, blocks, values) -> np.ndarray:
        """X's entries that best give the b̂_ij on the lines (weighted least squares: linear in X)."""
        s, e = self.line_vectors(tau, blocks, values)
        design = np.einsum("ia,abk,jb->ijk", s, self.support_basis(), e) / self.sigma[..., None]
        present = self.data.present
        return np.linalg.lstsq(design[present], (self.data.support / self.sigma)[present])[0]


def jacobian(problem: Problem, x: np.ndarray, blocks, columns=None) -> np.ndarray:
    """∂r/∂x by central differences (only ``columns`` when given; a check of ``Problem.jacobian``)."""
    h = 1e-6 * np.maximum(np.abs(x), 1e-2)
    out = []
    for k in range(len(x)) if columns is None else columns:
        e = np.zeros_like(x)
        e[k] = h[k]
        out.append((problem.residual(x + e, blocks) - problem.residual(x - e, blocks)) / (2 * h[k]))
    return np.array(out).reshape(-1, len(problem.residual(x, blocks))).T
