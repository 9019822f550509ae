"""massline.placement — the core: lines, rigid-body algebra, masslines, the paper's methods, the planner.

Pure functions over numpy arrays and small frozen dataclasses, in the one frame O xyz, SI units
(DESIGN.md, "Conventions"). Modules:

- rigid-body algebra: :mod:`.lines` (6-vector lines), :mod:`.rigid_body` (the 10 parameters, M_O),
  :mod:`.masslines` (H = S M_O⁻¹ Wᵀ), :mod:`.properties` (the reported quantities and their 1-σ),
  :mod:`.band` (the massline band);
- the paper: :mod:`.kinematics` (eqs. 5–7), :mod:`.dynamics` (eq. 8, methods 1–3), :mod:`.plate`
  (§2.3), :mod:`.methods` (all of them by name), :mod:`.linear_system`, :mod:`.degeneracy`;
- planning: :mod:`.mesh` (a closed surface → nominal properties), :mod:`.candidates`, :mod:`.model`,
  :mod:`.information` (Fisher information), :mod:`.accuracy` (Cramér–Rao), :mod:`.selection`,
  :mod:`.relaxation`, :mod:`.certificate`, :mod:`.planner`, :mod:`.plan_file`, :mod:`.hand_layouts`;
- shared by every layer: :mod:`.errors` (the user's mistakes), :mod:`.files` (atomic writes),
  :mod:`.effect_names` (the effects' names), :mod:`.numbers` (numbers as printed: a value to its ±).
"""

from massline.placement.band import Band
from massline.placement.dynamics import MethodResult
from massline.placement.errors import MasslineError, SingularLayoutError
from massline.placement.lines import Lines
from massline.placement.masslines import Masslines, synthesise
from massline.placement.methods import identify
from massline.placement.rigid_body import RigidBody

__all__ = [
    "Band",
    "Lines",
    "MasslineError",
    "Masslines",
    "MethodResult",
    "RigidBody",
    "SingularLayoutError",
    "identify",
    "synthesise",
]
