"""Is the identified body a body at all? Dimensional checks that catch a wrong unit label.

A wrong label scales the file's numbers without touching the fit: mm coordinates labelled m make the body
1000× larger (inertia 10⁶×, the mass unchanged), accelerance in (m/s²)/N labelled g/N makes it 9.81× lighter
(mass and inertia alike). χ² cannot see either; only the body's density can:

* a bound from the inertia: of all bodies of mass m no denser than ρ, the ball of density ρ has the least
  Σ∫|r − c|² dm = (3/5) m R², so tr J_G = 2 Σ∫|r − c|² dm ≥ (6/5) m R² with (4/3)πR³ρ = m. The identified
  body therefore holds material at least ρ_min = 3m / (4π R³), R² = 5 tr J_G / (6m), dense: above the densest
  element (osmium, 22.6 t/m³) the geometry is labelled too small (m labelled mm) or the accelerance too low;
* a plausibility from the measured points: the accelerometers and hits sit on the body, so it spans their
  convex hull; a mass over that volume lighter than air is no solid body (mm or inches labelled m). It is no
  bound (a frame fills little of its hull), hence the threshold far below any structure;
* against a nominal mesh (``--mesh``): the identified mass more than ``NOMINAL`` off the mesh's.

A factor 9.81 (g/N against (m/s²)/N) hides inside the spread of real densities: only the mesh check sees it.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from massline.core.rigid_body import RigidBody

DENSEST = 22_600.0  # kg/m³, osmium: no body holds denser material
LIGHTEST = 1.2  # kg/m³, air: a body this light over the hull of its measured points would float
NOMINAL = 0.2  # relative mass difference from a nominal mesh that says a unit label is wrong
LABELS = "check the file's unit labels (dataset 164's length unit, and g/N against (m/s²)/N in the FRF labels)"


def density_bound(mass: float, inertia_cog: np.ndarray, planar: bool = False) -> float:
    """ρ_min = 3m/(4πR³), R² = 5 tr J_G/(6m): the least peak density (kg/m³) of a body of mass ``mass`` (kg) with
    inertia ``inertia_cog`` (3×3, kg·m², about the CoG). Plate data (``planar``) see J_xx, J_yy only:
    tr J_G ≤ 2 (J_xx + J_yy) keeps the bound a bound. nan for a mass or trace that is not positive (no body)."""
    trace = 2 * (inertia_cog[0, 0] + inertia_cog[1, 1]) if planar else np.trace(inertia_cog)
    if not (mass > 0 and trace > 0):
        return np.nan
    radius = np.sqrt(5 * trace / (6 * mass))
    return float(3 * mass / (4 * np.pi * radius**3))


def hull_density(mass: float, points: np.ndarray) -> float:
    """Mass (kg) over the convex hull volume (m³) of ``points`` (k, 3) m, kg/m³; nan when they span no volume."""
    try:
        return float(mass / ConvexHull(points).volume)
    except (QhullError, ValueError, ZeroDivisionError):
        return np.nan


def units_warnings(body: RigidBody, points: np.ndarray, planar: bool = False) -> list[str]:
    """The identified ``body`` (SI) denser than any material, or lighter than air over the hull of ``points``
    (the sensors' and hits' points, m)."""
    if not body.mass > 0:
        return []
    found = []
    bound = density_bound(body.mass, body.inertia_cog, planar)
    if bound > DENSEST:
        found.append(
            f"the identified body ({body.mass:.4g} kg) is too heavy for its inertia: it must hold material at "
            f"least {bound:.3g} kg/m³ dense, more than any element ({DENSEST:g}); coordinates in m labelled mm, "
            f"or accelerance too small? {LABELS}"
        )
    apparent = hull_density(body.mass, points) if not planar else np.nan
    if apparent < LIGHTEST:
        found.append(
            f"the identified body ({body.mass:.4g} kg) is {apparent:.3g} kg/m³ over the hull of its measured points, "
            f"lighter than air; coordinates in mm or inches labelled m? {LABELS}"
        )
    return found


def nominal_warnings(body: RigidBody, nominal: RigidBody) -> list[str]:
    """The identified mass (kg) more than NOMINAL off the nominal mesh's."""
    ratio = body.mass / nominal.mass
    if abs(ratio - 1) <= NOMINAL:
        return []
    return [
        f"the identified mass {body.mass:.4g} kg is {ratio:.3g}× the mesh's nominal {nominal.mass:.4g} kg (a factor "
        f"9.81 is g/N read as (m/s²)/N or the reverse); {LABELS}, then the mesh's density"
    ]
