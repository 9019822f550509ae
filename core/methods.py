"""Every method of the paper, by name, as one pipeline over masslines.

    identify(data, kinematics="method2", dynamics="method3")

Kinematics: ``method1`` (eq. 5), ``method2`` (eq. 6), ``method2-difference``
(eq. 7). Dynamics: ``method1`` (eq. 8 + differences, no mass), ``method2``
(mass among the unknowns), ``method3`` (the paper's choice). ``plate`` runs
§2.3 (eqs. 10–13) on its own.
"""

from __future__ import annotations

from massline.core.dynamics import MethodResult
from massline.core.errors import MasslineError
from massline.core.masslines import Masslines
from massline.core.plate import identify_plate
from massline.core.rigid_body import RigidBody

from . import dynamics, kinematics

KINEMATICS = {
    "method1": kinematics.method1,
    "method2": kinematics.method2,
    "method2-difference": kinematics.method2_difference,
}
DYNAMICS = {"method1": dynamics.method1, "method2": dynamics.method2, "method3": dynamics.method3}


def identify(data: Masslines, kinematics: str = "method2", dynamics: str = "method3") -> MethodResult:
    """Mass, CoG and inertia about the CoG from masslines by the paper's methods."""
    if kinematics == "plate" or dynamics == "plate":
        return identify_plate(data)
    try:
        kin, dyn = KINEMATICS[kinematics], DYNAMICS[dynamics]
    except KeyError as missing:
        raise MasslineError(
            f"unknown method {missing}: kinematics is one of {sorted(KINEMATICS)}, "
            f"dynamics one of {sorted(DYNAMICS)} (or 'plate')"
        ) from None
    return dyn(data, kin(data))


def starting_body(data: Masslines, planar: bool) -> RigidBody:
    """A first body from the masslines: the paper's methods 2 + 3 (or the plate's eqs. 10–13), to start an
    iterative estimate from; a plate's unobservable entries are a thin plate's."""
    found = identify(data, "plate" if planar else "method2", "plate" if planar else "method3")
    if not planar:
        return found.body
    J = found.inertia_cog.copy()
    J[2, :] = J[:, 2] = 0.0
    J[2, 2] = J[0, 0] + J[1, 1]  # unobservable for a plate: a thin plate's value, never used
    return RigidBody(found.mass, found.cog, J)
