"""Round parts planned as engineers mount and hit them.

A turned part's surface normals all meet its axis: no normal line reads or drives the rotation about it. The
planner puts as few lines on mounting blocks as that motion needs (one line and one hit to identify, three and two
to diagnose, ``alternation.BLOCKS``), the rest on the surface; the default search finds a diagnosable layout from
random diagnosable ones where its walk stalls. ``python benchmarks/round_parts.py --virtual`` prints the full
table (four parts × 16, 32, 128 sections × default, minimal, triaxial).
"""

from __future__ import annotations

import json
from functools import lru_cache

import numpy as np
import pytest
from conftest import FIXTURE_MESHES
from test_cli import massline

from massline.meshes.loader import BodyMesh, load_body
from massline.meshes.round_parts import PARTS, STEEL
from massline.placement.alternation import BLOCKS
from massline.placement.candidates import CandidateOptions, candidate_points
from massline.placement.diagnosable_plan import cheapest_diagnosable
from massline.placement.mountable import PAD_GAP, Surface, feature_edges, foot_on_segments
from massline.placement.mounts import mounts
from massline.placement.on_surface import plan
from massline.placement.planner import Budget


@lru_cache(maxsize=None)
def part(name: str, sections: int, folder: str = "/tmp") -> BodyMesh:
    path = f"{folder}/massline-round-{name.replace(' ', '_')}-{sections}.stl"
    PARTS[name](sections).export(path)
    return load_body(path, "m", STEEL)


@pytest.fixture(scope="module")
def parts(tmp_path_factory):
    folder = str(tmp_path_factory.mktemp("round"))
    return lambda name, sections: part(name, sections, folder)


def on_blocks(p) -> tuple[int, int]:
    """Lines and hits of plan ``p`` mounted on blocks."""
    return tuple([m.kind for m in mounts(p, side)].count("block") for side in (0, 1))


def edge_margin(body: BodyMesh, p) -> float:
    """Least distance (m) of a planned point from a sharp edge, minus its clearance (sensors', hits')."""
    edges = feature_edges(body.mesh)
    points = np.vstack([p.sensors.points, p.exciters.points])
    clearance = np.repeat(p.clearances, [len(p.sensors), len(p.exciters)])
    a, b = (np.tile(edges[:, k], (len(points), 1)) for k in (0, 1))
    q = np.repeat(points, len(edges), axis=0)
    distance = np.linalg.norm(q - foot_on_segments(q, a, b), axis=1).reshape(len(points), -1).min(axis=1)
    return float((distance - clearance).min())


def largest_gap(body: BodyMesh, p) -> float:
    """The largest gap (m) under a 10 mm base at the plan's accelerometers on the surface (not on blocks)."""
    faces = body.mesh.nearest.on_surface(p.sensors.points)[2]
    gaps = Surface.of(body.mesh).base_gap(p.sensors.points, faces, 0.01)
    return float(gaps[[m.kind != "block" for m in mounts(p, 0)]].max())


def test_the_paper_s_layout_on_a_cylinder_puts_one_line_and_one_hit_on_blocks(parts):
    """A cylinder's minimal plan: non-singular, with the one line and the one hit the axis needs on blocks (not
    the most informative tangential lines everywhere), every other point on the surface along its normal."""
    body = parts("cylinder", 32)
    p = plan(body, Budget(6, 3), certify_steps=0)
    assert on_blocks(p) == BLOCKS[False]
    assert np.isfinite(p.worst_relative_std) and p.worst_relative_std < 0.02
    assert edge_margin(body, p) > -1e-9 and largest_gap(body, p) <= PAD_GAP


@pytest.mark.long  # the diagnosable search on a turned part (a minute each): the long tier
@pytest.mark.parametrize("name", ["cylinder", "shaft"])
def test_the_default_plan_of_a_turned_part_is_diagnosable(parts, name):
    """The plans once refused: the cheapest diagnosable layout of a stepped shaft and a cylinder (32 sections),
    three lines and two hits on blocks, clear of every sharp edge, every base's gap within a pad's."""
    body = parts(name, 32)
    p = cheapest_diagnosable(body, certify_steps=0)
    assert p.diagnosability.diagnosable, p.search
    assert on_blocks(p) == BLOCKS[True]
    assert p.log_det > p.minimal.log_det and p.worst_relative_std < 0.02  # more information (D, not every 1-σ)
    assert edge_margin(body, p) > -1e-9 and largest_gap(body, p) <= PAD_GAP


@pytest.mark.long  # a 128-section cylinder planned: the long tier
def test_plans_on_32_and_128_sections_agree(parts):
    """The same cylinder tessellated at 32 and 128 sections: the minimal plans' worst predicted 1-σ within 10 %."""
    worst = [plan(parts("cylinder", n), Budget(6, 3), certify_steps=0).worst_relative_std for n in (32, 128)]
    assert worst[1] == pytest.approx(worst[0], rel=0.10)


def test_a_flat_face_that_fillets_meet_keeps_its_own_normal(parts):
    """The filleted box (32 sections): the fillets' facets meet its flat faces tangentially, so a point anywhere on a
    flat face is read along that face's normal exactly (before, the corner normals shared with the fillet tilted
    them by a median 2.1°, up to 6.2°), while a point on a fillet takes the interpolated normal of the round."""
    body = parts("filleted box", 32)
    surface = Surface.of(body.mesh)
    points = candidate_points(body.mesh, CandidateOptions(), surface)
    facet = body.mesh.face_normals[points.faces]
    flat = surface.patch_width[surface.patch[points.faces]] > 0.02  # the box's faces, not the fillets' 2 mm strips
    assert flat.sum() > 100 and (~flat).sum() > 100
    np.testing.assert_allclose(points.normals[flat], facet[flat], atol=1e-12)
    tilt = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", points.normals[~flat], facet[~flat]), -1, 1)))
    assert 1.0 < tilt.max() < 15  # about a facet's turn (11.25°) on the fillets and their spherical corners


def test_points_slide_along_a_curve_and_their_lines_turn_with_it(parts):
    """The cylinder's minimal plan: points on the curved side move off their candidates along the surface the facets
    tessellate (on it, to 1e-9 m), and a line along the normal stays along the interpolated normal there (to 1e-9);
    the criterion rises; the mounts are read where the points went (a pad's gap under each base on the curve)."""
    body = parts("cylinder", 32)
    p = plan(body, Budget(6, 3), certify_steps=0)
    surface = Surface.of(body.mesh)
    region = surface.smooth[0]
    faces = p.candidates.faces[p.sensor_nodes]
    on_curve = surface.curved[faces]
    moved = [k for k in np.flatnonzero(on_curve) if np.linalg.norm(p.sensors.points[k] - p.candidates.points[
        p.sensor_nodes[k]]) > 1e-4]  # fmt: skip
    assert moved and p.sliding.gain > 0
    kinds = mounts(p, 0)
    for k in moved:
        foot, face = surface.onto_region(p.sensors.points[k], region[faces[k]])
        assert np.linalg.norm(foot - p.sensors.points[k]) < 1e-9
        if kinds[k].kind != "block":
            normal = surface.surface_normal(foot[None], np.array([face]))[0]
            assert abs(p.sensors.directions[k] @ normal) == pytest.approx(1.0, abs=1e-9)
            gap = surface.base_gap(foot[None], np.array([face]), 0.01)[0]
            assert kinds[k].kind in ("film", "pad") and kinds[k].gap == pytest.approx(gap, abs=1e-12)
            assert gap <= PAD_GAP


def test_triaxials_on_a_turned_part_need_one_hit_on_a_block(parts):
    """Triaxials see every motion: no accelerometer on a block, one hit on one to drive the rotation about the axis;
    every point sits on a curve or an end face."""
    body = parts("shaft", 16)
    p = plan(body, Budget(6, 3, 3), certify_steps=0)
    assert on_blocks(p) == (0, 1)
    assert edge_margin(body, p) > -1e-9 and np.isfinite(p.worst_relative_std)


@pytest.mark.long  # planned and rendered end to end through the command line (over a minute): the long tier
def test_a_part_rounded_all_over_is_planned_and_rendered(tmp_path):
    """A box with every edge filleted has no sharp edge at all: planned (its flat faces and fillets), its report
    rendered without edge lines, its mounts in plan.json."""
    path = tmp_path / "box.stl"
    PARTS["filleted box"](32).export(path)
    run = massline("plan", path, "--units", "m", "--density", STEEL, "--minimal", "--out", tmp_path / "plan")
    assert run.returncode == 0, run.stderr
    doc = json.loads((tmp_path / "plan" / "plan.json").read_text())
    assert (tmp_path / "plan" / "report.html").stat().st_size > 0
    assert {line["mount"]["kind"] for line in doc["sensors"]} <= {"flat", "film", "pad"}


def test_more_blocks_where_one_leaves_no_well_posed_layout():
    """The idler riser's normals miss a translation (along x: only the walls of its bore, 44-51 mm across, face that way,
    and there the hammer cannot swing in nor an accelerometer stand); one line on a block leaves its kinematics
    ill-conditioned, so the paper's layout takes the next count, two on each side, rather than being refused."""
    body = load_body(FIXTURE_MESHES / "idler_riser.STL", "in", 2700.0)
    p = plan(body, Budget(6, 3), certify_steps=0)
    assert on_blocks(p) == (2, 2) and np.isfinite(p.worst_relative_std)
