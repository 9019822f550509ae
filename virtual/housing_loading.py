"""What the accelerometers' housings do to the body a plan tests: the loading ``massline plan --sensor-mass``
predicts, kept in plan.json for ``simulate`` and the engineer.

Each housing is a point mass m_k at its accelerometer's point r_k (a triaxial counts once,
:mod:`massline.core.numbering`), so the body the masslines weigh is

    θ_tested = θ_bare + Σ_k m_k (1, r_k, |r_k|² I − r_k r_kᵀ)        (DESIGN.md's θ about O)

exactly (the mass matrix is linear in θ, the paper's eq. 9 about O). The plan states how far the tested body is
from the bare one — the mass, the CoG and the principal moments — against the plan's own predicted 1-σ, so that
the engineer sees before the test whether the housings must be given to identify (``--sensor-mass``, the same
tokens) or are within what the test resolves anyway.

Without ``--sensor-mass`` the plan assumes weightless accelerometers, and says so: plan.json's
``sensor_mass_assumed`` holds what housings of a typical :data:`TYPICAL_HOUSING_KG` each would do to the body, and
the console warns when that is more than the test resolves (beyond the plan's predicted 1-σ in the mass, the CoG or
a principal moment).
"""

from __future__ import annotations

import numpy as np

from massline.core.housing_masses import HousingMasses
from massline.core.rigid_body import RigidBody
from massline.core.lines import Lines
from massline.virtual.acquisition import accelerometer_masses, sensor_mass_payload
from massline.virtual.simulation import loaded_body

TYPICAL_HOUSING_KG = 0.005  # a general-purpose ICP accelerometer, uniaxial or triaxial (miniatures weigh 0.5-2 g)


def planned_masses(doc: dict) -> HousingMasses:
    """The housings plan.json's ``loading`` was predicted with (none: 0 kg each)."""
    return HousingMasses.from_payload(doc.get("loading", {}).get("sensor_mass", 0.0))


def tokens(masses: HousingMasses) -> str:
    """The ``--sensor-mass`` tokens that give ``masses``: '0.008 1=0.025'."""
    return " ".join([f"{masses.default:g}"] + [f"{k}={m:g}" for k, m in sorted(masses.by_label.items())])


def loading(nominal: RigidBody, housings: tuple, masses: HousingMasses, predicted_std: dict | None = None) -> dict:
    """plan.json's ``loading``: the body as tested with its ``housings`` (masses (k,) kg and points (k, 3) m, of
    ``masses`` on the plan's sensors, :func:`massline.virtual.acquisition.accelerometer_masses`) against
    ``nominal`` (the bare body).

    Returns the housings' count and total (kg), the tested body's mass change (kg and %), its CoG's shift (mm),
    its principal moments' changes (%, each in ascending order), the option that gives them to identify, and,
    with the plan's ``predicted_std`` (plan.json's: 1-σ in kg, m and kg·m²), each change in those 1-σ (the CoG's:
    its largest component's).
    """
    tested = loaded_body(nominal, housings, masses)
    moments = tested.principal_moments - nominal.principal_moments
    out = {
        "sensor_mass": sensor_mass_payload(masses),
        "housings": int(len(housings[0])),
        "total_kg": float(housings[0].sum()),
        "mass_percent": float(100 * (tested.mass / nominal.mass - 1)),
        "cog_shift_mm": float(1e3 * np.linalg.norm(tested.cog - nominal.cog)),
        "principal_moments_percent": (100 * moments / nominal.principal_moments).tolist(),
        "identify_option": f"--sensor-mass {tokens(masses)}",
    }
    if predicted_std:
        out["in_predicted_std"] = {
            "mass": float((tested.mass - nominal.mass) / predicted_std["mass"]),
            "cog": float(np.max(np.abs(tested.cog - nominal.cog) / np.asarray(predicted_std["cog"]))),
            "principal_moments": (moments / np.asarray(predicted_std["principal_moments"])).tolist(),
        }
    return out


def loading_sentence(found: dict) -> str:
    """The console's line: what the housings add and the option that takes them off."""
    moments = " / ".join(f"{m:+.2g}" for m in found["principal_moments_percent"])
    sigmas = found.get("in_predicted_std")
    beyond = "" if not sigmas else f" ({abs(sigmas['mass']):.3g}× the plan's predicted 1-σ)"
    return (
        f"housings: {found['housings']} weighing {1e3 * found['total_kg']:.4g} g make the body as tested "
        f"{found['mass_percent']:+.3g} % in mass{beyond}, move its CoG {found['cog_shift_mm']:.3g} mm and its "
        f"principal moments {moments} %; identify {found['identify_option']} takes them off"
    )


def assumed_loading(nominal: RigidBody, sensors: Lines, predicted_std: dict) -> dict:
    """plan.json's ``sensor_mass_assumed`` for a plan given no housing masses: 0 kg planned, and the
    :func:`loading` of typical housings (:data:`TYPICAL_HOUSING_KG` each, a triaxial once) on ``sensors`` with
    ``beyond_predicted_std``: whether any change exceeds the plan's predicted 1-σ."""
    typical = HousingMasses(TYPICAL_HOUSING_KG)
    found = loading(nominal, accelerometer_masses(sensors, typical), typical, predicted_std)
    sigmas = found["in_predicted_std"]
    changes = np.abs([sigmas["mass"], sigmas["cog"], *sigmas["principal_moments"]])  # NaN: unobservable (a plate)
    return {"sensor_mass_kg": 0.0, "typical": found, "beyond_predicted_std": bool(np.any(changes > 1.0))}


def assumed_sentence(assumed: dict) -> str:
    """The console's line: the weightless assumption, what typical housings would add, and the option."""
    found = assumed["typical"]
    each = 1e3 * found["total_kg"] / max(found["housings"], 1)
    moments = " / ".join(f"{m:+.2g}" for m in found["principal_moments_percent"])
    sigma = abs(found["in_predicted_std"]["mass"])
    head = "warning: " if assumed["beyond_predicted_std"] else ""
    return (
        f"{head}accelerometers planned weightless (no --sensor-mass): {found['housings']} typical {each:.3g} g "
        f"housings would weigh {1e3 * found['total_kg']:.3g} g, {found['mass_percent']:.3g} % of the body "
        f"({sigma:.3g}× the predicted 1-σ of the mass), move its CoG {found['cog_shift_mm']:.3g} mm and its "
        f"principal moments {moments} %; give --sensor-mass KG to plan with yours"
    )
