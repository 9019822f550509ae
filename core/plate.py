"""The plate (paper §2.3, eqs. 10–13): all lines normal to the plate.

The plate lies in z = 0 of the frame with z a principal direction, so a line
along ±z at (x, y) sees only q_p = (a_z, α_x, α_y) through its plate
coordinates (d_z, y d_z, −x d_z), eq. (10). Six parameters are identifiable:

    θ_p = (m, m x_G, m y_G, J_xx, J_yy, J_xy)   (J about O, tensor sign)

and the CoG is taken in the plate's plane (z_G = 0). J_zz, J_xz, J_yz are
unobservable and reported as NaN.
"""

from __future__ import annotations

import numpy as np

from massline.core.degeneracy import exciter_hint
from massline.core.dynamics import MethodResult
from massline.core.errors import MasslineError
from massline.core.linear_system import solve
from massline.core.lines import Lines
from massline.core.masslines import Masslines
from massline.core.rigid_body import steiner

PLATE_PARAMETER_NAMES = ("m", "mc_x", "mc_y", "J_xx", "J_yy", "J_xy")


def plate_coordinates(lines: Lines, what: str = "line") -> np.ndarray:
    """(d_z, y d_z, −x d_z) per line, shape (n, 3); every line must be along ±z."""
    d = lines.directions
    off = np.flatnonzero(np.abs(np.abs(d[:, 2]) - 1.0) > 1e-9)
    if off.size:
        raise MasslineError(
            f"the plate method needs every line normal to the plate (±z); {what} {off[0]} is "
            f"{lines.describe(off[0])}: use the 3-D methods for in-plane lines"
        )
    ell = lines.coordinates
    return ell[:, [2, 3, 4]]


def plate_mass_matrix(theta: np.ndarray) -> np.ndarray:
    """3×3 mass matrix on (a_z, α_x, α_y) about O from θ_p."""
    m, mcx, mcy, jxx, jyy, jxy = theta
    return np.array([[m, mcy, -mcx], [mcy, jxx, jxy], [-mcx, jxy, jyy]])


def plate_kinematics(data: Masslines) -> tuple[np.ndarray, float]:
    """Eq. (10): S_p Q_p = H, three non-collinear transduction points at least."""
    S = plate_coordinates(data.sensors, "sensor")
    return solve(
        S,
        data.values,
        "plate kinematics, eq. (10)",
        "all transduction points lie on one line, so rotation about it is unseen; add a point off that line",
    )


def identify_plate(data: Masslines) -> MethodResult:
    """The plate's mass, in-plane CoG and in-plane inertia (eqs. 10, 12, 13).

    Eq. (12), per exciter: F_z = [a_z, −α_y, α_x] · (M, M x_G, M y_G); three
    exciters not on one line. Eq. (13), per exciter:
    ((y_E − y_G) F_z, −(x_E − x_G) F_z) = [[α_x, 0, α_y], [0, α_y, α_x]] · (J_xx, J_yy, J_xy)
    about G, tensor sign (the paper writes the product of inertia, −J_xy).
    Three exciters × three sensors = 9 measurements.
    """
    Qp, kappa_k = plate_kinematics(data)
    a_z, ax, ay = Qp
    Fz = plate_coordinates(data.exciters, "exciter")[:, 0]
    m_mc, kappa_f = solve(
        np.column_stack([a_z, -ay, ax]),
        Fz,
        "plate dynamics, eq. (12)",
        "the exciters lie on one line; " + exciter_hint(data.exciters),
    )
    mass, xg, yg = m_mc[0], m_mc[1] / m_mc[0], m_mc[2] / m_mc[0]
    x_e, y_e = data.exciters.points[:, 0], data.exciters.points[:, 1]
    rows = np.vstack([np.column_stack([ax, 0 * ax, ay]), np.column_stack([0 * ax, ay, ax])])
    rhs = np.concatenate([(y_e - yg) * Fz, -(x_e - xg) * Fz])
    (jxx, jyy, jxy), kappa_m = solve(
        rows, rhs, "plate dynamics, eq. (13)", "the exciters lie on one line; hit three points not in a row"
    )
    nan = np.nan
    J = np.array([[jxx, jxy, nan], [jxy, jyy, nan], [nan, nan, nan]])
    condition = {"kinematic": kappa_k, "translation": kappa_f, "rotation": kappa_m}
    return MethodResult(mass, np.array([xg, yg, 0.0]), J, condition, "plate (eqs. 10, 12, 13)")


def plate_theta(mass: float, cog: np.ndarray, inertia_cog: np.ndarray) -> np.ndarray:
    """θ_p of a body whose plane of symmetry is z = 0 (J moved to O)."""
    J = inertia_cog + steiner(mass, cog)
    return np.array([mass, mass * cog[0], mass * cog[1], J[0, 0], J[1, 1], J[0, 1]])
