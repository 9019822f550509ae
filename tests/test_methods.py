"""Every method of the paper recovers exact bodies from exact masslines."""

import numpy as np
import pytest
from conftest import assert_body_close

from massline.core import Lines, identify, synthesise
from massline.placement.hand_layouts import (
    bracket_exciters,
    bracket_sensors,
    plate_table1,
    structure_exciters,
    structure_origin_sensors,
    structure_sensors,
)
from massline.core.plate import identify_plate

# Table 1, "Theoretical data, Expected": M, x_G, y_G, J_x, J_y
TABLE1 = {"mass": 5.67e-1, "x_G": 0.0, "y_G": 6.36e-2, "J_x": 4.25e-3, "J_y": 9.26e-4}


def test_plate_table1_theoretical_row(plate):
    """12 measurements (3 exciters × 4 sensors), overdetermined, as in Table 1."""
    sensors, exciters = plate_table1()
    data = synthesise(plate, sensors, exciters)
    assert data.values.shape == (4, 3)
    found = identify(data, "plate")
    # the exact solid plate (5 mm thick) to 1e-9
    assert found.mass == pytest.approx(0.567, rel=1e-9)
    assert abs(found.cog[0]) < 1e-12
    assert found.cog[1] == pytest.approx(0.0636, rel=1e-9)
    assert found.inertia_cog[0, 0] == pytest.approx(0.567 * (0.30**2 + 0.005**2) / 12, rel=1e-9)
    assert found.inertia_cog[1, 1] == pytest.approx(0.567 * (0.14**2 + 0.005**2) / 12, rel=1e-9)
    assert found.inertia_cog[1, 1] == pytest.approx(9.273e-4, rel=1e-4)
    assert abs(found.inertia_cog[0, 1]) < 1e-12
    # the paper's printed (rounded, thin-plate) row within its 0.2 %
    assert found.mass == pytest.approx(TABLE1["mass"], rel=2e-3)
    assert found.cog[1] == pytest.approx(TABLE1["y_G"], rel=2e-3)
    assert found.inertia_cog[0, 0] == pytest.approx(TABLE1["J_x"], rel=2e-3)
    assert found.inertia_cog[1, 1] == pytest.approx(TABLE1["J_y"], rel=2e-3)
    # unobservable entries are reported as such
    assert np.isnan(found.inertia_cog[2, 2]) and np.isnan(found.inertia_cog[0, 2])


def test_plate_nine_measurement_minimum(plate):
    """§2.3: three exciters × three sensors is the determined plate system."""
    sensors, exciters = plate_table1()
    found = identify_plate(synthesise(plate, sensors[:3], exciters))
    assert found.mass == pytest.approx(plate.mass, rel=1e-9)
    np.testing.assert_allclose(found.cog[:2], plate.cog[:2], atol=1e-9 * plate.radius_of_gyration)
    np.testing.assert_allclose(found.inertia_cog[:2, :2], plate.inertia_cog[:2, :2], rtol=1e-9, atol=1e-15)
    assert found.condition["kinematic"] < 1e3


def test_structure_determined_eighteen(structure):
    """Eq. (6) + method 3 with 3 exciters × 6 sensors = 18 masslines."""
    data = synthesise(structure, structure_sensors(), structure_exciters())
    assert data.values.size == 18
    found = identify(data, "method2", "method3")
    assert_body_close(found.body, structure)
    assert set(found.condition) == {"kinematic", "translation", "rotation"}
    assert all(np.isfinite(v) and v >= 1 for v in found.condition.values())


@pytest.mark.parametrize("seed", range(5))
def test_structure_overdetermined_sets(structure, seed):
    """More sensors and exciters than needed: least squares is still exact."""
    rng = np.random.default_rng(seed)
    n_s, n_e = rng.integers(7, 15), rng.integers(4, 8)
    sensors = Lines(rng.uniform(0, 0.16, (n_s, 3)), rng.normal(size=(n_s, 3)))
    exciters = Lines(rng.uniform(0, 0.16, (n_e, 3)), rng.normal(size=(n_e, 3)))
    found = identify(synthesise(structure, sensors, exciters), "method2", "method3")
    assert_body_close(found.body, structure)


def test_structure_triaxial_sensors(bracket):
    """Three triaxial accelerometers not in a row see every rigid motion."""
    sensors = Lines.triaxials([[0.0, 0.0, 0.0], [0.1, 0.0, 0.02], [0.0, 0.07, 0.05]]).transformed(
        np.eye(3), [0.02, -0.01, 0.03]
    )
    exciters = Lines.along_axes([[0.05, 0.0, 0.0], [0.0, 0.05, 0.01], [0.02, 0.02, 0.0]], [0, 1, 2])
    found = identify(synthesise(bracket, sensors, exciters))
    assert_body_close(found.body, bracket)


def test_dynamics_method1_with_36_measurements(structure):
    """Method 1: six exciters (two per direction) × six sensors; no mass."""
    data = synthesise(structure, structure_sensors(), structure_exciters(sets=2))
    assert data.values.size == 36
    found = identify(data, "method2", "method1")
    assert found.mass is None
    np.testing.assert_allclose(found.cog, structure.cog, atol=1e-9 * structure.radius_of_gyration)
    np.testing.assert_allclose(
        found.inertia_cog, structure.inertia_cog, atol=1e-9 * np.abs(structure.inertia_cog).max()
    )
    assert {"inverse_inertia", "cog"} <= set(found.condition)
    with pytest.raises(Exception, match="does not identify the mass"):
        found.body


def test_dynamics_method2_with_24_measurements(structure):
    """Method 2: four excitations × six transductions, the mass among the unknowns."""
    data = synthesise(structure, structure_sensors(), structure_exciters(sets=2)[:4])
    assert data.values.size == 24
    found = identify(data, "method2", "method2")
    assert_body_close(found.body, structure)


def test_dynamics_method2_needs_four_excitations(structure):
    data = synthesise(structure, structure_sensors(), structure_exciters())
    with pytest.raises(Exception, match="rank 3 of 4.*four excitations"):
        identify(data, "method2", "method2")


def test_kinematics_method1_origin_measured(structure):
    data = synthesise(structure, structure_origin_sensors(), structure_exciters())
    found = identify(data, "method1", "method3")
    assert_body_close(found.body, structure)


def test_kinematics_difference_form(structure):
    """Eq. (7): six transduction points in x, y, z pairs."""
    data = synthesise(structure, structure_sensors(), structure_exciters())
    found = identify(data, "method2-difference", "method3")
    assert_body_close(found.body, structure)


@pytest.mark.parametrize("kin", ["method2", "method2-difference"])
@pytest.mark.parametrize("dyn", ["method1", "method2", "method3"])
def test_every_combination_on_the_oblique_bracket(bracket, kin, dyn):
    found = identify(synthesise(bracket, bracket_sensors(), bracket_exciters()), kin, dyn)
    np.testing.assert_allclose(found.cog, bracket.cog, atol=1e-9 * bracket.radius_of_gyration)
    np.testing.assert_allclose(found.inertia_cog, bracket.inertia_cog, atol=1e-9 * np.abs(bracket.inertia_cog).max())
    if found.mass is not None:
        assert found.mass == pytest.approx(bracket.mass, rel=1e-9)


def test_unknown_method_is_named():
    with pytest.raises(Exception, match="unknown method"):
        identify(None, "method7")
