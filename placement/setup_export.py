"""The plan as a technician loads it into test software: the geometry as a Universal File and a channel table.

``setup.uff`` holds 151 (what it is), 164 (the plan's units: m, mm or in), 2420 (one Cartesian coordinate
system per node, numbered like it, at its point) and 2411 (the nodes, coordinates in the global system,
displacements in their own) — or 18 and 15, as Test.Lab exports geometry (six digits) — and, given the mesh, 82:
the part's wireframe, its sharp edges (creases over 30°, those the planner keeps points off) as one traceline
through nodes of their own in the global system, numbered from the thousand after the test's points (1001, …).
A lone accelerometer or hit is its node's +Z, whatever its direction in the part's frame: an oblique
(0.569, 0.577, 0.585) is typed nowhere; a triaxial's channels are its node's +X, +Y, +Z
(:func:`massline.uff.node_layout.setup_layout`). A direction code c at a node of frame R is the global
sign(c)·R[:, |c|−1], as every reader places it.

``channels.csv`` has one row per accelerometer channel (channels 1…n in the plan's order) and one per hit (the
hammer's channel n + 1, one run per hit): the channel, ``role`` (accelerometer or hammer), the plan's ``node``,
``direction`` in the node's system (+Z, or +X/+Y/+Z of a triaxial), its coordinate system ``cs``, the ``run``
(all for accelerometers), the ``mount`` the plan chose, the housing's mass the plan assumed (g, per
accelerometer, repeated on each of a triaxial's rows), an empty ``sensitivity`` with its unit (mV/g, mV/N) for
the calibration sheet, the point (plan units) and the direction in the part's frame; with the wireframe, two
edges to mark the point from with a rule (the nearest, and the nearest at least 30° from it: a corner's two sides),
each by its wireframe nodes ('1003-1007') and the point's distance from it.
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh

from massline.core.errors import MasslineError, param
from massline.core.files import atomic_file, claim_folder
from massline.core.housing_masses import HousingMasses
from massline.core.lines import Lines
from massline.meshes.loader import UNITS
from massline.placement.mountable import SHARP_EDGE_DEG
from massline.placement.plan_file import read_plan
from massline.uff.node_layout import UffLayout, setup_layout
from massline.uff.recording import code_name
from massline.uff.writer import write_geometry

FILES = ("setup.uff", "channels.csv")
UFF_UNITS = {"m": "SI", "mm": "MM", "in": "IN"}  # a plan's units → dataset 164's system
SENSITIVITY = {"accelerometer": "mV/g", "hammer": "mV/N"}



@dataclass(frozen=True)
class Setup:
    """What :func:`export_setup` wrote: the two files, the nodes (with their systems), the channels and the
    wireframe's edges (0: none)."""

    uff: Path
    channels: Path
    nodes: int
    accelerometer_channels: int
    hits: int
    units: str
    edges: int = 0


def _chains(edges: np.ndarray, count: int) -> list[int]:
    """The edges (k, 2) between ``count`` vertices walked as few polylines as a greedy walk finds (from the
    vertices of odd degree first), -1 between two; each edge once."""
    neighbours: list[list[tuple[int, int]]] = [[] for _ in range(count)]
    for k, (a, b) in enumerate(edges):
        neighbours[a].append((int(b), k))
        neighbours[b].append((int(a), k))
    left, trace = np.ones(len(edges), dtype=bool), []
    for start in sorted(range(count), key=lambda v: len(neighbours[v]) % 2 == 0):
        while any(left[k] for _, k in neighbours[start]):
            vertex, chain = start, [start]
            while (step := next(((w, k) for w, k in neighbours[vertex] if left[k]), None)) is not None:
                left[step[1]], vertex = False, step[0]
                chain.append(vertex)
            trace += [*chain, -1]
    return trace[:-1]


def wireframe(mesh: trimesh.Trimesh, first: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The mesh's sharp edges (creases over :data:`~.mountable.SHARP_EDGE_DEG`) as test software draws a part:
    node labels from ``first`` (k,), their points (k, 3) in the mesh's metres, and one traceline of those labels
    with 0 where the pen lifts."""
    sharp = mesh.face_adjacency_angles > np.radians(SHARP_EDGE_DEG)
    used, inverse = np.unique(mesh.face_adjacency_edges[sharp], return_inverse=True)
    ids = first + np.arange(len(used))
    trace = np.array(_chains(inverse.reshape(-1, 2), len(used)), dtype=int)
    return ids, np.asarray(mesh.vertices)[used], np.where(trace < 0, 0, ids[np.maximum(trace, 0)])


def nearest_edges(points: np.ndarray, outline) -> list[list[tuple[str, float]]]:
    """For each point (n, 3) m, two edges of the wireframe ``outline`` (:func:`wireframe`) to measure it from
    with a rule: the nearest, and the nearest of those at least 30° from it (a corner's other side), each as
    ('1003-1007', its distance in m); fewer where the part has fewer."""
    ids, vertices, trace = outline
    where = dict(zip(ids.tolist(), vertices))
    pairs = [(int(a), int(b)) for a, b in zip(trace[:-1], trace[1:]) if a and b]
    a, b = np.array([where[i] for i, _ in pairs]), np.array([where[j] for _, j in pairs])
    along = (b - a) / np.linalg.norm(b - a, axis=1)[:, None]
    found = []
    for point in points:
        t = np.clip(np.einsum("kj,kj->k", point - a, b - a) / np.einsum("kj,kj->k", b - a, b - a), 0.0, 1.0)
        distance = np.linalg.norm(point - (a + t[:, None] * (b - a)), axis=1)
        order = np.argsort(distance, kind="stable")
        first = order[0]
        other = next((k for k in order if abs(along[k] @ along[first]) < np.cos(np.radians(SHARP_EDGE_DEG))), None)
        found.append([(f"{pairs[k][0]}-{pairs[k][1]}", float(distance[k])) for k in (first, other) if k is not None])
    return found


def _mount_kinds(entries: list) -> list[str]:
    return [str((e.get("mount") or {}).get("kind", "")) for e in entries]


def _edge_columns(edges: list[tuple[str, float]], scale: float, units: str) -> dict:
    """The table's 'edge 1', 'from edge 1 (mm)', 'edge 2', … cells of one point (empty without a wireframe)."""
    cells = {}
    for k in (1, 2):
        name, distance = edges[k - 1] if len(edges) >= k else ("", None)
        cells |= {f"edge {k}": name, f"from edge {k} ({units})": "" if distance is None else f"{distance / scale:.4g}"}
    return cells


def channel_rows(
    layout: UffLayout,
    sensors: Lines,
    exciters: Lines,
    mounts: tuple[list, list],
    grams: np.ndarray,
    units: str,
    outline=None,
) -> list[dict]:
    """The channel table's rows (see the module's docstring); ``grams``: each sensor line's housing (g),
    ``units``: m, mm or in for the points; ``outline``: the wireframe the points are measured from (None: no
    edge columns)."""
    scale = UNITS[units]
    first_force = len(sensors) + 1
    rows = []
    for role, lines, nodes, codes, mounted in (
        ("accelerometer", sensors, layout.sensor_nodes, layout.sensor_codes, mounts[0]),
        ("hammer", exciters, layout.exciter_nodes, layout.exciter_codes, mounts[1]),
    ):
        near = None if outline is None else nearest_edges(lines.points, outline)
        for k, (point, direction, node, code, mount) in enumerate(
            zip(lines.points, lines.directions, nodes, codes, mounted)
        ):
            accelerometer = role == "accelerometer"
            rows.append(
                {
                    "channel": k + 1 if accelerometer else first_force,
                    "role": role,
                    "node": int(node),
                    "direction": code_name(int(code)),
                    "cs": int(node),
                    "run": "all" if accelerometer else k + 1,
                    "mount": mount,
                    "mass (g)": f"{grams[k]:g}" if accelerometer else "",
                    "sensitivity": "",
                    "sensitivity unit": SENSITIVITY[role],
                    **{f"{a} ({units})": f"{v / scale:.12g}" for a, v in zip("xyz", point)},
                    **{f"d{a}": f"{v:.12g}" for a, v in zip("xyz", direction)},
                    **({} if near is None else _edge_columns(near[k], scale, units)),
                }
            )
    return rows


def channel_csv(rows: list[dict]) -> str:
    """The rows as CSV text, a header line first."""
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=list(rows[0]), lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return out.getvalue()


def export_setup(
    plan_path,
    folder=None,
    *,
    units: str | None = None,
    nodes_dataset: int = 2411,
    mesh: trimesh.Trimesh | None = None,
    force: bool = False,
) -> Setup:
    """Write ``setup.uff`` and ``channels.csv`` for a plan.json into ``folder`` (default: the plan's).

    Parameters
    ----------
    plan_path : str or Path
        A plan.json written by ``massline plan``.
    folder : str or Path or None
        Where the two files go; both are refused before either is written when one exists and ``force`` is False,
        and each is written whole or not at all.
    units : {"m", "mm", "in"} or None
        The files' length unit (dataset 164, the table's points); None: the plan's.
    nodes_dataset : {2411, 15}
        Nodes and systems in 2411/2420 (exact) or in 15/18 (six digits, as older software reads).
    mesh : trimesh.Trimesh or None
        The part's surface, m, the plan's frame: its sharp edges are written as the wireframe (none: no 82).

    Raises
    ------
    MasslineError (a ValueError)
        A missing or malformed plan, an unknown unit or dataset, an output that exists without ``force``.
    """
    plan_path = Path(plan_path)
    sensors, exciters, doc = read_plan(plan_path)
    units = units or str(doc.get("units", "m"))
    if units not in UFF_UNITS:
        raise MasslineError(f"{param('units', repr(units))}: the setup's units are one of m, mm, in")
    if nodes_dataset not in (15, 2411):
        raise MasslineError(f"{param('nodes_dataset', repr(nodes_dataset))}: the nodes' dataset is 2411 or 15")
    uff_path, csv_path = claim_folder(plan_path.parent if folder is None else Path(folder), FILES, force)
    layout = setup_layout(sensors, exciters)
    housings = HousingMasses.from_payload(doc.get("loading", {}).get("sensor_mass", 0.0))
    grams = 1e3 * housings.of(layout.sensor_nodes)
    first = 1000 * (int(layout.node_ids.max()) // 1000 + 1) + 1
    outline = None if mesh is None else wireframe(mesh, first)
    edges = 0 if outline is None else int(np.count_nonzero(outline[2][1:] * outline[2][:-1]))
    outline = outline if edges else None  # a part with no sharp edge (a sphere) has no wireframe
    mounts = (_mount_kinds(doc["sensors"]), _mount_kinds(doc["exciters"]))
    rows = channel_rows(layout, sensors, exciters, mounts, grams, units, outline)
    description = (
        f"setup of {doc.get('mesh', 'the plan')}: {len(sensors)} accelerometer channels, {len(exciters)} hits"
    )
    uff_path.parent.mkdir(parents=True, exist_ok=True)
    write_geometry(
        uff_path, layout, description=description, nodes_dataset=nodes_dataset, units=UFF_UNITS[units],
        wireframe=outline, force=True,
    )  # fmt: skip
    with atomic_file(csv_path) as temporary:
        temporary.write_text(channel_csv(rows))
    return Setup(uff_path, csv_path, len(layout.node_ids), len(sensors), len(exciters), units, edges)
