"""URDF export, read back by a URDF reader (yourdfpy) and by MuJoCo's URDF importer: the link's inertial is the
body massline measured."""

import numpy as np
import pytest
import yourdfpy
from export_bodies import assert_same_body, measured, rigid_bodies
from test_export_mjcf import loaded

from massline.core.errors import MasslineError
from massline.export import Body, export_text, write_export
from massline.export.units import UNITS


@pytest.mark.parametrize("name", ["bracket", "far"])
def test_yourdfpy_reads_the_link_inertial(tmp_path, name):
    body = rigid_bodies()[name]
    path = write_export(measured(body), tmp_path / f"{name}.urdf")
    inertial = yourdfpy.URDF.load(str(path), load_meshes=False).link_map["body"].inertial
    origin = inertial.origin
    np.testing.assert_allclose(origin[:3, :3], np.eye(3), atol=0)  # the inertia is along the link's axes
    assert_same_body(inertial.mass, origin[:3, 3], inertial.inertia, body, rtol=1e-9)


KEEP_STATIC = '<mujoco><compiler fusestatic="false"/></mujoco>'  # MuJoCo's URDF extension: keep a jointless link


def test_mujoco_imports_the_urdf_as_the_same_body():
    """MuJoCo's own URDF parser: the link becomes a body whose mass, CoG and inertia are massline's (without
    the extension MuJoCo fuses the jointless link into the world)."""
    body = rigid_bodies()["far"]
    text = export_text(measured(body), "far.urdf").replace(
        '<robot name="massline_body">', f'<robot name="massline_body">{KEEP_STATIC}'
    )
    assert_same_body(*loaded(text), body, rtol=1e-9)


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
