"""Is the identified body a body at all? Dimensional checks that catch a wrong unit label.

A wrong label scales the file's numbers without touching the fit: mm coordinates labelled m make the body
1000× larger (inertia 10⁶×, the mass unchanged), accelerance in (m/s²)/N labelled g/N makes it 9.81× lighter
(mass and inertia alike). χ² cannot see either; only the body's density can:

* a bound from the inertia: of all bodies of mass m with second moments Σ = ∫(r − c)(r − c)ᵀ dm = ½ tr(J_G) I − J_G
  and no denser than ρ, the uniform ellipsoid of density ρ has the least det Σ (an affine map takes Σ to a
  multiple of I, scaling every density alike, and there the ball has the least Σ∫|r − c|² dm = (3/5) m R²).
  The ellipsoid with semi-axes² 5 eig(Σ)/m therefore bounds the body's peak density from below,
  ρ_min = m / ((4/3)π √det(5Σ/m)): above the densest element (osmium, 22.6 t/m³) the geometry is labelled too
  small (m labelled mm) or the accelerance too low. Plate data see J_xx and J_yy only: the ball's bound on
  tr J_G ≤ 2 (J_xx + J_yy) stands in for it;
* plausibility from the measured points: the accelerometers and hits sit on the body, so it spans their
  convex hull roughly, and its mass over that hull is an apparent density. Lighter than air is no body at all
  (mm or inches labelled m). Heavier than HEAVY (above steel, brass and copper) or lighter than LIGHT (a hollow
  sheet-metal housing's floor) is no bound (points bunched inside a solid body raise it, a thin shell or a
  honeycomb panel lowers it) but says what a factor 9.81 does to an ordinary structure: (m/s²)/N labelled g/N
  makes it 9.81× lighter, g/N labelled (m/s²)/N 9.81× heavier, and the inertia cannot tell (J/m is unchanged);
* against a nominal mesh (``--mesh``): the identified mass more than ``NOMINAL`` off the mesh's.

Each check is a :class:`.CodedWarning` (codes ``denser_than_any_material``, ``lighter_than_air``,
``heavy_for_extent``, ``light_for_extent``, ``nominal_mass_mismatch``).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from massline.core.rigid_body import RigidBody
from massline.identify.warning_codes import CodedWarning

DENSEST = 22_600.0  # kg/m³, osmium: no body holds denser material
LIGHTEST = 1.2  # kg/m³, air: a body this light over the hull of its measured points would float
HEAVY = 10_000.0  # kg/m³ over the points' hull: above steel (7 850), brass (8 700), copper (8 960); lead is 11 340
LIGHT = 250.0  # kg/m³ over the points' hull: a closed 1.5 mm aluminium box of 10 cm is 240
NOMINAL = 0.2  # relative mass difference from a nominal mesh that says a unit label is wrong
LABELS = "check the file's unit labels (dataset 164's length unit, and g/N against (m/s²)/N in the FRF labels)"


def ball_bound(mass: float, trace: float) -> float:
    """ρ_min = 3m/(4πR³), R² = 5 ``trace``/(6m): the ball's bound (kg/m³) from tr J_G (kg·m²)."""
    radius = np.sqrt(5 * trace / (6 * mass))
    return float(3 * mass / (4 * np.pi * radius**3))


def ellipsoid_bound(mass: float, inertia_cog: np.ndarray) -> float:
    """ρ_min = m / ((4/3)π √det(5Σ/m)), Σ = ½ tr(J_G) I − J_G: the uniform ellipsoid's density (kg/m³) of the
    body's mass (kg) and second moments; nan when Σ is not positive definite (no body)."""
    sigma = 0.5 * np.trace(inertia_cog) * np.eye(3) - inertia_cog
    det = np.linalg.det(5 * sigma / mass)
    if not (np.linalg.eigvalsh(sigma).min() > 0 and det > 0):
        return np.nan
    return float(mass / (4 / 3 * np.pi * np.sqrt(det)))


def density_bound(mass: float, inertia_cog: np.ndarray, planar: bool = False) -> float:
    """The least peak density (kg/m³) of a body of mass ``mass`` (kg) with inertia ``inertia_cog`` (3×3, kg·m²,
    about the CoG): the ellipsoid's bound, or for plate data (``planar``, J_xx and J_yy seen) the ball's with
    tr J_G ≤ 2 (J_xx + J_yy). nan for a mass, trace or second moment that is not positive (no body)."""
    trace = 2 * (inertia_cog[0, 0] + inertia_cog[1, 1]) if planar else np.trace(inertia_cog)
    if not (mass > 0 and trace > 0):
        return np.nan
    return ball_bound(mass, trace) if planar else ellipsoid_bound(mass, inertia_cog)


def hull_density(mass: float, points: np.ndarray) -> float:
    """Mass (kg) over the convex hull volume (m³) of ``points`` (k, 3) m, kg/m³; nan when they span no volume."""
    try:
        return float(mass / ConvexHull(points).volume)
    except (QhullError, ValueError, ZeroDivisionError):
        return np.nan


def inertia_warnings(body: RigidBody, planar: bool) -> list[CodedWarning]:
    """The identified ``body`` (SI) needing material denser than any element."""
    bound = density_bound(body.mass, body.inertia_cog, planar)
    if not bound > DENSEST:
        return []
    return [
        CodedWarning(
            "denser_than_any_material",
            f"the identified body ({body.mass:.4g} kg) is too heavy for its inertia: it must hold material at "
            f"least {bound:.3g} kg/m³ dense, more than any element ({DENSEST:g}); coordinates in m labelled mm, "
            f"or accelerance too small? {LABELS}",
        )
    ]


def extent_warnings(mass: float, apparent: float) -> list[CodedWarning]:
    """The identified ``mass`` (kg) at an ``apparent`` density (kg/m³ over the measured points' hull) below air's,
    or outside LIGHT–HEAVY, where an ordinary structure 9.81× off would sit."""
    where = f"the identified body ({mass:.4g} kg) is {apparent:.3g} kg/m³ over the hull of its measured points"
    if apparent < LIGHTEST:
        return [
            CodedWarning(
                "lighter_than_air", f"{where}, lighter than air; coordinates in mm or inches labelled m? {LABELS}"
            )
        ]
    if apparent > HEAVY:
        return [
            CodedWarning(
                "heavy_for_extent",
                f"{where}, heavier than steel, brass or copper: unless it is solid lead or tungsten (or the points "
                f"bunch inside a solid body), the accelerance is in g/N labelled (m/s²)/N, 9.81× heavy? {LABELS}",
            )
        ]
    if apparent < LIGHT:
        return [
            CodedWarning(
                "light_for_extent",
                f"{where}, lighter than a closed sheet-metal housing ({LIGHT:g} kg/m³): unless it is a thin shell or a "
                f"honeycomb panel, the accelerance is in (m/s²)/N labelled g/N, 9.81× light? {LABELS}",
            )
        ]
    return []


def units_warnings(body: RigidBody, points: np.ndarray, planar: bool = False) -> list[CodedWarning]:
    """The identified ``body`` (SI) denser than any material, or at an implausible density over the hull of
    ``points`` (the sensors' and hits' points, m; not for plate data, whose points span no volume)."""
    if not body.mass > 0:
        return []
    found = inertia_warnings(body, planar)
    apparent = hull_density(body.mass, points) if not planar else np.nan
    if np.isnan(apparent) or (found and apparent > HEAVY):
        return found
    return found + extent_warnings(body.mass, apparent)


def nominal_warnings(body: RigidBody, nominal: RigidBody) -> list[CodedWarning]:
    """The identified mass (kg) more than NOMINAL off the nominal mesh's."""
    ratio = body.mass / nominal.mass
    if abs(ratio - 1) <= NOMINAL:
        return []
    return [
        CodedWarning(
            "nominal_mass_mismatch",
            f"the identified mass {body.mass:.4g} kg is {ratio:.3g}× the mesh's nominal {nominal.mass:.4g} kg (a "
            f"factor 9.81 is g/N read as (m/s²)/N or the reverse); {LABELS}, then the mesh's density",
        )
    ]
