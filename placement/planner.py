"""The pre-test planner: the sensor and exciter layout of greatest information.

    maximise over S, E   log det F(S, E),   F = Σ_{i∈S, j∈E} g_ij g_ijᵀ / σ_ij²

F is linear in the sensors for fixed exciters and vice versa, so the layout is
found by alternating the two selection problems (greedy, then exchanges), from
several starts, until neither side improves. Each side's convex relaxation
bounds the best layout from above; the plan states the certified D-efficiency
exp((log det F − U)/p) of the worse side. Only layouts that the paper's
equations can solve are admitted (rank S = 6, non-singular dynamic systems).
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

from .accuracy import predicted_std, worst_relative_std
from .candidates import CandidateOptions, CandidatePoints, candidate_points
from .errors import MasslineError, SingularLayoutError
from .information import NoiseModel, log_det, weighted_sensitivities
from .lines import Lines
from .masslines import synthesise
from .mesh import BodyMesh
from .methods import identify
from .model import RigidModel
from .certificate import certify_admissible
from .relaxation import relax_cvxpy, relax_first_order
from .selection import BlockProblem, greedy, swap

PLATE_THINNESS = 0.05  # thickness / size below which a body normal to z is planned as a plate


@dataclass(frozen=True)
class Budget:
    """Uniaxial sensor lines, triaxial accelerometers and exciters (hammer hits)."""

    sensors: int = 6
    exciters: int = 3
    triaxial: int = 0

    def check(self, planar: bool) -> None:
        lines = self.sensors + 3 * self.triaxial
        need = 3 if planar else 6
        if lines < need:
            raise MasslineError(
                f"{lines} sensor lines cannot see the {'3 plate' if planar else '6 rigid-body'} motions: "
                f"give at least {need} (--sensors, or --triaxial N for 3 lines each)"
            )
        if self.triaxial == 2 and self.sensors == 0:
            raise MasslineError(
                "two triaxial accelerometers alone never see rotation about the line joining them: "
                "add a third triaxial (--triaxial 3) or uniaxial sensors (--sensors)"
            )
        if self.exciters < 3:
            raise MasslineError(f"{self.exciters} exciter(s) are too few: the paper's minimum is 3 (--exciters 3)")
        if planar and self.triaxial:
            raise MasslineError("a plate is planned with out-of-plane lines (§2.3): drop --triaxial")


@dataclass(frozen=True, eq=False)
class Plan:
    """A layout with its certificate and predicted accuracy.

    ``sensor_nodes`` / ``exciter_nodes`` index the candidate points.
    ``bounds`` holds the relaxation's upper bound U for each side.
    """

    model: RigidModel
    sensors: Lines
    sensor_nodes: np.ndarray
    exciters: Lines
    exciter_nodes: np.ndarray
    log_det: float
    bounds: dict
    condition: dict
    predicted_std: dict
    noise: NoiseModel
    candidates: CandidatePoints | None = None
    n_candidate_lines: dict = field(default_factory=dict)

    @property
    def d_efficiency_lower_bound(self) -> float:
        """exp((log det F − U)/p) for the worse of the two sides."""
        return float(np.exp((self.log_det - max(self.bounds.values())) / self.model.p))

    @property
    def worst_relative_std(self) -> float:
        return worst_relative_std(self.model, self.predicted_std)


def is_plate(body: BodyMesh) -> bool:
    """Thin along z, with z a principal axis: the paper's §2.3 case."""
    extents = body.mesh.extents
    J = body.nominal.inertia_cog
    thin = extents[2] < PLATE_THINNESS * extents[:2].max()
    return bool(thin and np.abs(J[2, :2]).max() <= 1e-9 * np.abs(J).max() and abs(body.nominal.cog[2]) < 1e-9 * extents.max())


@dataclass(frozen=True, eq=False)
class CandidateLines:
    """Candidates of one side: their lines, the lines each candidate is made of
    (one, or three for a triaxial), its budget group (0 uniaxial, 1 triaxial) and
    the candidate point (node) of each line."""

    lines: Lines
    members: list
    group: np.ndarray
    node: np.ndarray

    @classmethod
    def single(cls, lines: Lines) -> "CandidateLines":
        """Every line a candidate of its own (group 0, node = its index)."""
        n = len(lines)
        return cls(lines, [[i] for i in range(n)], np.zeros(n, int), np.arange(n))


def _compress(blocks: np.ndarray) -> np.ndarray:
    """Blocks with more rows than parameters replaced by p rows of the same information."""
    n, r, p = blocks.shape
    if r <= p:
        return blocks
    G = np.einsum("nrp,nrq->npq", blocks, blocks)
    w, V = np.linalg.eigh(G)
    return np.sqrt(np.clip(w, 0, None))[:, :, None] * V.transpose(0, 2, 1)


class Planner:
    """Alternating D-optimal selection of sensors and exciters on one model."""

    def __init__(self, model: RigidModel, sensor_side: CandidateLines, exciter_side: CandidateLines, budget: Budget,
                 noise: NoiseModel, fixed_sensors: Lines | None = None, fixed_exciters: Lines | None = None):
        self.model, self.budget, self.noise = model, budget, noise
        self.s, self.e = sensor_side, exciter_side
        self.s_coords = model.coordinates(sensor_side.lines)
        self.e_coords = model.coordinates(exciter_side.lines)
        empty = np.zeros((0, self.s_coords.shape[1]))
        self.fixed_sensors, self.fixed_exciters = fixed_sensors, fixed_exciters
        self.fixed_s = empty if fixed_sensors is None else model.coordinates(fixed_sensors)
        self.fixed_e = empty if fixed_exciters is None else model.coordinates(fixed_exciters)

    # one side's selection problem, the other side fixed
    def _problem(self, side: CandidateLines, coords: np.ndarray, other: np.ndarray, fixed: np.ndarray,
                 budgets: tuple, sensors_side: bool) -> BlockProblem:
        def sens(a, b):
            g = weighted_sensitivities(self.model, a, b, self.noise)
            return g if sensors_side else g.transpose(1, 0, 2)

        per_line = sens(coords, other) if sensors_side else sens(other, coords)
        r = max(len(m) for m in side.members) * per_line.shape[1]
        blocks = np.zeros((len(side.members), r, self.model.p))
        for k, m in enumerate(side.members):
            rows = per_line[m].reshape(-1, self.model.p)
            blocks[k, : len(rows)] = rows
        A0 = (sens(fixed, other) if sensors_side else sens(other, fixed)).reshape(-1, self.model.p)
        return BlockProblem(_compress(blocks), side.group, budgets, A0.T @ A0)

    def sensor_problem(self, exciter_rows: np.ndarray) -> BlockProblem:
        other = np.vstack([self.fixed_e, exciter_rows])
        return self._problem(self.s, self.s_coords, other, self.fixed_s, (self.budget.sensors, self.budget.triaxial), True)

    def exciter_problem(self, sensor_rows: np.ndarray) -> BlockProblem:
        other = np.vstack([self.fixed_s, sensor_rows])
        return self._problem(self.e, self.e_coords, other, self.fixed_e, (self.budget.exciters,), False)

    def sensor_rows(self, chosen) -> np.ndarray:
        return self.s_coords[np.concatenate([self.s.members[c] for c in chosen])] if len(chosen) else self.fixed_s[:0]

    def exciter_rows(self, chosen) -> np.ndarray:
        return self.e_coords[[self.e.members[c][0] for c in chosen]]

    def lines(self, side: CandidateLines, chosen) -> Lines:
        index = np.concatenate([side.members[c] for c in chosen])
        return side.lines[index]

    def sensor_cover(self, exciters: list):
        """Cover sets for the sensor side: candidates that see a motion the selection leaves unseen."""
        def cover_for(sensors: list):
            rows = np.vstack([self.fixed_s, self.sensor_rows(sensors)])
            _, s, Vt = np.linalg.svd(rows)
            if len(s) == rows.shape[1] and s[-1] > 1e-10 * s[0]:
                return None  # all motions seen: the failure lies elsewhere, no cut known
            q0 = Vt[-1]
            sees = np.abs(self.s_coords @ q0) > 1e-9 * np.linalg.norm(self.s_coords, axis=1)
            return np.array([sees[m].any() for m in self.s.members])
        return cover_for

    def exciter_cover(self, exciters: list):
        """Cover set for the exciter side: when all hits are parallel, the hits that are not."""
        lines = self.layout([], exciters)[1]
        d = lines.directions[0]
        if np.linalg.norm(np.cross(lines.directions, d), axis=1).max() > 1e-9:
            return None
        off = np.linalg.norm(np.cross(self.e.lines.directions, d), axis=1) > 1e-9
        return np.array([off[m].any() for m in self.e.members])

    def regular(self, sensors: Lines, exciters: Lines) -> bool:
        """The paper's equations solve this layout (exact masslines identify the body)."""
        try:
            identify(synthesise(self.model.nominal, sensors, exciters), "plate" if self.model.planar else "method2")
        except SingularLayoutError:
            return False
        return True

    def layout(self, sensors, exciters) -> tuple[Lines, Lines]:
        """All sensor and exciter lines of a selection, fixed ones first."""
        S, E = self.lines(self.s, sensors), self.lines(self.e, exciters)
        return (S if self.fixed_sensors is None else self.fixed_sensors + S,
                E if self.fixed_exciters is None else self.fixed_exciters + E)

    def alternate(self, exciters: list, sensors: list | None = None, rounds: int = 12) -> tuple[list, list, float]:
        """Sensors for the exciters, exciters for the sensors, … until both are stable."""
        value = -np.inf
        for _ in range(rounds):
            sp = self.sensor_problem(self.exciter_rows(exciters))
            admissible_s = lambda c: self.regular(*self.layout(c, exciters))  # noqa: E731
            sensors = swap(sp, sensors if sensors else greedy(sp), admissible_s)
            ep = self.exciter_problem(self.sensor_rows(sensors))
            admissible_e = lambda c: self.regular(*self.layout(sensors, c))  # noqa: E731
            new_exciters = swap(ep, exciters if len(exciters) == self.budget.exciters else greedy(ep), admissible_e)
            new_value = ep.value(new_exciters)
            if new_value <= value + 1e-9:
                break
            exciters, value = new_exciters, new_value
        return sensors, exciters, value

    def starts(self, n_random: int, seed: int) -> list:
        """Exciter sets to start from: greedy against a spread of reference sensors, and random ones."""
        rng = np.random.default_rng(seed)
        n_ref = min(len(self.s.members), 200)
        reference = rng.choice(len(self.s.members), n_ref, replace=False)
        ep = self.exciter_problem(self.sensor_rows(reference))
        starts = [greedy(ep)]
        starts += [list(rng.choice(len(self.e.members), self.budget.exciters, replace=False)) for _ in range(n_random)]
        return starts


TARGET_EFFICIENCY = 0.99  # branch and bound stops once the certificate reaches this


def certify(problem: BlockProblem, chosen: list, relaxation: str = "first-order", admissible=None, cover_for=None,
            seconds: float = 10.0) -> tuple[float, list]:
    """Upper bound U on ``problem`` over the admissible selections, and the best one met.

    The relaxation's bound first; when it leaves the per-parameter D-efficiency
    below TARGET_EFFICIENCY (small budgets), branch and bound and admissibility
    cuts tighten it (certificate.py).
    """
    if relaxation == "cvxpy":
        return relax_cvxpy(problem)[1], chosen
    _, bound = relax_first_order(problem, chosen)
    slack = problem.p * np.log(1 / TARGET_EFFICIENCY)
    if bound - problem.value(chosen) <= slack:
        return bound, chosen
    return certify_admissible(problem, chosen, slack, admissible or (lambda c: True), cover_for or (lambda c: None),
                              seconds)


def candidate_lines(points: CandidatePoints, axes: bool, planar: bool, triaxial: bool) -> tuple[CandidateLines, CandidateLines]:
    if planar:
        on_faces = np.abs(points.normals[:, 2]) > 1 - 1e-6
        if on_faces.sum() < 3:
            raise MasslineError("fewer than 3 candidate points on the plate's faces: relax the exclusions")
        pts = points.points[on_faces]
        lines = Lines(pts, np.tile([0.0, 0.0, 1.0], (len(pts), 1)))
        node = np.flatnonzero(on_faces)
        side = CandidateLines(lines, [[i] for i in range(len(lines))], np.zeros(len(lines), int), node)
        return side, side
    lines, node = points.lines(axes)
    members = [[i] for i in range(len(lines))]
    group = np.zeros(len(lines), int)
    sensor_lines, sensor_node = lines, node
    if triaxial:
        tri, tri_node = points.triaxial_lines()
        offset = len(lines)
        members += [[offset + 3 * k, offset + 3 * k + 1, offset + 3 * k + 2] for k in range(len(points))]
        group = np.concatenate([group, np.ones(len(points), int)])
        sensor_lines, sensor_node = lines + tri, np.concatenate([node, tri_node])
    sensors = CandidateLines(sensor_lines, members, group, sensor_node)
    exciters = CandidateLines(lines, [[i] for i in range(len(lines))], np.zeros(len(lines), int), node)
    return sensors, exciters


def plan_on_candidates(model: RigidModel, sensor_side: "CandidateLines", exciter_side: "CandidateLines",
                       budget: Budget, noise: NoiseModel = NoiseModel(), fixed_sensors: Lines | None = None,
                       fixed_exciters: Lines | None = None, relaxation: str = "first-order", starts: int = 3,
                       seed: int = 0, progress: Callable[[str, float], None] = lambda stage, fraction: None) -> Plan:
    """The best layout of ``budget`` among given candidate lines, certified, with predicted 1-σ."""
    budget.check(model.planar)
    for name, side, need in (("sensor", sensor_side, budget.sensors), ("exciter", exciter_side, budget.exciters)):
        if len(side.members) < need:
            raise MasslineError(f"only {len(side.members)} {name} candidates for a budget of {need}: "
                                "sample more points (--candidates) or relax the exclusions")
    planner = Planner(model, sensor_side, exciter_side, budget, noise, fixed_sensors, fixed_exciters)
    best = None
    start_sets = planner.starts(starts - 1, seed)
    for k, start in enumerate(start_sets):
        progress("alternating sensors and exciters", 0.8 * k / len(start_sets))
        result = planner.alternate(start)
        if best is None or result[2] > best[2]:
            best = result
    sensors, exciters, value = best

    def self_regular(s, e):
        return planner.regular(*planner.layout(s, e))

    if not self_regular(sensors, exciters):
        raise MasslineError("the candidates and keep-outs leave only degenerate layouts: allow points that are "
                            "not all in one line or plane, and hits in several directions")
    for _ in range(3):
        progress("certifying", 0.85)
        sp = planner.sensor_problem(planner.exciter_rows(exciters))
        ep = planner.exciter_problem(planner.sensor_rows(sensors))
        U_s, better_s = certify(sp, sensors, relaxation, lambda c: self_regular(c, exciters),
                                planner.sensor_cover(exciters))
        U_e, better_e = certify(ep, exciters, relaxation, lambda c: self_regular(sensors, c), planner.exciter_cover)
        improved = [(sp.value(better_s), better_s, exciters), (ep.value(better_e), sensors, better_e)]
        improved = [c for c in improved if c[0] > value + 1e-9 and planner.regular(*planner.layout(c[1], c[2]))]
        if not improved:
            break
        # the certificate's search met a better layout: adopt it and settle both sides again
        _, start_s, start_e = max(improved, key=lambda c: c[0])
        sensors, exciters, value = planner.alternate(start_e, start_s)
    S_all, E_all = planner.layout(sensors, exciters)
    F = ep.information(exciters)
    found = identify(synthesise(model.nominal, S_all, E_all), "plate" if model.planar else "method2")
    progress("done", 1.0)
    return Plan(model, planner.lines(sensor_side, sensors),
                sensor_side.node[np.concatenate([sensor_side.members[c] for c in sensors])],
                planner.lines(exciter_side, exciters), exciter_side.node[[exciter_side.members[c][0] for c in exciters]],
                log_det(F), {"sensors": U_s, "exciters": U_e}, found.condition, predicted_std(model, F), noise, None,
                {"sensors": len(sensor_side.lines), "exciters": len(exciter_side.lines)})


def plan(body: BodyMesh, budget: Budget = Budget(), options: CandidateOptions = CandidateOptions(),
         noise: NoiseModel = NoiseModel(), fixed_sensors: Lines | None = None, fixed_exciters: Lines | None = None,
         relaxation: str = "first-order", starts: int = 3, planar: bool | None = None,
         progress: Callable[[str, float], None] = lambda stage, fraction: None) -> Plan:
    """The best layout of ``budget`` on the body's surface, certified and with predicted 1-σ."""
    planar = is_plate(body) if planar is None else planar
    budget.check(planar)
    progress("candidates", 0.0)
    points = candidate_points(body.mesh, options)
    sensor_side, exciter_side = candidate_lines(points, options.axes, planar, budget.triaxial > 0)
    result = plan_on_candidates(RigidModel(body.nominal, planar), sensor_side, exciter_side, budget, noise,
                                fixed_sensors, fixed_exciters, relaxation, starts, options.seed, progress)
    return replace(result, candidates=points)
