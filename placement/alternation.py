"""The planner's alternation: the sensor and exciter selection problems of one model, one criterion and one
budget over given candidate lines, solved in turn (greedy, then exchanges) until neither side improves
(:mod:`.planner` runs it from several starts and certifies the result).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from massline.placement.admissible import regular, weakly_seen
from massline.placement.candidates import BLOCK, CandidateLines
from massline.placement.criteria import Criterion, D
from massline.placement.diagnosability import H_MAX, R_MAX, confusion, excesses
from massline.placement.footprints import Footprints, conflicts, hits_blocked, sensors_blocked
from massline.placement.random_layouts import drawn
from massline.core.errors import MasslineError, param
from massline.core.information import NoiseModel, weighted_sensitivities
from massline.placement.plans import Budget
from massline.core.lines import Lines
from massline.core.model import RigidModel
from massline.placement.selection import BlockProblem, best_gains, compress, descend, greedy, leverages, settle
from massline.placement.work import Work

WORKING_SET = 2000  # candidates per side the combinatorial search runs on
RELIEF = 20  # sensor lines tried for the channels that cannot be checked, beside the most informative exchanges
EVALUATIONS = 1_000_000  # diagnosability evaluations a planner may spend when not given a budget of its own
BLOCKS = {False: (1, 1), True: (3, 2)}  # lines and hits on mounting blocks: to identify, to diagnose


def _stacked(side: CandidateLines, coords: np.ndarray, fixed: np.ndarray, chosen: list) -> np.ndarray:
    """Line coordinates (T, n, q) of T selections of one side, the fixed lines first; the selections hold
    candidates of the same groups position by position (a triaxial where a triaxial is), as trial exchanges do."""
    members = side.members[np.asarray(chosen, dtype=int)].reshape(len(chosen), -1)  # (T, lines), −1 pads
    if not np.all((members >= 0) == (members[:1] >= 0)):
        raise ValueError("selections of different groups position by position cannot be stacked")
    rows = coords[members[:, members[0] >= 0]]
    return np.concatenate([np.broadcast_to(fixed, (len(chosen),) + fixed.shape), rows], axis=1)


@dataclass(frozen=True, kw_only=True)
class PlannerSettings:
    """What a :class:`Planner` plans besides its candidates: the model, the budget, the noise, the lines held
    fixed, the criterion it climbs, whether only diagnosable layouts are admitted and the footprints it keeps apart
    (None: none)."""

    model: RigidModel
    budget: Budget
    noise: NoiseModel = NoiseModel()
    fixed_sensors: Lines | None = None
    fixed_exciters: Lines | None = None
    criterion: Criterion = D
    diagnosable: bool = False
    work: Work | None = None
    footprints: Footprints | None = None
    blocks: tuple | None = None

    def planner(self, sensor_side: CandidateLines, exciter_side: CandidateLines) -> Planner:
        """The planner of these settings over the given candidate lines."""
        return Planner(
            self.model,
            sensor_side,
            exciter_side,
            self.budget,
            self.noise,
            fixed_sensors=self.fixed_sensors,
            fixed_exciters=self.fixed_exciters,
            criterion=self.criterion,
            diagnosable=self.diagnosable,
            work=self.work,
            footprints=self.footprints,
            blocks=self.blocks,
        )


class Planner:
    """Alternating selection of sensors and exciters on one model, by one criterion."""

    def __init__(
        self,
        model: RigidModel,
        sensor_side: CandidateLines,
        exciter_side: CandidateLines,
        budget: Budget,
        noise: NoiseModel = NoiseModel(),
        *,
        fixed_sensors: Lines | None = None,
        fixed_exciters: Lines | None = None,
        criterion: Criterion = D,
        diagnosable: bool = False,
        work: Work | None = None,
        footprints: Footprints | None = None,
        blocks: tuple | None = None,
    ):
        self.model, self.budget, self.noise, self.criterion = model, budget, noise, criterion
        self.diagnosable = diagnosable
        self.blocks = BLOCKS[diagnosable] if blocks is None else blocks  # lines and hits on mounting blocks
        self.work = Work(EVALUATIONS, "diagnosability evaluations") if work is None else work
        self.s, self.e = sensor_side, exciter_side
        self.s_coords = model.coordinates(sensor_side.lines)
        self.e_coords = model.coordinates(exciter_side.lines)
        empty = np.zeros((0, self.s_coords.shape[1]))
        self.fixed_sensors, self.fixed_exciters = fixed_sensors, fixed_exciters
        self.fixed_s = empty if fixed_sensors is None else model.coordinates(fixed_sensors)
        self.fixed_e = empty if fixed_exciters is None else model.coordinates(fixed_exciters)
        self._built = {}
        self._excess = {}  # (sensors, exciters) → its excess: a search meets a third of its trials again
        self.footprints = footprints
        if footprints is not None:
            self.s_sites = footprints.candidates.take(self.sensor_node)
            self.e_sites = footprints.candidates.take(exciter_side.node[exciter_side.members[:, 0]])

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
                f"use triaxial accelerometers ({param('budget.triaxial', cli='N')}), mounting blocks "
                f"({param('options.axes')}), a smaller {param('options.sensor_base')} or fewer exclusions"
            )

    @cached_property
    def sensor_budgets(self) -> tuple:
        """Candidates to choose per group (uniaxial, triaxial, on blocks): on blocks as few as the motion the
        normals miss needs (``blocks``, by default ``BLOCKS``: one line reads it, three check each other), the rest
        on the surface."""
        blocks = self._blocks(self.s, self.blocks[0])
        return (self.budget.sensors - blocks, self.budget.triaxial) + ((blocks,) if blocks else ())

    @cached_property
    def exciter_budgets(self) -> tuple:
        """Hits to choose per group (on the surface, -, on blocks): on blocks one drives the motion the normals
        miss, two check each other (``BLOCKS``)."""
        blocks = self._blocks(self.e, self.blocks[1])
        return (self.budget.exciters - blocks,) + ((0, blocks) if blocks else ())

    @staticmethod
    def _blocks(side: CandidateLines, wanted: int) -> int:
        """Block candidates to choose on ``side``: ``wanted``, none where it has none."""
        return min(wanted, int(np.sum(side.group == BLOCK)))

    def sensor_problem(self, exciter_rows: np.ndarray, exciters=()) -> BlockProblem:
        """The sensors' problem seen through the exciters' rows; with footprints, open only where an accelerometer
        keeps clear of the fixed lines and of the hits ``exciters`` (candidate indices), a base from the others."""
        other = np.vstack([self.fixed_e, exciter_rows])
        budgets = self.sensor_budgets
        problem = self._kept("s", other, lambda: self._problem(self.s, self.s_coords, other, self.fixed_s, budgets))
        if self.footprints is None:
            return problem
        f = self.footprints
        hits = f.fixed_hits + self.e_sites.take(exciters)
        allowed = ~sensors_blocked(self.s_sites, f.fixed_sensors, hits, f.footprint)
        return replace(problem, allowed=allowed, sites=self.s_sites.points, spacing=f.footprint.sensor_base)

    def exciter_problem(self, sensor_rows: np.ndarray, sensors=()) -> BlockProblem:
        """The exciters' problem seen through the sensors' rows; with footprints, open only where a hit keeps clear
        of the fixed accelerometers and of ``sensors`` (candidate indices)."""
        other = np.vstack([self.fixed_s, sensor_rows])
        budgets = self.exciter_budgets
        problem = self._kept("e", other, lambda: self._problem(self.e, self.e_coords, other, self.fixed_e, budgets))
        if self.footprints is None:
            return problem
        f = self.footprints
        placed = f.fixed_sensors + self.s_sites.take(sensors)
        return replace(problem, allowed=~hits_blocked(self.e_sites, placed, f.footprint))

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
            return self.seeing(Vt[-1])

        return cover_for

    def seeing(self, motion: np.ndarray) -> np.ndarray:
        """Per sensor candidate: does any of its lines see the rigid motion ``motion`` (q,)?"""
        return self.s.any_line(np.abs(self.s_coords @ motion) > 1e-9 * np.linalg.norm(self.s_coords, axis=1))

    def sensor_relief(self, sensors: list) -> np.ndarray:
        """Per sensor candidate: is it among the ``RELIEF`` lines that most lower the leverage of the selection's
        channels that cannot be checked (:mod:`.diagnosability`)? Adding line c to rows R lowers channel i's
        leverage by (c G r_iᵀ)² / (1 + c G cᵀ), G = (RᵀR)⁻¹; where R sees too few motions, the lines that see one
        it leaves unseen. The lines a diagnosable layout lacks (on a thick plate's thin sides) rarely add much
        information, so the exchanges that weigh information first never try them."""
        rows = np.vstack([self.fixed_s, self.sensor_rows(sensors)])
        U, s, Vt = np.linalg.svd(rows, full_matrices=False)
        if len(s) < rows.shape[1] or s[-1] <= 1e-10 * s[0]:
            return self.seeing(Vt[-1])
        P = U @ U.T  # the kinematic hat matrix S S⁺ of rows that see every motion
        weak = np.flatnonzero((np.diagonal(P) > H_MAX) | (confusion(P) > R_MAX))
        if not len(weak):
            return np.zeros(len(self.s), bool)
        C = (self.s_coords @ Vt.T) / s**2 @ Vt  # c G, G = (RᵀR)⁻¹ = V S⁻² Vᵀ
        relief = ((C @ rows[weak].T) ** 2).sum(axis=1) / (1 + np.einsum("lq,lq->l", C, self.s_coords))
        relief[self.s.line_index(sensors)] = 0.0  # the selection's own lines are no exchange
        best = np.zeros(len(relief), bool)
        best[np.argsort(-relief)[:RELIEF]] = True
        return self.s.any_line(best & (relief > 0))

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

    def violations(self, selections: list) -> np.ndarray:
        """How far each selection ((sensors, exciters) candidate indices, of one size) is from diagnosable (0
        when it is, or when that is not asked); evaluated together, each one unit of the planner's work."""
        if not self.diagnosable or not selections:
            return np.zeros(len(selections))
        self.work.spend(len(selections))  # a selection met before still counts: the search's reach is in trials
        keys = [(tuple(map(int, s)), tuple(map(int, e))) for s, e in selections]
        new = list(dict.fromkeys(k for k in keys if k not in self._excess))
        if new:  # each layout's excess is its own (stacked gufuncs): a stack of the new ones gives the same values
            S = _stacked(self.s, self.s_coords, self.fixed_s, [s for s, _ in new])
            W = _stacked(self.e, self.e_coords, self.fixed_e, [e for _, e in new])
            self._excess.update(zip(new, excesses(self.model, S, W, self.noise)))
        return np.array([self._excess[k] for k in keys])

    def violation(self, sensors: list, exciters: list) -> float:
        """How far the selection is from diagnosable (0 when it is, or when that is not asked)."""
        return float(self.violations([(sensors, exciters)])[0])

    def admits(self, sensors: list, exciters: list) -> bool:
        """Is the selection (candidate indices, fixed lines added) a regular layout with one accelerometer
        (uniaxial or triaxial) per point (and, if asked, a diagnosable one)?"""
        nodes = self.sensor_node[np.asarray(sensors, dtype=int)]
        return (
            len(set(nodes.tolist())) == len(nodes)
            and self.mountable(sensors, exciters)
            and self.violation(sensors, exciters) == 0
            and self.regular(*self.layout(sensors, exciters))
        )

    def mountable(self, sensors: list, exciters: list) -> bool:
        """Do the selection's accelerometers keep a base apart and its hits clear of them (fixed lines included,
        :mod:`.footprints`)? True without footprints."""
        if self.footprints is None:
            return True
        f = self.footprints
        placed = f.fixed_sensors + self.s_sites.take(sensors)
        return not conflicts(placed, f.fixed_hits + self.e_sites.take(exciters), f.footprint)

    @property
    def sensor_node(self) -> np.ndarray:
        """The candidate point of each sensor candidate."""
        return self.s.node[self.s.members[:, 0]]

    def separated(self, problem: BlockProblem, sensors: list) -> list:
        """Each accelerometer on a point another one holds, or not free beside the others (a footprint's
        conflict, :meth:`BlockProblem.free`), the later one first, exchanged for the candidate of its group, on a
        free point, that adds the most information."""
        chosen = list(sensors)
        for position in reversed(range(len(chosen))):
            taken = np.delete(self.sensor_node[chosen], position)
            others = problem.free(np.delete(chosen, position))
            if self.sensor_node[chosen[position]] not in taken and others[chosen[position]]:
                continue
            free = (problem.group == problem.group[chosen[position]]) & ~np.isin(self.sensor_node, taken) & others
            free[chosen] = False
            M = problem.information(np.delete(chosen, position)) + problem.regulariser()
            best = best_gains(problem.blocks, np.linalg.inv(M), free)[0]
            chosen[position] = int(best[0]) if len(best) else chosen[position]
        return chosen

    def settled(self, problem: BlockProblem, start: list, side, cover, relief=None) -> list:
        """``settle`` with the other side fixed (``side(c)`` → (sensors, exciters)); when diagnosability is asked,
        an inadmissible result is walked towards it by ``descend`` (trying the candidates
        ``relief(c)`` too) and settled again, the trials of a walk's pass and of a repair evaluated together."""
        admissible = lambda c: self.admits(*side(c))  # noqa: E731
        violations = lambda cs: self.violations([side(c) for c in cs])  # noqa: E731
        screen = (lambda cs: violations(cs) == 0) if self.diagnosable else None
        chosen = settle(problem, start, admissible, cover, screen)
        if admissible(chosen) or not self.diagnosable:
            return chosen
        walked = settle(problem, descend(problem, chosen, violations, relief), admissible, cover, screen)
        solvable = admissible(walked) or self.regular(*self.layout(*side(walked)))
        return walked if solvable else chosen  # a walk that ends where the equations cannot solve: not taken

    def layout(self, sensors, exciters) -> tuple[Lines, Lines]:
        """All sensor and exciter lines of a selection, fixed ones first."""
        S, E = self.lines(self.s, sensors), self.lines(self.e, exciters)
        return (
            S if self.fixed_sensors is None else self.fixed_sensors + S,
            E if self.fixed_exciters is None else self.fixed_exciters + E,
        )

    def alternate(self, exciters: list, sensors: list | None = None, rounds: int = 12) -> tuple[list, list, float]:
        """Sensors for the exciters, exciters for the sensors, … until both are stable, or, when diagnosability
        is asked, until a round leaves the layout as far from diagnosable as the round before (a walk that
        stalls: its exchanges climb back to where the next round's walk starts again)."""
        value, settled_for, short = -np.inf, None, np.inf
        for _ in range(rounds):
            sp = self.sensor_problem(self.exciter_rows(exciters), exciters)
            sensors = self.settled(
                sp,
                self.separated(sp, sensors if sensors else greedy(sp)),
                lambda c: (c, exciters),
                self.sensor_cover(exciters, conditioning=True),
                self.sensor_relief,
            )
            if sorted(sensors) == settled_for:  # the exciters were settled against these very sensors
                break
            ep = self.exciter_problem(self.sensor_rows(sensors), sensors)
            start = exciters if len(exciters) == self.budget.exciters else greedy(ep)
            new_exciters = self.settled(ep, start, lambda c: (sensors, c), self.exciter_cover)
            new_value = ep.value(new_exciters)
            if new_value <= value + 1e-9:
                break
            exciters, value, settled_for = new_exciters, new_value, sorted(sensors)
            short, before = self.violation(sensors, exciters), short
            if 0 < before <= short:
                break
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
        starts += [drawn(rng, self.e, self.exciter_budgets) for _ in range(n_random)]
        return starts
