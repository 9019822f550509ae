"""massline.core — the kernel every stage stands on; it imports nothing else of the project.

Pure functions over numpy arrays and small frozen dataclasses, in the one frame O xyz, SI units
(DESIGN.md, "Conventions"). Modules:

- rigid-body algebra: :mod:`.lines` (6-vector lines), :mod:`.rigid_body` (the 10 parameters, M_O),
  :mod:`.masslines` (H = S M_O⁻¹ Wᵀ), :mod:`.properties` (the reported quantities and their 1-σ),
  :mod:`.band` (the massline band type);
- the paper: :mod:`.kinematics` (eqs. 5–7), :mod:`.dynamics` (eq. 8, methods 1–3), :mod:`.plate`
  (§2.3), :mod:`.methods` (all of them by name), :mod:`.linear_system`, :mod:`.degeneracy`;
- a layout's worth: :mod:`.model` (3-D or plate), :mod:`.information` (Fisher information),
  :mod:`.accuracy` (Cramér–Rao);
- shared by every stage: :mod:`.errors` (the user's mistakes), :mod:`.files` (atomic writes),
  :mod:`.effect_names` (the effects' vocabulary), :mod:`.numbers` (numbers as printed: a value to its ±).
"""

from massline.core.band import Band
from massline.core.dynamics import MethodResult
from massline.core.errors import MasslineError, SingularLayoutError
from massline.core.lines import Lines
from massline.core.masslines import Masslines, synthesise
from massline.core.methods import identify
from massline.core.rigid_body import RigidBody

__version__ = "0.1.0"

__all__ = [
    "Band",
    "Lines",
    "MasslineError",
    "Masslines",
    "MethodResult",
    "RigidBody",
    "SingularLayoutError",
    "__version__",
    "identify",
    "synthesise",
]
