"""The band's spectral lines, reduced to one massline per FRF for any set of tail laws.

Over the massline band each FRF is the rigid body's massline A plus, when the
model admits them, the tails of its neighbours (mismatch notes A1, A3), each a
single mode whose frequency is shared by every FRF (x = ω²/ω_mid²):

    suspension             b/(x − x_s) + i b'/x       a support mode at x_s below the band
    residual_flexibility   c x/(1 − x/x_r) + i c' x   an elastic mode at x_r above it

(b, b', c, c' per FRF; the imaginary parts carry the damping). As x_s → 0 and
x_r → ∞ they become the first-order tails B/ω² and Cω²; the pole is what keeps
a tail that reaches tens of per cent inside the band from leaking into the
massline. For given poles the per-FRF coefficients enter linearly and are
projected out (variable projection); the poles are chosen by a bounded search
on the total weighted RSS. The residual sum of squares of FRF ij over all its
lines is then a parabola in its massline,

    RSS_ij(A) = rss_ij + κ (A − â_ij)²,

so a rigid-body model is fitted to the n_s × n_e numbers â_ij with weights
κ/σ_ij², while every χ², BIC and relative residual still counts each spectral
line.

The support acts on the rigid body, so its tail need not be free per FRF: on a
support of stiffness K the rigid accelerance is S(M − K/ω²)⁻¹Wᵀ = SM⁻¹Wᵀ +
S M⁻¹KM⁻¹ Wᵀ/ω² + O(ω⁻⁴), exact with the pole for a support of one spring, so
b_ij = s_iᵀ X e_j with one symmetric X shared by every FRF. For that *shared*
form the support column s is kept and only the other tail columns are projected
out, and each FRF's RSS is a parabola in the pair (A, b),

    RSS_ij(A, b) = rss_ij + [A − â_ij, b − b̂_ij] K₂ [A − â_ij, b − b̂_ij]ᵀ,

with one 2×2 curvature K₂ for every FRF (they share the design). σ_ij, the noise of one real component of
one line, comes from a free fit of each FRF (massline, B/ω² + B₂/ω⁴, Cω² + Dω⁴ per FRF), whose residual is
the measurement scatter.

Each FRF is reduced on the lines it has (:mod:`.missing_lines`; a recording assembled from several test runs
lacks the pairs no run measured and the lines a coarser run's axis has not): a pair not measured, or with fewer
than ``MIN_LINES`` lines in the band, has no massline (0, σ = ∞, RSS 0, outside ``present``); FRFs on another
axis (NaN at the lines they lack) are reduced with the design on their own lines, one design per set of lines
(:attr:`BandData.designs`), so κ and K₂ are then per FRF. A complete recording, or one with whole pairs missing,
keeps one shared design.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np
from scipy.optimize import minimize, minimize_scalar

from massline.core.band import GIVE_BAND
from massline.core.errors import MasslineError
from massline.identify.line_correlation import variance_inflation
from massline.identify.missing_lines import present as has_lines
from massline.identify.tail_projection import reduce_design, support_design

# Below the band, above it: each a single mode shared by every FRF, named as the test-physics effect whose
# tail it is (the registry, massline.identify.diagnose.effects)
TAIL_LAWS = ("suspension", "residual_flexibility")
BELOW, ABOVE = TAIL_LAWS
MIN_LINES = 12
POLE_RANGE = 1e3  # the poles are searched from the band edge to this factor beyond it (in x)


def scaled_frequency(omega: np.ndarray) -> np.ndarray:
    """x = ω²/ω_mid², ω_mid the geometric middle of the band."""
    return (omega / np.sqrt(omega[0] * omega[-1])) ** 2


def free_columns(omega: np.ndarray) -> np.ndarray:
    """Each FRF's own tails for the noise estimate: B/ω² (complex), B₂/ω⁴, Cω² (complex), Dω⁴ over [Re; Im]."""
    x = scaled_frequency(omega)
    zero = np.zeros_like(x)
    columns = [(1 / x, zero), (zero, 1 / x), (1 / x**2, zero), (x, zero), (zero, x), (x**2, zero)]
    return np.array([np.concatenate(c) for c in columns]).T


def tail_columns(omega: np.ndarray, poles: dict) -> np.ndarray:
    """Columns (2n, 2 per law) over [Re; Im] of n lines for the laws in ``poles`` (law → pole in x)."""
    x = scaled_frequency(omega)
    zero = np.zeros_like(x)
    columns = []
    if BELOW in poles:
        columns += [(1 / (x - poles[BELOW]), zero), (zero, 1 / x)]
    if ABOVE in poles:
        columns += [(x / (1 - x / poles[ABOVE]), zero), (zero, x)]
    return np.array([np.concatenate(c) for c in columns]).reshape(-1, 2 * len(x)).T


@dataclass(frozen=True, eq=False)
class Reduced:
    """The band reduced for one set of tail laws.

    Attributes
    ----------
    massline : (n_s, n_e) array
        â_ij, the massline that best fits FRF ij with those tails, (m/s²)/N.
    kappa : float or (n_s, n_e) array
        Curvature of every RSS_ij in A (lines' worth of information on a massline); per FRF when the FRFs are
        on different lines.
    rss : (n_s, n_e) array
        RSS_ij at â_ij, ((m/s²)/N)².
    tails : (n_s, n_e, k) array
        The tail coefficients at â_ij (of ``tail_columns``).
    poles : dict
        Each admitted law's pole, in x = ω²/ω_mid².
    free : bool
        Each FRF's own first- and second-order tails (identify's band fit).
    support : (n_s, n_e) array or None
        b̂_ij, the support column's coefficient at the joint minimum, (m/s²)/N: set when the support's tail is
        shared (left to the model as s_iᵀ X e_j); None when it is projected out per FRF.
    coupling : (2, 2) or (n_s, n_e, 2, 2) array, or None
        K₂, the curvature of every RSS_ij in (A, b) when shared (per FRF as κ is).
    present : (n_s, n_e) bool array
        The FRFs that have a massline (every one by default); the others weigh nothing in any sum.
    """

    massline: np.ndarray
    kappa: float | np.ndarray
    rss: np.ndarray
    tails: np.ndarray
    poles: dict = field(default_factory=dict)
    free: bool = False
    support: np.ndarray | None = None
    coupling: np.ndarray | None = None
    present: np.ndarray | None = None

    def __post_init__(self):
        if self.present is None:
            object.__setattr__(self, "present", np.ones(self.massline.shape, dtype=bool))

    @property
    def laws(self) -> frozenset:
        return frozenset(TAIL_LAWS) if self.free else frozenset(self.poles)

    @property
    def shared(self) -> bool:
        """Whether the support tail is left to the model (b_ij = s_iᵀ X e_j) rather than fitted per FRF."""
        return self.support is not None

    @property
    def n_tail_parameters(self) -> int:
        """Per-FRF coefficients and the shared poles (a shared support's X is the model's)."""
        return (self.tails.shape[2] - self.shared) * int(np.count_nonzero(self.present)) + len(self.poles)

    @property
    def targets(self) -> np.ndarray:
        """(n_s, n_e, m): â_ij, and b̂_ij when the support is shared."""
        return np.stack([self.massline] + ([self.support] if self.shared else []), axis=-1)

    @property
    def curvature(self) -> np.ndarray:
        """(m, m), or (n_s, n_e, m, m) per FRF: [[κ]], or K₂ of the pair (A, b) when the support is shared,
        ((m/s²)/N)⁻² per line."""
        return self.coupling if self.shared else np.asarray(self.kappa)[..., None, None]

    @property
    def per_frf(self) -> bool:
        """Whether each FRF has its own curvature (FRFs on different lines)."""
        return self.curvature.ndim == 4

    @property
    def whitening(self) -> np.ndarray:
        """Upper-triangular L with LᵀL = ``curvature`` (per FRF as it is): ‖L d‖² is the RSS a deviation d adds."""
        return np.swapaxes(np.linalg.cholesky(self.curvature), -1, -2)

    def rss_at(self, A: np.ndarray, b: np.ndarray | None = None) -> np.ndarray:
        """RSS_ij of every FRF with masslines A (n_s, n_e) and, when shared, support tails b (0 where absent)."""
        d = np.stack([A] + ([b] if self.shared else []), axis=-1) - self.targets
        added = np.einsum("ija,ijab,ijb->ij" if self.per_frf else "ija,ab,ijb->ij", d, self.curvature, d)
        return np.where(self.present, self.rss + added, 0.0)


@dataclass(frozen=True, eq=False)
class BandData:
    """The recorded FRFs inside the band.

    Attributes
    ----------
    frequencies : (n,) array
        Lines inside the band, Hz.
    frf : (n_s, n_e, n) complex array
        Accelerance, (m/s²)/N; NaN at the lines an FRF does not have (a pair not measured: at every line).
    """

    frequencies: np.ndarray
    frf: np.ndarray
    _reductions: dict = field(default_factory=dict, init=False, repr=False)

    @classmethod
    def from_recording(cls, frequencies: np.ndarray, frf: np.ndarray, low: float, high: float) -> "BandData":
        keep = (frequencies >= low) & (frequencies <= high)
        if keep.sum() < MIN_LINES:
            raise MasslineError(
                f"the band {low:g}–{high:g} Hz holds {keep.sum()} spectral lines; diagnosis needs {MIN_LINES}: "
                f"widen it with {GIVE_BAND}"
            )
        band = cls(frequencies[keep], frf[:, :, keep])
        if not band.present.any():
            raise MasslineError(f"no FRF has {MIN_LINES} spectral lines in the band {low:g}–{high:g} Hz: widen it "
                                f"with {GIVE_BAND}")  # fmt: skip
        return band

    @cached_property
    def present(self) -> np.ndarray:
        """(n_s, n_e) bool: the FRFs with a massline, those with at least ``MIN_LINES`` lines in the band."""
        return np.count_nonzero(has_lines(self.frf), axis=2) >= MIN_LINES

    @cached_property
    def lines(self) -> np.ndarray:
        """(n_s, n_e, 2n) bool over [Re; Im]: the lines of each FRF with a massline."""
        has = has_lines(self.frf) & self.present[..., None]
        return np.concatenate([has, has], axis=2)

    @cached_property
    def omega(self) -> np.ndarray:
        return 2 * np.pi * self.frequencies

    @cached_property
    def values(self) -> np.ndarray:
        """[Re; Im] of every FRF, (n_s, n_e, 2n); 0 at the lines it does not have (``lines``)."""
        return np.where(self.lines, np.concatenate([self.frf.real, self.frf.imag], axis=2), 0.0)

    @property
    def n_values(self) -> int:
        """The real numbers behind the fit: 2 × the lines of every FRF with a massline (BIC's n)."""
        return int(np.count_nonzero(self.lines))

    @cached_property
    def unit(self) -> np.ndarray:
        """The massline's column over [Re; Im]: 1 on the real parts."""
        n = len(self.frequencies)
        return np.concatenate([np.ones(n), np.zeros(n)])

    @cached_property
    def designs(self) -> tuple:
        """The FRFs that share their lines, one design each: (rows (2n,) bool over [Re; Im], FRFs (n_s, n_e)
        bool). One design when every FRF with a massline has the same lines (a complete recording, or whole pairs
        missing)."""
        rows, which = np.unique(self.lines[self.present], axis=0, return_inverse=True)
        groups = []
        for k, row in enumerate(rows):
            frfs = np.zeros_like(self.present)
            frfs[self.present] = which.ravel() == k
            groups.append((row, frfs))
        return tuple(groups)

    @property
    def one_design(self) -> bool:
        return len(self.designs) == 1

    def _group(self, rows: np.ndarray, frfs: np.ndarray) -> np.ndarray:
        """One design's FRFs on its lines: every FRF (n_s, n_e, ·) with one design (the others are 0), else (k, ·)."""
        return self.values[..., rows] if self.one_design else self.values[frfs][:, rows]

    def _joined(self, values: list, fill) -> np.ndarray:
        """Each design's per-FRF values (ordered as ``_group`` gives them) on (n_s, n_e, …), ``fill`` at the FRFs
        with no massline."""
        first = np.asarray(values[0])
        if self.one_design:
            return np.where(self.present.reshape(self.present.shape + (1,) * (first.ndim - 2)), first, fill)
        out = np.empty(self.present.shape + first.shape[1:])
        out[...] = fill
        for (_, frfs), value in zip(self.designs, values):
            out[frfs] = value
        return out

    @cached_property
    def noise(self) -> np.ndarray:
        """σ_ij (n_s, n_e): scatter of one real component of one line, from each FRF's free fit on its own lines,
        its variance scaled by how alike neighbouring lines' residuals are (:mod:`.line_correlation`): every χ²
        and BIC of the diagnosis then counts the lines the noise is worth, as identify's 1-σ does; ∞ for an FRF
        with no massline (it weighs nothing, as in identify)."""
        X = free_columns(self.omega)
        dof = np.maximum(np.count_nonzero(self.lines, axis=2) - 1 - X.shape[1], 1)
        inflation = self._joined([self._inflation(rows, frfs) for rows, frfs in self.designs], 1.0)
        sigma = np.sqrt(np.maximum(self.free.rss / dof * inflation, 1e-300))
        return np.where(self.present, sigma, np.inf)

    def _inflation(self, rows: np.ndarray, frfs: np.ndarray) -> np.ndarray:
        """The variance inflation of one design's FRFs, from the residual of their free fit on its lines."""
        design = np.column_stack([self.unit, free_columns(self.omega)])[rows]
        values = self._group(rows, frfs)
        flat = values.reshape(-1, design.shape[0])
        residual = flat - (design @ np.linalg.lstsq(design, flat.T, rcond=None)[0]).T
        n = design.shape[0] // 2
        with np.errstate(invalid="ignore", divide="ignore"):  # a pair not measured: zeros, set aside by _joined
            return variance_inflation(residual[:, :n], residual[:, n:]).reshape(values.shape[:-1])

    @cached_property
    def free(self) -> Reduced:
        """Each FRF with its own tails (identify's band fit): robust to several support and elastic modes."""
        return self._reduce(free_columns(self.omega), {}, free=True)

    @cached_property
    def energy(self) -> np.ndarray:
        """Σ over lines of |H_ij|², per FRF (0 for a pair with no massline): the scale of the relative residuals."""
        return np.sum(self.values**2, axis=2)

    def at_poles(self, poles: dict) -> Reduced:
        """The reduction with the tails of ``poles`` projected out (one QR shared by the FRFs of each design)."""
        return self._reduce(tail_columns(self.omega, poles), poles)

    def shared_support(self, laws: frozenset) -> Reduced:
        """The reduction for ``laws`` (with "suspension", at the same poles) keeping the support column s:
        the other tails projected out, (â, b̂) = K₂⁻¹ [Pu, Ps]ᵀ PY and K₂ = [Pu, Ps]ᵀ[Pu, Ps] (per design)."""
        per_frf = self.reduced(laws)
        X = tail_columns(self.omega, per_frf.poles)
        parts = [support_design(X[rows], self.unit[rows], self._group(rows, frfs)) for rows, frfs in self.designs]
        ab, rss = (self._joined([part[k] for part in parts], 0.0) for k in (0, 1))
        if self.one_design:
            K2 = parts[0][2]
        else:
            K2 = self._joined([np.broadcast_to(K, (len(a), 2, 2)) for a, _, K in parts], np.eye(2))
        return replace(per_frf, rss=rss, massline=ab[..., 0], support=ab[..., 1], coupling=K2, kappa=K2[..., 0, 0])

    def _reduce(self, X: np.ndarray, poles: dict, free: bool = False) -> Reduced:
        parts = [reduce_design(X[rows], self.unit[rows], self._group(rows, frfs)) for rows, frfs in self.designs]
        massline, rss, tails = (self._joined([part[k] for part in parts], 0.0) for k in (0, 2, 3))
        if self.one_design:
            kappa = parts[0][1]
        else:
            kappa = self._joined([np.full(len(part[0]), part[1]) for part in parts], 1.0)
        return Reduced(massline=massline, kappa=kappa, rss=rss, tails=tails, poles=dict(poles), free=free,
                       present=self.present)  # fmt: skip

    def reduced(self, laws: frozenset) -> Reduced:
        """The reduction for ``laws``, each pole placed where the weighted RSS over all FRFs is least."""
        laws = frozenset(laws)
        if laws not in self._reductions:
            self._reductions[laws] = self._search(laws)
        return self._reductions[laws]

    def _search(self, laws: frozenset) -> Reduced:
        x = scaled_frequency(self.omega)
        bounds = {
            BELOW: (np.log(x[0] / POLE_RANGE), np.log(0.95 * x[0])),
            ABOVE: (np.log(1.05 * x[-1]), np.log(x[-1] * POLE_RANGE)),
        }
        poles = {law: np.exp(bounds[law][0] if law == BELOW else bounds[law][1]) for law in laws}
        weight = 1 / self.noise**2

        def cost(law, log_pole):
            return float(np.sum(self.at_poles({**poles, law: np.exp(log_pole)}).rss * weight))

        order = sorted(laws, key=TAIL_LAWS.index)
        for law in order:  # one at a time, then both together
            best = minimize_scalar(
                lambda t: cost(law, t), bounds=bounds[law], method="bounded", options={"xatol": 1e-9}
            )
            poles[law] = float(np.exp(best.x))
        if len(order) == 2:
            joint = minimize(
                lambda t: float(np.sum(self.at_poles(dict(zip(order, np.exp(t)))).rss * weight)),
                np.log([poles[law] for law in order]),
                method="Nelder-Mead",
                bounds=[bounds[law] for law in order],
                options={"xatol": 1e-9, "fatol": 0.0, "maxiter": 300},
            )
            poles = dict(zip(order, np.exp(joint.x)))
        return self.at_poles(poles)

    def tail_size(self, reduced: Reduced, law: str) -> np.ndarray:
        """Each FRF's fitted ``law`` tail at the band edge where it is largest, relative to the RMS of every
        massline (the FRF matrix's scale: a small cross massline is none)."""
        n = len(self.omega)
        line = 0 if law == BELOW else n - 1
        X = tail_columns(self.omega, reduced.poles)[[line, n + line]]  # Re and Im rows of the edge line
        k = sorted(reduced.laws, key=TAIL_LAWS.index).index(law)
        value = np.einsum("rk,ijk->ijr", X[:, 2 * k : 2 * k + 2], reduced.tails[..., 2 * k : 2 * k + 2])
        scale = np.sqrt(np.sum(reduced.massline**2) / np.count_nonzero(reduced.present))  # over the FRFs present
        return np.hypot(value[..., 0], value[..., 1]) / max(scale, 1e-300)

    def pole_hz(self, reduced: Reduced, law: str) -> float:
        """The law's mode frequency, Hz."""
        return float(np.sqrt(reduced.poles[law] * self.frequencies[0] * self.frequencies[-1]))
