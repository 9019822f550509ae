"""The rigid-body algebra: parameters, mass matrix, principal axes, frames."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from massline.core.lines import Lines, skew
from massline.core.rigid_body import (
    RigidBody,
    mass_matrix,
    mass_matrix_basis,
    mass_matrix_regressor,
    theta_from_mass_matrix,
)

finite = st.floats(-1.0, 1.0, allow_nan=False)
vectors = st.tuples(finite, finite, finite).map(np.array)


@st.composite
def bodies(draw):
    """Physical bodies: positive mass, J_G = R diag(p) Rᵀ with triangle-inequality moments."""
    mass = draw(st.floats(0.05, 500.0))
    a, b, c = (draw(st.floats(0.01, 1.0)) for _ in range(3))  # half-extents of an equivalent box
    p = mass / 3 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])
    R = Rotation.from_rotvec(draw(vectors) * 3).as_matrix()
    return RigidBody(mass, draw(vectors), R @ np.diag(p) @ R.T)


@given(bodies())
def test_theta_mass_matrix_theta_round_trip(body):
    theta = body.theta
    np.testing.assert_allclose(
        theta_from_mass_matrix(mass_matrix(theta)), theta, rtol=0, atol=1e-12 * np.abs(theta).max()
    )
    back = RigidBody.from_theta(theta)
    np.testing.assert_allclose(back.cog, body.cog, atol=1e-12)
    np.testing.assert_allclose(back.inertia_cog, body.inertia_cog, atol=1e-12 * np.abs(body.inertia_cog).max() + 1e-15)


@given(bodies())
def test_mass_matrix_is_the_newton_euler_operator(body):
    """M_O q gives the wrench about O of the rigid acceleration q (eqs. 3, 2)."""
    q = np.array([0.3, -1.2, 0.7, 2.0, 0.5, -1.5])
    a_O, alpha = q[:3], q[3:]
    a_G = a_O + np.cross(alpha, body.cog)
    force = body.mass * a_G
    moment_O = body.inertia_cog @ alpha + np.cross(body.cog, force)  # no ω² terms: linearised
    np.testing.assert_allclose(body.mass_matrix @ q, np.concatenate([force, moment_O]), atol=1e-9 * np.abs(force).max())


@given(bodies(), st.tuples(*[finite] * 6).map(np.array))
def test_regressor_and_basis_are_linear_in_theta(body, q):
    theta = body.theta
    np.testing.assert_allclose(mass_matrix_regressor(q) @ theta, body.mass_matrix @ q, atol=1e-9 * np.abs(theta).max())
    np.testing.assert_allclose(
        np.einsum("k,kij->ij", theta, mass_matrix_basis()), body.mass_matrix, atol=1e-12 * np.abs(theta).max()
    )


@given(bodies())
def test_principal_axes_are_a_right_handed_eigenbasis(body):
    moments, axes = body.principal_moments, body.principal_axes
    assert np.all(np.diff(moments) >= 0)
    np.testing.assert_allclose(axes.T @ axes, np.eye(3), atol=1e-12)
    assert np.linalg.det(axes) > 0
    np.testing.assert_allclose(axes @ np.diag(moments) @ axes.T, body.inertia_cog, atol=1e-10 * moments.max())


@given(bodies(), vectors, vectors)
def test_frame_change_keeps_principal_moments_and_rotates_axes(body, rotvec, t):
    R = Rotation.from_rotvec(rotvec * 3).as_matrix()
    moved = body.transformed(R, t)
    np.testing.assert_allclose(moved.principal_moments, body.principal_moments, rtol=1e-10, atol=1e-14)
    np.testing.assert_allclose(moved.cog, R @ body.cog + t, atol=1e-12)
    np.testing.assert_allclose(np.linalg.inv(R) @ (moved.cog - t), body.cog, atol=1e-12)


def test_lines_carry_point_direction_and_moment():
    lines = Lines([[1.0, 2.0, 3.0]], [[0.0, 0.0, 2.0]])
    np.testing.assert_allclose(lines.coordinates, [[0, 0, 1, 2, -1, 0]])
    np.testing.assert_allclose(skew(np.array([1.0, 2, 3])) @ np.array([4.0, 5, 6]), np.cross([1, 2, 3], [4, 5, 6]))
    tri = Lines.triaxials([[0, 0, 0], [1, 0, 0]])
    assert list(tri.triaxial) == [0, 0, 0, 1, 1, 1]
    assert list((tri + tri).triaxial) == [0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3]


@settings(max_examples=50)
@given(bodies(), vectors, vectors)
def test_a_sensor_reads_the_acceleration_of_its_point(body, point, direction):
    """ℓ · q = d · (a_O + α × r) for every line (DESIGN.md conventions)."""
    if np.linalg.norm(direction) < 1e-3:
        return
    q = np.array([0.1, 0.2, -0.3, 1.0, -2.0, 0.5])
    ell = Lines(point, direction)
    d = ell.directions[0]
    np.testing.assert_allclose(ell.coordinates[0] @ q, d @ (q[:3] + np.cross(q[3:], point)), atol=1e-12)
