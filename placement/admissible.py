"""Which layouts the planner admits: the paper's equations solve them and their kinematic step is well posed.

The kinematic step (eq. 6) is judged free of units and origin: S̃ has the rows (d, (r − c) × d / L)
about the CoG c, with L the radius of gyration (a plate's, §2.3: d_z (1, (y − c_y)/L, −(x − c_x)/L)),
a linear map T of the lines' coordinates.
When κ(S̃) exceeds KINEMATIC_LIMIT the sensors read some motion an order of magnitude more weakly than
the others: the paper's solve, and the start of every estimator, amplify the noise along it. The
bundled bodies' plans have κ(S̃) of 3–8.
"""

from __future__ import annotations

import numpy as np

from massline.core.errors import SingularLayoutError
from massline.core.lines import Lines, skew
from massline.core.masslines import synthesise
from massline.core.methods import identify
from massline.core.model import RigidModel

KINEMATIC_LIMIT = 30.0


def kinematic_transform(model: RigidModel) -> np.ndarray:
    """T (q × q) taking a line's coordinates ℓ about O to ℓ̃ = T ℓ about the CoG, moments over L."""
    c, L = model.nominal.cog, model.nominal.radius_of_gyration
    if model.planar:  # ℓ = d_z (1, y, −x)
        return np.array([[1.0, 0.0, 0.0], [-c[1] / L, 1 / L, 0.0], [c[0] / L, 0.0, 1 / L]])
    return np.block([[np.eye(3), np.zeros((3, 3))], [-skew(c) / L, np.eye(3) / L]])


def kinematic_condition(model: RigidModel, sensors: Lines) -> float:
    """κ(S̃), the scale-free condition number of the kinematic step."""
    s = np.linalg.svd(model.coordinates(sensors) @ kinematic_transform(model).T, compute_uv=False)
    return float(s[0] / s[-1]) if s[-1] > 0 else np.inf


def weakly_seen(model: RigidModel, rows: np.ndarray, candidates: np.ndarray) -> np.ndarray | None:
    """For sensor rows ℓ (n, q) with κ(S̃) > KINEMATIC_LIMIT, which candidate lines (m, q) read the motion
    they see least with at least a tenth of their sensitivity; None when the rows are well conditioned."""
    T = kinematic_transform(model)
    _, s, Vt = np.linalg.svd(rows @ T.T)
    if len(s) == rows.shape[1] and s[-1] * KINEMATIC_LIMIT >= s[0]:
        return None
    scaled = candidates @ T.T
    return np.abs(scaled @ Vt[-1]) > 0.1 * np.linalg.norm(scaled, axis=1)


def regular(model: RigidModel, sensors: Lines, exciters: Lines) -> bool:
    """The paper's equations solve this layout (exact masslines identify the body), κ(S̃) ≤ KINEMATIC_LIMIT."""
    if not kinematic_condition(model, sensors) <= KINEMATIC_LIMIT:  # the cheap test first
        return False
    try:
        identify(synthesise(model.nominal, sensors, exciters), "plate" if model.planar else "method2")
    except SingularLayoutError:
        return False
    return True
