"""Every warning's premise is checked against the data: silent where the premise is false, raised where it holds.

The blind suite (benchmarks/diagnose_blind.py) showed warnings with false premises: a record-length advice for a
resonance the record did not hold, an impact test's window on shaker data, cables blamed for small cross-axis
FRFs, an elastic mode quoted at the edge of the resonance-free stretch (827 Hz for a mode at 2008 Hz), and a tail
truncation the data did not show.
Each code of :data:`massline.identify.warning_codes.CODES` is tested here both ways, on virtual tests where the
virtual test can make the premise true, else on the check itself; the clean files of the bracket's default plan
(``massline plan bracket``) carry no warning, and every resonance identify, diagnose and the report quote is the
truth's within 5 %.
"""

import inspect
import json
import re
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest
from conftest import bundled
from scipy.stats import chi2 as chi2_distribution
from test_cli import massline
import test_recording_noise as noise_tests

from massline.core.band import Band
from massline.core.lines import Lines
from massline.core.rigid_body import RigidBody
from massline.identify.diagnose.diagnosis import test_physics_modes as physics_modes
from massline.identify.diagnose.effect_model import Layout
from massline.identify.diagnose.effects import parse_effect
from massline.identify.diagnose.undone import identified
from massline.identify.pipeline import against_nominal, identify_recording, usable_lines, without_mains
from massline.identify.plausibility import nominal_warnings, units_warnings
from massline.meshes.loader import load_body
from massline.meshes.round_parts import PARTS, STEEL
from massline.identify.suspicions import (
    band_warnings,
    fit_warnings,
    given_band_warnings,
    rolloff_warnings,
    short_record_warnings,
    truncation_warnings,
    weighing_warnings,
)
from massline.identify.tails import BandData
from massline.identify.uncertainty import SEEN, seen_truncation
from massline.identify.warning_codes import CODES, codes_of
from massline.identify.weighing import WeighedMass
from massline.placement.hand_layouts import structure_exciters, structure_sensors
from massline.reports.identification_report import resonances_note
from massline.uff.grid import to_recording
from massline.uff.reader import read_uff
from massline.uff.writer import write_runs, write_uff
from massline.virtual.acquisition import Acquisition, run
from massline.virtual.measurement import ImpactTest, Noise
from massline.virtual.planned_test import plan_fe_model
from massline.virtual.support_model import SupportModel
from massline.virtual.suspension import Cord, Foam, Suspension

GIVEN = {"given_band_near_support", "given_band_near_elastic"}


@pytest.fixture(scope="module")
def structure():
    return bundled("structure").nominal


@pytest.fixture(scope="module")
def cord(structure):
    """A soft 1 m cord 2 cm above the CoG: pendulum and bounce modes 0.9–1.4 Hz."""
    return Suspension(cords=(Cord(structure.cog + [0, 0, 0.02], structure.mass * 9.81 / 0.25, 1.0),))


def structure_test(structure, support, setup, sensors=None, effects=()):
    """The structure's hand layout (or ``sensors``) on ``support``, rigid, recorded with ``setup``, seed 0."""
    return run(structure, sensors or structure_sensors(), structure_exciters(), None, support, effects, setup, 0)


# --- the fit, the scale, the band: the checks themselves --------------------------------------------------


def test_the_fit_statistic_warns_only_when_it_has_something_to_say():
    assert fit_warnings(1.1, 40) == [] and fit_warnings(1.5, 40) == []  # 1.5 over 40 dof: chance
    assert codes_of(fit_warnings(np.nan, 0)) == {"no_redundancy"}
    assert codes_of(fit_warnings(4.0, 40)) == {"model_misfit"}


def test_the_misfit_warning_has_its_false_alarm_rate_at_ten_dof():
    """The stated rate, one false alarm in a thousand fits of a right model: at 10 degrees of freedom the χ² tail
    decides (above the MISFIT floor 2), so the warning fires just above the 0.999 quantile's reduced χ² (2.959)
    and not just below it; a rate of 1e-2 would fire at 2.321, one of 1e-4 only at 3.556."""
    limit = chi2_distribution.isf(1e-3, 10) / 10
    assert limit == pytest.approx(2.9588, abs=1e-4)
    assert codes_of(fit_warnings(1.005 * limit, 10)) == {"model_misfit"}
    assert fit_warnings(0.995 * limit, 10) == []


def test_the_scale_disagrees_only_beyond_three_sigma():
    scale = WeighedMass(2.0, 0.002)
    assert weighing_warnings(2.5, scale, 0.0) == [] and weighing_warnings(9.0, None, 0.0) == []
    [warning] = weighing_warnings(-3.5, scale, 0.02)
    assert warning.code == "weighed_mass_disagrees" and "0.02 kg of accelerometers" in warning.text


def test_a_band_edge_is_near_a_resonance_only_when_the_record_shows_one():
    """The clean bracket's band 28–661 Hz, whose stretch ends at 827 Hz: identify quoted that edge as where the
    elastic modes start; the record's first elastic mode is at 2007 Hz and its support modes unresolved (nan)."""
    assert band_warnings(Band(28.2, 661.3, np.nan, 2007.1, "chosen"), 421) == []
    assert band_warnings(Band(28.2, 661.3, 45.0, 2007.1, "chosen"), 421) == []  # a support mode above the band
    low, high = band_warnings(Band(28.2, 661.3, 22.0, 850.0, "chosen"), 421)
    assert (low.code, high.code) == ("band_near_support", "band_near_elastic")
    assert "resolves, at 22 Hz" in low.text and "first elastic mode at 850 Hz" in high.text
    assert band_warnings(Band(28.2, 661.3, 22.0, 850.0, "given"), 421) == []  # given_band_near_* say it
    assert codes_of(band_warnings(Band(28.2, 661.3, np.nan, np.nan, "chosen"), 39)) == {"few_lines"}


def test_the_tails_truncation_is_held_to_what_fitting_the_next_term_shows():
    """A massline whose single-mode law (B²/A) claims 8 times its size, where the richer fit moves it by 6 % of
    that: the data's move and SEEN of its 1-σ are what is kept, with the law's sign; smaller claims stay."""
    fit = SimpleNamespace(values=np.array([[1e-3, 0.5]]))
    richer = SimpleNamespace(values=np.array([[1.06e-3, 0.5001]]), std=np.array([[5e-6, 1e-4]]))
    held = seen_truncation(np.array([[-8e-3, 2e-4]]), fit, richer)
    np.testing.assert_allclose(held, [[-(6e-5 + SEEN * 5e-6), 2e-4]])
    body = bundled("bracket").nominal
    statistical = {"mass": 1e-3, "principal_moments": 1e-3 * body.principal_moments}
    shift = np.zeros(25)
    shift[14] = 1.5e-3 * body.principal_moments[1]
    assert truncation_warnings(shift, statistical, body) == []  # 1.5σ: within the ±
    shift[14] = 3e-3 * body.principal_moments[1]
    [warning] = truncation_warnings(shift, statistical, body)
    assert warning.code == "tail_truncation" and "J2 by 0.3%, 3×" in warning.text
    [unbounded] = truncation_warnings(np.full(25, np.inf), statistical, body)  # the moved masslines fit no body
    assert unbounded.code == "tail_truncation" and "unbounded (∞)" in unbounded.text


def test_a_given_band_is_named_only_across_or_near_the_records_resonances(structure, cord):
    recording = structure_test(structure, cord, Acquisition(200.0, 2000))[0]
    assert not codes_of(identify_recording(recording, (20.0, 150.0), draws=0).warnings) & GIVEN
    found = identify_recording(recording, (1.0, 150.0), draws=0)
    assert "given_band_near_support" in codes_of(found.warnings)
    free = Band(5.0, 900.0, 5.0, 900.0, "stretch")
    assert codes_of(given_band_warnings(Band(20.0, 2500.0, rule="given"), free)) == {"given_band_near_elastic"}


# --- the coherence: small is not faulty ---------------------------------------------------------------------


def cross_axis(structure) -> Lines:
    """The hand layout and a 7th accelerometer at the 1st one's point, turned square to the motion hit 1 drives
    but for 1e-3 rad: its FRF with hit 1 is 0.4 % of the strong ones'."""
    sensors, exciters = structure_sensors(), structure_exciters()
    driven = np.linalg.solve(structure.mass_matrix, exciters.coordinates[0])  # (d, r × d)·(v, ω) = d·(v + ω × r)
    point = sensors.points[0]
    normal = driven[:3] + np.cross(driven[3:], point)
    square = np.cross(normal, [0.3, -0.2, 1.0])
    square = square / np.linalg.norm(square) + 1e-3 * normal / np.linalg.norm(normal)
    return sensors + Lines(point[None], square[None])


def test_a_small_cross_axis_frf_at_the_noise_floor_blames_no_cable(structure, cord):
    """A noise floor of 1 % of 1/m: the cross-axis FRF's median coherence is far below 0.9 at the noise its
    channel and its hit show everywhere else; a channel whose own noise is ten times its hits' is named."""
    setup = Acquisition(200.0, 2000, Noise(0.01, 0.01))
    recording = structure_test(structure, cord, setup, cross_axis(structure))[0]
    found = identify_recording(recording, None, draws=0)
    f = recording.frequencies
    in_band = (f >= found.band.low) & (f <= found.band.high)
    assert np.median(recording.coherence[6, 0, in_band]) < 0.5  # the premise of the old warning
    assert "poor_coherence" not in codes_of(found.warnings)
    noisy = recording.coherence.copy()
    noisy[2] = 0.6  # the 3rd channel's cable: 1 − γ² of 0.4 on every hit, its noise 0.67 |H|²
    [poor] = [w for w in identify_recording(replace(recording, coherence=noisy), None, draws=0).warnings
              if w.code == "poor_coherence"]  # fmt: skip
    assert "3 FRF(s)" in poor.text and "sensor 3 / hit 1" in poor.text and "sensor 7" not in poor.text


# --- the record: a resonance it holds, a window it says it had ----------------------------------------------


def test_an_impact_tests_file_says_its_window_and_a_shakers_does_not(structure, cord, tmp_path):
    for setup, windowed in ((Acquisition(200.0, 400, impact=ImpactTest()), True), (Acquisition(200.0, 400), False)):
        recording = structure_test(structure, cord, setup)[0]
        assert recording.exponential_window is windowed
        write_uff(tmp_path / "test.uff", recording, force=True)
        contents = read_uff(tmp_path / "test.uff")
        assert set(contents.windows) == ({6} if windowed else set())
        assert to_recording(contents).exponential_window is windowed


def test_a_short_record_is_said_only_of_a_windowed_record_and_a_resonance_it_holds(structure, cord):
    """Δf 0.5 Hz on the cord (modes 0.9–1.4 Hz, 2–3 lines up): an impact test's window broadens them into the
    band; a shaker's record has no window. On foam (lowest mode 6 Hz, 12 lines up) nothing is unresolved,
    though the impact test's noisy lowest lines are imaginary-dominated."""
    impact = Acquisition(200.0, 400, impact=ImpactTest())
    recording, truth = structure_test(structure, cord, impact)
    [short] = [w for w in identify_recording(recording, None, draws=0).warnings if w.code == "short_record"]
    near = float(re.search(r"near ([\d.]+) Hz", short.text).group(1))
    modes = np.array(truth["suspension"]["modes_hz"])
    assert np.abs(modes - near).min() <= 0.5 and "exponential window the file says" in short.text
    shaker = structure_test(structure, cord, Acquisition(200.0, 400))[0]
    assert "short_record" not in codes_of(identify_recording(shaker, None, draws=0).warnings)
    pads = structure.cog + [[0.1, 0.1, -0.1], [-0.1, 0.1, -0.1], [0.0, -0.1, -0.1]]
    foam = Suspension(foam=Foam(pads, structure.mass * (2 * np.pi * 12.0) ** 2))
    recording, truth = structure_test(structure, foam, impact)
    assert min(truth["suspension"]["modes_hz"]) > 5 * 0.5
    assert "short_record" not in codes_of(identify_recording(recording, None, draws=0).warnings)
    band = Band(20.0, 200.0, np.nan, np.nan, "chosen")
    f = np.arange(1, 401) * 2.0
    spring = (-((2 * np.pi * f) ** 2) / ((2 * np.pi * 2.5) ** 2 * (1 + 0.6j) - (2 * np.pi * f) ** 2))[None, None]
    assert short_record_warnings(f, spring, band, windowed=False) == []
    assert codes_of(short_record_warnings(f, spring, band, windowed=True)) == {"short_record"}


def test_a_falling_force_spectrum_blames_a_hammer_only_on_an_impact_tests_record():
    f = np.arange(1, 2001) * 0.5
    band = Band(20.0, 200.0, 5.0, 600.0, "chosen")
    flat = np.full((2, 2, len(f)), 0.9999)
    assert rolloff_warnings(f, flat, band, windowed=True) == []
    falling = np.broadcast_to(1 - 1e-4 * (1 + (f / 100.0) ** 6), flat.shape)
    [hammer] = rolloff_warnings(f, falling, band, windowed=True)
    [either] = rolloff_warnings(f, falling, band, windowed=False)
    assert hammer.code == either.code == "force_roll_off"
    assert "hit with a harder tip" in hammer.text and "shaker" not in hammer.text
    assert "shaker's force" in either.text and "harder tip" not in either.text


# --- what was set aside, what was refused, what the body's size says ----------------------------------------


def test_lines_are_said_to_be_set_aside_only_when_they_were(structure, cord):
    recording = structure_test(structure, cord, Acquisition(200.0, 2000))[0]
    assert codes_of(usable_lines(recording)[1]) == {"dc_line_set_aside"}
    kept = usable_lines(recording)[0]
    assert usable_lines(kept)[1] == () and without_mains(kept)[2] == ()
    hum = (parse_effect("mains_interference=0.1"),)
    hummed = usable_lines(structure_test(structure, cord, Acquisition(200.0, 2000), effects=hum)[0])[0]
    assert codes_of(without_mains(hummed)[2]) == {"mains_set_aside"}


def test_diagnose_says_identify_refused_only_when_it_did(structure, cord):
    clean = structure_test(structure, cord, Acquisition(200.0, 2000))[0]
    assert identified(clean, None, 0.01, {})[1] == ()
    low = structure_test(structure, cord, Acquisition(8.0, 10))[0]  # to 8 Hz: no 8 lines clear of the cord's modes
    assert codes_of(identified(low, None, 0.01, {})[1]) == {"identify_refused"}
    assert codes_of(identified(low, (0.5, 8.0), 0.01, {})[1]) == {"identify_no_band"}


def round_part(name: str, folder):
    path = folder / f"{name.replace(' ', '_')}.stl"
    PARTS[name](32).export(path)
    return load_body(path, "m", STEEL)


def test_the_bodys_size_and_the_mesh_warn_only_on_a_mislabelled_body(tmp_path):
    """Silent on every bundled and round part as it is; on the same bodies read 9.81× heavy or light, the mesh names
    the label every time, and the inertia ellipsoid alone where no solid is so dense or so light (a steel part read
    heavy, the aluminium bracket read light); a length label is never taken for g."""
    meshes = {name: bundled(name) for name in ("plate", "bracket", "structure")}
    meshes |= {name: round_part(name, tmp_path) for name in PARTS}
    alone = {"heavy_for_extent": {"shaft", "cylinder", "hollow cylinder", "filleted box"}, "light_for_extent": {"bracket"}}
    for name, mesh in meshes.items():
        body, points, planar = mesh.nominal, mesh.mesh.vertices, name == "plate"
        assert units_warnings(body, points, planar) == [] and nominal_warnings(body, body, 1e-3, 8) == [], name
        for code, factor in (("heavy_for_extent", 9.80665), ("light_for_extent", 1 / 9.80665)):
            read = type(body)(body.mass * factor, body.cog, body.inertia_cog * factor)
            assert codes_of(nominal_warnings(read, body)) == {code}, name
            assert codes_of(units_warnings(read, points, planar)) == ({code} if name in alone[code] else set()), name
    body, points = meshes["bracket"].nominal, meshes["bracket"].mesh.vertices
    small = type(body)(body.mass, body.cog * 1e-3, body.inertia_cog * 1e-6)
    large = type(body)(body.mass, body.cog * 1e3, body.inertia_cog * 1e6)
    assert codes_of(units_warnings(small, points * 1e-3)) == {"denser_than_any_material"}
    assert codes_of(units_warnings(large, points * 1e3)) == {"lighter_than_air"}


def test_a_body_heavier_than_its_mesh_names_the_masses_not_given():
    """8 accelerometers of 5 g on a 0.295 kg hub: 13.6 % heavier than the mesh, named with the housings' mass that
    explains it; silent within 3σ or within 2 %; lighter, the masses taken off twice."""
    hub = RigidBody(0.295, np.zeros(3), np.diag([2e-4, 2e-4, 3e-4]))
    loaded = replace(hub, mass=0.335)
    [warned] = nominal_warnings(loaded, hub, 5e-4, 8)
    assert warned.code == "nominal_mass_mismatch" and "13.6% heavier" in warned.text, warned.text
    assert "8 accelerometers of 5 g would be 40 g" in warned.text
    assert "--sensor-mass" in warned.text and "--exciter-mass" in warned.text
    assert nominal_warnings(loaded, hub, 0.014, 8) == []  # 40 g within 3σ
    assert nominal_warnings(replace(hub, mass=0.300), hub, 1e-4, 8) == []  # 1.7 %: within 2 %
    [lighter] = nominal_warnings(replace(hub, mass=0.280), hub, 1e-4, 8)
    assert "lighter" in lighter.text and "taken off twice" in lighter.text
    [misfit] = nominal_warnings(loaded, hub, 5e-4, 8, misfit=True)
    assert "the rigid model does not fit" in misfit.text and "massline diagnose" in misfit.text


# --- the bracket's default plan: quiet, and its frequencies the truth's ------------------------------------


def simulated(plan, folder, name, *options) -> tuple:
    """``massline simulate`` of the plan with ``options``: identify's result on the file, and its truth."""
    path = folder / f"{name}.uff"
    result = massline("simulate", plan, "--out", path, *options)
    assert result.returncode == 0, result.stderr
    return identify_recording(path, draws=30), json.loads(path.with_suffix(".truth.json").read_text())


@pytest.mark.slow
def test_accelerometers_left_on_are_named_against_the_mesh(bracket_default_plan, tmp_path):
    """5 g on each of the bracket's 9 accelerometers, --sensor-mass forgotten: 13 % heavier than the mesh, named
    with the housings' mass that explains it (within 10 % of 5 g); given, the mesh agrees and nothing is said."""
    found, _ = simulated(bracket_default_plan, tmp_path, "loaded", "--effect", "sensor_mass_loading=0.005@all")
    mesh = bundled("bracket").nominal
    [warned] = [w for w in against_nominal(found, mesh).warnings if w.code == "nominal_mass_mismatch"]
    grams = float(re.search(r"9 accelerometers of ([\d.]+) g would be", warned.text).group(1))
    assert abs(grams - 5.0) < 0.5 and "--sensor-mass" in warned.text, warned.text
    given = identify_recording(tmp_path / "loaded.uff", draws=30, sensor_mass=0.005)
    assert "nominal_mass_mismatch" not in codes_of(against_nominal(given, mesh).warnings)


def quoted_resonances(found) -> list[float]:
    """Every frequency the report's band note quotes (:func:`resonances_note`), Hz."""
    return [float(x) for x in re.findall(r"at ([\d.e+]+) Hz", resonances_note(found.band))]


@pytest.mark.slow
@pytest.mark.parametrize(
    "name, options",
    [("cord", ("--seed", "0")), ("seed1", ("--seed", "1")), ("seed2", ("--seed", "2")),
     pytest.param("impact", ("--impact",), marks=pytest.mark.long),  # a 51,200-line hammer record: long tier
     ("foam", ("--suspension", "foam"))],
)  # fmt: skip
def test_the_default_plans_clean_files_are_quiet_and_quote_the_truths_resonances(
    bracket_default_plan, tmp_path, name, options
):
    """identify gives no warning; the resonances it keeps with its band (what the warnings and the report
    quote) are the truth's top support mode and first elastic mode within 5 %, or none; diagnose's rule, on the
    same record and band, finds the same ones."""
    found, truth = simulated(bracket_default_plan, tmp_path, name, *options)
    assert found.warnings == (), [w.text for w in found.warnings]
    band = found.band
    support, elastic = max(truth["suspension"]["modes_hz"]), truth["elastic_hz"][0]
    for quoted, true in ((band.suspension_top, support), (band.first_elastic, elastic)):
        assert np.isnan(quoted) or abs(quoted / true - 1) < 0.05, (quoted, true)
    quoted = [x for x in (band.suspension_top, band.first_elastic) if x > 0]
    assert quoted_resonances(found) == pytest.approx(quoted, rel=5e-3)  # to the 3 or 4 digits printed
    record = found.recording
    layout = Layout.of(record.sensors, record.exciters, found.planar)
    whole = BandData.from_recording(record.frequencies, record.frf, record.frequencies[0], record.frequencies[-1])
    edges = BandData.from_recording(record.frequencies, record.frf, band.low, band.high)
    diagnosed = physics_modes(whole, edges, layout)
    np.testing.assert_equal(
        [diagnosed["suspension"], diagnosed["residual_flexibility"]], [band.suspension_top, band.first_elastic]
    )


def test_missing_pairs_and_disagreeing_repeats_are_said_only_when_there_are_some(tmp_path):
    """"frf_missing" only when a pair has no FRF (not for one file per run that holds them all); "repeat_disagrees"
    only when a pair measured twice differs beyond its noise (not for a repeat with its own noise)."""
    from test_runs_identify import BAND, gaps, recording

    body = bundled("structure").nominal
    first, again = recording(body, 6), recording(body, 7)
    whole = identify_recording(write_runs(tmp_path / "whole.uff", first), BAND, draws=0)
    assert "frf_missing" not in codes_of(whole.warnings + whole.notes)
    holed = write_runs(tmp_path / "holed.uff", gaps(first, [(1, 1)]))
    assert "frf_missing" in codes_of(identify_recording(holed, BAND, draws=0).warnings)
    write_uff(tmp_path / "a.uff", first)
    write_uff(tmp_path / "b.uff", again, columns=[1])
    quiet = identify_recording([tmp_path / "a.uff", tmp_path / "b.uff"], BAND, draws=0)
    assert quiet.recording.repeats and "repeat_disagrees" not in codes_of(quiet.warnings)
    off = again.frf.copy()
    off[2, 1] *= 0.9
    write_uff(tmp_path / "c.uff", replace(again, frf=off), columns=[1])
    assert "repeat_disagrees" in codes_of(identify_recording([tmp_path / "a.uff", tmp_path / "c.uff"], BAND).warnings)


def test_the_support_model_is_said_where_it_was_taken_off_and_relied_on_where_it_moves():
    """No support model: no "support_modelled" note. The structure on a soft cord, its model given: the note, and
    no "support_model_reliance" (its FRFs leave their masslines by a per mille in the band); the check itself
    warns where the median departure is beyond 5 % or the fixed point was not reached."""
    mesh = bundled("structure")
    body, modes = mesh.nominal, plan_fe_model(mesh, "structure").modes
    soft = Suspension.parse("cord", mesh.mesh, body)
    quiet = Acquisition(noise=Noise(0.005, 0.0), dc_line=False)
    recording, _ = run(body, structure_sensors(), structure_exciters(), modes, soft, (), quiet, 1)
    plain = identify_recording(recording, draws=0)
    assert "support_modelled" not in codes_of(plain.notes) and not plain.support_fit
    modelled = identify_recording(recording, draws=0, support=SupportModel(modes, soft, body))
    assert "support_modelled" in codes_of(modelled.notes)
    assert "support_model_reliance" not in codes_of(modelled.warnings), modelled.support_fit.departure
    fit = modelled.support_fit
    assert not replace(fit, departure=(0.049, 3.0)).warnings
    assert codes_of(replace(fit, departure=(0.2, 3.0)).warnings) == {"support_model_reliance"}
    assert codes_of(replace(fit, converged=False).warnings) == {"support_model_reliance"}


PREMISES = {  # each code, and the test above that checks it silent on a false premise and raised on a true one
    "no_redundancy": test_the_fit_statistic_warns_only_when_it_has_something_to_say,
    "model_misfit": test_the_fit_statistic_warns_only_when_it_has_something_to_say,
    "weighed_mass_disagrees": test_the_scale_disagrees_only_beyond_three_sigma,
    "band_near_support": test_a_band_edge_is_near_a_resonance_only_when_the_record_shows_one,
    "band_near_elastic": test_a_band_edge_is_near_a_resonance_only_when_the_record_shows_one,
    "few_lines": test_a_band_edge_is_near_a_resonance_only_when_the_record_shows_one,
    "poor_coherence": test_a_small_cross_axis_frf_at_the_noise_floor_blames_no_cable,
    "tail_truncation": test_the_tails_truncation_is_held_to_what_fitting_the_next_term_shows,
    "given_band_near_support": test_a_given_band_is_named_only_across_or_near_the_records_resonances,
    "given_band_near_elastic": test_a_given_band_is_named_only_across_or_near_the_records_resonances,
    "short_record": test_a_short_record_is_said_only_of_a_windowed_record_and_a_resonance_it_holds,
    "force_roll_off": test_a_falling_force_spectrum_blames_a_hammer_only_on_an_impact_tests_record,
    "denser_than_any_material": test_the_bodys_size_and_the_mesh_warn_only_on_a_mislabelled_body,
    "lighter_than_air": test_the_bodys_size_and_the_mesh_warn_only_on_a_mislabelled_body,
    "heavy_for_extent": test_the_bodys_size_and_the_mesh_warn_only_on_a_mislabelled_body,
    "light_for_extent": test_the_bodys_size_and_the_mesh_warn_only_on_a_mislabelled_body,
    "nominal_mass_mismatch": test_a_body_heavier_than_its_mesh_names_the_masses_not_given,
    "dc_line_set_aside": test_lines_are_said_to_be_set_aside_only_when_they_were,
    "mains_set_aside": test_lines_are_said_to_be_set_aside_only_when_they_were,
    "identify_no_band": test_diagnose_says_identify_refused_only_when_it_did,
    "identify_refused": test_diagnose_says_identify_refused_only_when_it_did,
    "frf_missing": test_missing_pairs_and_disagreeing_repeats_are_said_only_when_there_are_some,
    "repeat_disagrees": test_missing_pairs_and_disagreeing_repeats_are_said_only_when_there_are_some,
    "support_modelled": test_the_support_model_is_said_where_it_was_taken_off_and_relied_on_where_it_moves,
    "support_model_reliance": test_the_support_model_is_said_where_it_was_taken_off_and_relied_on_where_it_moves,
    "fit_below_noise": noise_tests.test_a_fit_below_the_noise_and_noise_the_coherence_does_not_see_are_warned,
    "noise_above_coherence": noise_tests.test_a_fit_below_the_noise_and_noise_the_coherence_does_not_see_are_warned,
}


def test_every_registered_code_is_tested_both_ways():
    """Every code of CODES has a test here, and that test names the code."""
    assert set(PREMISES) == set(CODES), set(CODES) ^ set(PREMISES)
    assert all(f'"{code}"' in inspect.getsource(test) for code, test in PREMISES.items())
