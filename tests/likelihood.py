"""The efficient estimator of the planner's accuracy tests: all masslines at once, weighted by their noise.

Gauss–Newton on the weighted residuals (H_ij − ℓ_iᵀ M(θ)⁻¹ w_j) / σ_ij from the paper's methods;
its covariance is the inverse Fisher information at the solution, the Cramér–Rao bound the planner
predicts (the product's estimator is :mod:`massline.identify.estimator`).
"""

from __future__ import annotations

import numpy as np

from massline.core.information import NoiseModel, weighted_sensitivities
from massline.core.masslines import Masslines
from massline.core.methods import starting_body
from massline.core.model import RigidModel
from massline.core.rigid_body import RigidBody


def maximum_likelihood(
    data: Masslines, noise: NoiseModel, planar: bool = False, iterations: int = 20, tol: float = 1e-12
) -> tuple[RigidBody, np.ndarray, RigidModel]:
    """The weighted least-squares body, the covariance of its scaled parameters, and its model."""
    model = RigidModel(starting_body(data, planar), planar)
    s, e = model.coordinates(data.sensors), model.coordinates(data.exciters)
    sigma = noise.sigma(data.values, model.nominal.mass)
    theta = model.theta
    for _ in range(iterations):
        predicted = s @ np.linalg.solve(model.mass_matrix(theta), e.T)
        residual = ((data.values - predicted) / sigma).ravel()
        J = (
            weighted_sensitivities(model, s, e, noise)
            * (noise.sigma(predicted, model.nominal.mass) / sigma)[:, :, None]
        )
        step = np.linalg.lstsq(J.reshape(-1, model.p), residual, rcond=None)[0]
        theta = theta + model.scale * step
        model = RigidModel(model.body(theta), planar)
        if np.abs(step).max() < tol:
            break
    J = weighted_sensitivities(model, s, e, noise).reshape(-1, model.p)
    return model.nominal, np.linalg.inv(J.T @ J), model
