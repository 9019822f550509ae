"""The pre-test planner: the sensor and exciter layout of greatest information.

    maximise over S, E   φ(F(S, E)),   F = Σ_{i∈S, j∈E} g_ij g_ijᵀ / σ_ij²,

φ = log det (D, the default), −tr(·)⁻¹ (A) or λ_min (E) of the scaled
information (criteria.py).

F is linear in the sensors for fixed exciters and vice versa, so the layout is
found by alternating the two selection problems (greedy, then exchanges), from
several starts, until neither side improves. Each side's convex relaxation
bounds from above the best layout that changes that side alone, the other held
(certification.py); the plan states the certified efficiency of the worse side in
the criterion's sense (D: exp((log det F − U)/p)): a lower bound against every
layout that changes the sensors alone or the exciters alone, not both at once. A and E
start from the D layout and climb their own criterion from there. Only layouts that the paper's
equations can solve, with a well-posed kinematic step and one accelerometer per point, are admitted
(:mod:`.admissible`: rank S = 6, non-singular dynamic systems, κ(S̃) bounded), and, when asked, only
diagnosable ones (:mod:`.diagnosability`): an inadmissible selection is first walked by single exchanges
to one that is. On a mesh (:func:`.on_surface.plan`) the chosen points then slide off the candidate
grid on their flat faces (:mod:`.sliding`), which raises the criterion beyond the certified layout.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from massline.placement.admissible import regular, weakly_seen
from massline.placement.candidates import (
    CandidateLines,
)
from massline.placement.certification import certify_criterion, certify_d
from massline.placement.criteria import CRITERIA, Criterion, D
from massline.placement.diagnosability import UndiagnosableError, of_coordinates
from massline.core.errors import MasslineError
from massline.core.information import NoiseModel, weighted_sensitivities
from massline.placement.plans import Budget, Plan, assessed, fixed_nodes
from massline.core.lines import Lines
from massline.core.model import RigidModel
from massline.placement.selection import BlockProblem, best_gains, compress, descend, greedy, leverages, settle

WORKING_SET = 2000  # candidates per side the combinatorial search runs on


class Planner:
    """Alternating selection of sensors and exciters on one model, by one criterion."""

    def __init__(
        self,
        model: RigidModel,
        sensor_side: CandidateLines,
        exciter_side: CandidateLines,
        budget: Budget,
        noise: NoiseModel,
        fixed_sensors: Lines | None = None,
        fixed_exciters: Lines | None = None,
        criterion: Criterion = D,
        diagnosable: bool = False,
    ):
        self.model, self.budget, self.noise, self.criterion = model, budget, noise, criterion
        self.diagnosable = diagnosable
        self.s, self.e = sensor_side, exciter_side
        self.s_coords = model.coordinates(sensor_side.lines)
        self.e_coords = model.coordinates(exciter_side.lines)
        empty = np.zeros((0, self.s_coords.shape[1]))
        self.fixed_sensors, self.fixed_exciters = fixed_sensors, fixed_exciters
        self.fixed_s = empty if fixed_sensors is None else model.coordinates(fixed_sensors)
        self.fixed_e = empty if fixed_exciters is None else model.coordinates(fixed_exciters)
        self._built = {}

    # one side's selection problem, the other side fixed
    def _problem(
        self,
        side: CandidateLines,
        coords: np.ndarray,
        other: np.ndarray,
        fixed: np.ndarray,
        budgets: tuple,
    ) -> BlockProblem:
        per_line = weighted_sensitivities(self.model, coords, other, self.noise)  # symmetric: lines first
        padded = np.concatenate([per_line, np.zeros((1,) + per_line.shape[1:])])  # row −1: nothing
        blocks = padded[side.members].reshape(len(side), -1, self.model.p)
        A0 = weighted_sensitivities(self.model, fixed, other, self.noise).reshape(-1, self.model.p)
        return BlockProblem(compress(blocks), side.group, budgets, A0.T @ A0, self.criterion)

    def check_directions(self) -> None:
        """Refuse sensor candidates (with the fixed sensors) whose lines cannot see every rigid-body motion."""
        coords = np.vstack([self.fixed_s, self.s_coords])
        rank = np.linalg.matrix_rank(coords, tol=1e-9 * np.abs(coords).max(initial=1.0))
        if rank < coords.shape[1]:
            raise MasslineError(
                f"the places an accelerometer fits (flat, clear of every edge, not excluded) leave only degenerate "
                f"layouts: they face too few directions to see all {coords.shape[1]} rigid-body motions (rank {rank}); "
                "use triaxial accelerometers (--triaxial N), mounting blocks (--axes), a smaller --sensor-base or "
                "fewer exclusions"
            )

    def sensor_problem(self, exciter_rows: np.ndarray) -> BlockProblem:
        other = np.vstack([self.fixed_e, exciter_rows])
        budgets = (self.budget.sensors, self.budget.triaxial)
        return self._kept("s", other, lambda: self._problem(self.s, self.s_coords, other, self.fixed_s, budgets))

    def exciter_problem(self, sensor_rows: np.ndarray) -> BlockProblem:
        other = np.vstack([self.fixed_s, sensor_rows])
        budgets = (self.budget.exciters,)
        return self._kept("e", other, lambda: self._problem(self.e, self.e_coords, other, self.fixed_e, budgets))

    def _kept(self, side: str, other: np.ndarray, build) -> BlockProblem:
        """The last problem built for the side, by held lines: the search, the polish and the certificate come
        back to the same ones, which take a tenth of a second each to build at 1e5 candidates."""
        key = (other.shape, other.tobytes())
        if self._built.get(side, (None,))[0] != key:
            self._built[side] = (key, build())
        return self._built[side][1]

    def sensor_rows(self, chosen) -> np.ndarray:
        return self.s_coords[self.s.line_index(chosen)]

    def exciter_rows(self, chosen) -> np.ndarray:
        return self.e_coords[self.e.line_index(chosen)]

    def lines(self, side: CandidateLines, chosen) -> Lines:
        return side.lines[side.line_index(chosen)]

    def sensor_cover(self, exciters: list, conditioning: bool = False):
        """Cover sets for the sensor side: candidates that see a motion the selection leaves unseen; with
        ``conditioning`` (a search's repair, not a certificate's cut), those that read well the motion an
        ill-conditioned selection reads weakly (``admissible.weakly_seen``)."""

        def cover_for(sensors: list):
            rows = np.vstack([self.fixed_s, self.sensor_rows(sensors)])
            _, s, Vt = np.linalg.svd(rows)
            if len(s) == rows.shape[1] and s[-1] > 1e-10 * s[0]:
                weak = weakly_seen(self.model, rows, self.s_coords) if conditioning else None
                return None if weak is None else self.s.any_line(weak)  # else no cut known
            q0 = Vt[-1]
            sees = np.abs(self.s_coords @ q0) > 1e-9 * np.linalg.norm(self.s_coords, axis=1)
            return self.s.any_line(sees)

        return cover_for

    def exciter_cover(self, exciters: list):
        """Cover set for the exciter side: when all hits are parallel, the hits that are not."""
        lines = self.layout([], exciters)[1]
        d = lines.directions[0]
        if np.linalg.norm(np.cross(lines.directions, d), axis=1).max() > 1e-9:
            return None
        off = np.linalg.norm(np.cross(self.e.lines.directions, d), axis=1) > 1e-9
        return self.e.any_line(off)

    def regular(self, sensors: Lines, exciters: Lines) -> bool:
        return regular(self.model, sensors, exciters)

    def violation(self, sensors: list, exciters: list) -> float:
        """How far the selection is from diagnosable (0 when it is, or when that is not asked)."""
        if not self.diagnosable:
            return 0.0
        S = np.vstack([self.fixed_s, self.sensor_rows(sensors)])
        W = np.vstack([self.fixed_e, self.exciter_rows(exciters)])
        return of_coordinates(self.model, S, W, self.noise).excess

    def admits(self, sensors: list, exciters: list) -> bool:
        """Is the selection (candidate indices, fixed lines added) a regular layout with one accelerometer
        (uniaxial or triaxial) per point (and, if asked, a diagnosable one)?"""
        nodes = self.sensor_node[np.asarray(sensors, dtype=int)]
        return (
            len(set(nodes.tolist())) == len(nodes)
            and self.violation(sensors, exciters) == 0
            and self.regular(*self.layout(sensors, exciters))
        )

    @property
    def sensor_node(self) -> np.ndarray:
        """The candidate point of each sensor candidate."""
        return self.s.node[self.s.members[:, 0]]

    def separated(self, problem: BlockProblem, sensors: list) -> list:
        """Each accelerometer on a point another one holds (the later one) exchanged for the candidate of its
        group, on a free point, that adds the most information."""
        chosen = list(sensors)
        for position in reversed(range(len(chosen))):
            taken = np.delete(self.sensor_node[chosen], position)
            if self.sensor_node[chosen[position]] not in taken:
                continue
            free = (problem.group == problem.group[chosen[position]]) & ~np.isin(self.sensor_node, taken)
            free[chosen] = False
            M = problem.information(np.delete(chosen, position)) + problem.regulariser()
            best = best_gains(problem.blocks, np.linalg.inv(M), free)[0]
            chosen[position] = int(best[0]) if len(best) else chosen[position]
        return chosen

    def settled(self, problem: BlockProblem, start: list, side, cover) -> list:
        """``settle`` with the other side fixed (``side(c)`` → (sensors, exciters)); when diagnosability is asked,
        an inadmissible result is walked towards it by ``descend`` among regular layouts and settled again."""
        admissible = lambda c: self.admits(*side(c))  # noqa: E731
        chosen = settle(problem, start, admissible, cover)
        if admissible(chosen) or not self.diagnosable:
            return chosen
        walked = descend(
            problem, chosen, lambda c: self.violation(*side(c)), lambda c: self.regular(*self.layout(*side(c)))
        )
        return settle(problem, walked, admissible, cover)

    def layout(self, sensors, exciters) -> tuple[Lines, Lines]:
        """All sensor and exciter lines of a selection, fixed ones first."""
        S, E = self.lines(self.s, sensors), self.lines(self.e, exciters)
        return (
            S if self.fixed_sensors is None else self.fixed_sensors + S,
            E if self.fixed_exciters is None else self.fixed_exciters + E,
        )

    def alternate(self, exciters: list, sensors: list | None = None, rounds: int = 12) -> tuple[list, list, float]:
        """Sensors for the exciters, exciters for the sensors, … until both are stable."""
        value, settled_for = -np.inf, None
        for _ in range(rounds):
            sp = self.sensor_problem(self.exciter_rows(exciters))
            sensors = self.settled(
                sp,
                self.separated(sp, sensors if sensors else greedy(sp)),
                lambda c: (c, exciters),
                self.sensor_cover(exciters, conditioning=True),
            )
            if sorted(sensors) == settled_for:  # the exciters were settled against these very sensors
                break
            ep = self.exciter_problem(self.sensor_rows(sensors))
            start = exciters if len(exciters) == self.budget.exciters else greedy(ep)
            new_exciters = self.settled(ep, start, lambda c: (sensors, c), self.exciter_cover)
            new_value = ep.value(new_exciters)
            if new_value <= value + 1e-9:
                break
            exciters, value, settled_for = new_exciters, new_value, sorted(sensors)
        return sensors, exciters, value

    def working_sets(self, seed: int, size: int = WORKING_SET) -> tuple[np.ndarray, np.ndarray]:
        """Candidates the combinatorial search runs on: all of them up to ``size``; beyond,
        the most informative half (largest trace of information against a random
        reference layout) and a random half.
        The certificate still covers every candidate."""
        rng = np.random.default_rng(seed)

        def pick(n: int, problem_for) -> np.ndarray:
            if n <= size:
                return np.arange(n)
            score = leverages(problem_for().blocks, np.eye(self.model.p))
            top = np.argsort(-score)[: size // 2]
            rest = np.setdiff1d(np.arange(n), top)
            return np.sort(np.concatenate([top, rng.choice(rest, size - len(top), replace=False)]))

        ref_s = rng.choice(len(self.s), min(len(self.s), 10), replace=False)
        ref_e = rng.choice(len(self.e), min(len(self.e), 3), replace=False)
        return (
            pick(len(self.s), lambda: self.sensor_problem(self.exciter_rows(ref_e))),
            pick(len(self.e), lambda: self.exciter_problem(self.sensor_rows(ref_s))),
        )

    def starts(self, n_random: int, seed: int) -> list:
        """Exciter sets to start from: greedy against a spread of reference sensors, and random ones."""
        rng = np.random.default_rng(seed)
        reference = rng.choice(len(self.s), min(len(self.s), 50), replace=False)
        ep = self.exciter_problem(self.sensor_rows(reference))
        starts = [greedy(ep)]
        starts += [list(rng.choice(len(self.e), self.budget.exciters, replace=False)) for _ in range(n_random)]
        return starts


def _search(searcher: Planner, starts: list, progress) -> tuple[list, list, float, bool]:
    """The best alternation over the starts (exciter sets), by the searcher's criterion: an admitted layout
    before any other, then the greater value; with whether it is admitted."""
    best = None
    for k, start in enumerate(starts):
        progress("alternating sensors and exciters", 0.8 * k / len(starts))
        result = searcher.alternate(*start)
        admitted = searcher.admits(result[0], result[1])
        if best is None or (admitted, result[2]) > (best[3], best[2]):
            best = (*result, admitted)
    return best


def polished(planner: Planner, sensors: list, exciters: list) -> tuple[list, list]:
    """The working sets' layout carried on by exchanges among every candidate, each side in turn, staying
    admitted: the working sets hold a few thousand lines, and the best admitted layout of 1e5 may lie
    between them (a sensor a few millimetres from a working-set point)."""
    s, e, _ = planner.alternate(exciters, sensors)
    return (s, e) if planner.admits(s, e) else (sensors, exciters)


def plan_on_candidates(
    model: RigidModel,
    sensor_side: CandidateLines,
    exciter_side: CandidateLines,
    budget: Budget,
    noise: NoiseModel = NoiseModel(),
    fixed_sensors: Lines | None = None,
    fixed_exciters: Lines | None = None,
    relaxation: str = "first-order",
    starts: int = 3,
    seed: int = 0,
    certify_seconds: float = 20.0,
    progress: Callable[[str, float], None] = lambda stage, fraction: None,
    criterion: str = "D",
    diagnosable: bool = False,
) -> Plan:
    """The best layout of ``budget`` among given candidate lines, certified, with predicted 1-σ.

    ``certify_seconds`` bounds the branch and bound that tightens the D certificate;
    what it reaches by then is what the plan states. ``criterion`` is "D", "A" or "E"
    (criteria.py): A and E alternate from the D layout by their own criterion. ``diagnosable``: only
    layouts in which one faulty channel or hit can be located are admitted (the certificate's bound covers
    all layouts).
    """
    budget.check(model.planar)
    sides = (
        ("sensor", sensor_side, budget.sensors, "--sensor-base"),
        ("exciter", exciter_side, budget.exciters, "--tip"),
    )
    for name, side, need, option in sides:
        if len(side) < need:
            raise MasslineError(
                f"only {len(side)} {name} candidates for a budget of {need}: sample more points (--candidates), "
                f"relax the exclusions or give a smaller {option} (flat places clear of edges are few)"
            )
    chosen = CRITERIA[criterion]
    fixed = (fixed_sensors, fixed_exciters)
    planner = Planner(model, sensor_side, exciter_side, budget, noise, *fixed, diagnosable=diagnosable)
    planner.check_directions()
    s_work, e_work = planner.working_sets(seed)
    subsets = sensor_side.subset(s_work), exciter_side.subset(e_work)
    searcher = Planner(model, *subsets, budget, noise, *fixed, diagnosable=diagnosable)
    best = _search(searcher, [(start,) for start in searcher.starts(starts - 1, seed)], progress)
    if chosen is not D:
        searcher = Planner(model, *subsets, budget, noise, *fixed, chosen, diagnosable)
        best = _search(searcher, [(best[1], best[0])], progress)
    sensors, exciters = [int(i) for i in s_work[best[0]]], [int(i) for i in e_work[best[1]]]
    if diagnosable and not best[3]:
        raise UndiagnosableError(f"no diagnosable layout of {budget} was found among the candidates")
    if not best[3]:
        raise MasslineError(
            "the candidates and keep-outs leave only degenerate or ill-conditioned layouts: allow points that are "
            "not all in one line or plane, and hits in several directions (relax the exclusions, "
            "--sensor-base or --tip)"
        )
    if len(s_work) < len(sensor_side) or len(e_work) < len(exciter_side):
        progress("exchanging on every candidate", 0.82)
        polisher = (
            planner
            if chosen is D
            else Planner(model, sensor_side, exciter_side, budget, noise, *fixed, chosen, diagnosable)
        )
        sensors, exciters = polished(polisher, sensors, exciters)
    progress("certifying", 0.85)
    if chosen is D:
        sensors, exciters, d_bounds = certify_d(planner, sensors, exciters, relaxation, certify_seconds)
        bounds = d_bounds
    else:
        d_bounds = certify_d(planner, sensors, exciters, relaxation, 0.0)[2]
        bounds = certify_criterion(
            Planner(model, sensor_side, exciter_side, budget, noise, *fixed, chosen), sensors, exciters
        )
    S_all, E_all = planner.layout(sensors, exciters)
    assessment = assessed(model, S_all, E_all, noise)
    progress("done", 1.0)
    return Plan(
        model,
        S_all,
        fixed_nodes(fixed_sensors, sensor_side.node[sensor_side.line_index(sensors)]),
        E_all,
        fixed_nodes(fixed_exciters, exciter_side.node[exciter_side.line_index(exciters)]),
        bounds=bounds,
        noise=noise,
        n_candidate_lines={"sensors": len(sensor_side.lines), "exciters": len(exciter_side.lines)},
        criterion=chosen,
        value=chosen.value(assessment["information"]),
        d_bounds=d_bounds,
        candidate_log_det=assessment["log_det"],
        **assessment,
    )
