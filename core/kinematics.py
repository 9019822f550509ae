"""Kinematics: rigid-body accelerations from masslines (paper §2.1).

Each exciter j produces, per unit force, the rigid acceleration
q_j = (a_O, α) at the origin O, and a sensor line ℓ_i reads H_ij = ℓ_i · q_j
(eq. 2). The three solvers return Q = [q_1 … q_K] (6 × K): a_O in (m/s²)/N,
α in (rad/s²)/N.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from massline.core.degeneracy import distinct_points, unseen_motion
from massline.core.errors import MasslineError, SingularLayoutError
from massline.core.linear_system import solve
from massline.core.lines import Lines
from massline.core.masslines import Masslines
from massline.core.numbers import vector_text


@dataclass(frozen=True, eq=False)
class RigidAccelerations:
    """Q (6 × K): rigid acceleration at O per unit force of each exciter."""

    Q: np.ndarray
    condition: dict = field(default_factory=dict)
    method: str = ""

    @property
    def a_origin(self) -> np.ndarray:
        return self.Q[:3]

    @property
    def alpha(self) -> np.ndarray:
        return self.Q[3:]


def method2(data: Masslines) -> RigidAccelerations:
    """Method 2, eq. (6): S Q = H with the origin's acceleration unknown.

    Every sensor line is one row ℓ_i = (d, r × d); rank S = 6 needs at least
    six lines that together see every rigid motion (the paper: two sets of
    transduction points, six for each excitation).
    """
    S = data.sensors.coordinates
    Q, kappa = solve(S, data.values, "kinematics method 2, eq. (6)", lambda: unseen_motion(data.sensors))
    return RigidAccelerations(Q, {"kinematic": kappa}, "method2")


def _through_origin(lines: Lines) -> np.ndarray:
    scale = max(1.0, float(np.abs(lines.points).max(initial=0.0)))
    return np.linalg.norm(lines.moments, axis=1) < 1e-12 * scale


def method1(data: Masslines) -> RigidAccelerations:
    """Method 1, eq. (5): the origin's acceleration is measured.

    Sensor lines through O give a_O directly (three directions needed); the
    other sensors give (r × d) · α = H − d · a_O, eq. (5). A single triaxial
    point T makes the skew matrix of eq. (5) singular (rotation about O–T is
    unseen), so a transduction point may serve at most two directions.
    """
    at_origin = _through_origin(data.sensors)
    origin, others = data.sensors[at_origin], data.sensors[~at_origin]
    H_origin, H_others = data.values[at_origin], data.values[~at_origin]
    a_origin, kappa_o = solve(
        origin.directions,
        H_origin,
        "kinematics method 1, origin acceleration",
        f"method 1 needs the origin's acceleration in three independent directions, "
        f"got {len(origin)} line(s) through O",
    )

    def why() -> str:
        points = distinct_points(others)
        if len(points) == 1:
            return (
                f"all transducers of eq. (5) sit at one point {vector_text(points[0])} m: its skew matrix is singular "
                "(rotation about the line from O to that point is unseen); use a point for at most two directions"
            )
        return "the transducer moments r × d do not span three directions; add points off the line through O"

    rhs = H_others - others.directions @ a_origin
    alpha, kappa = solve(others.moments, rhs, "kinematics method 1, eq. (5)", why)
    return RigidAccelerations(
        np.vstack([a_origin, alpha]), {"kinematic_origin": kappa_o, "kinematic": kappa}, "method1"
    )


def default_pairs(lines: Lines) -> list[tuple[int, int]]:
    """Pair each line with the next one parallel to it (1–2, 3–4, 5–6 in the paper)."""
    pairs, used = [], set()
    for i in range(len(lines)):
        if i in used:
            continue
        for k in range(i + 1, len(lines)):
            if k not in used and np.linalg.norm(np.cross(lines.directions[i], lines.directions[k])) < 1e-9:
                pairs.append((i, k))
                used |= {i, k}
                break
    return pairs


def difference_rows(lines: Lines, values: np.ndarray, pairs, what: str):
    """Rows of a difference system: (r_i − r_k) × d against the difference of values.

    Two parallel lines (signs aligned) differ by the moment (r_i − r_k) × d
    only; a pair whose points differ along d alone gives a zero row, which is
    reported as coincident coordinates.
    """
    rows, rhs = [], []
    for i, k in pairs:
        di, dk = lines.directions[i], lines.directions[k]
        if np.linalg.norm(np.cross(di, dk)) > 1e-9:
            raise MasslineError(f"{what} {i} and {k} are not parallel; a difference pair needs one direction")
        sign = np.sign(di @ dk)
        moment = lines.moments[i] - sign * lines.moments[k]
        scale = max(np.linalg.norm(lines.points[i]), np.linalg.norm(lines.points[k]), 1e-3)
        if np.linalg.norm(moment) < 1e-9 * scale:
            raise SingularLayoutError(
                f"{what} {i} ({lines.describe(i)}) and {k} ({lines.describe(k)}) have coincident coordinates "
                "across their direction: their difference row is zero; move one of them sideways"
            )
        rows.append(moment)
        rhs.append(values[i] - sign * values[k])
    return np.array(rows), np.array(rhs)


def method2_difference(data: Masslines, pairs=None) -> RigidAccelerations:
    """Method 2 in difference form, eq. (7): α from pairs of parallel sensors.

    Subtracting the readings of two parallel sensors removes a_O:
    d · (a_1 − a_2) = ((r_1 − r_2) × d) · α. Three pairs (x, y, z in the paper,
    six transduction points) give the 3 × 3 system; a_O then follows from
    d · a_O = H − (r × d) · α over all sensors.
    """
    pairs = default_pairs(data.sensors) if pairs is None else pairs
    rows, rhs = difference_rows(data.sensors, data.values, pairs, "sensors")
    if len(rows) < 3:
        raise SingularLayoutError(
            f"kinematics eq. (7) needs three pairs of parallel sensors, found {len(rows)}: add parallel sensor pairs"
        )
    alpha, kappa = solve(
        rows,
        rhs,
        "kinematics eq. (7)",
        "the sensor pairs' moment differences do not span three directions; "
        "use pairs along x, y and z, separated across their direction",
    )
    a_origin, kappa_a = solve(
        data.sensors.directions,
        data.values - data.sensors.moments @ alpha,
        "kinematics eq. (7), origin acceleration",
        "the sensor directions do not span three dimensions; add sensors in x, y and z",
    )
    return RigidAccelerations(
        np.vstack([a_origin, alpha]), {"kinematic": kappa, "kinematic_origin": kappa_a}, "method2-difference"
    )
