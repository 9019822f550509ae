"""What the accelerometers' housings do to the body a plan tests: the loading ``massline plan --sensor-mass``
predicts, kept in plan.json for ``simulate`` and the engineer.

Each housing is a point mass m_k at its accelerometer's point r_k (a triaxial counts once,
:mod:`massline.core.numbering`), so the body the masslines weigh is

    θ_tested = θ_bare + Σ_k m_k (1, r_k, |r_k|² I − r_k r_kᵀ)        (DESIGN.md's θ about O)

exactly (the mass matrix is linear in θ, the paper's eq. 9 about O). The plan states how far the tested body is
from the bare one — the mass, the CoG and the principal moments — against the plan's own predicted 1-σ, so that
the engineer sees before the test whether the housings must be given to identify (``--sensor-mass``, the same
tokens) or are within what the test resolves anyway.
"""

from __future__ import annotations

import numpy as np

from massline.core.housing_masses import HousingMasses
from massline.core.rigid_body import RigidBody
from massline.virtual.acquisition import sensor_mass_payload
from massline.virtual.simulation import loaded_body


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
