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

from massline.core.housing_masses import check_exciter_mass
from massline.core.lines import Lines
from massline.identify.sensor_mass import point_mass_theta


def riding_masses(exciters: Lines, mass: float, planar: bool = False) -> np.ndarray | None:
    """θ_j (n_e, p) SI of ``mass`` kg at each exciter's point (one per column), None for no mass."""
    if check_exciter_mass(mass) == 0:
        return None
    return np.array([point_mass_theta(mass, r, planar) for r in exciters.points])
