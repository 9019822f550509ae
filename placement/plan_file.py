"""plan.json: the plan as other tools read it (DESIGN.md / the planner issue).

Keys: ``mesh``, ``units``, ``density``, ``planar``, ``nominal`` (identify's keys),
``sensors`` and ``exciters`` (``{"node", "point", "direction", "triaxial"}``, metres, mesh frame;
fixed lines first, snapped onto the surface, with node null and ``"fixed": true``), ``criterion`` (``log_det``,
``condition_numbers``, ``d_efficiency_lower_bound`` and ``upper_bounds`` of the candidate layout,
``sliding``: ``candidate_log_det``, ``gain``, ``largest_move_m``), ``mounting`` (the clearance from
edges, m, a sensor and a hit keep), ``noise``, ``predicted_std`` (identify's std keys).
NaN (unobservable) is written as null.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from massline.placement.errors import MasslineError
from massline.placement.layout import Plan
from massline.placement.lines import Lines


def _lines(lines: Lines, nodes: np.ndarray) -> list:
    groups = {g: k for k, g in enumerate(dict.fromkeys(int(t) for t in lines.triaxial if t >= 0))}
    return [
        {
            "node": int(n) if n >= 0 else None,
            "point": p.tolist(),
            "direction": d.tolist(),
            "triaxial": groups.get(int(t)),
        }
        | ({"fixed": True} if n < 0 else {})
        for n, p, d, t in zip(nodes, lines.points, lines.directions, lines.triaxial)
    ]


def _sliding(plan: Plan) -> dict:
    moved = np.zeros(0) if plan.sliding is None else plan.sliding.moved
    return {
        "candidate_log_det": plan.candidate_log_det,
        "gain": plan.log_det - plan.candidate_log_det,
        "largest_move_m": float(moved.max(initial=0.0)),
    }


def plan_to_dict(plan: Plan, mesh: str, units: str, density: float) -> dict:
    nominal = plan.model.nominal
    return {
        "mesh": mesh,
        "units": units,
        "density": density,
        "planar": plan.model.planar,
        "nominal": nominal.as_dict(),
        "sensors": _lines(plan.sensors, plan.sensor_nodes),
        "exciters": _lines(plan.exciters, plan.exciter_nodes),
        "criterion": {
            "log_det": plan.log_det,
            "parameters": list(plan.model.names),
            "condition_numbers": plan.condition,
            "d_efficiency_lower_bound": plan.d_efficiency_lower_bound,
            "upper_bounds": plan.bounds,
            "worst_relative_std": plan.worst_relative_std,
            "sliding": _sliding(plan),
        },
        "mounting": {"sensor_clearance_m": plan.clearances[0], "hit_clearance_m": plan.clearances[1]},
        "noise": {"relative": plan.noise.relative, "floor": plan.noise.floor},
        "predicted_std": plan.predicted_std,
        "candidates": {
            "points": len(plan.candidates) if plan.candidates is not None else None,
            "lines": plan.n_candidate_lines,
        },
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
