"""MuJoCo MJCF export, read back by MuJoCo itself: the compiled model's body mass, CoG and inertia (rebuilt from
``body_inertia`` and ``body_iquat``) are massline's."""

import mujoco
import numpy as np
import pytest
from export_bodies import assert_same_body, measured, rigid_bodies

from massline.core import __version__
from massline.core.errors import MasslineError
from massline.export import export_text, write_export
from massline.export.units import UNITS


def loaded(text: str) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass (kg), CoG (m, world frame) and inertia about the CoG (kg·m², world axes) of the model's body 1,
    as MuJoCo compiled them: J = R diag(body_inertia) Rᵀ with R the rotation of the quaternion body_iquat."""
    model = mujoco.MjModel.from_xml_string(text)
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    R = np.zeros(9)
    mujoco.mju_quat2Mat(R, model.body_iquat[1])
    R = R.reshape(3, 3)
    return float(model.body_mass[1]), data.xipos[1].copy(), R @ np.diag(model.body_inertia[1]) @ R.T


@pytest.mark.parametrize("name", ["bracket", "far"])
def test_mujoco_loads_the_body_massline_measured(name):
    body = rigid_bodies()[name]
    mass, cog, inertia = loaded(export_text(measured(body), "body.xml"))
    assert_same_body(mass, cog, inertia, body, rtol=1e-9)


def test_the_products_of_inertia_keep_their_sign():
    """Negating J_xy changes the principal moments MuJoCo finds: the bracket's read back is its own, not that."""
    body = rigid_bodies()["bracket"]
    _, _, inertia = loaded(export_text(measured(body), "body.xml"))
    flipped = body.inertia_cog * np.where(np.eye(3) == 1, 1, -1)
    assert np.abs(np.linalg.eigvalsh(inertia) - np.linalg.eigvalsh(flipped)).max() > 1e-2 * body.principal_moments[2]
    np.testing.assert_allclose(np.linalg.eigvalsh(inertia), body.principal_moments, rtol=1e-9)


def test_the_file_says_what_it_holds(tmp_path):
    text = write_export(measured(rigid_bodies()["far"]), tmp_path / "far.xml").read_text()
    assert "mass = 0.34560 +/- 0.00035 kg" in text and f"massline {__version__} export" in text
    assert "fullinertia = M(1,1) M(2,2) M(3,3) M(1,2)" in text and "units: length m, mass kg" in text


@pytest.mark.parametrize("units", ["mm-kg", "mm-t"])
def test_mujoco_takes_metres_and_kilograms_only(tmp_path, units):
    with pytest.raises(MasslineError, match="takes metres and kilograms"):
        write_export(measured(rigid_bodies()["far"]), tmp_path / "far.xml", UNITS[units])
    assert not (tmp_path / "far.xml").exists()
