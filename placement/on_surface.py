"""A plan on the body's surface: candidates on its mountable faces, fixed lines snapped onto it, the layout
planned among the candidates (:mod:`.planner`), the chosen points slid on its surface (flat faces and curves).

Points and distances in metres, mesh frame (:mod:`.mountable`, :mod:`.sliding`).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Callable

import numpy as np

from massline.placement.admissible import regular
from massline.placement.candidates import (
    CandidateOptions,
    CandidatePoints,
    blocks_needed,
    candidate_lines,
    candidate_points,
)
from massline.placement.diagnosability import diagnosability
from massline.placement.footprints import Footprint, Footprints, Sites, check_fixed
from massline.core.information import NoiseModel
from massline.placement.plans import Budget, Plan, assessed
from massline.core.lines import Lines
from massline.meshes.loader import UNITS, BodyMesh
from massline.core.model import RigidModel
from massline.placement.mountable import Surface, closest_on_surface, snap
from massline.placement.certification import CERTIFY_STEPS
from massline.placement.planner import plan_on_candidates
from massline.placement.reach import reach
from massline.placement.sliding import slide
from massline.placement.work import Work

PLATE_THINNESS = 0.05  # thickness / size below which a body normal to z is planned as a plate


def snapped(body: BodyMesh, lines: Lines | None, what: str) -> Lines | None:
    """Fixed lines with their points moved onto the surface (refused when farther than ``mountable.snap`` allows)."""
    if lines is None:
        return None
    return Lines(snap(body.mesh, lines.points, what, UNITS[body.units]), lines.directions, lines.triaxial)


def fixed_sites(surface: Surface, lines: Lines | None) -> Sites:
    """The points (m) of fixed lines already on the surface, each with the outward normal of the smooth surface
    there (its face's on a flat region, interpolated on a curve)."""
    if lines is None:
        return Sites.none()
    faces = np.array([closest_on_surface(surface.mesh, p)[1] for p in lines.points], dtype=int)
    return Sites(lines.points, surface.surface_normal(lines.points, faces).reshape(-1, 3))


def anchored(
    body: BodyMesh,
    fixed_sensors: Lines | None,
    fixed_exciters: Lines | None,
    options: CandidateOptions,
    surface: Surface | None = None,
) -> tuple[Lines | None, Lines | None, tuple[Sites, Sites]]:
    """The fixed lines snapped onto the surface and their sites; refused when two of them conflict
    (:func:`.footprints.check_fixed`). ``surface``: the body's, when the caller has it (built here only when a
    line is fixed)."""
    fixed_sensors = snapped(body, fixed_sensors, "--fixed-sensor")
    fixed_exciters = snapped(body, fixed_exciters, "--fixed-exciter")
    if surface is None and (fixed_sensors is not None or fixed_exciters is not None):
        surface = Surface.of(body.mesh)
    anchors = fixed_sites(surface, fixed_sensors), fixed_sites(surface, fixed_exciters)
    check_fixed(*anchors, Footprint(options.sensor_base, options.hammer_tip))
    return fixed_sensors, fixed_exciters, anchors


def slid(
    plan: Plan,
    surface: Surface,
    points: CandidatePoints,
    options: CandidateOptions,
    diagnosable: bool = False,
    footprints: Footprints | None = None,
) -> Plan:
    """The plan with its points slid on their flat patches and along curves by its criterion, among the layouts the
    planner admits (regular, and diagnosable when asked), their footprints kept apart (``footprints``' fixed
    sites)."""

    def admitted(sensors: Lines, exciters: Lines) -> bool:
        return regular(plan.model, sensors, exciters) and (
            not diagnosable or diagnosability(plan.model, sensors, exciters, plan.noise).diagnosable
        )

    moved = slide(
        surface,
        plan.model,
        plan.noise,
        layout=(plan.sensors, plan.exciters),
        nodes=(plan.sensor_nodes, plan.exciter_nodes),
        points=points,
        options=options,
        admissible=admitted,
        criterion=plan.criterion.value,
        anchors=None if footprints is None else (footprints.fixed_sensors, footprints.fixed_hits),
    )
    assessment = assessed(plan.model, moved.sensors, moved.exciters, plan.noise)
    value = plan.criterion.value(assessment["information"])
    return replace(
        plan,
        sensors=moved.sensors,
        exciters=moved.exciters,
        value=value,
        candidate_value=plan.value,
        sliding=moved,
        **assessment,
    )


def is_plate(body: BodyMesh) -> bool:
    """Thin along z, with z a principal axis: the paper's §2.3 case."""
    extents = body.mesh.extents
    J = body.nominal.inertia_cog
    thin = extents[2] < PLATE_THINNESS * extents[:2].max()
    return bool(
        thin and np.abs(J[2, :2]).max() <= 1e-9 * np.abs(J).max() and abs(body.nominal.cog[2]) < 1e-9 * extents.max()
    )


def monotone(progress: Callable[[str, float], None]) -> Callable[[str, float], None]:
    """``progress(stage, fraction)`` never told less than it was before: a search that starts over (another
    criterion, more mounting blocks) says its stage at the fraction already reached."""
    reached = [0.0]

    def told(stage: str, fraction: float) -> None:
        reached[0] = max(reached[0], fraction)
        progress(stage, reached[0])

    return told


def plan(
    body: BodyMesh,
    budget: Budget = Budget(),
    options: CandidateOptions = CandidateOptions(),
    noise: NoiseModel = NoiseModel(),
    *,
    fixed_sensors: Lines | None = None,
    fixed_exciters: Lines | None = None,
    relaxation: str = "first-order",
    starts: int = 3,
    planar: bool | None = None,
    certify_steps: int = CERTIFY_STEPS,
    progress: Callable[[str, float], None] = lambda stage, fraction: None,
    criterion: str = "D",
    diagnosable: bool = False,
    work: Work | None = None,
) -> Plan:
    """The best layout of ``budget`` on the body's surface by ``criterion`` (D, A or E), certified, slid off
    the candidate grid on the surface, with predicted 1-σ (``diagnosable``: the best of the layouts in which
    one faulty channel or hit can be located, the search spending ``work``, :mod:`.work`). Fixed lines are
    snapped onto the surface."""
    planar = is_plate(body) if planar is None else planar
    budget.check(planar)
    progress = monotone(progress)
    progress("candidates", 0.0)
    surface = Surface.of(body.mesh)
    fixed_sensors, fixed_exciters, anchors = anchored(body, fixed_sensors, fixed_exciters, options, surface)
    footprint = Footprint(options.sensor_base, options.hammer_tip)
    points = candidate_points(body.mesh, options, surface)
    footprints = Footprints(footprint, Sites(points.points, points.normals), *anchors)
    blocks = blocks_needed(points, planar or options.axes, budget.triaxial > 0)  # --axes: the user's blocks
    sensor_side, exciter_side = candidate_lines(points, options.axes, planar, budget.triaxial > 0, blocks)
    result = plan_on_candidates(
        RigidModel(body.nominal, planar),
        sensor_side,
        exciter_side,
        budget,
        noise,
        fixed_sensors=fixed_sensors,
        fixed_exciters=fixed_exciters,
        relaxation=relaxation,
        starts=starts,
        seed=options.seed,
        certify_steps=certify_steps,
        progress=progress,
        criterion=criterion,
        diagnosable=diagnosable,
        work=work,
        footprints=footprints,
    )
    progress("sliding the points on their faces", 0.95)
    located = replace(result, candidates=points, clearances=options.clearances, blocks=blocks)
    moved = slid(located, surface, points, options, diagnosable, footprints)
    return replace(moved, reach=reached(moved, surface, options))


def reached(plan: Plan, surface: Surface, options: CandidateOptions) -> tuple:
    """The reach (:mod:`.reach`) of every sensor and hit line where it ended, along the smooth surface's outward
    normal there (fixed lines' too)."""
    out = []
    for lines in (plan.sensors, plan.exciters):
        faces = np.array([closest_on_surface(surface.mesh, p)[1] for p in lines.points], dtype=int)
        normals = surface.surface_normal(lines.points, faces).reshape(-1, 3)
        out.append(reach(surface.mesh, lines.points, normals, options.reach_sizes))
    return tuple(out)
