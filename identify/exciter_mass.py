"""The force gauges' mass: what rides on the body at each drive point while that exciter drives it.

A shaker drives the body through a force gauge (an impedance head) whose structure side, m_g kg with the
stinger's attachment, is glued to the body and moves with it: the gauge measures the force into that mass, so
column j of the FRF matrix is the body plus m_g at drive point r_j (the shaker is moved between runs: each
column has its own body). With M(θ) linear in θ (eq. 9 about O), that body is θ + θ_j with

    θ_j = m_g (1, r_j, |r_j|² I − r_j r_jᵀ),

and the estimator fits every column on its own body (mass cancellation by the model,
:func:`massline.core.information.sensitivities`), so the body it reports is the bare one. A hammer has none.
"""

from __future__ import annotations

import numpy as np

from massline.core.errors import MasslineError, param
from massline.core.lines import Lines
from massline.identify.sensor_mass import point_mass_theta


def check_exciter_mass(mass: float, given: str | None = None) -> float:
    """The gauge's structure-side mass (kg), refused unless finite and ≥ 0 (``given``: as the user wrote it)."""
    if not (np.isfinite(mass) and mass >= 0):
        name = param("exciter_mass", given or f"{mass:g}")
        raise MasslineError(f"{name}: give the force gauge's structure-side mass in kg, 0 ≤ KG < inf (0: a hammer)")
    return float(mass)


def parse_exciter_mass(text: str) -> float:
    """``--exciter-mass KG``: a force gauge's structure-side mass, kg (finite, ≥ 0)."""
    try:
        mass = float(text)
    except ValueError:
        mass = np.nan
    return check_exciter_mass(mass, f"'{text}'")


def riding_masses(exciters: Lines, mass: float, planar: bool = False) -> np.ndarray | None:
    """θ_j (n_e, p) SI of ``mass`` kg at each exciter's point (one per column), None for no mass."""
    if check_exciter_mass(mass) == 0:
        return None
    return np.array([point_mass_theta(mass, r, planar) for r in exciters.points])
