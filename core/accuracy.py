"""Predicted accuracy of a layout: Cramér–Rao bounds on every property.

The covariance of the scaled parameters is F⁻¹; it is carried to mass, CoG,
inertia about the CoG and the principal moments and axes through the Jacobian
of the map θ → properties (central differences, linearisation at the nominal
body). The keys match identify's ``std`` (DESIGN.md). For the plate only the
in-plane quantities are observable; the others are NaN.
"""

from __future__ import annotations

import numpy as np

from massline.core.model import RigidModel
from massline.core.properties import property_vector, std_of

STEP = 1e-6  # relative step of the central differences, in scaled parameters


def property_jacobian(model: RigidModel) -> np.ndarray:
    """∂(property vector)/∂θ̃ (25, p) at the model's body, by central differences in the scaled parameters."""
    theta0 = model.theta
    columns = []
    for k in range(model.p):
        step = np.zeros(model.p)
        step[k] = STEP * model.scale[k]
        plus = property_vector(model.body(theta0 + step), model.planar)
        minus = property_vector(model.body(theta0 - step), model.planar)
        columns.append((plus - minus) / (2 * STEP))
    return np.array(columns).T


def property_covariance(model: RigidModel, covariance_scaled: np.ndarray) -> np.ndarray:
    """Covariance of ``property_vector`` from that of the scaled parameters."""
    jac = property_jacobian(model)
    return jac @ covariance_scaled @ jac.T


def predicted_std(model: RigidModel, F: np.ndarray) -> dict:
    """1-σ of every property (identify's std keys) for information F (scaled)."""
    return covariance_std(model, np.linalg.inv(F))


def covariance_std(model: RigidModel, covariance: np.ndarray) -> dict:
    """1-σ of every property (identify's std keys) for the parameters' ``covariance`` (scaled)."""
    C = property_covariance(model, covariance)
    return std_of(np.sqrt(np.clip(np.diag(C), 0, None)), planar=model.planar)


def worst_relative_std(model: RigidModel, std: dict) -> float:
    """max(σ_m / m, σ_c / L, σ_λ / λ): the figure a layout is judged by.

    L is the radius of gyration, so CoG errors compare with the body's size.
    """
    b = model.nominal
    moments = property_vector(b, model.planar)[13:16]
    terms = [std["mass"] / b.mass, *(std["cog"] / b.radius_of_gyration), *(std["principal_moments"] / moments)]
    return float(np.nanmax(terms))


def layout_worst_std(model: RigidModel, F: np.ndarray) -> float:
    """``worst_relative_std`` of information F; inf when F is singular."""
    if not np.all(np.isfinite(F)) or np.linalg.cond(F) > 1e14:
        return float("inf")
    return worst_relative_std(model, predicted_std(model, F))
