"""massline.placement — pre-test: the rigid-body algebra, the paper's methods, meshes in.

The rigid-body algebra lives here once; ``massline.identify`` builds on it.
"""

from .dynamics import Identification
from .errors import MasslineError, SingularLayoutError
from .lines import Lines
from .masslines import Masslines, synthesise
from .methods import identify
from .rigid_body import RigidBody

__all__ = [
    "Identification",
    "Lines",
    "Masslines",
    "MasslineError",
    "RigidBody",
    "SingularLayoutError",
    "identify",
    "synthesise",
]
