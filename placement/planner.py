"""The pre-test planner: the sensor and exciter layout of greatest information.

    maximise over S, E   φ(F(S, E)),   F = Σ_{i∈S, j∈E} g_ij g_ijᵀ / σ_ij²,

φ = log det (D, the default), −tr(·)⁻¹ (A) or λ_min (E) of the scaled
information (criteria.py).

F is linear in the sensors for fixed exciters and vice versa, so the layout is
found by alternating the two selection problems (greedy, then exchanges), from
several starts, until neither side improves. Each side's convex relaxation
bounds the best layout from above; the plan states the certified efficiency of
the worse side in the criterion's sense (D: exp((log det F − U)/p)). A and E
start from the D layout and climb their own criterion from there. Only layouts that the paper's
equations can solve are admitted (rank S = 6, non-singular dynamic systems).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

from massline.placement.accuracy import predicted_std, worst_relative_std
from massline.placement.candidates import (
    CandidateLines,
    CandidateOptions,
    CandidatePoints,
    candidate_lines,
    candidate_points,
)
from massline.placement.certification import certify_criterion, certify_d
from massline.placement.criteria import CRITERIA, Criterion, D
from massline.placement.errors import MasslineError, SingularLayoutError
from massline.placement.information import NoiseModel, log_det, weighted_sensitivities
from massline.placement.lines import Lines
from massline.placement.masslines import synthesise
from massline.placement.mesh import BodyMesh
from massline.placement.methods import identify
from massline.placement.model import RigidModel
from massline.placement.selection import BlockProblem, compress, greedy, leverages, settle

PLATE_THINNESS = 0.05  # thickness / size below which a body normal to z is planned as a plate
WORKING_SET = 2000  # candidates per side the combinatorial search runs on


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
    ``bounds`` holds the upper bound U of the plan's criterion for each side
    (``value`` is the layout's), ``d_bounds`` that of log det F.
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
    criterion: Criterion = D
    value: float = np.nan
    d_bounds: dict = field(default_factory=dict)
    information: np.ndarray | None = None

    @property
    def d_efficiency_lower_bound(self) -> float:
        """exp((log det F − U)/p) for the worse of the two sides."""
        return float(np.exp((self.log_det - max(self.d_bounds.values())) / self.model.p))

    @property
    def efficiency_lower_bound(self) -> float:
        """The certified efficiency in the plan's criterion, for the worse of the two sides."""
        return self.criterion.efficiency(self.value, max(self.bounds.values()), self.model.p)

    @property
    def smallest_eigenvalue(self) -> float:
        """λ_min of the scaled information: 1/√λ_min is the worst relative 1-σ of any parameter combination."""
        return float(np.linalg.eigvalsh(self.information)[0])

    @property
    def worst_relative_std(self) -> float:
        return worst_relative_std(self.model, self.predicted_std)


def is_plate(body: BodyMesh) -> bool:
    """Thin along z, with z a principal axis: the paper's §2.3 case."""
    extents = body.mesh.extents
    J = body.nominal.inertia_cog
    thin = extents[2] < PLATE_THINNESS * extents[:2].max()
    return bool(
        thin and np.abs(J[2, :2]).max() <= 1e-9 * np.abs(J).max() and abs(body.nominal.cog[2]) < 1e-9 * extents.max()
    )


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
    ):
        self.model, self.budget, self.noise, self.criterion = model, budget, noise, criterion
        self.s, self.e = sensor_side, exciter_side
        self.s_coords = model.coordinates(sensor_side.lines)
        self.e_coords = model.coordinates(exciter_side.lines)
        empty = np.zeros((0, self.s_coords.shape[1]))
        self.fixed_sensors, self.fixed_exciters = fixed_sensors, fixed_exciters
        self.fixed_s = empty if fixed_sensors is None else model.coordinates(fixed_sensors)
        self.fixed_e = empty if fixed_exciters is None else model.coordinates(fixed_exciters)

    # one side's selection problem, the other side fixed
    def _problem(
        self,
        side: CandidateLines,
        coords: np.ndarray,
        other: np.ndarray,
        fixed: np.ndarray,
        budgets: tuple,
        sensors_side: bool,
    ) -> BlockProblem:
        def sens(a, b):
            g = weighted_sensitivities(self.model, a, b, self.noise)
            return g if sensors_side else g.transpose(1, 0, 2)

        per_line = sens(coords, other) if sensors_side else sens(other, coords)
        padded = np.concatenate([per_line, np.zeros((1,) + per_line.shape[1:])])  # row −1: nothing
        blocks = padded[side.members].reshape(len(side), -1, self.model.p)
        A0 = (sens(fixed, other) if sensors_side else sens(other, fixed)).reshape(-1, self.model.p)
        return BlockProblem(compress(blocks), side.group, budgets, A0.T @ A0, self.criterion)

    def sensor_problem(self, exciter_rows: np.ndarray) -> BlockProblem:
        other = np.vstack([self.fixed_e, exciter_rows])
        return self._problem(
            self.s, self.s_coords, other, self.fixed_s, (self.budget.sensors, self.budget.triaxial), True
        )

    def exciter_problem(self, sensor_rows: np.ndarray) -> BlockProblem:
        other = np.vstack([self.fixed_s, sensor_rows])
        return self._problem(self.e, self.e_coords, other, self.fixed_e, (self.budget.exciters,), False)

    def sensor_rows(self, chosen) -> np.ndarray:
        return self.s_coords[self.s.line_index(chosen)]

    def exciter_rows(self, chosen) -> np.ndarray:
        return self.e_coords[self.e.line_index(chosen)]

    def lines(self, side: CandidateLines, chosen) -> Lines:
        return side.lines[side.line_index(chosen)]

    def sensor_cover(self, exciters: list):
        """Cover sets for the sensor side: candidates that see a motion the selection leaves unseen."""

        def cover_for(sensors: list):
            rows = np.vstack([self.fixed_s, self.sensor_rows(sensors)])
            _, s, Vt = np.linalg.svd(rows)
            if len(s) == rows.shape[1] and s[-1] > 1e-10 * s[0]:
                return None  # all motions seen: the failure lies elsewhere, no cut known
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
        """The paper's equations solve this layout (exact masslines identify the body)."""
        try:
            identify(synthesise(self.model.nominal, sensors, exciters), "plate" if self.model.planar else "method2")
        except SingularLayoutError:
            return False
        return True

    def admits(self, sensors: list, exciters: list) -> bool:
        """Is the selection (candidate indices, fixed lines added) a regular layout?"""
        return self.regular(*self.layout(sensors, exciters))

    def layout(self, sensors, exciters) -> tuple[Lines, Lines]:
        """All sensor and exciter lines of a selection, fixed ones first."""
        S, E = self.lines(self.s, sensors), self.lines(self.e, exciters)
        return (
            S if self.fixed_sensors is None else self.fixed_sensors + S,
            E if self.fixed_exciters is None else self.fixed_exciters + E,
        )

    def alternate(self, exciters: list, sensors: list | None = None, rounds: int = 12) -> tuple[list, list, float]:
        """Sensors for the exciters, exciters for the sensors, … until both are stable."""
        value = -np.inf
        for _ in range(rounds):
            sp = self.sensor_problem(self.exciter_rows(exciters))
            sensors = settle(
                sp, sensors if sensors else greedy(sp), lambda c: self.admits(c, exciters), self.sensor_cover(exciters)
            )
            ep = self.exciter_problem(self.sensor_rows(sensors))
            start = exciters if len(exciters) == self.budget.exciters else greedy(ep)
            new_exciters = settle(ep, start, lambda c: self.admits(sensors, c), self.exciter_cover)
            new_value = ep.value(new_exciters)
            if new_value <= value + 1e-9:
                break
            exciters, value = new_exciters, new_value
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


def _search(searcher: Planner, starts: list, progress) -> tuple[list, list, float]:
    """The best alternation over the starts (exciter sets), by the searcher's criterion."""
    best = None
    for k, start in enumerate(starts):
        progress("alternating sensors and exciters", 0.8 * k / len(starts))
        result = searcher.alternate(*start)
        if best is None or result[2] > best[2]:
            best = result
    return best


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
) -> Plan:
    """The best layout of ``budget`` among given candidate lines, certified, with predicted 1-σ.

    ``certify_seconds`` bounds the branch and bound that tightens the D certificate;
    what it reaches by then is what the plan states. ``criterion`` is "D", "A" or "E"
    (criteria.py): A and E alternate from the D layout by their own criterion.
    """
    budget.check(model.planar)
    for name, side, need in (("sensor", sensor_side, budget.sensors), ("exciter", exciter_side, budget.exciters)):
        if len(side) < need:
            raise MasslineError(
                f"only {len(side)} {name} candidates for a budget of {need}: "
                "sample more points (--candidates) or relax the exclusions"
            )
    chosen = CRITERIA[criterion]
    fixed = (fixed_sensors, fixed_exciters)
    planner = Planner(model, sensor_side, exciter_side, budget, noise, *fixed)
    s_work, e_work = planner.working_sets(seed)
    searcher = Planner(model, sensor_side.subset(s_work), exciter_side.subset(e_work), budget, noise, *fixed)
    best = _search(searcher, [(start,) for start in searcher.starts(starts - 1, seed)], progress)
    if chosen is not D:
        searcher = Planner(searcher.model, searcher.s, searcher.e, budget, noise, *fixed, chosen)
        best = _search(searcher, [(best[1], best[0])], progress)
    sensors, exciters = [int(i) for i in s_work[best[0]]], [int(i) for i in e_work[best[1]]]
    if not planner.admits(sensors, exciters):
        raise MasslineError(
            "the candidates and keep-outs leave only degenerate layouts: allow points that are "
            "not all in one line or plane, and hits in several directions"
        )
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
    F = planner.exciter_problem(planner.sensor_rows(sensors)).information(exciters)
    found = identify(synthesise(model.nominal, S_all, E_all), "plate" if model.planar else "method2")
    progress("done", 1.0)
    return Plan(
        model,
        planner.lines(sensor_side, sensors),
        sensor_side.node[sensor_side.line_index(sensors)],
        planner.lines(exciter_side, exciters),
        exciter_side.node[exciter_side.line_index(exciters)],
        log_det(F),
        bounds,
        found.condition,
        predicted_std(model, F),
        noise,
        None,
        {"sensors": len(sensor_side.lines), "exciters": len(exciter_side.lines)},
        chosen,
        chosen.value(F),
        d_bounds,
        F,
    )


def plan(
    body: BodyMesh,
    budget: Budget = Budget(),
    options: CandidateOptions = CandidateOptions(),
    noise: NoiseModel = NoiseModel(),
    fixed_sensors: Lines | None = None,
    fixed_exciters: Lines | None = None,
    relaxation: str = "first-order",
    starts: int = 3,
    planar: bool | None = None,
    certify_seconds: float = 20.0,
    progress: Callable[[str, float], None] = lambda stage, fraction: None,
    criterion: str = "D",
) -> Plan:
    """The best layout of ``budget`` on the body's surface by ``criterion`` (D, A or E), certified and
    with predicted 1-σ."""
    planar = is_plate(body) if planar is None else planar
    budget.check(planar)
    progress("candidates", 0.0)
    points = candidate_points(body.mesh, options)
    sensor_side, exciter_side = candidate_lines(points, options.axes, planar, budget.triaxial > 0)
    result = plan_on_candidates(
        RigidModel(body.nominal, planar),
        sensor_side,
        exciter_side,
        budget,
        noise,
        fixed_sensors,
        fixed_exciters,
        relaxation,
        starts,
        options.seed,
        certify_seconds,
        progress,
        criterion,
    )
    return replace(result, candidates=points)
