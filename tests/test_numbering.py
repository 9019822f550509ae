"""One numbering from the plan to the reports: the labels a test engineer writes beside each point are those of
plan.json, the plan's console table, the placement report and the Universal File the plan's test writes."""

import numpy as np
import pytest
from conftest import bundled
from rich.console import Console

from massline import plan_layout, plan_to_dict, read_uff, simulate_test, to_recording, write_uff
from massline.placement.mounts import mounts
from massline.cli.plan_console import layout_table
from massline.core.lines import Lines
from massline.core.numbering import first_hit_label, point_groups, point_labels
from massline.reports.plan_scene import markers_of
from massline.virtual.acquisition import Acquisition
from massline.virtual.measurement import Noise


def test_a_triaxial_and_orthogonal_uniaxials_at_one_spot_are_one_point_each():
    s = Lines.triaxials([[0, 0, 0], [1, 0, 0]])
    o = np.array([1.0, 1.0, 0.0]) / np.sqrt(2)
    u = Lines([[2, 0, 0], [2, 0, 0], [2, 0, 0], [3, 0, 0]], [o, [0, 0, 1], o, o])  # a repeat starts a new point
    groups = point_groups(s + u)
    np.testing.assert_array_equal(groups, [0, 0, 0, 1, 1, 1, 2, 2, 3, 4])


def test_hits_are_numbered_from_the_hundred_after_the_accelerometers():
    assert [first_hit_label(n) for n in (1, 9, 99, 100, 150)] == [101, 101, 101, 201, 201]
    sensors = Lines.along_axes(np.arange(300).reshape(-1, 3), [0] * 100)
    hits = Lines.along_axes([[0, 0, 0], [0, 0, 0], [1, 0, 0]], [0, 1, 2])  # two hits at one spot: one point
    s, e = point_labels(sensors, hits)
    np.testing.assert_array_equal(s, np.arange(1, 101))
    np.testing.assert_array_equal(e, [201, 201, 202])


@pytest.fixture(scope="module")
def plate_plan():
    body = bundled("plate")
    return body, plan_layout(body)


def test_plan_console_report_and_file_carry_the_same_labels(plate_plan, tmp_path):
    body, plan = plate_plan
    sensor_labels, hit_labels = plan.point_labels
    doc = plan_to_dict(plan, "plate", "m", body.density)
    assert [e["node"] for e in doc["sensors"]] == sensor_labels.tolist()
    assert [e["node"] for e in doc["exciters"]] == hit_labels.tolist()
    assert set(hit_labels.tolist()) == set(range(101, 101 + len(set(hit_labels.tolist()))))

    console = Console(record=True, width=200)
    console.print(layout_table("Accelerometers", plan.sensors, plan.sensor_nodes, sensor_labels, mounts(plan, 0)))
    console.print(layout_table("Hammer hits", plan.exciters, plan.exciter_nodes, hit_labels, mounts(plan, 1)))
    rows = [line.split("│") for line in console.export_text().splitlines() if line.startswith("│")]
    assert [int(r[2]) for r in rows] == sensor_labels.tolist() + hit_labels.tolist()

    markers = markers_of(plan.sensors, plan.exciters)
    assert {m.label for m in markers} == {str(n) for n in [*sensor_labels, *hit_labels]}

    quiet = Acquisition(noise=Noise(0.0, 0.0), dc_line=False)
    sim = simulate_test(doc, plan.sensors, plan.exciters, body, rigid=True, acquisition=quiet)
    write_uff(tmp_path / "test.uff", sim.recording)
    read = to_recording(read_uff(tmp_path / "test.uff"))
    assert [c.node for c in read.sensor_labels] == sensor_labels.tolist()
    assert [c.node for c in read.exciter_labels] == hit_labels.tolist()
