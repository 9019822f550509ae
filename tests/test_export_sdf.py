"""SDFormat export, read by a parser written here from the SDFormat specification (link → inertial: ``<pose>``
of the inertial frame in the link frame, ``<mass>``, ``<inertia>`` the matrix's entries ixx … izz).

No SDFormat reader installs from PyPI on this machine (the Gazebo bindings need the system's libsdformat): the
spec is the reader, and the same numbers go through MuJoCo in test_export_mjcf.py."""

import xml.etree.ElementTree as ET

import numpy as np
import pytest
from export_bodies import assert_same_body, measured, rigid_bodies
from scipy.spatial.transform import Rotation

from massline.export import export_text


def read_inertial(text: str) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass, CoG and inertia about the CoG along the link's axes, as the SDFormat spec defines the elements:
    pose = x y z roll pitch yaw (fixed-axis XYZ), inertia = the symmetric matrix of ixx ixy ixz iyy iyz izz."""
    root = ET.fromstring(text)
    assert root.tag == "sdf" and root.get("version")
    links = root.findall("./model/link")
    assert len(links) == 1
    inertial = links[0].find("inertial")
    x, y, z, roll, pitch, yaw = map(float, inertial.findtext("pose").split())
    R = Rotation.from_euler("xyz", [roll, pitch, yaw]).as_matrix()
    e = {name: float(inertial.findtext(f"inertia/{name}")) for name in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
    J = np.array([[e["ixx"], e["ixy"], e["ixz"]], [e["ixy"], e["iyy"], e["iyz"]], [e["ixz"], e["iyz"], e["izz"]]])
    return float(inertial.findtext("mass")), np.array([x, y, z]), R @ J @ R.T


@pytest.mark.parametrize("name", ["bracket", "far"])
def test_the_spec_reads_the_body_back(name):
    body = rigid_bodies()[name]
    assert_same_body(*read_inertial(export_text(measured(body), "body.sdf")), body, rtol=1e-9)
