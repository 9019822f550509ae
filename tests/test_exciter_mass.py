"""A force gauge's mass at every drive point (a shaker test): each column of the FRF matrix its own body.

Simulated column by column, fitted column by column by identify (``--exciter-mass``: exact on noiseless
masslines, inside the bounds on noisy ones), and found by the diagnosis — in the masslines where a layout sees
it, against the mesh where it does not — never as a hit's direction or location.
"""

import numpy as np
import pytest
from conftest import bundled

from massline import plan_layout
from massline.core.information import sensitivities
from massline.core.masslines import Masslines
from massline.core.model import RigidModel
from massline.identify.diagnose.effects import parse_effect
from massline.identify.diagnose.pipeline import diagnose_recording
from massline.identify.estimator import estimate
from massline.identify.exciter_mass import riding_masses
from massline.identify.pipeline import identify_recording
from massline.virtual.acquisition import Acquisition, run
from massline.virtual.measurement import Noise

GAUGES = (0.005, 0.02)  # kg
SEEDS = (1, 2, 3)
BOUND = 0.3  # %: the lab matrix's bound on the mass


@pytest.fixture(scope="module", params=["bracket", "structure", "plate"])
def planned(request):
    body = bundled(request.param)
    return request.param, body, plan_layout(body)


def shaker_test(body, plan, gauge: float, seed: int, noise: float = 0.01):
    """A rigid body's virtual shaker test with ``gauge`` kg at every drive point."""
    effects = (parse_effect(f"excitation_mass_loading={gauge}@all"),)
    acquisition = Acquisition(noise=Noise(noise, 0.0), dc_line=False)
    return run(body.nominal, plan.sensors, plan.exciters, None, None, effects, acquisition, seed=seed)


def test_each_column_is_the_body_its_exciter_drives(planned):
    """The simulated massline of column j is ℓ_iᵀ M(θ + θ_j)⁻¹ ℓ_j, with the gauge at drive point j only."""
    _, body, plan = planned
    recording, truth = shaker_test(body, plan, 0.02, seed=0, noise=0.0)
    assert truth["exciter_masses"] == [0.02] * len(plan.exciters)
    model = RigidModel(body.nominal)  # 3-D: the simulator's body, a plate's too
    s, e = plan.sensors.coordinates, plan.exciters.coordinates
    expected = sensitivities(model, s, e, riding_masses(plan.exciters, 0.02))[1]
    plateau = np.abs(recording.frf[:, :, len(recording.frequencies) // 2])  # a free rigid body: flat everywhere
    np.testing.assert_allclose(plateau, np.abs(expected), rtol=1e-9)


def test_noiseless_masslines_give_the_bare_body_exactly(planned):
    _, body, plan = planned
    planar = plan.model.planar
    model = RigidModel(body.nominal, planar)
    riding = riding_masses(plan.exciters, 0.02, planar)
    H = sensitivities(model, model.coordinates(plan.sensors), model.coordinates(plan.exciters), riding)[1]
    data, sigma = Masslines(H, plan.sensors, plan.exciters), np.full(H.shape, 1e-3 * np.abs(H).max())
    found = estimate(data, sigma, planar, riding=riding)
    assert np.abs(found.model.theta - model.theta).max() < 1e-9 * np.abs(model.theta).max()
    left_out = estimate(data, sigma, planar).body
    assert left_out.mass > body.nominal.mass + 0.02  # the gauges weighed as the body's: at least one of 20 g


@pytest.mark.parametrize("gauge", GAUGES)
def test_identify_with_the_gauge_is_inside_the_bounds(planned, gauge):
    name, body, plan = planned
    for seed in SEEDS:
        recording, _ = shaker_test(body, plan, gauge, seed)
        found = identify_recording(recording, draws=20, exciter_mass=gauge)
        error = 100 * abs(found.body.mass / body.nominal.mass - 1)
        assert error < BOUND and error < 3 * 100 * found.std["mass"] / body.nominal.mass, (name, seed, error)
        assert found.payload["exciter_mass"] == gauge


@pytest.mark.slow
@pytest.mark.parametrize("gauge", GAUGES)
def test_the_diagnosis_names_the_gauge_never_a_hit(planned, gauge):
    """With the mesh: the excess over it located at the drive points, the body after inside the bounds."""
    name, body, plan = planned
    for seed in SEEDS:
        recording, _ = shaker_test(body, plan, gauge, seed)
        run_ = diagnose_recording(recording, None, body.nominal)
        effects = [f.effect for f in run_.findings if f.kind == "fault"]
        assert effects == ["excitation_mass_loading"], (name, seed, effects)
        found = run_.findings[0].parameters
        assert abs(found["mass_kg"] - gauge) < max(4 * found["mass_std_kg"], 0.1 * gauge), (name, seed, found)
        error = 100 * abs(run_.after_body.mass / body.nominal.mass - 1)
        assert error < max(BOUND, 200 * run_.after.std["mass"] / body.nominal.mass), (name, seed, error)  # bounds or 2σ


def test_a_hammer_test_has_no_gauge(planned):
    """A clean file: no gauge found in it, with or without the mesh."""
    _, body, plan = planned
    recording, _ = shaker_test(body, plan, 0.0, seed=4)
    run_ = diagnose_recording(recording, None, body.nominal)
    assert not [f for f in run_.findings if f.kind == "fault"]


def test_a_gauge_with_a_paper_method_or_a_bad_mass_is_refused(planned):
    from massline.core.errors import MasslineError

    _, body, plan = planned
    recording, _ = shaker_test(body, plan, 0.02, seed=0)
    with pytest.raises(MasslineError, match="needs method='best'|needs --method best"):
        identify_recording(recording, method="plate" if plan.model.planar else "method2+method3", exciter_mass=0.02)
    with pytest.raises(MasslineError, match="structure-side mass"):
        identify_recording(recording, exciter_mass=float("nan"))


def test_with_the_gauge_out_of_the_library_no_hit_fault_stands_in_for_it(planned, monkeypatch):
    """The gauge's effect taken out of the registry, 20 g at every drive point: no hit's direction or location is
    named (a tilt of one hit fits one column of a gauge's misfit); what is reported is the misfit, unexplained, on
    the excitation side (the excess over the mesh at the drive points, or a hit's place)."""
    import massline.identify.diagnose.effects as registry

    name, body, plan = planned
    recordings = [shaker_test(body, plan, 0.02, seed)[0] for seed in SEEDS]  # simulated with the whole registry
    monkeypatch.setattr(registry, "EFFECTS", tuple(e for e in registry.EFFECTS if e.name != "excitation_mass_loading"))
    for seed, recording in zip(SEEDS, recordings):
        run_ = diagnose_recording(recording, None, body.nominal)
        assert not [f.effect for f in run_.findings if f.kind == "fault"], (name, seed)
        [left] = [f for f in run_.findings if f.kind == "unexplained"]
        p = left.parameters
        assert p.get("excitation_side") or p["hits"] or not left.channels, (name, seed, left)
