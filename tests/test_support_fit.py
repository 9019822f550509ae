"""A stiff support acts through the body's flexibility, and identify takes the model's departure off with the mesh.

The simulator couples the support's springs to the elastic modes (:mod:`massline.virtual.suspended`): to first
order every massline moves by −(A_ia K_a R_aj + R_ia K_a A_aj). identify with a support model
(:mod:`massline.identify.support_fit`: ``--mesh --suspension``) recovers the body from a cord whose bounce is a
quarter of the first elastic mode, given only the support's kind: the springs' stiffness and the elastic
frequencies are fitted to the record.
"""

import json

import numpy as np
import pytest
from conftest import bundled
from test_cli import massline

from massline import plan_layout
from massline.identify.pipeline import identify_recording
from massline.placement.hand_layouts import structure_exciters, structure_sensors
from massline.uff.writer import write_uff
from massline.virtual.acquisition import Acquisition, run
from massline.virtual.attachment import point_above
from massline.virtual.measurement import Noise
from massline.virtual.planned_test import plan_fe_model
from massline.virtual.support_model import ScaledModes, SupportModel
from massline.virtual.suspended import SuspendedBody
from massline.virtual.suspension import Cord, Suspension, point_map

EXACT = Acquisition(noise=Noise(0.0, 0.0), dc_line=False)


@pytest.fixture(scope="module")
def bracket():
    """The bundled bracket, its minimal plan's lines and its FE model's modes."""
    mesh = bundled("bracket")
    layout = plan_layout(mesh)
    return mesh, layout.sensors, layout.exciters, plan_fe_model(mesh, "bracket").modes


@pytest.fixture(scope="module")
def structure():
    """The bundled structure, the hand layout's 14 accelerometers and 4 hits, and its FE model's modes."""
    mesh = bundled("structure")
    return mesh, structure_sensors(), structure_exciters(), plan_fe_model(mesh, "structure").modes


def cord(mesh, modes, fraction: float) -> Suspension:
    """A 1 m cord tied to the surface above the CoG, its bounce at ``fraction`` of the first elastic mode."""
    body = mesh.nominal
    k = body.mass * (2 * np.pi * modes.frequencies_hz[0] * fraction) ** 2
    return Suspension(cords=(Cord(point_above(mesh.mesh, body.cog)[0], k, 1.0),))


def accelerance(model: SuspendedBody, f: float, sensors, exciters) -> np.ndarray:
    return model.accelerance(np.array([f]), sensors.points, sensors.directions, exciters.points, exciters.directions)[
        :, :, 0
    ]


def test_a_support_moves_the_masslines_through_the_flexibility_as_first_order_says(bracket):
    """Between a bounce at f₁/15 and f₁, the FRFs of the coupled model less the rigid body's on the support and the
    free body's elastic modes are the cross term −(A_ia K R_aj + R_ia K A_aj), R = Σ φφᵀ/ω², to within its
    second-order terms ((f_b/f)² + (f/f₁)² ≈ 13 % at f = f₁/3.9)."""
    mesh, sensors, exciters, modes = bracket
    body, support = mesh.nominal, cord(mesh, modes, 1 / 15)
    f = modes.frequencies_hz[0] / 3.9
    coupled = accelerance(SuspendedBody(body, modes, support), f, sensors, exciters)
    springs = accelerance(SuspendedBody(body, None, support), f, sensors, exciters)
    free = accelerance(SuspendedBody(body, modes), f, sensors, exciters)
    massline = accelerance(SuspendedBody(body), f, sensors, exciters)
    cross = coupled - springs - free + massline
    (point, k), = support.point_springs(body)

    def rigid(points, directions):  # accelerance between the lines and the attachment's three directions
        P = np.stack([d @ point_map(p) for p, d in zip(points, directions)])
        return P @ np.linalg.solve(body.mass_matrix, point_map(point).T)

    def flexibility(points, directions):
        phi = np.einsum("pc,mpc->pm", directions, modes.shapes_at(points))
        at = modes.shapes_at(modes.nearest(point[None]))[:, 0, :]
        return phi @ (at / modes.omega[:, None] ** 2)

    A_s, A_e = rigid(sensors.points, sensors.directions), rigid(exciters.points, exciters.directions)
    R_s, R_e = flexibility(sensors.points, sensors.directions), flexibility(exciters.points, exciters.directions)
    predicted = -(A_s @ k @ R_e.T + R_s @ k @ A_e.T)
    scale = np.abs(predicted).max()
    assert scale > 1e-3 * np.abs(massline).max()  # a per mille of the masslines: the term tested is there
    np.testing.assert_allclose(cross.real, predicted, atol=0.2 * scale)


@pytest.mark.long  # the support model fitted to every FRF of a stiff-cord test (a minute): the long tier
def test_identify_recovers_the_body_from_a_stiff_cord_given_its_kind_alone(structure):
    """A noiseless record on a cord whose bounce is f₁/4: identify as it comes is off by per cents; with the support
    model built from the soft default cord ('--suspension cord') and the elastic frequencies assumed 5 % high,
    the fitted scales find the cord's stiffness (to 1e-3) and the modes (to 1e-4), and the body comes back to
    5e-5 in mass, 0.05 mm in CoG and 0.3 % in the principal moments (a twentieth of the mass and CoG bounds, a
    third of the moments': what the scales' residual leaves near the bounce)."""
    mesh, sensors, exciters, modes = structure
    body, support = mesh.nominal, cord(mesh, modes, 1 / 4)
    recording, _ = run(body, sensors, exciters, modes, support, (), EXACT, 0)
    plain = identify_recording(recording, draws=0)
    assert abs(plain.body.mass / body.mass - 1) > 0.01
    described = Suspension.parse("cord", mesh.mesh, body)  # a soft cord: its stiffness is fitted
    model = SupportModel(ScaledModes(modes, 1.05), described, body)
    found = identify_recording(recording, draws=0, support=model)
    fit = found.support_fit
    assert fit.stiffness * described.cords[0].stiffness == pytest.approx(support.cords[0].stiffness, rel=1e-3)
    assert fit.frequency == pytest.approx(1 / 1.05, rel=1e-4)
    assert found.body.mass == pytest.approx(body.mass, rel=5e-5)
    np.testing.assert_allclose(found.body.cog, body.cog, atol=5e-5)
    np.testing.assert_allclose(found.body.principal_moments, body.principal_moments, rtol=3e-3)
    assert "support_modelled" in {n.code for n in found.notes} and found.payload["support_model"]["steps"] > 1


@pytest.mark.slow
def test_identify_and_diagnose_take_the_support_off_on_the_command_line(structure, tmp_path):
    """The lab's file (mm, g/N, 1 % noise) of the structure on a cord bouncing at f₁/4: ``identify --mesh structure
    --suspension cord`` says what it fitted and comes within the bounds (0.3 % mass, 1 mm CoG), where identify as
    the file comes is per cents off; the report draws the corrected FRFs; diagnose, given the same, names no fault
    and its body before is identify's."""
    mesh, sensors, exciters, modes = structure
    body = mesh.nominal
    recording, _ = run(body, sensors, exciters, modes, cord(mesh, modes, 1 / 4), (), Acquisition(), 3)
    path = tmp_path / "stiff.uff"
    write_uff(path, recording, units="MM", acceleration="g")
    given = ["--mesh", "structure", "--suspension", "cord"]
    plain = massline("identify", path, "--json", tmp_path / "plain.json", "--bootstrap", "0")
    assert plain.returncode == 0, plain.stderr
    assert abs(json.loads((tmp_path / "plain.json").read_text())["mass"] / body.mass - 1) > 0.01
    done = massline("identify", path, *given, "--json", tmp_path / "i.json", "--bootstrap", "20", "--report",
                    tmp_path / "i.html")  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "i.html").stat().st_size > 0  # its FRF figures pass over the lines left out (NaN)
    assert "modelled with the mesh's FE model" in done.stdout
    found = json.loads((tmp_path / "i.json").read_text())
    assert found["support_model"]["converged"] and found["support_model"]["recorded_hz"][0] is not None
    assert abs(found["mass"] / body.mass - 1) < 0.003
    assert np.abs(np.subtract(found["cog"], body.cog)).max() < 1e-3
    diagnosed = massline("diagnose", path, *given, "--json", tmp_path / "d.json")
    assert diagnosed.returncode == 0, diagnosed.stderr
    doc = json.loads((tmp_path / "d.json").read_text())
    assert not [f for f in doc["findings"] if f["kind"] == "fault"], doc["findings"]
    assert doc["properties"]["before"]["mass"] == pytest.approx(found["mass"], rel=1e-9)  # identify's, corrected
