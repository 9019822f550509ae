"""Which layouts the planner admits: the paper's equations solve them and their kinematic step is well posed.

The kinematic step (eq. 6) is judged free of units and origin: S̃ has the rows (d, (r − c) × d / L)
about the CoG c, with L the radius of gyration (a plate's, §2.3: d_z (1, (y − c_y)/L, −(x − c_x)/L)).
When κ(S̃) exceeds KINEMATIC_LIMIT the sensors read some motion an order of magnitude more weakly than
the others: the paper's solve, and the start of every estimator, amplify the noise along it. The
bundled bodies' plans have κ(S̃) of 3–8.
"""

from __future__ import annotations

import numpy as np

from massline.placement.errors import SingularLayoutError
from massline.placement.lines import Lines
from massline.placement.masslines import synthesise
from massline.placement.methods import identify
from massline.placement.model import RigidModel

KINEMATIC_LIMIT = 30.0


def scaled_sensor_matrix(model: RigidModel, sensors: Lines) -> np.ndarray:
    """S̃ (n, q): the sensor lines about the CoG, moments over the radius of gyration (dimensionless)."""
    c, L = model.nominal.cog, model.nominal.radius_of_gyration
    r, d = sensors.points - c, sensors.directions
    if model.planar:
        return d[:, 2:3] * np.column_stack([np.ones(len(r)), r[:, 1] / L, -r[:, 0] / L])
    return np.hstack([d, np.cross(r, d) / L])


def kinematic_condition(model: RigidModel, sensors: Lines) -> float:
    """κ(S̃), the scale-free condition number of the kinematic step."""
    s = np.linalg.svd(scaled_sensor_matrix(model, sensors), compute_uv=False)
    return float(s[0] / s[-1]) if s[-1] > 0 else np.inf


def regular(model: RigidModel, sensors: Lines, exciters: Lines) -> bool:
    """The paper's equations solve this layout (exact masslines identify the body), κ(S̃) ≤ KINEMATIC_LIMIT."""
    try:
        identify(synthesise(model.nominal, sensors, exciters), "plate" if model.planar else "method2")
    except SingularLayoutError:
        return False
    return kinematic_condition(model, sensors) <= KINEMATIC_LIMIT
