"""Masslines with pairs missing: exact from what is present, the ± that the present pairs give, and a refusal
that names what the missing pairs leave undetermined and the FRF that would restore it."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from massline.core.errors import MasslineError
from massline.core.lines import Lines
from massline.core.masslines import Masslines, synthesise
from massline.core.rigid_body import RigidBody
from massline.identify.estimator import estimate
from massline.identify.missing_pairs import (
    check_determined,
    missing_warnings,
    most_restoring,
    numerical_rank,
    parameter_words,
    undetermined,
)
from massline.identify.uncertainty import combined_std

ROTATION = Rotation.from_euler("xyz", [25, -40, 60], degrees=True).as_matrix()
BODY = RigidBody(3.2, np.array([0.01, -0.02, 0.03]), ROTATION @ np.diag([0.02, 0.03, 0.045]) @ ROTATION.T)


def layout(n_s: int = 12, n_e: int = 4, seed: int = 1) -> tuple[Lines, Lines]:
    """Oblique sensor and exciter lines over a 0.4 m body."""
    rng = np.random.default_rng(seed)
    sensors = Lines(rng.uniform(-0.2, 0.2, (n_s, 3)), rng.normal(size=(n_s, 3)))
    return sensors, Lines(rng.uniform(-0.2, 0.2, (n_e, 3)), rng.normal(size=(n_e, 3)))


def dropped(shape: tuple, share: float, seed: int) -> np.ndarray:
    """A present mask with ``share`` of the pairs missing at random (at least one)."""
    rng = np.random.default_rng(seed)
    present = np.ones(shape, bool)
    present.flat[rng.choice(present.size, size=max(1, round(share * present.size)), replace=False)] = False
    return present


def masked(data: Masslines, present: np.ndarray) -> Masslines:
    return Masslines(np.where(present, data.values, 0.0), data.sensors, data.exciters)


LABELS = ([f"{k + 1}:+X" for k in range(12)], [f"{k + 101}:+Z" for k in range(4)])


@pytest.mark.parametrize("share, transverse", [(0.15, 0.0), (0.15, 0.03), (0.3, 0.03)])
def test_noiseless_masslines_with_pairs_missing_identify_exactly(share, transverse):
    data = synthesise(BODY, *layout())
    present = dropped(data.values.shape, share, 4)
    sigma = np.where(present, 1e-3, np.inf)
    found = estimate(masked(data, present), sigma, transverse=transverse)
    assert found.body.mass == pytest.approx(BODY.mass, rel=1e-9)
    np.testing.assert_allclose(found.body.cog, BODY.cog, atol=1e-9 * BODY.radius_of_gyration)
    np.testing.assert_allclose(found.body.inertia_cog, BODY.inertia_cog, atol=1e-9 * BODY.principal_moments[2])
    assert np.isnan(found.residual[~present]).all()
    assert found.dof == pytest.approx(present.sum() - 10, abs=1e-6) if transverse == 0 else found.dof < present.sum()


def test_the_pm_of_the_present_pairs_is_the_scatter_over_seeds():
    """Cramér–Rao on the present pairs within 15 % of the observed scatter (300 draws: ~4 % sampling error), and
    larger than the complete matrix's."""
    data = synthesise(BODY, *layout())
    present = dropped(data.values.shape, 0.15, 4)
    sigma = 0.01 * np.abs(data.values) + 0.002 / BODY.mass
    rng = np.random.default_rng(11)
    found, predicted = [], []
    for _ in range(300):
        noisy = Masslines(data.values + sigma * rng.normal(size=sigma.shape), data.sensors, data.exciters)
        result = estimate(masked(noisy, present), np.where(present, sigma, np.inf), transverse=0.0)
        found.append([result.body.mass, *result.body.cog, *result.body.principal_moments])
        std = combined_std(result, [], 0)
        predicted.append([std["mass"], *std["cog"], *std["principal_moments"]])
    ratio = np.std(found, axis=0, ddof=1) / np.mean(predicted, axis=0)
    assert np.all(np.abs(ratio - 1) < 0.15), ratio
    complete = combined_std(estimate(data, sigma, transverse=0.0), [], 0)
    whole = np.array([complete["mass"], *complete["cog"], *complete["principal_moments"]])
    assert np.all(np.mean(predicted, axis=0) >= whole * (1 - 1e-9)) and np.any(np.mean(predicted, axis=0) > whole)


def test_a_column_whose_rotation_is_unseen_names_the_frf_that_restores_it():
    """A minimal 6 × 3 layout keeping only three responses of the first reference: that column sees 3 motions,
    the present pairs leave parameters undetermined, and the FRF named is one of the missing."""
    sensors, exciters = layout(6, 3)
    data = synthesise(BODY, sensors, exciters)
    present = np.ones((6, 3), bool)
    present[3:, :] = False
    labels = (LABELS[0][:6], LABELS[1][:3])
    with pytest.raises(MasslineError) as refused:
        check_determined(masked(data, present), present, False, labels)
    words = str(refused.value)
    assert "undetermined (9 of 18 pairs missing)" in words and "present responses see 3 of 6 motions" in words
    assert "measure response " in words and "\n" not in words
    named = words.split("measure response ")[1].split(" against reference ")
    i, j = labels[0].index(named[0]), labels[1].index(named[1].split(",")[0])
    assert not present[i, j]
    restored = present.copy()
    restored[i, j] = True
    assert undetermined(masked(data, restored), restored, False, None, labels).count("undetermined") <= 1


def test_too_few_references_left_for_the_moments_is_refused():
    """One reference's FRFs alone (the others all missing) cannot give the inertia: named, and no missing FRF of
    the existing references is too few to say so."""
    data = synthesise(BODY, *layout())
    present = np.zeros((12, 4), bool)
    present[:, 0] = True
    words = undetermined(masked(data, present), present, False, None, LABELS)
    assert "J_yz" in words and "(36 of 48 pairs missing)" in words and "measure response" in words


def test_what_is_present_determines_the_body_then_nothing_is_said():
    data = synthesise(BODY, *layout())
    present = dropped(data.values.shape, 0.05, 2)
    check_determined(masked(data, present), present, False, LABELS)
    assert undetermined(masked(data, present), present, False, None, LABELS) == ""
    (warning,) = missing_warnings([("1:+X", "101:+Z")] * 6, 48)
    assert warning.code == "frf_missing" and warning.text.startswith("6 of 48") and ", …" in warning.text
    assert missing_warnings([], 48) == []


def test_what_is_named_lost_is_the_null_space_s_not_one_basis_vector_s():
    """Two lost directions in any orthonormal basis name the same parameters (their shares of the null space),
    where a single basis vector of it names others by basis; one lost direction is named as its components
    are."""
    names = ("m", "mc_x", "mc_y", "mc_z", "J_xx")
    null = np.array([[0.0, 0.0, 0.0, 0.6, 0.8], [0.0, 0.2, 0.0, 0.0, 0.0]])  # orthogonal, not yet unit
    null /= np.linalg.norm(null, axis=1)[:, None]
    words = {parameter_words(null, names)}
    for angle in np.linspace(0, np.pi, 7):
        c, s = np.cos(angle), np.sin(angle)
        words.add(parameter_words(np.array([[c, s], [-s, c]]) @ null, names))
    assert words == {"the CoG's x, the CoG's z and J_xx"}
    assert parameter_words(null[:1], names) == "the CoG's z and J_xx"
    assert parameter_words(np.array([[0.0, 0.0, 0.0, 0.2, 0.98]]), names) == "J_xx"


def test_ties_are_decided_by_a_stated_rule_not_by_rounding():
    """A gain within 1e-6 of the best ties and the first pair is taken; a singular value at the rank's cut counts
    as 0."""
    assert most_restoring(np.array([0.1, 0.5 * (1 - 1e-9), 0.5, 0.2])) == 1
    assert most_restoring(np.array([0.1, 0.49, 0.5])) == 2
    assert numerical_rank(np.array([1.0, 1e-3, 1e-7 * (1 + 1e-9)])) == 2
    assert numerical_rank(np.array([1.0, 1e-3, 1e-6, 1e-17])) == 3
