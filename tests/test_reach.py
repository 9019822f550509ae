"""Reach: no hit or accelerometer where the hammer cannot swing in or the housing and its cable do not fit (holes,
bores, re-entrant corners), on the flanged hub of tests/fixtures/meshes/flanged_hub.stl (tests/hub_mesh.py: a tube,
bore Ø30, on a flange with four Ø9 bolt holes, mm).

Each check is made again here independently of the ray casts that chose the points: dense samples of the surface
must not enter the hammer's approach cylinder or the accelerometer's housing.
"""

from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest
import trimesh
from scipy.spatial import cKDTree

from massline.meshes.clearance import cylinder_free
from massline.meshes.loader import load_body
from massline.placement.candidates import CandidateOptions, candidate_points
from massline.placement.on_surface import plan
from massline.placement.plans import Budget
from massline.placement.reach import ReachSizes

HUB = Path(__file__).parent / "fixtures" / "meshes" / "flanged_hub.stl"
BORE, HOLE, BOLT_CIRCLE, FLANGE_TOP = 15e-3, 4.5e-3, 38e-3, 6e-3  # m, as tests/hub_mesh.py builds it
HOLES = BOLT_CIRCLE * np.array([[np.cos(a), np.sin(a)] for a in np.pi / 4 + np.pi / 2 * np.arange(4)])
SIZES = ReachSizes()
SETTLE = 0.5e-3  # m: surface samples this close to a point's own surface (along its axis) are its own face


@lru_cache(maxsize=None)
def part(path: Path = HUB):
    """A part of tests/fixtures/meshes in millimetres, aluminium (the hub by default)."""
    return load_body(path, "mm", 2700)


def hub():
    return part(HUB)


@lru_cache(maxsize=None)
def samples(path: Path = HUB, count: int = 200_000, seed: int = 1) -> tuple[np.ndarray, cKDTree]:
    """Dense surface samples of the part (the hub's about 0.4 mm apart), m, and their k-d tree."""
    points = trimesh.sample.sample_surface_even(part(path).mesh, count, seed=seed)[0]
    return points, cKDTree(points)


def inside_cylinder(point: np.ndarray, axis: np.ndarray, radius: float, length: float, sampled=None) -> int:
    """How many surface samples (``sampled``, default the hub's) lie inside the cylinder of ``radius`` along ``axis``
    from ``point`` (m), beyond ``SETTLE`` along the axis (the face the point is on, curved under a base, stays
    below it)."""
    points, tree = sampled or samples()
    near = tree.query_ball_point(point + axis * length / 2, np.hypot(length / 2, radius))
    r = points[near] - point
    along = r @ axis
    across = np.linalg.norm(r - np.outer(along, axis), axis=1)
    return int(np.sum((along > SETTLE) & (along < length) & (across < radius)))


def in_a_hole(points: np.ndarray) -> np.ndarray:
    """Which points (n, 3) m lie on the bore's wall or a bolt hole's wall (or inside either)."""
    radius = np.hypot(points[:, 0], points[:, 1])
    hole = np.linalg.norm(points[:, None, :2] - HOLES[None], axis=2).min(axis=1)
    return (radius < BORE + 0.3e-3) | ((hole < HOLE + 0.3e-3) & (points[:, 2] < FLANGE_TOP + 1e-6))


def outward_normal(point: np.ndarray, path: Path = HUB) -> np.ndarray:
    """The part's (the hub's) outward normal at a surface point (m), from its nearest triangle."""
    mesh = part(path).mesh
    near = trimesh.triangles.closest_point(mesh.triangles, np.tile(point, (len(mesh.faces), 1)))
    return mesh.face_normals[np.argmin(np.linalg.norm(near - point, axis=1))]


def test_cylinder_free_meets_holes_bores_and_corners():
    """The ray probe: clear on the flange's open top and the tube's side; blocked in the bore, in a bolt hole, and
    on the flange 3 mm from the tube (a re-entrant corner narrower than the head)."""
    mesh = hub().mesh
    hole = np.append(HOLES[0] * (1 - HOLE / BOLT_CIRCLE), 3e-3)  # on the hole's wall nearest the axis, mid-depth
    cases = {
        "flange top": ([40e-3, 0.0, 6e-3], True),
        "tube side": ([25e-3, 0.0, 40e-3], True),
        "bore wall": ([BORE, 0.0, 30e-3], False),
        "bolt hole wall": (hole, False),
        "flange by the tube": ([28e-3, 0.0, 6e-3], False),
    }
    for name, (point, clear) in cases.items():
        point = np.asarray(point)
        normal = outward_normal(point)
        free = cylinder_free(mesh, point[None], normal[None], SIZES.hammer_head / 2, SIZES.hammer_swing)[0]
        assert (free >= SIZES.hammer_swing) == clear, name
        assert (inside_cylinder(point, normal, SIZES.hammer_head / 2, SIZES.hammer_swing) == 0) == clear, name


def test_candidates_keep_out_of_holes():
    """No hit or sensor candidate in the bore or a bolt hole; every hit candidate's approach cylinder and every
    sensor candidate's housing free of the surface; and the reasons counted."""
    points = candidate_points(hub().mesh, CandidateOptions())
    hits, sensors = points.hit_points(), points.sensor_points()
    assert not in_a_hole(points.points[hits]).any() and not in_a_hole(points.points[sensors]).any()
    for k in hits:
        assert inside_cylinder(points.points[k], points.normals[k], SIZES.hammer_head / 2, SIZES.hammer_swing) == 0
    for k in sensors:
        assert inside_cylinder(points.points[k], points.normals[k], SIZES.sensor_base / 2, SIZES.sensor_height) == 0
    dropped = {reason.split(" (")[0]: n for reason, n in points.excluded.items()}
    assert dropped["hammer's approach blocked"] > 100 and dropped["accelerometer's housing blocked"] > 100


def test_reach_sizes_are_options():
    """A head small enough for the bolt holes (a 4 mm probe over 5 mm) lets hits into them again: the sizes steer
    the check."""
    small = CandidateOptions(hammer_head=4e-3, hammer_swing=5e-3, sensor_height=3e-3, cable_run=1e-3)
    points = candidate_points(hub().mesh, small)
    assert in_a_hole(points.points[points.hit_points()]).any()


def assert_clear(sensors: np.ndarray, sensor_normals: np.ndarray, hits: np.ndarray, hit_normals: np.ndarray):
    """Every hit's approach and every accelerometer's housing free of the surface, none in a hole."""
    assert not in_a_hole(hits).any(), hits[in_a_hole(hits)]
    assert not in_a_hole(sensors).any(), sensors[in_a_hole(sensors)]
    for p, n in zip(hits, hit_normals):
        assert inside_cylinder(p, n, SIZES.hammer_head / 2, SIZES.hammer_swing) == 0, p
    for p, n in zip(sensors, sensor_normals):
        assert inside_cylinder(p, n, SIZES.sensor_base / 2, SIZES.sensor_height) == 0, p


@pytest.mark.parametrize("budget", [Budget(6, 3), Budget(0, 3, 3)], ids=["minimal", "triaxial"])
def test_planned_points_in_reach(budget):
    """The planner's layouts (slid off the candidates) on the hub: every hit's approach and every accelerometer's
    housing clear, none in a hole."""
    result = plan(hub(), budget, CandidateOptions(n_samples=150), certify_steps=500)
    normals = [np.array([outward_normal(p) for p in side.points]) for side in (result.sensors, result.exciters)]
    assert_clear(result.sensors.points, normals[0], result.exciters.points, normals[1])
    assert all(r.hit.all() for r in result.reach[1:]) and result.reach[0].sensor.all()


def cli_plan(*extra: str) -> dict:
    import session_cache

    return json.loads(session_cache.plan(HUB, "--units", "mm", "--density", "2700", *extra).read_text())


@pytest.mark.long  # three plans of the hub through the command, 25-35 s each
@pytest.mark.parametrize("extra", [(), ("--minimal",), ("--triaxial", "3")], ids=["default", "minimal", "triaxial"])
def test_hub_plans_in_reach(extra):
    """``massline plan hub.stl --units mm --density 2700`` (and --minimal, --triaxial 3): no hit or accelerometer in
    a bolt hole or the bore, every approach and housing clear, each point's reach in plan.json, the drops counted, the
    support rigged outside the bore."""
    doc = cli_plan(*extra)
    sides = [np.array([e["point"] for e in doc[key]]) for key in ("sensors", "exciters")]
    normals = [np.array([outward_normal(p) for p in side]) for side in sides]
    assert_clear(sides[0], normals[0], sides[1], normals[1])
    assert all(e["reach"]["clear"] for key in ("sensors", "exciters") for e in doc[key])
    assert all(e["reach"]["approach_m"] >= e["reach"]["swing_m"] for e in doc["exciters"])
    assert doc["mounting"]["reach"]["hammer_head_m"] == SIZES.hammer_head
    dropped = doc["candidates"]["dropped"]
    assert any(reason.startswith("hammer's approach blocked") and n > 0 for reason, n in dropped.items())
    rig = doc["rig"]  # the support as rigged: a bridle tied outside the bore and the holes, or the foam's pads
    assert rig["legs"] if "apex" in rig else len(rig["pads"]) >= 3
    assert not in_a_hole(np.array([leg["attachment"] for leg in rig.get("legs", [])]).reshape(-1, 3)).any()
