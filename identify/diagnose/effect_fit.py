"""Fitting the massline model: least squares with some effect blocks, and what a block would add.

``fit`` is Levenberg–Marquardt on :class:`~.effect_model.Problem`'s weighted residual with its
analytic Jacobian; ``score`` is Rao's score statistic of a block not yet in the model (mismatch
notes §5.4), and ``penalty`` what the block costs in BIC: k ln n, or the Occam factor of a widened
axis prior. ``base_fit`` is the nominal model (no effects) from a starting body, ``refit`` a model with other
tail laws or blocks started from a fit, ``plausible`` whether a block's fitted values are a technician's.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import least_squares

from massline.identify.diagnose.effect_model import MISALIGNMENT, Block, Layout, Problem, jacobian
from massline.identify.diagnose.effects import named
from massline.identify.estimator import estimate
from massline.identify.tails import BandData
from massline.core.errors import MasslineError, solver_errors
from massline.core.masslines import Masslines
from massline.core.methods import starting_body
from massline.core.model import RigidModel
from massline.core.rigid_body import RigidBody

MAX_EVALUATIONS = 1000  # a fit still moving after this many steps is far from any model that could be accepted
RCOND = 1e-10  # singular values of the column-scaled Jacobian below this share of the largest: unidentified


def is_body(body) -> bool:
    """Finite parameters, a positive mass and a positive definite inertia about the CoG."""
    return bool(np.isfinite(body.theta).all() and body.mass > 0 and np.linalg.eigvalsh(body.inertia_cog).min() > 0)


@dataclass(frozen=True, eq=False)
class Fit:
    """A fitted model: parameters, χ² over every spectral line, and what was fitted.

    Attributes
    ----------
    problem : Problem
    blocks : tuple of Block
    x : array
        Scaled θ̃, τ (n_s × 2), then each block's values.
    chi2 : float
        Σ RSS_ij/σ_ij² over all lines plus the prior's rows.
    spread : (len(x), len(x)) array
        Covariance of x (from the Jacobian, scaled by the reduced χ² when above 1).
    """

    problem: Problem
    blocks: tuple
    x: np.ndarray
    chi2: float
    spread: np.ndarray

    @property
    def covariance(self) -> np.ndarray:
        """Covariance of θ in SI units."""
        p, scale = self.problem.model.p, self.problem.model.scale
        return self.spread[:p, :p] * np.outer(scale, scale)

    def block_std(self, block: Block) -> np.ndarray:
        """1-σ of a block's values (empty for a widened axis prior: see ``tau_std``)."""
        k = self.problem.head
        for b in self.blocks:
            n = self.problem.layout.size(b)
            if b == block:
                return np.sqrt(np.diag(self.spread)[k : k + n])
            k += n
        raise KeyError(block)

    @property
    def tau_std(self) -> np.ndarray:
        """1-σ of every channel's transverse components (n_s, 2)."""
        p = self.problem.model.p
        return np.sqrt(np.diag(self.spread)[p : p + self.problem.n_tau]).reshape(-1, 2)

    @property
    def n_parameters(self) -> int:
        """Free parameters: θ, the effect blocks' and the tails' (a shared support's X among them; widened priors
        are counted in ``bic``)."""
        lay = self.problem.layout
        tails = self.problem.data.n_tail_parameters + self.problem.support_rank
        free = [lay.size(b) for b in self.blocks]
        return self.problem.model.p + sum(free) + tails

    @property
    def bic(self) -> float:
        """χ² + k ln n, plus the Occam factor of every widened axis prior."""
        widened = 2 * np.count_nonzero(self.problem.released(self.blocks))
        occam = widened * 2 * np.log(MISALIGNMENT / self.problem.transverse)
        return self.chi2 + self.n_parameters * np.log(self.problem.n_values) + occam

    @property
    def theta(self) -> np.ndarray:
        return self.problem.model.scale * self.x[: self.problem.model.p]

    @property
    def body(self):
        """The fitted body; None when θ is no body (a negative mass or inertia: the data need the effects first)."""
        try:
            with np.errstate(invalid="ignore"):  # a radius of gyration of a non-body is NaN, and says so below
                body = self.problem.model.body(self.theta)
        except MasslineError:
            return None
        return body if is_body(body) else None

    @property
    def parts(self):
        return self.problem.unpack(self.x, self.blocks)

    @property
    def masslines(self) -> np.ndarray:
        return self.problem.predicted(self.x, self.blocks)[..., 0]

    @property
    def support_matrix(self) -> np.ndarray | None:
        """The shared support's X (None with per-FRF tails)."""
        return self.problem.support_matrix(self.x) if self.problem.n_support else None

    @property
    def rss(self) -> np.ndarray:
        """RSS_ij over every line of every FRF at the fitted masslines (and shared support tails)."""
        return self.problem.data.rss_at(*np.moveaxis(self.problem.predicted(self.x, self.blocks), -1, 0))


def rejected(problem: Problem, blocks: tuple, x0: np.ndarray) -> Fit:
    """A fit that failed (a start no body could have, a singular or non-converging solve): χ² infinite, so
    it is never the best model and its candidate is rejected."""
    return Fit(problem, blocks, x0, np.inf, np.full((len(x0),) * 2, np.nan))


def unscaled_covariance(jac: np.ndarray) -> np.ndarray:
    """(JᵀJ)⁺ through the SVD of J with its columns scaled to unit norm.

    The columns (θ̃, the transverse τ, a shared support's X in kg⁻²·N/m, the effects) differ in scale by many
    orders: JᵀJ formed and inverted directly lost θ's small directions to rounding (negative variances, a
    4 kg body's mass "± 0.25 mg"). Directions with a singular value below ``RCOND`` of the largest are
    left out (unidentified, as a pseudo-inverse leaves them).
    """
    norms = np.linalg.norm(jac, axis=0)
    norms[norms == 0] = 1.0
    _, s, vt = np.linalg.svd(jac / norms, full_matrices=False)
    keep = s > RCOND * s[0]
    return ((vt[keep].T / s[keep] ** 2) @ vt[keep]) / np.outer(norms, norms)


def fit(problem: Problem, blocks=(), previous: Fit | None = None) -> Fit:
    """Least squares of the masslines with ``blocks`` (Levenberg–Marquardt); a failed solve is ``rejected``."""
    blocks = tuple(blocks)
    x0 = problem.start(previous, blocks)
    residual = problem.residual(x0, blocks) if np.isfinite(x0).all() else None
    if residual is None or not np.isfinite(residual).all() or residual.size < len(x0):  # or more unknowns than data
        return rejected(problem, blocks, x0)
    try:
        with np.errstate(all="ignore"):
            result = least_squares(
                problem.residual,
                x0,
                jac=problem.jacobian,
                args=(blocks,),
                method="lm",
                x_scale=1.0,  # MINPACK's column scaling ("jac", lm's default since SciPy 1.16) left 28 of a bracket
                xtol=1e-10,  # file's 85 fits at MAX_EVALUATIONS and took a 10 % gain for a moved sensor (2.7× slower)
                ftol=1e-10,
                max_nfev=MAX_EVALUATIONS,
            )
        spread = unscaled_covariance(result.jac)
    except (ValueError, np.linalg.LinAlgError):  # non-finite steps, an SVD that does not converge
        return rejected(problem, blocks, x0)
    if not (np.isfinite(result.x).all() and np.isfinite(result.cost)):
        return rejected(problem, blocks, x0)
    chi2 = float(np.sum(problem.data.rss / problem.sigma**2) + 2 * result.cost)
    dof = max(len(result.fun) - len(x0), 1)
    return Fit(problem, blocks, result.x, chi2, spread * max(2 * result.cost / dof, 1.0))


def score(current: Fit, block: Block, J: np.ndarray) -> float:
    """Rao's score statistic: the χ² one Gauss–Newton step with ``block`` added would remove (notes §5.4).

    ``J`` is ∂r/∂x at the current fit; only the new block's columns are differenced.
    """
    problem, blocks = current.problem, current.blocks + (block,)
    x = problem.start(current, blocks)
    r_now = problem.residual(current.x, current.blocks)
    r = problem.residual(x, blocks)
    J_new = np.hstack([J, jacobian(problem, x, blocks, range(len(current.x), len(x)))])
    if named(block.effect).widens_prior:  # the widened prior's rows: ∂(τ_k / t_k)/∂τ_k = 1/t_k
        scale = np.where(problem.released(blocks), MISALIGNMENT, problem.transverse)
        rows = np.arange(len(r) - problem.n_tau, len(r))
        J_new[rows, problem.model.p + np.arange(problem.n_tau)] = np.repeat(1 / scale, 2)
    if not (np.isfinite(J_new).all() and np.isfinite(r).all()):
        return -np.inf  # a block the current fit cannot even linearise: never ranked
    try:
        step, *_ = np.linalg.lstsq(J_new, r, rcond=None)
    except np.linalg.LinAlgError:
        return -np.inf
    return float(r_now @ r_now - np.sum((r - J_new @ step) ** 2))


def penalty(problem: Problem, block: Block) -> float:
    """What ``block`` adds to the BIC besides χ²: k ln n, or the Occam factor of a widened axis prior."""
    if named(block.effect).widens_prior:
        return 2 * len(problem.layout.groups[block.target]) * 2 * np.log(MISALIGNMENT / problem.transverse)
    return problem.layout.size(block) * np.log(problem.n_values)


def with_model_form(result: Fit, other: Fit) -> Fit:
    """``result`` with the spread between two tail models added to θ's covariance.

    A single shared mode is the tail's physics when one support or elastic mode dominates; each
    FRF's own first- and second-order tails are the model-free alternative. Where they disagree
    the data cannot choose, and the difference is as much the properties' uncertainty as the noise.
    """
    p = result.problem.model.p
    delta = other.x[:p] - result.x[:p]
    spread = result.spread.copy()
    spread[: len(delta), : len(delta)] += np.outer(delta, delta)
    return replace(result, spread=spread)


def rigid_tail(laws) -> bool:
    """Whether one of the tail ``laws`` can be the rigid body's own, s_iᵀ X e_j (the support's)."""
    return any(named(law).rigid_tail for law in laws)


def problem_for(band: BandData, layout: Layout, laws, model: RigidModel, transverse: float, shared=False) -> Problem:
    """The fit problem on ``band`` with the tail ``laws`` (or "free": identify's per-FRF tails); ``shared``: the
    support's tail is the rigid body's, s_iᵀ X e_j, on the model's lines (:mod:`massline.identify.tails`)."""
    if laws == "free":
        data = band.free
    else:
        data = band.shared_support(laws) if shared and rigid_tail(laws) else band.reduced(laws)
    return Problem(layout, data, band.noise, model, transverse, band.n_values, band.energy)


def starting_point(masslines: Masslines, sigma: np.ndarray, layout: Layout, transverse: float) -> RigidBody:
    """A body to start the fit from: the weighted estimate, else the paper's, else one of the data's scale
    (data with a gross fault may admit no body at all)."""
    for attempt in (
        lambda: estimate(masslines, sigma, layout.planar, 0.0 if layout.planar else transverse).body,
        lambda: starting_body(masslines, layout.planar),
    ):
        try:
            with np.errstate(invalid="ignore"):  # data with a gross fault can drive the estimate through no-bodies
                body = attempt()
            if is_body(body):
                return body
        except (np.linalg.LinAlgError, MasslineError, *solver_errors()):
            continue
    mass = 1 / np.median(np.abs(masslines.values))
    return RigidBody(mass, layout.sensors.points.mean(axis=0), mass * layout.extent**2 * np.eye(3))


def base_fit(band: BandData, layout: Layout, laws: frozenset, transverse: float) -> Fit:
    """The nominal model fitted (no effects), started from ``starting_point``."""
    data = band.reduced(laws)
    masslines = Masslines(data.massline, layout.sensors, layout.exciters)
    start = starting_point(masslines, band.noise / np.sqrt(data.kappa), layout, transverse)
    return fit(problem_for(band, layout, laws, RigidModel(start, layout.planar), transverse))


def refit(current: Fit, band: BandData, laws: frozenset, blocks, shared: bool = False) -> Fit:
    """The model with ``laws`` and ``blocks`` (the support's tail ``shared`` or per FRF), started from ``current``."""
    lay, model, transverse = current.problem.layout, current.problem.model, current.problem.transverse
    return fit(problem_for(band, lay, laws, model, transverse, shared), blocks, current)


def plausible(result: Fit, block: Block) -> bool:
    """Fitted values a technician could have produced (notes §6: angles, gains, offsets within reason), as
    the block's effect judges them."""
    theta, tau, values = result.parts
    return named(block.effect).plausible(result, block, values[result.blocks.index(block)], tau)
