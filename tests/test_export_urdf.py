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


def test_mujoco_loads_the_urdf_file_as_written_as_the_same_body(tmp_path):
    """MuJoCo's own URDF parser, given the file as a user would: the link becomes a body whose mass, CoG and inertia
    are massline's (the file's MuJoCo extension keeps the jointless link from being fused into the world)."""
    body = rigid_bodies()["far"]
    path = write_export(measured(body), tmp_path / "far.urdf")
    model = mujoco.MjModel.from_xml_path(str(path))
    assert model.nbody == 2 and model.body_mass[1] == pytest.approx(body.mass, rel=1e-9)
    assert_same_body(*loaded(path.read_text()), body, rtol=1e-9)
    without = path.read_text().replace(KEEP_LINK, "")
    assert mujoco.MjModel.from_xml_string(without).nbody == 1  # fused into the world: what the extension prevents


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
