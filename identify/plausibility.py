"""Is the identified body a body at all, and the mesh's? Checks that catch a wrong unit label or a forgotten mass.

A wrong label scales the file's numbers without touching the fit: mm coordinates labelled m make the body
1000× larger (inertia 10⁶×, the mass unchanged), accelerance in (m/s²)/N labelled g/N makes it 9.81× lighter
(mass and inertia alike). χ² cannot see either; only the body's density can:

* a bound from the inertia: of all bodies of mass m with second moments Σ = ∫(r − c)(r − c)ᵀ dm = ½ tr(J_G) I − J_G
  and no denser than ρ, the uniform ellipsoid of density ρ has the least det Σ (an affine map takes Σ to a
  multiple of I, scaling every density alike, and there the ball has the least Σ∫|r − c|² dm = (3/5) m R²).
  The ellipsoid with semi-axes² 5 eig(Σ)/m therefore bounds the body's peak density from below,
  ρ_min = m / ((4/3)π √det(5Σ/m)). Above the densest element (osmium, 22.6 t/m³) the data are no body: up to
  9.81× above it, the accelerance read 9.81× small (g/N labelled (m/s²)/N) would make it a solid's
  (``heavy_for_extent``); beyond, only a length label does (m labelled mm: ``denser_than_any_material``). Plate
  data see J_xx and J_yy only: the ball's bound on tr J_G ≤ 2 (J_xx + J_yy) stands in for it. The bundled bodies
  and the turned steel parts give 72 (the plate's ball) to 7 300 kg/m³ (a solid steel cylinder);
* a floor from the same ellipsoid, for 3-D data: below ``LIGHT`` a body is a thin closed shell, a foam or a
  honeycomb core, or the accelerance was read 9.81× large ((m/s²)/N labelled g/N: ``light_for_extent``, down to
  LIGHT / 9.81; below that the length, judged by the next check). A thin plate's ball has no floor (its thickness is
  unseen);
* plausibility from the measured points: the accelerometers and hits sit on the body, so it spans their
  convex hull roughly, and its mass over that hull is an apparent density. Lighter than air is no body at all
  (mm or inches labelled m: ``lighter_than_air``);
* against a nominal mesh (``--mesh``), which then decides the 9.81× suspicion in the density's place: the mass
  within ``BY_G`` of 9.81× or 1/9.81× the mesh's is a unit label (``heavy_for_extent``, ``light_for_extent``);
  any other difference beyond 3σ and ``NOMINAL`` is an attachment or a mesh (``nominal_mass_mismatch``): the
  accelerometers' or a force gauge's mass not given (``--sensor-mass``, ``--exciter-mass``), or the mesh's
  density.

Each check is a :class:`.CodedWarning`.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from massline.core.rigid_body import RigidBody
from massline.identify.sensor_mass import weight
from massline.identify.warning_codes import CodedWarning
from massline.uff.units import G

DENSEST = 22_600.0  # kg/m³, osmium: no body holds denser material
LIGHTEST = 1.2  # kg/m³, air: a body this light over the hull of its measured points would float
LIGHT = 100.0  # kg/m³, the inertia ellipsoid's floor: a closed shell's is 1.4 ρ t/R (aluminium, t/R = 1/40: 94)
NOMINAL = 0.02  # relative mass difference from a nominal mesh (with 3σ) that says something rides on the body
SIGMAS = 3.0  # ... and beyond this many of its 1-σ
BY_G = 0.15  # within this fraction of 9.81× (or 1/9.81×) the mesh's mass: a g label on a body within 15 % of its mesh
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
    """The identified ``body`` (SI) needing material denser than any element: 9.81× heavy, or beyond it."""
    bound = density_bound(body.mass, body.inertia_cog, planar)
    if not bound > DENSEST:
        return []
    needs = f"the identified body ({body.mass:.4g} kg) must hold material at least {bound:.3g} kg/m³ dense"
    if bound <= G * DENSEST:
        return [
            CodedWarning(
                "heavy_for_extent",
                f"{needs} for its inertia, more than any element ({DENSEST:g}); read 9.81× lighter it would be "
                f"{bound / G:.3g} kg/m³, a solid's: the accelerance is in g/N labelled (m/s²)/N, 9.81× heavy? {LABELS}",
            )
        ]
    return [
        CodedWarning(
            "denser_than_any_material",
            f"{needs} for its inertia, more than any element ({DENSEST:g}) even read 9.81× lighter; coordinates in "
            f"m labelled mm? {LABELS}",
        )
    ]


def floor_warnings(body: RigidBody, planar: bool) -> list[CodedWarning]:
    """The identified ``body`` (SI, 3-D data) whose inertia ellipsoid is lighter than LIGHT, by less than 9.81×."""
    bound = np.nan if planar else density_bound(body.mass, body.inertia_cog)
    if not LIGHT / G <= bound < LIGHT:
        return []
    return [
        CodedWarning(
            "light_for_extent",
            f"the identified body ({body.mass:.4g} kg) is {bound:.3g} kg/m³ as the uniform ellipsoid of its mass and "
            f"inertia, below {LIGHT:g} (a closed aluminium shell whose wall is 1/40 of its radius): unless it is a "
            f"thinner shell, a foam or a honeycomb core, the accelerance is in (m/s²)/N labelled g/N, 9.81× light "
            f"({G * bound:.3g} kg/m³ read right)? {LABELS}",
        )
    ]


def hull_warnings(mass: float, apparent: float) -> list[CodedWarning]:
    """The identified ``mass`` (kg) at an ``apparent`` density (kg/m³ over the measured points' hull) below air's."""
    if not apparent < LIGHTEST:
        return []
    return [
        CodedWarning(
            "lighter_than_air",
            f"the identified body ({mass:.4g} kg) is {apparent:.3g} kg/m³ over the hull of its measured points, "
            f"lighter than air; coordinates in mm or inches labelled m? {LABELS}",
        )
    ]


def units_warnings(body: RigidBody, points: np.ndarray, planar: bool = False) -> list[CodedWarning]:
    """The identified ``body`` (SI) denser than any material, lighter than the ellipsoid's floor, or lighter than
    air over the hull of ``points`` (the sensors' and hits' points, m; not for plate data, whose points span no
    volume)."""
    if not body.mass > 0:
        return []
    apparent = hull_density(body.mass, points) if not planar else np.nan
    return inertia_warnings(body, planar) + floor_warnings(body, planar) + hull_warnings(body.mass, apparent)


DENSITY_CODES = ("heavy_for_extent", "light_for_extent")  # the 9.81× suspicion the mesh decides in their place


def by_g_warnings(mass: float, nominal: float) -> list[CodedWarning]:
    """The identified ``mass`` (kg) within BY_G of 9.81× or 1/9.81× the mesh's ``nominal`` (kg)."""
    ratio = mass / nominal
    if abs(np.log(ratio / G)) <= np.log1p(BY_G):
        code, read = "heavy_for_extent", "g/N read as (m/s²)/N, 9.81× heavy"
    elif abs(np.log(ratio * G)) <= np.log1p(BY_G):
        code, read = "light_for_extent", "(m/s²)/N read as g/N, 9.81× light"
    else:
        return []
    return [
        CodedWarning(
            code, f"the identified mass {mass:.4g} kg is {ratio:.3g}× the mesh's nominal {nominal:.4g} kg: {read}? "
            f"{LABELS}"
        )
    ]


def excess_sentence(excess: float, housings: int) -> str:
    """What a mass ``excess`` over the mesh (kg) would be: ``housings`` accelerometers' of excess/housings each."""
    if excess > 0 and housings:
        return (
            f"{housings} accelerometers of {weight(excess / housings)} would be {weight(excess)}: give their mass "
            "with --sensor-mass, a force gauge's with --exciter-mass"
        )
    if excess > 0:
        return "something rides on the body: give a force gauge's mass with --exciter-mass"
    return "masses taken off twice (--sensor-mass, --exciter-mass), or a mesh heavier than the part"


def nominal_warnings(
    body: RigidBody, nominal: RigidBody, sd: float = 0.0, housings: int = 0, misfit: bool = False
) -> list[CodedWarning]:
    """The identified mass (kg, its 1-σ ``sd``) against the nominal mesh's: near 9.81× or 1/9.81× it, a unit label
    (:func:`by_g_warnings`); else beyond SIGMAS σ and NOMINAL of it, an attachment not given (``housings``: the
    accelerometers on the body) or the mesh; or, where the rigid model does not fit (``misfit``), the misfit."""
    by_g = by_g_warnings(body.mass, nominal.mass)
    excess = body.mass - nominal.mass
    if by_g or abs(excess) <= max(SIGMAS * sd, NOMINAL * nominal.mass):
        return by_g
    side = "heavier" if excess > 0 else "lighter"
    z = f", {abs(excess) / sd:.0f}σ" if sd > 0 else ""
    first = "the rigid model does not fit the masslines: the fault massline diagnose finds, or " if misfit else ""
    return [
        CodedWarning(
            "nominal_mass_mismatch",
            f"the identified mass {body.mass:.4g} kg is {abs(excess) / nominal.mass:.1%} {side} than the mesh's nominal "
            f"{nominal.mass:.4g} kg ({weight(abs(excess))}{z}): {first}{excess_sentence(excess, housings)}; else "
            "check the mesh's density",
        )
    ]
