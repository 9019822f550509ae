"""An open world: one χ² for identify and diagnose, faults proven on it, and what the library cannot name located.

Twelve lines on the structure, its four hits, a rigid virtual test with 1 % noise (fast). With the sensor
effects taken out of the registry a 10 % gain cannot be named: the diagnosis must say "unexplained" at that
channel, not give the misfit the nearest name. With the registry whole the gain is named and proven on
identify's χ² of the masslines.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from conftest import bundled
from test_diagnose import twelve_lines

import massline.identify.diagnose.effects as registry
from massline.identify.diagnose.finding import Finding
from massline.identify.diagnose.notes import finding_note, verdict
from massline.identify.diagnose.placed import where_the_misfit_is
from massline.identify.diagnose.pipeline import diagnose_recording
from massline.identify.diagnose.shapes import channel_factor, objective
from massline.identify.diagnose.unexplained import refused_misfit, sentence, unexplained
from massline.identify.diagnose.effects import parse_effect
from massline.identify.pipeline import identify_recording
from massline.placement.hand_layouts import structure_exciters
from massline.virtual.acquisition import Acquisition, run

SENSOR_BLOCKS = ("sensor_gain", "sensor_direction", "sensor_location", "transverse_sensitivity")


@pytest.fixture(scope="module")
def structure():
    return bundled("structure").nominal


def recorded(body, effect: str | None = None, seed: int = 1):
    effects = () if effect is None else (parse_effect(effect),)
    rec, _ = run(body, twelve_lines(), structure_exciters(), effects=effects, setup=Acquisition(100.0, 400), seed=seed)
    return rec


def test_identify_and_diagnose_measure_one_chi2(structure):
    """diagnose's χ² before is identify's on the same file; with no fault named, after = before."""
    rec = recorded(structure, "sensor_gain=-0.1@4")
    found = diagnose_recording(rec, None, structure)
    assert found.chi2["before"] == identify_recording(rec).best.chi2
    clean = diagnose_recording(recorded(structure), None, structure)
    assert clean.chi2["after"] == clean.chi2["before"] < 2
    assert verdict(clean.findings, clean.chi2).startswith("no fault")


def test_a_faulty_channel_is_located_by_leaving_it_out(structure):
    """identify alone on a 10 % gain at channel 4 (index 3): beyond chance, and the rest fit without that channel."""
    found = identify_recording(recorded(structure, "sensor_gain=-0.1@4"), draws=0)
    left = unexplained(found)
    assert left is not None and left.kind == "unexplained"
    assert left.channels == (3,) and left.parameters["shape"] == "one_channel"
    assert unexplained(identify_recording(recorded(structure), draws=0)) is None


def test_outside_the_library_the_misfit_is_unexplained_not_misnamed(structure, monkeypatch):
    """Every sensor block effect taken out of the registry: the gain is named as no other effect, and reported as
    unexplained at its channel; "no fault" is not said."""
    rec = recorded(structure, "sensor_gain=-0.1@4")
    monkeypatch.setattr(registry, "EFFECTS", tuple(e for e in registry.EFFECTS if e.name not in SENSOR_BLOCKS))
    found = diagnose_recording(rec, None, structure)
    assert [f.effect for f in found.findings if f.kind == "fault"] == []
    left = [f for f in found.findings if f.kind == "unexplained"]
    assert len(left) == 1 and left[0].channels == (3,)
    assert verdict(found.findings, found.chi2) is None
    note = finding_note(left[0], found.sensors, found.hits)
    assert note.startswith("unexplained") and "sensor" in note
    payload = found.document["findings"][-1]
    assert payload["kind"] == "unexplained" and payload["sensor"] is not None


def test_a_named_fault_is_proven_on_identifys_chi2(structure):
    """With the registry whole the gain is named at its channel, its evidence says how much of identify's χ² it
    explains, and the χ² after is within chance."""
    found = diagnose_recording(recorded(structure, "sensor_gain=-0.1@4"), None, structure)
    fault = next(f for f in found.findings if f.kind == "fault")
    assert (fault.effect, fault.channels) == ("sensor_gain", (3,))
    assert fault.evidence["chi2_explained"] > 10
    assert found.chi2["after"] < 2 and not [f for f in found.findings if f.kind == "unexplained"]
    assert np.isfinite(found.chi2["dof"])


def test_the_gain_named_is_identifys_factor_and_its_undoing_gives_the_properties_after(structure):
    """One estimator, one number: the −10 % gain named is the factor on identify's objective (θ estimated again)
    on the same file, not the line-level fit's; its ± covers the truth; the channel divided by it is what identify
    identifies after."""
    rec = recorded(structure, "sensor_gain=-0.1@4")
    found = diagnose_recording(rec, None, structure)
    fault = next(f for f in found.findings if f.kind == "fault")
    gain, std = channel_factor(identify_recording(rec, draws=0), 3)
    assert fault.parameters["gain"] == pytest.approx(gain, rel=1e-9)
    assert fault.parameters["gain_std"] == pytest.approx(std, rel=1e-3)  # the curvature read with another step
    assert abs(gain - 0.9) < 3 * std < 0.01
    mended = replace(rec, frf=rec.frf.copy())
    mended.frf[3] /= gain
    again = identify_recording(mended)
    assert objective(again.best) == pytest.approx(objective(found.after.best), rel=1e-6)


def test_a_tilted_channel_identify_took_up_is_found_off_its_axis(structure):
    """An 8° misalignment on channel 6: identify reads it along its true axis (the masslines fit within chance),
    and its transverse part beyond the datasheet's prior places the finding; diagnose names the tilt there."""
    rec = recorded(structure, "sensor_direction=8@6")
    found = identify_recording(rec, draws=0)
    left = unexplained(found)
    assert left is not None and left.parameters["shape"] == "off_axis" and left.channels == (5,)
    assert left.parameters["angle_deg"] == pytest.approx(8.0, abs=1.5)
    run_ = diagnose_recording(rec, None, structure)
    fault = next(f for f in run_.findings if f.kind == "fault")
    assert (fault.effect, fault.channels) == ("sensor_direction", (5,))
    assert max(fault.parameters["angle_deg"]) == pytest.approx(8.0, abs=1.0)


def test_a_factor_on_one_row_is_recovered_by_the_library_free_shape(structure):
    """shapes.scaled on identify's masslines of a 10 % gain at channel 4: the factor 0.9 (to its 1-σ) and a χ²
    within chance; on channel 1 (the wrong row) the misfit stays."""
    from massline.identify.diagnose.shapes import objective, scaled

    found = identify_recording(recorded(structure, "sensor_gain=-0.1@4"), draws=0)
    right, factor = scaled(found, rows=(3,))
    wrong, _ = scaled(found, rows=(0,))
    assert factor[0] == pytest.approx(0.9, abs=0.01)
    assert right < found.best.dof + 4 * np.sqrt(2 * found.best.dof) < wrong <= objective(found.best) + 1e-9


def test_with_only_the_gain_out_of_the_library_no_other_name_takes_it(structure, monkeypatch):
    """Only sensor_gain taken out: a moved sensor or a tilt could fit the gain's misfit, but one factor on the
    channel's row fits at least as well for its values, so no fault is named and the channel is reported
    unexplained, with the factor found."""
    rec = recorded(structure, "sensor_gain=-0.1@4")
    monkeypatch.setattr(registry, "EFFECTS", tuple(e for e in registry.EFFECTS if e.name != "sensor_gain"))
    found = diagnose_recording(rec, None, structure)
    assert [f.effect for f in found.findings if f.kind == "fault"] == []
    left = [f for f in found.findings if f.kind == "unexplained"]
    assert len(left) == 1 and left[0].channels == (3,)
    outfitted = left[0].evidence["outfitted"]
    assert outfitted and {s["effect"] for s in outfitted} <= {"sensor_location", "sensor_direction"}
    for shape in outfitted:
        assert shape["rows"] == [3] and shape["factors"][0] == pytest.approx(0.9, abs=0.01)
        assert shape["chi2"] < shape["named_chi2"]
    note = finding_note(left[0], found.sensors, found.hits)
    assert "one factor on sensor" in note and "cannot tell these apart, so none is named" in note


def test_a_gauge_is_no_stand_in_for_one_channels_misfit():
    """A gauge's mass (no place: every drive point) is withdrawn when leaving one channel out explains the file's
    misfit, kept when leaving one hit out does; a fault at the misfit's channel stays."""
    gauge = Finding("excitation_mass_loading", (), None, {"mass_kg": 0.02}, {})
    here = Finding("sensor_location", (3,), None, {}, {})
    channel = Finding("unexplained", (3,), None, {"shape": "one_channel", "hits": []}, {})
    hit = Finding("unexplained", (), None, {"shape": "one_hit", "hits": [2]}, {})
    assert where_the_misfit_is([gauge, here], channel) == ([here], [gauge])
    assert where_the_misfit_is([gauge], hit) == ([gauge], [])


def test_a_fault_named_where_the_misfit_still_is_explained_only_part_of_it():
    """The faults at the one channel or hit that still holds identify's misfit after every fault is undone are
    the ones withdrawn; a gain (the misfit's own shape) stays where what is left is one FRF, and goes where its
    whole row is left (a factor that does not fit its row), a flipped sign stays; a spread misfit, or one
    elsewhere, withdraws none."""
    from massline.identify.diagnose.finding import Finding
    from massline.identify.diagnose.placed import at_the_misfit

    gain = Finding("sensor_gain", (3,), None, {"gain": 0.9}, {})
    hit = Finding("excitation_location", (), 2, {}, {})
    at_channel = Finding("unexplained", (3,), None, {"shape": "one_channel", "hits": []}, {})
    spread = Finding("unexplained", (3,), None, {"shape": "spread", "hits": [2]}, {})
    at_hit = Finding("unexplained", (), None, {"shape": "one_hit", "hits": [2]}, {})
    location = Finding("sensor_location", (3,), None, {}, {})
    sign = Finding("sensor_polarity", (3,), None, {}, {})
    at_frf = Finding("unexplained", (3,), None, {"shape": "one_frf", "hits": [1]}, {})
    assert at_the_misfit([location, gain, sign, hit], at_channel) == [location, gain]
    assert at_the_misfit([location, gain, sign, hit], at_frf) == [location]
    assert at_the_misfit([location, hit], at_hit) == [hit]
    assert at_the_misfit([location, hit], spread) == [] and at_the_misfit([location], None) == []
    tied = {"shape": "one_hit", "hits": [0], "also_hits": [2, 3]}  # hits 1, 3 and 4 each hold the rest
    assert at_the_misfit([hit], Finding("unexplained", (), None, tied, {"chi2_reduced": 167.0})) == [hit]
    assert at_the_misfit([hit], Finding("unexplained", (), None, tied, {"chi2_reduced": 2.1})) == []


def test_faults_beside_a_misfit_no_place_holds_are_withdrawn():
    """Beyond chance and spread with the faults undone: every fault named beside it goes (it explained part of a
    misfit the library does not); within chance (None) or at one place, none."""
    from massline.identify.diagnose.finding import Finding
    from massline.identify.diagnose.placed import beside_a_spread_misfit

    tilt = Finding("excitation_direction", (), 2, {}, {})
    gain = Finding("sensor_gain", (3,), None, {"gain": 0.9}, {})
    tail = Finding("suspension", (), None, {}, {})  # test physics: its kind from the registry
    spread = Finding("unexplained", (), None, {"shape": "spread", "hits": [0]}, {"chi2_reduced": 167.0})
    at_hit = Finding("unexplained", (), None, {"shape": "one_hit", "hits": [2]}, {"chi2_reduced": 5.0})
    assert beside_a_spread_misfit([tilt, gain, tail], spread) == [tilt, gain]
    assert beside_a_spread_misfit([tilt, gain], at_hit) == [] and beside_a_spread_misfit([tilt], None) == []


def test_a_fault_stays_at_any_place_that_holds_the_whole_misfit():
    """Where leaving out channel 6 or channel 9 each leaves the rest within chance, a fault at either stays and
    one at a third channel is a stand-in, set aside (the structure's 8° tilt on channel 9 had been set aside for
    channel 6, the one channel that checks it)."""
    misfit = Finding("unexplained", (5,), None, {"hits": [], "shape": "one_channel", "also_channels": [8],
                                                  "also_hits": []})  # fmt: skip
    at_nine, at_six, at_three = (Finding("sensor_direction", (k,), None, {}) for k in (8, 5, 2))
    kept, aside = where_the_misfit_is([at_nine, at_six, at_three], misfit)
    assert kept == [at_nine, at_six] and aside == [at_three]
    kept, aside = where_the_misfit_is([at_nine], replace(misfit, parameters={**misfit.parameters, "also_channels": []}))
    assert kept == [] and aside == [at_nine]


def test_a_file_identify_refuses_is_unexplained_at_the_channel_the_screen_puts_it():
    """No rigid body fits (a flipped channel with sensor_polarity out of the library): the misfit is reported
    whole, at the channel farthest from the others' rigid motion, never silence."""
    found = refused_misfit({"channel_consistency": [0.01, 0.9, 0.05]})
    assert found.kind == "unexplained" and found.channels == (1,) and found.parameters["shape"] == "refused"
    text = sentence(found, ["1:+Z", "2:+Z", "3:+Z"], ["101:+Z"])
    assert "no rigid body" in text and "sensor 2:+Z" in text and "none is named" in text
    assert refused_misfit({"channel_consistency": None}).channels == ()
