"""The setup for the test software (``massline setup``): the plan's points read back from setup.uff by pyuff and by
the project's reader, each direction its node's +Z (a triaxial's +X, +Y, +Z), the part's wireframe, a channel table
that parses, and a recording in those systems that identifies as in the plan's frame."""

import csv
import json

import numpy as np
import pytest
import pyuff
import trimesh
from conftest import bundled
from test_cli import massline

from massline import identify_recording
from massline.core.errors import MasslineError
from massline.core.lines import Lines
from massline.placement.setup_export import export_setup
from massline.uff import read_uff, to_recording
from massline.uff.recording import code_direction
from massline.uff.writer import write_uff
from massline.virtual.acquisition import Acquisition, run
from massline.virtual.measurement import Noise

BOX = (120.0, 80.0, 40.0)  # mm: the part's 12 sharp edges
OBLIQUE = np.array([0.569, 0.577, 0.585])  # the bracket's sensor 5, as the issue saw it labelled '5:-Z'


def _rotation(seed: int) -> np.ndarray:
    q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


def _entry(point, direction, triaxial=None, mount="flat"):
    return {"point": list(point), "direction": list(direction), "triaxial": triaxial, "mount": {"kind": mount}}


@pytest.fixture
def hand_plan(tmp_path):
    """A plan in mm with what a file must carry: an oblique line, a −Z line, a +X line, a right- and a left-handed
    triaxial, hits along an oblique direction and −Y (metres in plan.json, as ``massline plan`` writes it)."""
    right, left = _rotation(1), _rotation(2) * np.array([1.0, 1.0, -1.0])
    sensors = [
        _entry([0.0123, -0.0456, 0.0789], OBLIQUE / np.linalg.norm(OBLIQUE)),
        _entry([0.1, 0.02, -0.003], [0.0, 0.0, -1.0], mount="film"),
        _entry([-0.05, 0.0, 0.01], [1.0, 0.0, 0.0]),
        *[_entry([0.03, 0.04, 0.05], right[:, k], 0) for k in range(3)],
        *[_entry([-0.03, 0.01, 0.02], left[:, k], 1) for k in range(3)],
    ]
    exciters = [_entry([0.0, 0.07, 0.0], -OBLIQUE / np.linalg.norm(OBLIQUE)), _entry([0.02, -0.01, 0.0], [0, -1, 0])]
    doc = {"mesh": "../part.stl", "units": "mm", "density": 2700.0, "sensors": sensors, "exciters": exciters}
    doc["loading"] = {"sensor_mass": {"default": 0.005, "by_point": {"4": 0.012}}}
    path = tmp_path / "plan" / "plan.json"
    path.parent.mkdir()
    trimesh.creation.box(extents=BOX).export(tmp_path / "part.stl")  # mm, as plan.json names it
    path.write_text(json.dumps(doc))
    return path, doc


def _plan_lines(doc):
    entries = doc["sensors"] + doc["exciters"]
    return np.array([e["point"] for e in entries]), np.array([e["direction"] for e in entries], dtype=float)


def _rows(setup):
    with open(setup.channels, newline="") as handle:
        return list(csv.DictReader(handle))


def test_the_project_reader_gives_the_plan_back_with_every_direction_a_local_axis(hand_plan):
    path, doc = hand_plan
    setup = export_setup(path)
    assert setup.uff == path.parent / "setup.uff" and setup.units == "mm"
    contents, rows = read_uff(setup.uff), _rows(setup)
    points, directions = _plan_lines(doc)
    assert contents.datasets == (151, 164, 2420, 2411)
    assert len(rows) == len(points) and set(contents.node_systems) == set(contents.node_ids)
    for row, point, direction in zip(rows, points, directions / np.linalg.norm(directions, axis=1)[:, None]):
        k = int(np.flatnonzero(contents.node_ids == int(row["node"]))[0])
        code = {"+X": 1, "+Y": 2, "+Z": 3, "-Z": -3}[row["direction"]]
        assert int(row["cs"]) == contents.node_systems[k]
        np.testing.assert_allclose(contents.node_points[k], point, rtol=0, atol=1e-12)
        np.testing.assert_allclose(code_direction(contents.node_frames[k], code), direction, rtol=0, atol=1e-9)
    uniaxial = [r for r, e in zip(rows, doc["sensors"] + doc["exciters"]) if e["triaxial"] is None]
    assert [r["direction"] for r in uniaxial] == ["+Z"] * 5  # the oblique line too, and the −Z line
    triaxial = [r["direction"] for r, e in zip(rows, doc["sensors"]) if e["triaxial"] is not None]
    assert triaxial == ["+X", "+Y", "+Z", "+X", "+Y", "-Z"]  # the left-handed one keeps a right-handed system


def test_pyuff_reads_the_same_points_systems_and_directions(hand_plan):
    path, doc = hand_plan
    setup = export_setup(path)
    sets = {s["type"]: s for s in pyuff.UFF(str(setup.uff)).read_sets()}
    length = sets[164]["length"]
    assert length == 1000.0 and sets[164]["units_code"] == 5  # mm
    nodes = sets[2411]
    systems = dict(zip(sets[2420]["CS_sys_labels"], sets[2420]["CS_matrices"]))
    points, directions = _plan_lines(doc)
    for row, point, direction in zip(_rows(setup), points, directions / np.linalg.norm(directions, axis=1)[:, None]):
        k = list(nodes["node_nums"]).index(int(row["node"]))
        assert nodes["disp_cs"][k] == int(row["cs"]) and nodes["def_cs"][k] == 0
        xyz = np.array([nodes["x"][k], nodes["y"][k], nodes["z"][k]]) / length
        np.testing.assert_allclose(xyz, point, rtol=0, atol=1e-12)
        matrix = systems[int(row["cs"])]  # rows: local x, y, z in the global frame; then the origin
        np.testing.assert_allclose(matrix[3] / length, point, rtol=0, atol=1e-12)
        axis, sign = "XYZ".index(row["direction"][1]), 1 if row["direction"][0] == "+" else -1
        np.testing.assert_allclose(sign * matrix[axis], direction, rtol=0, atol=1e-9)
        if row["direction"] == "+Z":  # the local components of the direction: (0, 0, 1) exactly
            np.testing.assert_allclose(matrix[:3] @ direction, [0.0, 0.0, 1.0], rtol=0, atol=1e-12)


def test_the_channel_table_names_channels_runs_mounts_and_masses(hand_plan):
    path, doc = hand_plan
    rows = _rows(export_setup(path))
    sensors = [r for r in rows if r["role"] == "accelerometer"]
    hits = [r for r in rows if r["role"] == "hammer"]
    assert [int(r["channel"]) for r in sensors] == list(range(1, 10))
    assert {r["channel"] for r in hits} == {"10"} and [r["run"] for r in hits] == ["1", "2"]
    assert [r["node"] for r in sensors] == ["1", "2", "3", "4", "4", "4", "5", "5", "5"]
    assert [r["node"] for r in hits] == ["101", "102"]
    assert [r["mass (g)"] for r in sensors][:4] == ["5", "5", "5", "12"] and sensors[1]["mount"] == "film"
    assert {r["sensitivity unit"] for r in sensors} == {"mV/g"} and hits[0]["sensitivity unit"] == "mV/N"
    points, _ = _plan_lines(doc)
    table = np.array([[float(r[f"{a} (mm)"]) for a in "xyz"] for r in rows])
    np.testing.assert_allclose(table, 1e3 * points, rtol=1e-11, atol=1e-12)


def test_dataset_15_and_18_in_inches_keep_six_digits(hand_plan):
    path, doc = hand_plan
    setup = export_setup(path, path.parent / "in", units="in", nodes_dataset=15)
    contents = read_uff(setup.uff)
    assert contents.datasets == (151, 164, 18, 15) and "x (in)" in _rows(setup)[0]
    points, _ = _plan_lines(doc)
    by_node = dict(zip(contents.node_ids, contents.node_points))
    found = np.array([by_node[int(r["node"])] for r in _rows(setup)])
    np.testing.assert_allclose(found, points, rtol=0, atol=1e-5 * 0.0254)


def test_the_bracket_plan_exported_reads_back(bracket_default_plan, tmp_path):
    """The README's plan: every uniaxial point its own +Z (no '5:-Z'), the plan's points back to 1e-9 m."""
    setup = export_setup(bracket_default_plan, tmp_path, units="mm")
    contents, rows = read_uff(setup.uff), _rows(setup)
    points, directions = _plan_lines(json.loads(bracket_default_plan.read_text()))
    assert {r["direction"] for r in rows} == {"+Z"}
    frames = dict(zip(contents.node_ids, contents.node_frames))
    placed = dict(zip(contents.node_ids, contents.node_points))
    found = np.array([frames[int(r["node"])][:, 2] for r in rows])
    np.testing.assert_allclose(found, directions, rtol=0, atol=1e-9)
    np.testing.assert_allclose(np.array([placed[int(r["node"])] for r in rows]), points, rtol=0, atol=1e-9)


def test_the_command_writes_the_wireframe_and_refuses_to_overwrite(hand_plan):
    path, _ = hand_plan
    first = massline("setup", path)
    assert first.returncode == 0, first.stderr
    assert "the part's 12 sharp edges as its wireframe" in first.stdout and (path.parent / "channels.csv").exists()
    before = (path.parent / "setup.uff").read_bytes()
    again = massline("setup", path)
    assert again.returncode == 2 and len(again.stderr.strip().splitlines()) == 1 and "--force" in again.stderr
    assert (path.parent / "setup.uff").read_bytes() == before
    assert massline("setup", path, "--force", "--nodes", "15", "--no-wireframe").returncode == 0
    assert read_uff(path.parent / "setup.uff").datasets == (151, 164, 18, 15)
    assert not [p for p in path.parent.iterdir() if p.name.endswith(".tmp")]


def test_units_and_dataset_are_checked_where_they_enter(hand_plan):
    path, _ = hand_plan
    with pytest.raises(MasslineError, match="units"):
        export_setup(path, units="ft")
    with pytest.raises(MasslineError, match="nodes_dataset"):
        export_setup(path, nodes_dataset=55)


def test_the_wireframe_is_the_parts_sharp_edges_in_the_global_system(hand_plan):
    path, _ = hand_plan
    box = trimesh.creation.box(extents=np.array(BOX) * 1e-3)
    setup = export_setup(path, mesh=box)
    assert setup.edges == 12
    sets = pyuff.UFF(str(setup.uff)).read_sets()
    [nodes] = [s for s in sets if s["type"] == 2411]
    [line] = [s for s in sets if s["type"] == 82]
    placed = {int(n): np.array(xyz) / 1e3 for n, *xyz in zip(nodes["node_nums"], nodes["x"], nodes["y"], nodes["z"])}
    corners = sorted(n for n in placed if n > 1000)
    assert corners == list(range(1001, 1009))
    assert all(nodes["disp_cs"][list(nodes["node_nums"]).index(n)] == 0 for n in corners)
    trace = [int(n) for n in line["nodes"]]
    segments = [(a, b) for a, b in zip(trace, trace[1:]) if a and b]
    assert len(segments) == 12 and len({frozenset(s) for s in segments}) == 12 and set(trace) - {0} == set(corners)
    lengths = sorted(np.linalg.norm(placed[a] - placed[b]) for a, b in segments)
    np.testing.assert_allclose(lengths, np.repeat(np.sort(BOX), 4) * 1e-3, rtol=1e-12)
    assert read_uff(setup.uff).datasets == (151, 164, 2420, 2411, 82)
    round_part = export_setup(path, path.parent / "sphere", mesh=trimesh.creation.icosphere(radius=0.05))
    assert round_part.edges == 0 and read_uff(round_part.uff).datasets == (151, 164, 2420, 2411)


def test_a_recording_in_the_setups_systems_identifies_as_in_the_plans_frame(tmp_path):
    """A free rigid test of oblique lines written with every node in its own system (each lone line its +Z, as
    ``massline setup`` gives them) reads back into the plan's frame and identifies the body as the file in the
    global systems does."""
    body = bundled("bracket").nominal
    rng = np.random.default_rng(3)
    directions = rng.normal(size=(11, 3))
    points = body.cog + 0.05 * rng.normal(size=(11, 3))
    sensors, exciters = Lines(points[:8], directions[:8]), Lines(points[8:], directions[8:])
    quiet = Acquisition(fmax=200.0, lines=400, noise=Noise(0.0, 0.0), dc_line=False)
    recorded, _ = run(body, sensors, exciters, None, None, (), quiet, 0)
    own, plain = tmp_path / "own.uff", tmp_path / "plain.uff"
    layout = write_uff(own, recorded, units="MM", nodes_dataset=2411, setup_systems=True)
    write_uff(plain, recorded, units="MM", nodes_dataset=2411)
    assert set(layout.sensor_codes) == set(layout.exciter_codes) == {3}
    back = to_recording(read_uff(own))
    np.testing.assert_allclose(back.sensors.directions, sensors.directions, rtol=0, atol=1e-9)
    np.testing.assert_allclose(back.exciters.points, exciters.points, rtol=0, atol=1e-12)
    found, reference = identify_recording(own, draws=0), identify_recording(plain, draws=0)
    assert found.mass == pytest.approx(reference.mass, rel=1e-9) and found.mass == pytest.approx(body.mass, rel=1e-6)
    np.testing.assert_allclose(found.inertia, reference.inertia, rtol=1e-8, atol=1e-15)


def test_each_point_is_measured_from_a_corners_two_edges(tmp_path):
    """On a 120 × 80 × 40 mm box, a sensor on the top face 15 mm from the +x side and 25 mm from the +y side is
    read off those two edges; a hit on the +x face, 10 mm below the top and 30 mm from the −y side, likewise."""
    box = trimesh.creation.box(extents=np.array(BOX) * 1e-3)
    sensors = [_entry([0.045, 0.015, 0.02], [0, 0, 1])]
    exciters = [_entry([0.06, -0.01, 0.01], [-1, 0, 0])]
    path = tmp_path / "plan.json"
    path.write_text(json.dumps({"units": "mm", "sensors": sensors, "exciters": exciters}))
    rows = _rows(export_setup(path, mesh=box))
    for row, expected in zip(rows, ({15.0, 25.0}, {10.0, 30.0})):
        assert {float(row["from edge 1 (mm)"]), float(row["from edge 2 (mm)"])} == expected
        assert row["edge 1"] != row["edge 2"] and all("-" in row[f"edge {k}"] for k in (1, 2))
