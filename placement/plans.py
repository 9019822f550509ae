"""A planned layout: the budget it fills, and the plan with its certificate and predicted accuracy.

Lines in metres in the mesh frame; information and bounds in the model's scaled parameters
(:mod:`.model`), so log det F is comparable between layouts of one body only.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from massline.core.accuracy import predicted_std, worst_relative_std
from massline.placement.candidates import CandidatePoints
from massline.placement.certification import certified_efficiency
from massline.placement.criteria import Criterion, D
from massline.placement.diagnosability import Diagnosability, diagnosability
from massline.core.errors import MasslineError, param
from massline.core.information import NoiseModel, fisher, log_det
from massline.core.numbering import point_labels
from massline.core.lines import Lines
from massline.core.masslines import synthesise
from massline.core.methods import identify
from massline.core.model import RigidModel
from massline.placement.sliding import Slide
from massline.placement.work import Reached


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
                f"give at least {need} ({param('budget.sensors')}, or {param('budget.triaxial', cli='N')} for 3 "
                "lines each)"
            )
        if self.triaxial == 2 and self.sensors == 0:
            raise MasslineError(
                "two triaxial accelerometers alone never see rotation about the line joining them: "
                f"add a third triaxial ({param('budget.triaxial', '3')}) or uniaxial sensors "
                f"({param('budget.sensors')})"
            )
        if self.exciters < 3:
            raise MasslineError(
                f"{self.exciters} exciter(s) are too few: the paper's minimum is 3 ({param('budget.exciters', '3')})"
            )
        if planar and self.triaxial:
            raise MasslineError(f"a plate is planned with out-of-plane lines (§2.3): drop {param('budget.triaxial')}")


@dataclass(frozen=True, eq=False)
class Plan:
    """A layout with its certificate and predicted accuracy.

    ``sensors`` / ``exciters`` hold the fixed lines first; ``sensor_nodes`` / ``exciter_nodes``
    index the candidate points (where a slid point started), −1 for a fixed line.
    ``bounds`` holds the upper bound U of the plan's criterion for each side over the candidates
    (``value`` is the layout's), ``d_bounds`` that of log det F: U of "sensors" bounds every sensor
    selection with the plan's exciters, U of "exciters" every exciter selection with the plan's sensors
    (certification.py). ``sliding`` is how sliding off the candidate grid changed the criterion;
    ``clearances`` the distance (m) from edges a sensor and a hit keep (``CandidateOptions.clearances``).
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
    minimal: Plan | None = None  # the paper's minimal layout this plan is compared with
    sliding: Slide | None = None
    clearances: tuple = (0.0, 0.0)
    candidate_log_det: float = np.nan  # log det F of the layout chosen among the candidates, before sliding
    candidate_value: float = np.nan  # its criterion value (NaN: not slid, ``value`` is the candidate layout's)
    search: Reached | None = None  # what the diagnosable search spent and reached (None: the budget was given)
    certificate: Reached | None = None  # what the D certificate's branch and bound spent of its relaxation steps
    blocks: tuple = (np.zeros((0, 6)), np.zeros((0, 6)))  # sensors, hits: the motions (k, 6) blocks were offered for
    reach: tuple = (None, None)  # sensors, hits: each line's Reach where it ended (:mod:`.reach`), None off a mesh

    @property
    def point_labels(self) -> tuple[np.ndarray, np.ndarray]:
        """The label of each sensor and exciter line: the test's numbering (:mod:`massline.core.numbering`), as the
        console, plan.json, the reports and the simulated Universal File give it."""
        return point_labels(self.sensors, self.exciters)

    @property
    def diagnosability(self) -> Diagnosability:
        """Can one faulty channel or hit of this layout be located (:mod:`.diagnosability`)?"""
        return diagnosability(self.model, self.sensors, self.exciters, self.noise)

    @property
    def d_efficiency_lower_bound(self) -> float:
        """The D certificate's efficiency of the candidate layout, exp((log det F − U)/p) for the worse of the two
        sides, against one-side changes among the candidate points: what the certificate covers (sliding's gain is
        stated beside it as a gain). Above 1 it would be a wrong certificate: raised (:func:`certified_efficiency`)."""
        return certified_efficiency(D, self.candidate_log_det, self.d_bounds, self.model.p)

    @property
    def efficiency_lower_bound(self) -> float:
        """The certificate's efficiency in the plan's criterion of the candidate layout, for the worse of the two
        sides (:func:`certified_efficiency`)."""
        value = self.value if np.isnan(self.candidate_value) else self.candidate_value
        return certified_efficiency(self.criterion, value, self.bounds, self.model.p)

    @property
    def smallest_eigenvalue(self) -> float:
        """λ_min of the scaled information: 1/√λ_min is the worst relative 1-σ of any parameter combination."""
        return float(np.linalg.eigvalsh(self.information)[0])

    @property
    def worst_relative_std(self) -> float:
        return worst_relative_std(self.model, self.predicted_std)


def assessed(model: RigidModel, sensors: Lines, exciters: Lines, noise: NoiseModel) -> dict:
    """A layout's Plan fields: log det F, the condition numbers of the paper's solve, the predicted 1-σ and
    the information F itself (scaled parameters)."""
    F = fisher(model, model.coordinates(sensors), model.coordinates(exciters), noise)
    found = identify(synthesise(model.nominal, sensors, exciters), "plate" if model.planar else "method2")
    return {
        "log_det": log_det(F),
        "condition": found.condition,
        "predicted_std": predicted_std(model, F),
        "information": F,
    }


def fixed_nodes(fixed: Lines | None, nodes: np.ndarray) -> np.ndarray:
    """Candidate point of each line of a layout with the fixed lines first: −1 for those."""
    return np.concatenate([np.full(0 if fixed is None else len(fixed), -1), nodes]).astype(int)
