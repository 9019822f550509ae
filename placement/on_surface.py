"""A plan on the body's surface: fixed lines snapped onto it, the chosen points slid on its flat faces.

Points and distances in metres, mesh frame (:mod:`.mountable`, :mod:`.sliding`).
"""

from __future__ import annotations

from dataclasses import replace

from massline.placement.admissible import regular
from massline.placement.candidates import CandidateOptions, CandidatePoints
from massline.placement.diagnosability import diagnosability
from massline.placement.layout import Plan, assessed
from massline.placement.lines import Lines
from massline.placement.mesh import UNITS, BodyMesh
from massline.placement.mountable import Surface, snap
from massline.placement.sliding import slide


def snapped(body: BodyMesh, lines: Lines | None, what: str) -> Lines | None:
    """Fixed lines with their points moved onto the surface (refused when farther than ``mountable.snap`` allows)."""
    if lines is None:
        return None
    return Lines(snap(body.mesh, lines.points, what, UNITS[body.units]), lines.directions, lines.triaxial)


def slid(
    plan: Plan, surface: Surface, points: CandidatePoints, options: CandidateOptions, diagnosable: bool = False
) -> Plan:
    """The plan with its points slid on their flat patches by its criterion, among the layouts the planner
    admits (regular, and diagnosable when asked)."""

    def admitted(sensors: Lines, exciters: Lines) -> bool:
        return regular(plan.model, sensors, exciters) and (
            not diagnosable or diagnosability(plan.model, sensors, exciters, plan.noise).diagnosable
        )

    moved = slide(
        surface,
        plan.model,
        plan.noise,
        (plan.sensors, plan.exciters),
        (plan.sensor_nodes, plan.exciter_nodes),
        points,
        options,
        admitted,
        plan.criterion.value,
    )
    assessment = assessed(plan.model, moved.sensors, moved.exciters, plan.noise)
    value = plan.criterion.value(assessment["information"])
    return replace(plan, sensors=moved.sensors, exciters=moved.exciters, value=value, sliding=moved, **assessment)
