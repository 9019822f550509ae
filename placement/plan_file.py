"""plan.json: the plan as other tools read it (DESIGN.md's lab contracts: the points, their mounts, the rig).

Keys: ``mesh``, ``units``, ``density``, ``planar``, ``nominal`` (identify's keys),
``sensors`` and ``exciters`` (``{"node", "candidate", "point", "direction", "triaxial", "mount", "reach"}``, metres,
mesh frame; ``mount``: ``kind`` flat, film, pad, curved, block or fixed and ``gap_m`` under the base, :mod:`.mounts`;
``reach``: a hit's ``approach_m``, the free length of the hammer head's cylinder along the normal, against its
``swing_m``; an accelerometer's ``housing_m`` against its ``height_m``, ``cable_m`` the free run sideways from half its
height and ``cable_exit`` its direction; ``clear``, :mod:`.reach`;
``blocks``: the rigid motions, in words, that the ``sensors``' and the ``hits``' normals leave unseen and that
mounting blocks were offered for;
``node`` is the point's label, the test's one numbering (:mod:`massline.core.numbering`: accelerometers from 1,
hits from 101), ``candidate`` the candidate point a slid point started from; fixed lines first, snapped onto the
surface, with candidate null and ``"fixed": true``), ``criterion`` (``name``
D, A or E, its ``value``, ``bounds`` and ``efficiency_lower_bound``; ``smallest_eigenvalue`` of the scaled
information; ``log_det``, ``condition_numbers`` with ``condition_systems`` naming each system by the paper's
equation, ``d_efficiency_lower_bound``, ``upper_bounds`` of log det; every bound and efficiency is against
the best layout of candidate points changing the sensors alone or the exciters alone, the other side held at
the plan's: placement/certification.py; ``sliding``: ``candidate_log_det``, ``gain`` in log det,
``criterion_gain``, ``largest_move_m``), ``mounting`` (the clearance from edges, m, a sensor and a hit keep, and
``reach``: the hammer's head and swing, the accelerometer's base, height and cable run, m), ``candidates``
(``points``, ``lines``, and ``dropped``: how many points each exclusion, edge or reach took, by reason),
``noise``, ``predicted_std`` (identify's std keys), ``diagnosability`` (``diagnosable``, per-channel and
per-hit leverage, ``hidden``: the faults each channel could hide, ``failures``; ``cost``: the minimal
layout's lines, hits and worst relative 1-σ against this plan's, null when the plan was not compared;
``search``: what the search for the cheapest diagnosable layout spent and reached — ``stopped`` when its budget
ended it, ``spent`` of ``limit`` ``unit``, ``reached``, ``sentence`` —, null when the budget was given).
NaN (unobservable) is written as null.

The test the plan sets up (absent in plans written before it was kept; their readers fall back to a
default cord): ``suspension`` (``cords``: ``{"attachment" m, "stiffness" N/m, "length" m, "direction"}``,
``foam``: ``{"points" m, "stiffness" N/m, "shear_ratio"}`` or null, ``loss_factor``, ``up``,
``description``), ``rig`` (how it is hung, :mod:`massline.virtual.rigging`: ``apex`` m straight above the CoG, where
the cord is tied, and ``legs``, the bridle's, each ``{"attachment" m on the surface, "normal", "length_m",
"tension_n"}``, none where the cord is tied on the surface; on foam ``pads``, its contact points, m;
``description``), ``band`` (the band it predicts: ``low_hz``, ``high_hz``, ``tolerance`` — every FRF within
it of its massline —, ``suspension_top_hz``, ``first_elastic_hz``), ``elastic`` (the FE model behind it:
``element_size`` m, ``modes``, ``dofs``, ``youngs`` Pa, ``poisson``, ``frequencies_hz``) and
``alternatives`` (the other supports considered: ``{"suspension": description, "band": {...}}``).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from massline.core.errors import MasslineError
from massline.placement.mounts import Mount, motion_text, mounts
from massline.placement.plans import Plan
from massline.core.lines import Lines


def _lines(lines: Lines, nodes: np.ndarray, labels: np.ndarray, mounted: list[Mount], reach, side: int) -> list:
    groups = {g: k for k, g in enumerate(dict.fromkeys(int(t) for t in lines.triaxial if t >= 0))}
    return [
        {
            "node": int(label),
            "candidate": int(n) if n >= 0 else None,
            "point": p.tolist(),
            "direction": d.tolist(),
            "triaxial": groups.get(int(t)),
            "mount": m.to_dict(),
        }
        | ({"fixed": True} if n < 0 else {})
        | ({"reach": reach.entry(k, side)} if reach is not None else {})
        for k, (n, label, p, d, t, m) in enumerate(
            zip(nodes, labels, lines.points, lines.directions, lines.triaxial, mounted)
        )
    ]


def _reach(plan: Plan) -> dict | None:
    """The instruments' sizes the reach was judged for, and how many candidate points each reason dropped."""
    if plan.candidates is None or plan.candidates.reach is None:
        return None
    sizes = plan.candidates.reach.sizes
    return {
        "hammer_head_m": sizes.hammer_head,
        "hammer_swing_m": sizes.hammer_swing,
        "sensor_base_m": sizes.sensor_base,
        "sensor_height_m": sizes.sensor_height,
        "cable_run_m": sizes.cable_run,
    }


def _sliding(plan: Plan) -> dict:
    moved = np.zeros(0) if plan.sliding is None else plan.sliding.moved
    return {
        "candidate_log_det": plan.candidate_log_det,
        "gain": plan.log_det - plan.candidate_log_det,
        "criterion_gain": 0.0 if plan.sliding is None else plan.sliding.gain,
        "largest_move_m": float(moved.max(initial=0.0)),
    }


def condition_systems(planar: bool) -> dict:
    """The paper's system behind each condition number of a layout (kinematics method 2 + dynamics method 3)."""
    if planar:
        return {
            "kinematic": "plate kinematics, eq. (10)",
            "translation": "plate mass and CoG, eq. (12)",
            "rotation": "plate inertia, eq. (13)",
        }
    return {
        "kinematic": "kinematics S Q = H, eq. (6)",
        "translation": "dynamics method 3, force rows (eq. 9)",
        "rotation": "dynamics method 3, moment rows (eq. 9)",
    }


def plan_to_dict(plan: Plan, mesh: str, units: str, density: float, test: dict | None = None) -> dict:
    """plan.json's document; ``test``: the support, band, elastic model and alternatives the plan chose."""
    nominal = plan.model.nominal
    return {
        "mesh": mesh,
        "units": units,
        "density": density,
        "planar": plan.model.planar,
        "nominal": nominal.as_dict(),
        "sensors": _lines(plan.sensors, plan.sensor_nodes, plan.point_labels[0], mounts(plan, 0), plan.reach[0], 0),
        "exciters": _lines(plan.exciters, plan.exciter_nodes, plan.point_labels[1], mounts(plan, 1), plan.reach[1], 1),
        "blocks": {side: [motion_text(t) for t in twists] for side, twists in zip(("sensors", "hits"), plan.blocks)},
        "criterion": {
            "name": plan.criterion.name,
            "title": plan.criterion.title,
            "value": plan.value,
            "bounds": plan.bounds,
            "efficiency_lower_bound": plan.efficiency_lower_bound,
            "smallest_eigenvalue": plan.smallest_eigenvalue,
            "log_det": plan.log_det,
            "parameters": list(plan.model.names),
            "condition_numbers": plan.condition,
            "condition_systems": {k: condition_systems(plan.model.planar).get(k, k) for k in plan.condition},
            "d_efficiency_lower_bound": plan.d_efficiency_lower_bound,
            "upper_bounds": plan.d_bounds,
            "certificate": None if plan.certificate is None else plan.certificate.as_dict(),
            "worst_relative_std": plan.worst_relative_std,
            "sliding": _sliding(plan),
        },
        "mounting": {
            "sensor_clearance_m": plan.clearances[0],
            "hit_clearance_m": plan.clearances[1],
            "reach": _reach(plan),
        },
        "noise": {"relative": plan.noise.relative, "floor": plan.noise.floor},
        "predicted_std": plan.predicted_std,
        "candidates": {
            "points": len(plan.candidates) if plan.candidates is not None else None,
            "lines": plan.n_candidate_lines,
            "dropped": None if plan.candidates is None else plan.candidates.excluded,
        },
        "diagnosability": {
            **plan.diagnosability.as_dict(),
            "cost": cost(plan),
            "search": None if plan.search is None else plan.search.as_dict(),
        },
    } | (test or {})


def cost(plan: Plan) -> dict | None:
    """What the plan costs over the minimal layout it was compared with (None: not compared)."""
    minimal = plan.minimal
    if minimal is None:
        return None
    return {
        "minimal_lines": len(minimal.sensors),
        "minimal_hits": len(minimal.exciters),
        "extra_lines": len(plan.sensors) - len(minimal.sensors),
        "extra_hits": len(plan.exciters) - len(minimal.exciters),
        "worst_relative_std": plan.worst_relative_std,
        "minimal_worst_relative_std": minimal.worst_relative_std,
    }


def _read_lines(entries: list, what: str) -> Lines:
    try:
        points = [e["point"] for e in entries]
        directions = [e["direction"] for e in entries]
        triaxial = [-1 if e.get("triaxial") is None else int(e["triaxial"]) for e in entries]
        lines = Lines(points, directions, triaxial)
    except MasslineError:
        raise
    except (KeyError, TypeError, ValueError, AttributeError):
        raise MasslineError(
            f"plan file: every {what} needs a 'point' and a 'direction' of three numbers each: write it again "
            "with 'massline plan'"
        ) from None
    return lines


def read_plan(path: str | Path) -> tuple[Lines, Lines, dict]:
    """Sensors, exciters and the whole document of a plan.json."""
    path = Path(path)
    try:
        doc = json.loads(path.read_text())
    except FileNotFoundError:
        raise MasslineError(f"plan file {path} does not exist: run 'massline plan' first") from None
    except IsADirectoryError:
        raise MasslineError(f"{path} is a folder: give the plan.json inside it") from None
    except json.JSONDecodeError as err:
        raise MasslineError(f"plan file {path} is not valid JSON ({err.msg} at line {err.lineno})") from None
    except UnicodeDecodeError:
        raise MasslineError(f"plan file {path} is not text: give the plan.json 'massline plan' wrote") from None
    except OSError as err:
        raise MasslineError(f"plan file {path} cannot be read ({err.strerror}): check its permissions") from None
    if not isinstance(doc, dict) or not doc.get("sensors") or not doc.get("exciters"):
        raise MasslineError(f"plan file {path} has no sensors or no exciters")
    return _read_lines(doc["sensors"], "sensor"), _read_lines(doc["exciters"], "exciter"), doc
