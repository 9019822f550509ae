"""The pipelines are library calls: a script plans and simulates a test, with or without a progress callback,
and gets the same answers the commands print."""

import numpy as np
import pytest
from conftest import bundled

from massline import plan_layout, plan_mesh, plan_test, plan_to_dict, simulate_test
from massline.core.errors import MasslineError
from massline.virtual.acquisition import Acquisition
from massline.virtual.measurement import Noise
from massline.virtual.planned_test import FE_STAGES, planned_band, planned_suspension
from massline.virtual.simulation import set_up_test


@pytest.fixture(scope="module")
def plate_plan():
    body = bundled("plate")
    return body, plan_layout(body)


def test_plan_test_reports_its_stages_and_reads_the_cache_back(plate_plan, tmp_path, monkeypatch):
    monkeypatch.setenv("MASSLINE_CACHE", str(tmp_path))
    body, layout = plate_plan
    calls = []
    test, fe = plan_test(body, "plate", layout.sensors, layout.exciters, lambda *c: calls.append(c))
    stages = ["meshing", "assembling stiffness", "assembling mass", "solving for modes", "solving for modes"]
    assert calls == [(s, k, FE_STAGES) for k, s in enumerate(stages)]
    assert not fe.kept and fe.assumed is None and fe.material.youngs == 70e9  # the bundled plate's aluminium
    assert {"suspension", "band", "elastic", "alternatives"} <= set(test)
    doc = plan_to_dict(layout, "plate", "m", body.density, test)
    assert planned_band(doc).exists and planned_suspension(doc) is not None
    again, kept = plan_test(body, "plate", layout.sensors, layout.exciters)  # silent, from the cache
    assert kept.kept and again["band"] == test["band"]
    np.testing.assert_array_equal(kept.modes.omega, fe.modes.omega)


def test_simulate_test_records_a_plan_without_the_command_line(plate_plan):
    """An older plan (no support kept): a soft cord above the CoG; a rigid body; exact FRFs."""
    body, layout = plate_plan
    doc = plan_to_dict(layout, "plate", "m", body.density)
    sensors, exciters = layout.sensors, layout.exciters
    quiet = Acquisition(noise=Noise(0.0, 0.0), dc_line=False)
    sim = simulate_test(doc, sensors, exciters, body, rigid=True, acquisition=quiet, plan_path="p/plan.json")
    assert sim.setup.fe is None and sim.setup.expected is None and sim.setup.planned_support is None
    (name, band, support), *advice = sim.setup.rows
    assert name.startswith("planned: ") and band.exists and not advice  # no support given: no advice
    assert sim.recording.frf.shape[:2] == (len(sensors), len(exciters))
    assert sim.truth["plan"] == "p/plan.json" and sim.truth["mesh"] == "plate" and "fe" not in sim.truth


def test_a_library_refusal_comes_before_the_fe_work(plate_plan):
    body, layout = plate_plan
    doc = plan_to_dict(layout, "plate", "m", body.density)
    with pytest.raises(MasslineError, match="as much as the body"):
        set_up_test(doc, layout.sensors, layout.exciters, body, sensor_mass=10.0, progress=lambda *c: 1 / 0)


def test_a_plan_whose_mesh_was_swapped_is_refused_before_the_fe_work(plate_plan, tmp_path):
    """plan.json names a mesh file; the file now holds another body: refused on reading, in the plan's unit."""
    body, layout = plate_plan
    bundled("bracket").mesh.apply_scale(1e3).export(tmp_path / "part.stl")
    doc = plan_to_dict(layout, "part.stl", "mm", body.density)
    with pytest.raises(MasslineError, match=r"not the body the plan was made on: .* mm where the plan says"):
        plan_mesh(doc, tmp_path / "plan.json")
    body.mesh.copy().apply_scale(1e3).export(tmp_path / "part.stl")
    assert plan_mesh(doc, tmp_path / "plan.json").nominal.mass == pytest.approx(body.nominal.mass, rel=1e-6)  # STL: float32
