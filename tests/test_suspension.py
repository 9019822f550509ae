"""Suspension physics (Appendix A): closed-form frequencies and the paper's trends."""

import numpy as np
import pytest

from massline.core.errors import MasslineError
from massline.core.lines import Lines
from massline.core.masslines import synthesise
from massline.core.rigid_body import RigidBody
from massline.virtual.band_prediction import predict_band
from massline.virtual.suspended import SuspendedBody
from massline.virtual.suspension import (
    GRAVITY,
    Cord,
    Foam,
    Suspension,
    rigid_suspension_modes,
    single_cord,
)


def block(a=0.3, b=0.2, c=0.1, mass=12.0):
    """A solid block, CoG at (0.01, -0.02, 0.03), edges along the axes."""
    J = mass / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    return RigidBody(mass, np.array([0.01, -0.02, 0.03]), J)


def pendulum_frequencies(mass, inertia, tension, length, height):
    """Cord + rigid body swinging in one vertical plane, coordinates (x_G, φ).

    V = ½ (T/L) (x_G + h φ)² + ½ m g h φ²,  T = ½ m ẋ_G² + ½ J_G φ̇².
    """
    s = tension / length
    K = np.array([[s, s * height], [s * height, s * height**2 + mass * GRAVITY * height]])
    M = np.diag([mass, inertia])
    return np.sort(np.sqrt(np.linalg.eigvals(np.linalg.solve(M, K)).real)) / (2 * np.pi)


@pytest.mark.parametrize("length,height", [(0.5, 0.05), (1.0, 0.12), (0.25, 0.3)])
def test_single_cord_matches_closed_form(length, height):
    body = block()
    k = 400.0
    f, _ = rigid_suspension_modes(body, single_cord(body, k, length, height))
    bounce = np.sqrt(k / body.mass) / (2 * np.pi)
    about_y = pendulum_frequencies(body.mass, body.inertia_cog[1, 1], body.mass * GRAVITY, length, height)
    about_x = pendulum_frequencies(body.mass, body.inertia_cog[0, 0], body.mass * GRAVITY, length, height)
    expected = np.sort(np.concatenate([[0.0, bounce], about_x, about_y]))
    np.testing.assert_allclose(f, expected, rtol=0.01, atol=1e-6)
    # the simple pendulum limit √(g/L)/2π bounds the lower swing mode from above
    assert about_y[0] < np.sqrt(GRAVITY / length) / (2 * np.pi)


def test_gravity_gives_mgh_on_pitch_and_roll():
    body = block()
    K = single_cord(body, 400.0, 1.0, 0.1).geometric_stiffness(body)
    np.testing.assert_allclose(K, body.mass * GRAVITY * 0.1 * np.diag([1.0, 1.0, 0.0]), atol=1e-9)


def test_free_body_gives_the_massline_at_every_frequency():
    rng = np.random.default_rng(3)
    body = block()
    sensors = Lines(rng.normal(size=(7, 3)) * 0.1, rng.normal(size=(7, 3)))
    exciters = Lines(rng.normal(size=(3, 3)) * 0.1, rng.normal(size=(3, 3)))
    H = SuspendedBody(body).accelerance(
        np.array([1.0, 50.0, 300.0]), sensors.points, sensors.directions, exciters.points, exciters.directions
    )
    ideal = synthesise(body, sensors, exciters).values
    np.testing.assert_allclose(H, np.repeat(ideal[:, :, None], 3, axis=2), rtol=1e-12, atol=1e-14)


def bounce_frequency(body, suspension):
    """The suspension mode with the most vertical translation of the CoG."""
    f, shapes = rigid_suspension_modes(body, suspension)
    cog_vertical = np.abs((shapes[:3] + np.cross(shapes[3:].T, body.cog).T)[2])
    return f[np.argmax(cog_vertical)]


def test_stiffer_spring_raises_bounce_and_shrinks_the_band():
    body = block()
    soft, stiff = (single_cord(body, k, 1.0, 0.05) for k in (200.0, 5000.0))
    assert bounce_frequency(body, stiff) > 3 * bounce_frequency(body, soft)
    lines = Lines(body.cog + np.eye(3) * 0.1, np.eye(3))
    low = [predict_band(SuspendedBody(body, suspension=s), lines, lines).low for s in (soft, stiff)]
    assert low[1] > 2 * low[0]


def test_longer_cord_lowers_the_pendulum_modes():
    body = block()
    short, long_ = (rigid_suspension_modes(body, single_cord(body, 400.0, L, 0.1))[0] for L in (0.2, 2.0))
    bounce = np.sqrt(400.0 / body.mass) / (2 * np.pi)
    swing = lambda f: f[(f > 1e-6) & ~np.isclose(f, bounce)]  # noqa: E731
    assert np.all(swing(long_) < swing(short))


def test_attachment_near_the_cog_lowers_the_rotational_modes():
    body = block()
    near, far = (rigid_suspension_modes(body, single_cord(body, 400.0, 1.0, h))[0] for h in (0.02, 0.3))
    assert near[-1] < far[-1] and near[-2] < far[-2]


def test_off_centre_single_cord_is_refused():
    body = block()
    cord = Cord(body.cog + np.array([0.05, 0.0, 0.1]), 400.0, 1.0)
    with pytest.raises(MasslineError, match="straight above the CoG"):
        Suspension(cords=(cord,)).reactions(body)


def test_foam_bounce_and_reactions():
    body = block()
    corners = body.cog + np.array([[x, y, -0.05] for x in (-0.15, 0.15) for y in (-0.1, 0.1)])
    foam = Suspension(foam=Foam(corners, 5000.0))
    np.testing.assert_allclose(foam.reactions(body), body.mass * GRAVITY / 4)
    f, _ = rigid_suspension_modes(body, foam)
    assert np.isclose(f, np.sqrt(5000.0 / body.mass) / (2 * np.pi), rtol=1e-9).any()
