"""Plans a test engineer can carry out: points on flat faces clear of edges, fixed points snapped, sliding."""

import json

import numpy as np
import pytest
import session_cache
import trimesh
from conftest import FIXTURE_MESHES, bundled
from test_cli import massline

from massline.placement.candidates import (
    CandidateOptions,
    CandidatePoints,
    blocks_needed,
    candidate_points,
    unseen_twists,
)
from massline.core.errors import MasslineError
from massline.core.information import fisher, log_det
from massline.core.lines import Lines
from massline.meshes.loader import load_body
from massline.placement.mountable import Surface, feature_edges, foot_on_segments
from massline.placement.mounts import motion_text
from massline.placement.on_surface import plan
from massline.placement.planner import Budget
from massline.uff.grid import to_recording
from massline.uff.reader import read_uff

MINIMAL = {"plate": Budget(3, 3), "structure": Budget(6, 3), "bracket": Budget(6, 3)}
# The real CAD parts that load, their units, a budget their flat places allow and the options: flat places
# facing two or three directions only (uniaxial normals cannot see every motion) take triaxials; the tray's
# 3.2 mm rims take a 2 mm hammer tip.
CAD = {
    "plate_holes.STL": ("mm", Budget(0, 3, 3), CandidateOptions()),
    "1002_tray_bottom.STL": ("mm", Budget(0, 3, 3), CandidateOptions(hammer_tip=2e-3)),
    "featuretype.STL": ("in", Budget(6, 3), CandidateOptions()),
    "idler_riser.STL": ("in", Budget(0, 3, 3), CandidateOptions()),
    "angle_block.STL": ("in", Budget(0, 3, 3), CandidateOptions()),
    "ADIS16480.STL": ("m", Budget(6, 3), CandidateOptions()),
}


def cad_plan(name: str):
    """The CAD part ``name`` (tests/fixtures/meshes) and its plan of ``CAD``'s budget, planned once this session
    (test_footprints keeps the same plan's points apart)."""
    units, budget, options = CAD[name]
    body = load_body(FIXTURE_MESHES / name, units, density=2700)
    return body, session_cache.value("CAD plan", lambda: plan(body, budget, options, certify_steps=12500), name)


IDLER_BORE = (0.375, 0.15, 0.25)  # inches: on the axis of the 0.2 in hole through the idler's foot


def brute_clearance(surface: Surface, points: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Every segment of the point's own patch and every feature edge, measured one by one."""
    out = []
    for p, f in zip(points, faces):
        mine = (surface.owner < 0) | (surface.owner == surface.patch[f])
        seg = surface.segments[mine]
        out.append(np.linalg.norm(p - foot_on_segments(np.tile(p, (len(seg), 1)), seg[:, 0], seg[:, 1]), axis=1).min())
    return np.array(out)


def edge_distance(mesh: trimesh.Trimesh, points: np.ndarray) -> np.ndarray:
    """Distance (m) from each point to the nearest feature edge, in space."""
    edges = feature_edges(mesh)
    return np.array(
        [
            np.linalg.norm(p - foot_on_segments(np.tile(p, (len(edges), 1)), edges[:, 0], edges[:, 1]), axis=1).min()
            for p in points
        ]
    )


def assert_mountable(body, p):
    """Every planned point that is not fixed is on its flat patch, or on its curved region's surface, holding its
    footprint, clear of every edge."""
    surface = Surface.of(body.mesh)
    region = surface.smooth[0]
    for lines, nodes, need in (
        (p.sensors, p.sensor_nodes, p.clearances[0]),
        (p.exciters, p.exciter_nodes, p.clearances[1]),
    ):
        points = lines.points[nodes >= 0]
        start = p.candidates.faces[nodes[nodes >= 0]]
        faces = np.array([surface.locate(q, surface.patch[f]) for q, f in zip(points, start)])
        for k in np.flatnonzero(surface.curved[start]):
            foot, faces[k] = surface.onto_region(points[k], region[start[k]])
            assert np.linalg.norm(foot - points[k]) < 1e-9, "a point left its curved region's surface"
        assert (faces >= 0).all(), "a point left its flat patch"
        assert (edge_distance(body.mesh, points) >= need * (1 - 1e-9)).all()
        assert (brute_clearance(surface, points, faces) >= need * (1 - 1e-9)).all()


@pytest.mark.parametrize("name,units", [("structure", "m"), ("idler_riser.STL", "in"), ("ADIS16480.STL", "m")])
def test_clearance_search_is_exact(name, units):
    body = bundled(name) if units == "m" and "." not in name else load_body(FIXTURE_MESHES / name, units, density=2700)
    surface = Surface.of(body.mesh)
    points, faces = trimesh.sample.sample_surface(body.mesh, 300, seed=1)
    reach = 0.006
    found = surface.clearance(points, faces, reach)
    np.testing.assert_allclose(found, np.minimum(brute_clearance(surface, points, faces), reach), atol=1e-12)


def test_no_candidate_near_an_edge_or_off_a_flat_face():
    body = bundled("bracket")
    points = candidate_points(body.mesh, CandidateOptions())
    sensors = points.points[points.sensor_fit]
    assert edge_distance(body.mesh, points.points).min() >= 0.003 - 1e-12
    assert edge_distance(body.mesh, sensors).min() >= 0.005 - 1e-12
    assert 0 < len(sensors) < len(points)


@pytest.fixture(scope="module")
def bundled_plans():
    return {name: plan(bundled(name), budget) for name, budget in MINIMAL.items()}


@pytest.mark.parametrize("name", list(MINIMAL))
def test_bundled_plans_are_mountable_and_sliding_gains(bundled_plans, name):
    p = bundled_plans[name]
    assert_mountable(bundled(name), p)
    assert p.sliding.gain > 0 and p.log_det == pytest.approx(p.candidate_log_det + p.sliding.gain)
    F = fisher(p.model, p.model.coordinates(p.sensors), p.model.coordinates(p.exciters), p.noise)
    assert log_det(F) == pytest.approx(p.log_det, rel=1e-12)
    assert p.d_efficiency_lower_bound >= 0.95


@pytest.mark.slow
@pytest.mark.parametrize("name", list(CAD))
def test_cad_plans_are_mountable(name):
    body, p = cad_plan(name)
    assert_mountable(body, p)
    assert p.sliding.gain >= 0


def test_broken_meshes_are_refused(tmp_path):
    busted = massline("plan", FIXTURE_MESHES / "busted.STL", "--units", "mm", "--density", "2700", "--out", tmp_path)
    # a 10 mm damaged bust: hits land on its smooth curves, no 10 mm base fits on it
    assert busted.returncode == 2 and "flat" in busted.stderr and "--sensor-base" in busted.stderr
    soup = massline("plan", FIXTURE_MESHES / "soup.stl", "--units", "m", "--density", "2700", "--out", tmp_path)
    assert soup.returncode == 2 and "soup" in soup.stderr


@pytest.mark.parametrize("shape, unseen", [("cylinder", 1), ("sphere", 3), ("box", 0)])
def test_normals_that_meet_one_axis_get_mounting_blocks_along_the_motion_they_miss(shape, unseen):
    """A surface of revolution's smooth normals all meet its axis (a sphere's its centre): rotation about it is
    neither seen nor driven. The blocks read it tangentially, and with them every motion is seen. A sphere's
    normals miss three motions: it offers too little for uniaxial lines, and no block is offered."""
    mesh = {
        "cylinder": lambda: trimesh.creation.cylinder(radius=0.04, height=0.12, sections=32),
        "sphere": lambda: trimesh.creation.icosphere(subdivisions=4, radius=0.05),
        "box": lambda: trimesh.creation.box((0.1, 0.06, 0.04)),
    }[shape]()
    points = candidate_points(mesh, CandidateOptions())
    assert len(unseen_twists(points, points.sensor_points())) == len(unseen_twists(points, np.arange(len(points))))
    assert len(unseen_twists(points, np.arange(len(points)))) == unseen
    for twists in blocks_needed(points, planar=False, triaxial=False):
        assert len(twists) == (unseen if unseen <= 1 else 0)
        if len(twists):
            np.testing.assert_allclose(np.abs(twists[:, :3]), 0.0, atol=1e-6)  # rotations about the axis / centre
            blocks, node = points.block_lines(twists)
            assert np.abs(np.einsum("nd,nd->n", blocks.directions, points.normals[node])).max() < 1e-6  # tangent
            lines = Lines(points.points, points.normals) + blocks
            assert np.linalg.matrix_rank(lines.coordinates) == 6
    assert blocks_needed(points, planar=False, triaxial=True)[0].shape == (0, 6)  # triaxials see every motion


def test_the_unseen_motions_of_many_candidates_take_memory_in_proportion():
    """`plan --candidates 100000` asked its SVD for the n × n left factor (97.5 GiB at 114 394 points) and died
    of it: 100 000 points on a cylinder's mantle, normals at its axis, take a few MB and miss two motions (sliding
    along the axis and turning about it)."""
    angle, height = np.random.default_rng(0).uniform([0, -0.06], [2 * np.pi, 0.06], (100_000, 2)).T
    normals = np.column_stack([np.cos(angle), np.sin(angle), np.zeros_like(angle)])
    points = 0.04 * normals + np.outer(height, [0, 0, 1])
    candidates = CandidatePoints(points, normals, np.zeros(len(angle), int))
    assert len(unseen_twists(candidates, np.arange(len(candidates)))) == 2


def test_a_base_larger_than_the_faces_is_refused(tmp_path):
    run = massline("plan", "plate", "--sensor-base", "150", "--out", tmp_path)
    assert run.returncode == 2 and "--sensor-base" in run.stderr


def test_fixed_sensor_is_snapped_onto_the_surface():
    body = bundled("structure")
    fixed = Lines([[0.006, 0.06, 0.1515]], [[0.0, 0.0, 2.0]])  # 1.5 mm above the column's top
    p = plan(body, Budget(6, 3), fixed_sensors=fixed, certify_steps=5000)
    np.testing.assert_allclose(p.sensors.points[0], [0.006, 0.06, 0.15], atol=1e-12)
    np.testing.assert_allclose(p.sensors.directions[0], [0.0, 0.0, 1.0])
    assert p.sensor_nodes[0] == -1 and len(p.sensors) == 7


def test_fixed_point_off_the_surface_is_refused_with_its_distance():
    body = bundled("structure")
    with pytest.raises(MasslineError, match=r"--fixed-exciter 1 at \(0.08, 0.06, 0.15\) is 68 mm from"):
        plan(body, Budget(6, 3), fixed_exciters=Lines([[0.08, 0.06, 0.15]], [[0.0, 0.0, 1.0]]))


def test_fixed_sensor_in_the_idlers_bore_is_refused(tmp_path):
    run = massline(
        "plan", FIXTURE_MESHES / "idler_riser.STL", "--units", "in", "--density", "2700", "--triaxial", "3",
        "--sensors", "0", "--fixed-sensor", *map(str, IDLER_BORE), "0", "0", "1", "--out", tmp_path,
    )  # fmt: skip
    assert run.returncode == 2 and "mm from the body's surface" in run.stderr


def test_fixed_sensor_with_no_direction_is_refused(tmp_path):
    run = massline("plan", "structure", "--fixed-sensor", "0.006", "0.06", "0.15", "0", "0", "0", "--out", tmp_path)
    assert run.returncode == 2 and "direction" in run.stderr


@pytest.mark.slow
def test_fixed_points_are_in_plan_json_the_table_and_the_simulated_test(tmp_path):
    out = tmp_path / "plan"
    run = massline(
        "plan", "structure", "--out", out, "--fixed-sensor", "0.006", "0.06", "0.151", "0", "0", "1",
        "--fixed-exciter", "0.16", "0.06", "0.006", "-1", "0", "0",
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    assert "fixed" in run.stdout and "changed log det F by +" in run.stdout
    doc = json.loads((out / "plan.json").read_text())
    assert doc["sensors"][0].pop("reach")["clear"]  # room for its housing and cable there
    assert doc["sensors"][0] == {"node": 1, "candidate": None, "point": [0.006, 0.06, 0.15], "direction": [0.0, 0.0, 1.0],
                                 "triaxial": None, "fixed": True, "mount": {"kind": "fixed", "gap_m": 0.0}}  # fmt: skip
    assert doc["exciters"][0]["fixed"] and "fixed" not in doc["exciters"][1]
    assert doc["criterion"]["sliding"]["gain"] > 0
    assert "(fixed)" in (out / "report.html").read_text()
    uff = tmp_path / "test.uff"
    assert massline("simulate", out / "plan.json", "--rigid", "--out", uff).returncode == 0
    recording = to_recording(read_uff(uff))
    assert recording.frf.shape[:2] == (len(doc["sensors"]), len(doc["exciters"]))
    np.testing.assert_allclose(recording.sensors.points[0], [0.006, 0.06, 0.15], atol=1e-6)
    np.testing.assert_allclose(recording.exciters.points[0], [0.16, 0.06, 0.006], atol=1e-6)


@pytest.mark.parametrize("radius, fits", [(0.04, True), (0.01, False)])
@pytest.mark.parametrize("sections", [32, 64, 128])
def test_a_cylinders_side_holds_an_accelerometer_where_its_gap_is_small(radius, fits, sections):
    """The side is one smooth region at any tessellation: its clearance is the distance to its rims (the 90°
    edges), a hit lands anywhere on it. A 10 mm base stands (5 mm)²/(2R) off it: 0.31 mm on R 40 mm (a cemented
    pad), 1.25 mm on R 10 mm (more than a pad fills: no accelerometer)."""
    mesh = trimesh.creation.cylinder(radius=radius, height=0.12, sections=sections)
    surface = Surface.of(mesh)
    side = np.flatnonzero(np.abs(mesh.face_normals[:, 2]) < 0.1)
    middle = mesh.triangles_center[side] * [1, 1, 0]  # each side face's point at mid-height
    np.testing.assert_allclose(surface.clearance(middle, side, 0.1), 0.06, rtol=1e-6)
    assert surface.roomy(side, 0.005).all()
    normals = surface.surface_normal(middle, side)
    np.testing.assert_allclose(np.cross(middle, normals)[:, 2], 0.0, atol=1e-9)  # radial: they meet the axis
    gap = surface.base_gap(middle, side, 0.010)
    true = 0.005**2 / (2 * radius)
    assert (gap <= 1e-3).all() == fits and np.median(gap) == pytest.approx(true, rel=0.6)
    points = candidate_points(mesh, CandidateOptions())
    on_side = np.abs(points.normals[:, 2]) < 0.1
    assert on_side.sum() > 0 and points.sensor_fit[on_side].any() == fits

def test_the_motion_the_normals_miss_reads_the_same_from_either_side():
    """The sensors' and the hits' unseen twists of one cylinder differ in their last digits (3e-9 against
    −1.6e-9): named once, as the axis and its point, with no e-notation."""
    near = [np.array([6.7e-11, -2.6e-11, 0, 3.2e-9, 6e-10, 1.0]), np.array([1.8e-11, 1.7e-11, 0, 3e-9, -1.6e-9, 1.0])]
    assert {motion_text(t) for t in near} == {"rotation about the axis along (0, 0, 1) through (0, 0, 0) mm"}
    assert motion_text(np.array([0.0, 2.0, 0.0, 0.0, 0.0, 0.0])) == "translation along (0, 1, 0)"
    shifted = np.concatenate([-np.cross([0.0, 0.0, 1.0], [0.01, 0.02, 0.0]), [0.0, 0.0, 1.0]])
    assert motion_text(shifted) == "rotation about the axis along (0, 0, 1) through (10, 20, 0) mm"
