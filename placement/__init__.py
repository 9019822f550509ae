"""massline.placement — pre-test: the rigid-body algebra, the paper's methods, meshes in.

The rigid-body algebra lives here once; ``massline.identify`` builds on it.
"""

from massline.placement.dynamics import MethodResult
from massline.placement.errors import MasslineError, SingularLayoutError
from massline.placement.lines import Lines
from massline.placement.masslines import Masslines, synthesise
from massline.placement.methods import identify
from massline.placement.rigid_body import RigidBody

__all__ = [
    "MethodResult",
    "Lines",
    "Masslines",
    "MasslineError",
    "RigidBody",
    "SingularLayoutError",
    "identify",
    "synthesise",
]
