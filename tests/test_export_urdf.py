"""URDF export, read back by a URDF reader (yourdfpy) and by MuJoCo's URDF importer: the link's inertial is the
body massline measured."""

import mujoco
import numpy as np
import pytest
import yourdfpy
from export_bodies import assert_same_body, measured, rigid_bodies
from test_export_mjcf import loaded

from massline.core.errors import MasslineError
from massline.export import Body, export_text, write_export
from massline.export.units import UNITS
from massline.export.urdf import KEEP_LINK


@pytest.mark.parametrize("name", ["bracket", "far"])
def test_yourdfpy_reads_the_link_inertial(tmp_path, name):
    body = rigid_bodies()[name]
    path = write_export(measured(body), tmp_path / f"{name}.urdf")
    inertial = yourdfpy.URDF.load(str(path), load_meshes=False).link_map["body"].inertial
    origin = inertial.origin
    np.testing.assert_allclose(origin[:3, :3], np.eye(3), atol=0)  # the inertia is along the link's axes
    assert_same_body(inertial.mass, origin[:3, 3], inertial.inertia, body, rtol=1e-9)


def test_mujoco_loads_the_urdf_file_as_written_as_the_same_free_body(tmp_path):
    """MuJoCo's own URDF parser, given the file as a user would: the link becomes a free body (one free joint; it
    falls at g) whose mass, CoG and inertia are massline's; without the floating joint the MuJoCo extension still
    keeps the link from being fused into the world."""
    body = rigid_bodies()["far"]
    path = write_export(measured(body), tmp_path / "far.urdf")
    model = mujoco.MjModel.from_xml_path(str(path))
    assert model.nbody == 2 and model.body_mass[1] == pytest.approx(body.mass, rel=1e-9)
    assert model.njnt == 1 and model.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE and model.jnt_bodyid[0] == 1
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    np.testing.assert_allclose(data.qacc[:3], model.opt.gravity, rtol=0, atol=1e-9 * 9.81)  # nothing holds it
    assert_same_body(*loaded(path.read_text()), body, rtol=1e-9)
    fixed = path.read_text().split('  <joint name="free"')[0] + path.read_text().split("  </joint>\n")[1]
    assert mujoco.MjModel.from_xml_string(fixed).nbody == 2  # jointless, kept by the extension
    assert mujoco.MjModel.from_xml_string(fixed.replace(KEEP_LINK, "")).nbody == 1  # fused: what it prevents


def test_a_plate_is_refused_with_its_unobserved_entries():
    J = np.array([[1e-3, 2e-4, np.nan], [2e-4, 2e-3, np.nan], [np.nan, np.nan, np.nan]])
    plate = Body(mass=0.5, cog=[0.01, 0.02, np.nan], inertia=J)
    with pytest.raises(MasslineError, match="z_G, J_xz, J_yz, J_zz unobserved"):
        export_text(plate, "plate.urdf")


def test_an_inertia_no_body_has_is_refused():
    """Principal moments 1, 1, 3 (J1 + J2 < J3): a paper method's noisy estimate can give it; no solver runs it."""
    with pytest.raises(MasslineError, match="no rigid body's"):
        export_text(Body(mass=1.0, cog=np.zeros(3), inertia=np.diag([1.0, 1.0, 3.0])), "bad.urdf")
    assert "ixx" in export_text(Body(mass=1.0, cog=np.zeros(3), inertia=np.diag([1.0, 2.0, 3.0])), "flat.urdf")


def test_urdf_takes_metres_and_kilograms_only(tmp_path):
    with pytest.raises(MasslineError, match="takes metres and kilograms"):
        write_export(measured(rigid_bodies()["far"]), tmp_path / "far.urdf", UNITS["mm-kg"])
