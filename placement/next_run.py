"""The next run from the first: the layout a recording measured, fixed, its information the prior, and the
cheapest additions that cut one property's 1-σ.

The first run's information is the one identify's estimator draws from it (identify/estimator.py): each
massline H_ij with the 1-σ σ_ij of its band fit, and each accelerometer's two transverse components τ_i
(prior 1-σ t, the datasheet's transverse sensitivity) estimated beside the parameters. In the augmented
parameters (θ̃, τ)

    F = Σ_ij g̃_ij g̃_ijᵀ / σ_ij² + diag(0, I/t²),   g̃_ij = (∂H_ij/∂θ̃, ∂H_ij/∂τ_i),

where ∂H_ij/∂τ_ia is the massline from exciter j to the transverse line (t_ia through sensor i's point); the
parameters' covariance is the θ̃ block of F⁻¹ (the τ marginalised). A second run repeats every pair of the
first (the accelerometers stay on, the hits are repeated) and measures the additions' pairs, at the first
run's noise (:meth:`Measured.noise`); the runs' information adds, each accelerometer's τ shared by both.
A property's 1-σ is √(jᵀ C j), j its gradient in θ̃ (:func:`massline.core.accuracy.property_covariance`).

An accelerometer moved in the second run costs what one added costs (a channel) and gives what it gives (the
first run's readings stay in the merged data), so the proposals add. The search is the planner's
(:mod:`.selection`): the additions of one kind are blocks of information on the fixed first run, grown greedily
by the target's criterion and exchanged (:func:`.selection.swap`) until no exchange helps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import nnls

from massline.core.accuracy import covariance_std, property_jacobian
from massline.core.errors import MasslineError
from massline.core.information import NoiseModel, sensitivities
from massline.core.lines import Lines, perpendicular_bases
from massline.core.model import RigidModel
from massline.core.properties import property_vector
from massline.placement.admissible import regular
from massline.placement.criteria import Criterion
from massline.placement.footprints import Footprint, Sites, accelerometers, hits_blocked, sensors_blocked
from massline.placement.mountable import SNAP_TOLERANCE, closest_on_surface
from massline.placement.selection import BlockProblem, swap

# property name → its entry of core.properties.property_vector
TARGETS = {
    "mass": 0, "cog_x": 1, "cog_y": 2, "cog_z": 3, "Jxx": 4, "Jxy": 5, "Jxz": 6, "Jyy": 8, "Jyz": 9, "Jzz": 12,
    "J1": 13, "J2": 14, "J3": 15,
}  # fmt: skip
PLATE_TARGETS = ("mass", "cog_x", "cog_y", "Jxx", "Jxy", "Jyy", "J1", "J2")
SHAPES = ((1, 0), (0, 1), (2, 0), (0, 2), (1, 1), (3, 0))  # (accelerometers, hits) a proposal adds
SINGULAR = 1e12  # condition number of the augmented information above which some parameter is not identified


@dataclass(frozen=True, eq=False, kw_only=True)
class Measured:
    """A first run as identify sees it: its lines (m, mesh frame), each massline's |H| and 1-σ σ_ij ((m/s²)/N, inf
    where no massline was measured), and the transverse-sensitivity prior t (fraction)."""

    sensors: Lines
    exciters: Lines
    magnitude: np.ndarray
    sigma: np.ndarray
    transverse: float

    def noise(self, mass: float) -> NoiseModel:
        """The noise model σ² = (r |H|)² + (f/m)² fitted (non-negative least squares) to the measured σ_ij: what a
        second run's masslines carry when it is measured as the first was."""
        ok = np.isfinite(self.sigma) & np.isfinite(self.magnitude)
        design = np.column_stack([self.magnitude[ok] ** 2, np.full(ok.sum(), 1.0 / mass**2)])
        (r2, f2), _ = nnls(design / self.sigma[ok, None] ** 2, np.ones(ok.sum()))  # relative misfit of σ²
        return NoiseModel(float(np.sqrt(r2)), float(np.sqrt(f2)))


@dataclass(frozen=True, eq=False)
class Room:
    """Where additions fit (:mod:`.footprints`): the body's mesh (m), the base and tip, and each candidate
    accelerometer's and hit's site (its point and outward normal)."""

    mesh: object
    footprint: Footprint
    sensors: Sites
    hits: Sites

    def sites(self, lines: Lines) -> Sites:
        """The sites of ``lines`` already placed: each point with its nearest face's outward normal."""
        faces = [closest_on_surface(self.mesh, p)[1] for p in lines.points]
        return Sites(lines.points.reshape(-1, 3), self.mesh.face_normals[faces].reshape(-1, 3))

    def free(self, side: str, S: Lines, E: Lines) -> np.ndarray:
        """(n,) bool: the candidates of ``side`` that clear the footprints of the accelerometers ``S`` (and, for
        an accelerometer, the hits ``E``)."""
        placed = accelerometers(self.sites(S))
        if side == "hits":
            return ~hits_blocked(self.hits, placed, self.footprint)
        return ~sensors_blocked(self.sensors, placed, self.sites(E), self.footprint)


def transverse_masslines(model: RigidModel, sensors: Lines, exciters: Lines) -> np.ndarray:
    """∂H_ij/∂τ_ia (n_s, n_e, 2): the massline from each exciter to each sensor's two transverse lines."""
    T = perpendicular_bases(sensors.directions)
    return np.stack(
        [sensitivities(model, model.coordinates(Lines(sensors.points, T[:, :, a])),
                       model.coordinates(exciters))[1] for a in range(2)], axis=2,
    )  # fmt: skip


def pair_rows(model: RigidModel, sensors: Lines, exciters: Lines, sigma: np.ndarray, per: int = 2) -> np.ndarray:
    """g̃_ij / σ_ij (n_s, n_e, p + per·n_s): each pair's row in the augmented parameters (θ̃, τ_1, …, τ_n_s), ``per``
    transverse components a sensor (2, or 0 where identify fits none: a plate); zero where σ_ij is inf (a pair
    not measured)."""
    G, _ = sensitivities(model, model.coordinates(sensors), model.coordinates(exciters))
    n_s, n_e = len(sensors), len(exciters)
    tau = np.zeros((n_s, n_e, per * n_s))
    if per:
        Ht = transverse_masslines(model, sensors, exciters)
        for i in range(n_s):
            tau[i, :, 2 * i : 2 * i + 2] = Ht[i]
    return np.concatenate([G, tau], axis=2) / sigma[..., None]


def run_sigma(model: RigidModel, sensors: Lines, exciters: Lines, noise: NoiseModel) -> np.ndarray:
    """σ_ij (n_s, n_e) of every pair of a run measured at ``noise``."""
    _, H = sensitivities(model, model.coordinates(sensors), model.coordinates(exciters))
    return noise.sigma(H, model.nominal.mass)


@dataclass(frozen=True, eq=False, kw_only=True)
class Runs:
    """The two runs: the first as measured, the second (its lines: the first's, then the additions) at ``noise``."""

    model: RigidModel
    first: Measured
    noise: NoiseModel

    @property
    def per(self) -> int:
        """Transverse components fitted a sensor: 2, none on a plate (§2.3: identify fits its z-lines as given)."""
        return 0 if self.model.planar or self.first.transverse <= 0 else 2

    def information(self, sensors: Lines, exciters: Lines, second: bool = True) -> np.ndarray:
        """F in (θ̃, τ) of the first run and (``second``) a second run of ``sensors`` × ``exciters`` (the first's
        lines first), τ of every sensor line of ``sensors``."""
        n1s, n1e, n = len(self.first.sensors), len(self.first.exciters), len(sensors)
        sigma1 = np.full((n, len(exciters)), np.inf)
        sigma1[:n1s, :n1e] = self.first.sigma
        rows = pair_rows(self.model, sensors, exciters, sigma1, self.per).reshape(-1, self.model.p + self.per * n)
        if second:
            sigma2 = run_sigma(self.model, sensors, exciters, self.noise)
            more = pair_rows(self.model, sensors, exciters, sigma2, self.per)
            rows = np.vstack([rows, more.reshape(rows.shape[0], -1)])
        prior = np.r_[np.zeros(self.model.p), np.full(self.per * n, 1 / max(self.first.transverse, 1e-300) ** 2)]
        return rows.T @ rows + np.diag(prior)


def scales(model: RigidModel) -> np.ndarray:
    """What each property's 1-σ is relative to (25,): the mass, the radius of gyration, the largest moment."""
    b = model.nominal
    moment = float(np.max(b.principal_moments))
    return np.r_[b.mass, np.full(3, b.radius_of_gyration), np.full(9, moment), np.full(3, moment), np.ones(9)]


def regularised(F: np.ndarray) -> np.ndarray:
    """F + ε I, ε 1e-12 of its mean diagonal: invertible where F is singular (an unseen motion then gets a
    1-σ of order 1e6 of the others)."""
    return F + 1e-12 * max(np.trace(F) / len(F), 1e-300) * np.eye(len(F))


def target_std(model: RigidModel, F: np.ndarray, index: int) -> float:
    """1-σ of property ``index`` (its unit) from the augmented information F."""
    j = np.r_[property_jacobian(model)[index], np.zeros(len(F) - model.p)]
    return float(np.sqrt(max(j @ np.linalg.solve(regularised(F), j), 0.0)))


def worst_target(model: RigidModel, F: np.ndarray) -> str:
    """The name of the property of largest relative 1-σ (mass, CoG, principal moments) under F."""
    names = [n for n in ("mass", "cog_x", "cog_y", "cog_z", "J1", "J2", "J3") if n in allowed_targets(model)]
    C = np.linalg.inv(regularised(F))[: model.p, : model.p]
    J, s = property_jacobian(model), scales(model)
    rel = [np.sqrt(max(J[TARGETS[n]] @ C @ J[TARGETS[n]], 0.0)) / s[TARGETS[n]] for n in names]
    return names[int(np.argmax(rel))]


def allowed_targets(model: RigidModel) -> tuple:
    return PLATE_TARGETS if model.planar else tuple(TARGETS)


def check_target(model: RigidModel, target: str | None) -> None:
    """Refuse a ``target`` that names no property the layout identifies."""
    if target is not None and target not in allowed_targets(model):
        raise MasslineError(
            f"--target {target}: not a property of this body; give one of {', '.join(allowed_targets(model))}"
        )


def c_criterion(j: np.ndarray) -> Criterion:
    """−jᵀ M⁻¹ j (the target's variance, negated: to maximise) and its value after each block (Woodbury)."""

    def value(M):
        return float(-j @ np.linalg.solve(regularised(M), j))

    def scores(blocks, M):
        Minv = np.linalg.inv(regularised(M))
        u = blocks @ (Minv @ j)  # (n, r)
        K = blocks @ Minv @ blocks.transpose(0, 2, 1) + np.eye(blocks.shape[1])
        return -(j @ Minv @ j) + np.einsum("nr,nr->n", u, np.linalg.solve(K, u[..., None])[..., 0])

    return Criterion("C", "−jᵀF⁻¹j", value, scores, lambda v, U, p: float(U / v) if v < 0 else 0.0)


def hit_blocks(runs: Runs, sensors: Lines, candidates: Lines) -> np.ndarray:
    """Each candidate hit's rows (n, n_s, dim) in the augmented parameters of ``sensors``: its column in both
    runs' second (the first did not measure it)."""
    sigma = run_sigma(runs.model, sensors, candidates, runs.noise)
    return pair_rows(runs.model, sensors, candidates, sigma, runs.per).transpose(1, 0, 2)


def sensor_blocks(runs: Runs, exciters: Lines, candidates: Lines, dim: int) -> np.ndarray:
    """Each candidate accelerometer's rows (n, n_e, dim) on θ̃, its own τ marginalised: its row of the second run
    seen through (I − D(DᵀD + I/t²)⁻¹Dᵀ)^½, D its (n_e, 2) transverse masslines over σ."""
    model = runs.model
    sigma = run_sigma(model, candidates, exciters, runs.noise)
    G, _ = sensitivities(model, model.coordinates(candidates), model.coordinates(exciters))
    if not runs.per:
        return np.concatenate([G / sigma[..., None], np.zeros((len(candidates), len(exciters), dim - model.p))], 2)
    D = transverse_masslines(model, candidates, exciters) / sigma[..., None]
    inner = np.linalg.inv(D.transpose(0, 2, 1) @ D + np.eye(2) / runs.first.transverse**2)
    P = np.eye(len(exciters)) - D @ inner @ D.transpose(0, 2, 1)
    w, V = np.linalg.eigh(P)
    root = V * np.sqrt(np.clip(w, 0, None))[:, None, :] @ V.transpose(0, 2, 1)
    rows = root @ (G / sigma[..., None])
    return np.concatenate([rows, np.zeros((len(candidates), len(exciters), dim - model.p))], axis=2)


def chosen(problem: BlockProblem, count: int) -> list:
    """``count`` blocks grown greedily by the problem's criterion, then exchanged until none helps."""
    picked = []
    for _ in range(count):
        free = problem.free(picked)
        M = problem.information(picked)
        index = np.flatnonzero(free)
        picked.append(int(index[np.argmax(problem.criterion.scores(problem.blocks[index], M))]))
    return swap(problem, picked)


@dataclass(frozen=True, eq=False, kw_only=True)
class Proposal:
    """An addition: the accelerometer lines and hits it adds (m, mesh frame), the target's 1-σ after both runs."""

    sensors: Lines
    exciters: Lines
    std_after: float

    @property
    def items(self) -> int:
        return len(self.sensors) + len(self.exciters)


def proposals(
    runs: Runs, index: int, sensor_candidates: Lines, hit_candidates: Lines, most: int, room: Room | None = None
) -> list[Proposal]:
    """The best addition of each shape of at most ``most`` items, by the 1-σ of property ``index`` after both
    runs, best first (those after which the paper's equations still cannot solve the layout last: a first run that
    lost a line is restored first). One kind is searched as one selection problem; a mixed one adds the
    accelerometer first, then the hit through every sensor; where the first run lost a line, accelerometers are
    chosen among those that restore it."""
    first = runs.first
    found = []
    for n_s, n_e in (s for s in SHAPES if sum(s) <= most):
        S, E = first.sensors, first.exciters
        if n_s:
            S = S + select(runs, index, S, E, sensor_candidates, n_s, "sensors", room)
        if n_e:
            E = E + select(runs, index, S, E, hit_candidates, n_e, "hits", room)
        std = target_std(runs.model, runs.information(S, E), index)
        found.append(Proposal(sensors=S[len(first.sensors):], exciters=E[len(first.exciters):], std_after=std))
    return sorted(found, key=lambda p: (not regular(runs.model, first.sensors + p.sensors, first.exciters + p.exciters),
                                        p.std_after, p.items))  # fmt: skip


def select(
    runs: Runs, index: int, S: Lines, E: Lines, candidates: Lines, count: int, side: str, room: Room | None = None
) -> Lines:
    """The ``count`` candidate lines of ``side`` that most cut property ``index``'s 1-σ, added to S × E, clear of
    the footprints of what is placed and of each other (``room``; None: anywhere)."""
    F = runs.information(S, E)
    dim = len(F)
    blocks = hit_blocks(runs, S, candidates) if side == "hits" else sensor_blocks(runs, E, candidates, dim)
    j = np.r_[property_jacobian(runs.model)[index], np.zeros(dim - runs.model.p)]
    allowed = np.ones(len(candidates), bool) if room is None else room.free(side, S, E)
    if side == "sensors" and not regular(runs.model, S, E):  # a lost line: only those that restore the layout
        restoring = allowed & [regular(runs.model, S + candidates[[k]], E) if ok else False
                               for k, ok in enumerate(allowed)]  # fmt: skip
        allowed = restoring if restoring.any() else allowed
    spread = {} if room is None or side == "hits" else {"sites": candidates.points, "spacing": room.footprint.sensor_base}
    problem = BlockProblem(blocks, np.zeros(len(blocks), int), (count,), F, criterion=c_criterion(j), allowed=allowed,
                           **spread)  # fmt: skip
    return candidates[np.array(chosen(problem, count))]


def check_on_surface(mesh, lines: Lines, labels: list, what: str, tolerance: float = SNAP_TOLERANCE) -> None:
    """Refuse a recorded line whose point (m, the recording's frame) lies farther than ``tolerance`` (m) from the
    mesh's surface (m, mesh frame): the recording was not measured on this body, or not in its frame."""
    for point, label in zip(lines.points, labels):
        distance = float(np.linalg.norm(closest_on_surface(mesh, point)[0] - point))
        if distance > tolerance:
            where = ", ".join(f"{1e3 * c:.4g}" for c in point)
            raise MasslineError(
                f"the recording's {what} {label} at ({where}) mm is {1e3 * distance:.3g} mm from the mesh's surface "
                f"(more than {1e3 * tolerance:g} mm): give the mesh the recording was measured on, in its units"
            )


@dataclass(frozen=True, eq=False, kw_only=True)
class NextRun:
    """The first run fixed and the additions proposed: the target property, its 1-σ after the first run alone
    (inf: not identified) and after repeating it unchanged, and the proposals, best first."""

    runs: Runs
    target: str
    std_before: float
    std_repeated: float
    proposals: list

    @property
    def identified(self) -> bool:
        """Does the first run identify the body: the paper's equations solve its layout, its information regular?"""
        S, E = self.runs.first.sensors, self.runs.first.exciters
        return regular(self.runs.model, S, E) and identifies(self.runs.model, self.runs.information(S, E, False))

    def std_after_both(self, proposal: Proposal) -> dict:
        """Every property's 1-σ (identify's std keys, SI) after the first run and a second with ``proposal``."""
        S, E = self.runs.first.sensors + proposal.sensors, self.runs.first.exciters + proposal.exciters
        p = self.runs.model.p
        return covariance_std(self.runs.model, np.linalg.inv(regularised(self.runs.information(S, E)))[:p, :p])

    def restores(self, proposal: Proposal) -> bool:
        """Does ``proposal`` identify every parameter where the first run did not?"""
        S, E = self.runs.first.sensors + proposal.sensors, self.runs.first.exciters + proposal.exciters
        model = self.runs.model
        return not self.identified and regular(model, S, E) and identifies(model, self.runs.information(S, E))


def identifies(model: RigidModel, F: np.ndarray) -> bool:
    """The θ̃ block of F⁻¹ finite: F regular (condition below 1/ε of double precision's reach)."""
    return bool(np.linalg.cond(F) < SINGULAR)


def plan_next_run(
    model: RigidModel, first: Measured, candidates: tuple[Lines, Lines], target: str | None = None, most: int = 2,
    room: Room | None = None,
) -> NextRun:
    """The additions (accelerometer and hit ``candidates`` (m, mesh frame), at most ``most`` items, clear of the
    footprints ``room`` says) that most cut the 1-σ of ``target`` (a :data:`TARGETS` name; None: the property of
    largest relative 1-σ after the first run) when a second run repeats the ``first`` with them (module
    docstring)."""  # fmt: skip
    check_target(model, target)
    runs = Runs(model=model, first=first, noise=first.noise(model.nominal.mass))
    S, E = first.sensors, first.exciters
    prior = runs.information(S, E, second=False)
    target = target or worst_target(model, prior)
    index = TARGETS[target]
    before = target_std(model, prior, index) if regular(model, S, E) and identifies(model, prior) else float("inf")
    repeated = target_std(model, runs.information(S, E), index)
    found = proposals(runs, index, *candidates, most, room)
    return NextRun(runs=runs, target=target, std_before=before, std_repeated=repeated, proposals=found)
