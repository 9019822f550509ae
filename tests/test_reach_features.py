"""Reach on a machined block (tests/feature_block.py): a through-hole, a blind hole, a slot and a pocket, each
narrower than an impact hammer's head. No hit candidate or planned hit on a feature's wall or floor, every hit's
approach and every accelerometer's housing free of the surface, checked on dense surface samples independently of
the ray casts that chose them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from feature_block import in_a_feature
from test_reach import SIZES, inside_cylinder, outward_normal, part, samples

from massline.placement.candidates import CandidateOptions, candidate_points
from massline.placement.on_surface import plan
from massline.placement.plans import Budget

BLOCK = Path(__file__).parent / "fixtures" / "meshes" / "feature_block.stl"


def block():
    return part(BLOCK)


def sampled():
    """Dense surface samples of the block (about 0.4 mm apart), m, and their k-d tree."""
    return samples(BLOCK, 120_000, 2)


def test_candidates_keep_out_of_holes_slots_and_pockets():
    points, dense = candidate_points(block().mesh, CandidateOptions()), sampled()
    hits, sensors = points.hit_points(), points.sensor_points()
    assert len(hits) > 50 and len(sensors) > 50
    assert not in_a_feature(points.points[hits]).any(), points.points[hits][in_a_feature(points.points[hits])]
    for p, n in zip(points.points[hits], points.normals[hits]):
        assert inside_cylinder(p, n, SIZES.hammer_head / 2, SIZES.hammer_swing, dense) == 0
    for p, n in zip(points.points[sensors], points.normals[sensors]):
        assert inside_cylinder(p, n, SIZES.sensor_base / 2, SIZES.sensor_height, dense) == 0
    every = candidate_points(block().mesh, CandidateOptions(hammer_head=2e-3, hammer_swing=3e-3, sensor_height=2e-3))
    assert in_a_feature(every.points[every.hit_points()]).any()  # the check, not the sampling, keeps them out


@pytest.mark.parametrize("budget", [Budget(6, 3), Budget(0, 3, 3)], ids=["minimal", "triaxial"])
def test_planned_points_on_the_block_in_reach(budget):
    result, dense = plan(block(), budget, CandidateOptions(n_samples=150), certify_steps=500), sampled()
    hits, sensors = result.exciters.points, result.sensors.points
    assert not in_a_feature(hits).any() and not in_a_feature(sensors).any()
    for p in hits:
        assert inside_cylinder(p, outward_normal(p, BLOCK), SIZES.hammer_head / 2, SIZES.hammer_swing, dense) == 0, p
    for p in np.unique(sensors, axis=0):
        assert inside_cylinder(p, outward_normal(p, BLOCK), SIZES.sensor_base / 2, SIZES.sensor_height, dense) == 0, p
