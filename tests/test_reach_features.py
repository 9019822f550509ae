"""Reach on a machined block (tests/feature_block.py): a through-hole, a blind hole, a slot and a pocket, each
narrower than an impact hammer's head. No hit candidate or planned hit on a feature's wall or floor, every hit's
approach and every accelerometer's housing free of the surface, checked on dense surface samples independently of
the ray casts that chose them."""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest
import trimesh
from feature_block import in_a_feature
from scipy.spatial import cKDTree

from massline.meshes.loader import load_body
from massline.placement.candidates import CandidateOptions, candidate_points
from massline.placement.on_surface import plan
from massline.placement.plans import Budget
from massline.placement.reach import ReachSizes

BLOCK = Path(__file__).parent / "fixtures" / "meshes" / "feature_block.stl"
SIZES = ReachSizes()
SETTLE = 0.5e-3  # m: samples this close along the axis are the point's own face


@lru_cache(maxsize=None)
def block():
    return load_body(BLOCK, "mm", 2700)


@lru_cache(maxsize=None)
def samples() -> tuple[np.ndarray, cKDTree]:
    """Dense surface samples of the block (about 0.4 mm apart), m, and their k-d tree."""
    points = trimesh.sample.sample_surface_even(block().mesh, 120_000, seed=2)[0]
    return points, cKDTree(points)


def inside_cylinder(point: np.ndarray, axis: np.ndarray, radius: float, length: float) -> int:
    """Surface samples inside the cylinder of ``radius`` (m) along ``axis`` from ``point``, beyond ``SETTLE``."""
    points, tree = samples()
    r = points[tree.query_ball_point(point + axis * length / 2, np.hypot(length / 2, radius))] - point
    along = r @ axis
    across = np.linalg.norm(r - np.outer(along, axis), axis=1)
    return int(np.sum((along > SETTLE) & (along < length) & (across < radius)))


def outward_normal(point: np.ndarray) -> np.ndarray:
    mesh = block().mesh
    near = trimesh.triangles.closest_point(mesh.triangles, np.tile(point, (len(mesh.faces), 1)))
    return mesh.face_normals[np.argmin(np.linalg.norm(near - point, axis=1))]


def test_candidates_keep_out_of_holes_slots_and_pockets():
    points = candidate_points(block().mesh, CandidateOptions())
    hits, sensors = points.hit_points(), points.sensor_points()
    assert len(hits) > 50 and len(sensors) > 50
    assert not in_a_feature(points.points[hits]).any(), points.points[hits][in_a_feature(points.points[hits])]
    for k in hits:
        assert inside_cylinder(points.points[k], points.normals[k], SIZES.hammer_head / 2, SIZES.hammer_swing) == 0
    for k in sensors:
        assert inside_cylinder(points.points[k], points.normals[k], SIZES.sensor_base / 2, SIZES.sensor_height) == 0
    every = candidate_points(block().mesh, CandidateOptions(hammer_head=2e-3, hammer_swing=3e-3, sensor_height=2e-3))
    assert in_a_feature(every.points[every.hit_points()]).any()  # the check, not the sampling, keeps them out


@pytest.mark.parametrize("budget", [Budget(6, 3), Budget(0, 3, 3)], ids=["minimal", "triaxial"])
def test_planned_points_on_the_block_in_reach(budget):
    result = plan(block(), budget, CandidateOptions(n_samples=150), certify_steps=500)
    hits, sensors = result.exciters.points, result.sensors.points
    assert not in_a_feature(hits).any() and not in_a_feature(sensors).any()
    for p in hits:
        assert inside_cylinder(p, outward_normal(p), SIZES.hammer_head / 2, SIZES.hammer_swing) == 0, p
    for p in np.unique(sensors, axis=0):
        assert inside_cylinder(p, outward_normal(p), SIZES.sensor_base / 2, SIZES.sensor_height) == 0, p
