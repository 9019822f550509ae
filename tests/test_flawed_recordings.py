"""No silent wrong answer: deliberately flawed recordings of the bracket, each identified from the file alone.

For every case the result (mass, CoG, principal moments) is within 2σ of the truth or carries a warning whose
code blames the flaw (never just any warning); where the flaw is gross, that warning is there. The recordings
are exporter-style files (0 Hz line, g/N, mm, coherence) of the planned bracket test (12 + 2 triaxial
accelerometers, 4 hits) on a cord, with 1 % noise and 3 % transverse sensitivity, fixed seeds.
"""

from dataclasses import replace

import numpy as np
import pytest
import session_cache
from scipy.spatial.transform import Rotation
from conftest import bundled
from test_identify import bracket_plan  # noqa: F401  (the plan fixture)

from massline.identify.pipeline import against_nominal, identify_recording
from massline.identify.plausibility import ball_bound, density_bound, nominal_warnings, units_warnings
from massline.identify.suspicions import given_band_warnings, rolloff_warnings, short_record_warnings
from massline.identify.warning_codes import codes_of
from massline.core.band import Band
from massline.core.errors import MasslineError
from massline.placement.plan_file import read_plan
from massline.uff.grid import to_recording
from massline.uff.reader import read_uff
from massline.uff.units import G
from massline.uff.writer import write_uff
from massline.identify.diagnose.effects import parse_effect
from massline.virtual.elastic import Material
from massline.virtual.measurement import ImpactTest
from massline.virtual.suspension import Cord, Suspension
from massline.virtual.acquisition import Acquisition, run

TRANSVERSE = (parse_effect("transverse_sensitivity=0.03@all"),)


# --- the checks on their own -------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["bracket", "structure", "plate"])
def test_no_bundled_body_looks_mislabelled(name):
    """The density bound and the hull density of every bundled body (its mesh's vertices as measured points)
    and the nominal check against itself raise nothing; the bound is below the true density."""
    mesh = bundled(name)
    planar = name == "plate"
    assert density_bound(mesh.nominal.mass, mesh.nominal.inertia_cog, planar) < mesh.density
    assert units_warnings(mesh.nominal, mesh.mesh.vertices, planar) == []
    assert nominal_warnings(mesh.nominal, mesh.nominal) == []


def test_no_density_bound_for_an_inertia_no_body_has():
    """A plate fit of a minimal layout can give J_xx + J_yy < 0: no bound, and no RuntimeWarning."""
    with np.errstate(all="raise"):
        assert np.isnan(density_bound(2.0, np.diag([-0.3, 0.1, 0.0]), planar=True))


def test_the_density_bound_is_the_uniform_ellipsoids_density():
    """A uniform ellipsoid (semi-axes 0.3, 0.2, 0.1 m, 7850 kg/m³, rotated) is its own bound, to 1e-12; a uniform
    box of the same density is above it (ρ / ((4/3)π (5/12)^1.5) = 0.89 ρ for any box) and above the ball's looser
    bound (equal only for an isotropic Σ)."""
    rotation = Rotation.from_euler("xyz", [0.4, -0.9, 1.3]).as_matrix()
    a, rho = np.array([0.3, 0.2, 0.1]), 7850.0
    mass = rho * 4 / 3 * np.pi * a.prod()
    second = mass / 5 * a**2  # ∫ x_k² dm
    ellipsoid = rotation @ np.diag(second.sum() - second) @ rotation.T
    assert density_bound(mass, ellipsoid) == pytest.approx(rho, rel=1e-12)
    sides = 2 * a
    box_mass = rho * sides.prod()
    box = box_mass / 12 * np.diag(sides @ sides - sides**2)
    bound = density_bound(box_mass, rotation @ box @ rotation.T)
    assert bound == pytest.approx(rho / (4 / 3 * np.pi * (5 / 12) ** 1.5), rel=1e-12) and bound < rho
    assert bound > 1.5 * ball_bound(box_mass, np.trace(box))


def test_a_mislabelled_body_is_named():
    """m labelled mm: 10⁹× too dense; mm labelled m: lighter than air; (m/s²)/N labelled g/N: the bracket's inertia
    ellipsoid 9.81× light, below any solid's but a thin shell's; g/N labelled (m/s²)/N: 7 070 kg/m³, a steel
    body's, which only the mesh (9.81× its mass) can call wrong."""
    mesh = bundled("bracket")
    body, points = mesh.nominal, mesh.mesh.vertices
    small = type(body)(body.mass, body.cog * 1e-3, body.inertia_cog * 1e-6)
    large = type(body)(body.mass, body.cog * 1e3, body.inertia_cog * 1e6)
    assert codes_of(units_warnings(small, points * 1e-3)) == {"denser_than_any_material"}
    assert codes_of(units_warnings(large, points * 1e3)) == {"lighter_than_air"}
    heavy = type(body)(body.mass * G, body.cog, body.inertia_cog * G)
    light = type(body)(body.mass / G, body.cog, body.inertia_cog / G)
    assert units_warnings(heavy, points) == []
    assert codes_of(units_warnings(light, points)) == {"light_for_extent"}
    [warning] = nominal_warnings(heavy, body)
    assert warning.code == "heavy_for_extent" and "9.81× heavy" in warning.text and "unit labels" in warning.text


def support_frf(frequencies: np.ndarray, resonance: float, loss: float) -> np.ndarray:
    """A (1, 1, n) accelerance: the massline 1 on a spring of ``loss`` factor, ``resonance`` Hz."""
    w2, k = (2 * np.pi * frequencies) ** 2, (2 * np.pi * resonance) ** 2 * (1 + 1j * loss)
    return (-w2 / (k - w2))[None, None, :]


def test_a_resonance_within_a_few_lines_of_zero_means_a_short_record():
    band = Band(20.0, 200.0, 5.0, np.nan, "chosen")
    coarse = np.arange(1, 401) * 2.0  # Δf 2 Hz: a 2.5 Hz mode is one line up
    [warning] = short_record_warnings(coarse, support_frf(coarse, 2.5, 0.6), band, windowed=True)
    assert warning.code == "short_record"
    assert "1 line(s) up the axis" in warning.text and "more lines, or a lower fmax" in warning.text
    fine = np.arange(1, 4001) * 0.1
    assert short_record_warnings(fine, support_frf(fine, 2.5, 0.04), band, windowed=True) == []


def test_coherence_falling_at_the_edge_or_the_band_top_is_a_force_roll_off():
    f = np.arange(1, 2001) * 0.5
    band = Band(20.0, 200.0, 5.0, 600.0, "chosen")
    flat = np.full((2, 2, len(f)), 0.9999)
    assert rolloff_warnings(f, flat, band, windowed=True) == []
    falling = 1 - 1e-4 * (1 + (f / 100.0) ** 6)  # G_ff ∝ 1/(1 + (f/100)⁶): 1 − γ² ∝ 1/G_ff
    [warning] = rolloff_warnings(f, np.broadcast_to(falling, flat.shape), band, windowed=True)
    assert (
        warning.code == "force_roll_off" and "the force spectrum rolls off" in warning.text and "600 Hz" in warning.text
    )


def test_a_given_band_across_a_resonance_is_named():
    free = Band(5.0, 900.0, 5.0, 900.0, "stretch")
    assert given_band_warnings(Band(20.0, 200.0, rule="given"), free) == []
    low, high = given_band_warnings(Band(1.0, 2500.0, rule="given"), free)
    assert (low.code, high.code) == ("given_band_near_support", "given_band_near_elastic")
    assert "starts at 1 Hz" in low.text and "ends at 2.5e+03" in high.text


# --- the flawed recordings ---------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def bracket(bracket_plan):  # noqa: F811
    """Body, sensors, exciters, FE modes and the cord 2 cm above the CoG (support modes 0.5–2.8 Hz)."""
    mesh = bundled("bracket")
    body = mesh.nominal
    sensors, exciters, _ = read_plan(bracket_plan)
    modes = session_cache.fe_modes(mesh.mesh, Material(70e9, 0.33, mesh.density), 6)
    cord = Suspension(cords=(Cord(body.cog + [0, 0, 0.02], body.mass * 9.81 / 0.25, 1.0),))
    return body, sensors, exciters, modes, cord


def from_file(folder, recording, units="MM", acceleration="g", band=None):
    """Write ``recording`` as an exporter would (geometry ``units``, accelerance in ``acceleration``), read it
    back and identify it with identify's defaults (``band`` only where the case is a given band)."""
    path = folder / "flawed.uff"
    write_uff(path, recording, units=units, acceleration=acceleration, force=True)
    return identify_recording(to_recording(read_uff(path)), band, draws=30)


def errors(found, body) -> dict:
    """|error|/σ of the mass, the worst CoG coordinate and the worst principal moment."""
    b, s = found.body, found.std
    return {
        "mass": abs(b.mass - body.mass) / s["mass"],
        "cog": np.max(np.abs(b.cog - body.cog) / s["cog"]),
        "moments": np.max(np.abs(b.principal_moments - body.principal_moments) / s["principal_moments"]),
    }


def assert_never_silently_wrong(found, body, codes=()):
    """Each of ``codes`` (the warnings that blame the flaw) among the warnings, and within 2σ unless one is."""
    warned = codes_of(found.warnings)
    assert set(codes) <= warned, (codes, found.warnings)
    z = errors(found, body)
    assert max(z.values()) < 2 or warned & set(codes), f"silently wrong: {z}, {found.warnings}"


@pytest.fixture(scope="module")
def cord_test(bracket):
    """The clean direct-route recording on the cord, rigid body to 200 Hz (2000 lines)."""
    body, sensors, exciters, _, cord = bracket
    return run(body, sensors, exciters, None, cord, TRANSVERSE, Acquisition(200.0, 2000), 0)[0]


@pytest.fixture(scope="module")
def elastic_test(bracket):
    """The clean direct-route recording with the FE modes, to 1.5 × the first elastic mode (2000 lines)."""
    body, sensors, exciters, modes, cord = bracket
    setup = Acquisition(1.5 * modes.frequencies_hz[0], 2000)
    return run(body, sensors, exciters, modes, cord, TRANSVERSE, setup, 0)[0]


def test_the_clean_recording_is_right_and_quiet(bracket, cord_test, tmp_path):
    found = from_file(tmp_path, cord_test)
    assert max(errors(found, bracket[0]).values()) < 2.5 and found.warnings == ()


def test_short_record(bracket, tmp_path):
    """An impact test of 400 lines to 800 Hz: Δf 2 Hz, the 0.5–2.8 Hz support modes unresolved and broadened by
    the window (the lab's rule wants 25 600 lines)."""
    body, sensors, exciters, _, cord = bracket
    setup = Acquisition(800.0, 400, impact=ImpactTest(response_noise=0.01))
    recording, truth = run(body, sensors, exciters, None, cord, TRANSVERSE, setup, 0)
    assert truth["fmax_hz"] == 800.0
    assert_never_silently_wrong(from_file(tmp_path, recording), body, ["short_record"])


@pytest.mark.parametrize(
    "band, code", [((1.0, 200.0), "given_band_near_support"), ((100.0, 2500.0), "given_band_near_elastic")]
)
def test_band_across_a_resonance(bracket, elastic_test, tmp_path, band, code):
    """--band across the support modes (1–200 Hz) or across the first elastic mode (2.0 kHz): a result the warning
    blames, or a refusal (no physical body fits) that says what is wrong with the band."""
    try:
        found = from_file(tmp_path, elastic_test, band=band)
    except MasslineError as refused:
        assert "the given band" in str(refused) and "Hz" in str(refused), refused
        return
    assert_never_silently_wrong(found, bracket[0], [code])


@pytest.mark.parametrize("effect", ["sensor_polarity@3", "channel_swap@2,5"])
def test_instrumentation_fault(bracket, tmp_path, effect):
    """A flipped or swapped channel: a result that warns of the misfit, or a refusal (no rigid body fits the
    masslines: the swap on channels 2 and 5) that names the likely fault and sends the user to diagnose."""
    body, sensors, exciters, _, cord = bracket
    faults = (*TRANSVERSE, parse_effect(effect))
    recording = run(body, sensors, exciters, None, cord, faults, Acquisition(200.0, 2000), 0)[0]
    try:
        found = from_file(tmp_path, recording)
    except MasslineError as refused:
        assert "swapped channel" in str(refused) and "massline diagnose" in str(refused), refused
        return
    assert_never_silently_wrong(found, body, ["model_misfit"])


@pytest.mark.parametrize(
    "scale, units, code", [(1e3, "SI", "lighter_than_air"), (1e-3, "MM", "denser_than_any_material")]
)
def test_geometry_unit_label(bracket, cord_test, tmp_path, scale, units, code):
    """Coordinates in mm labelled m (1000× too large) and in m labelled mm (1000× too small)."""
    relabel = {
        name: replace(lines, points=lines.points * scale)
        for name, lines in (("sensors", cord_test.sensors), ("exciters", cord_test.exciters))
    }
    found = from_file(tmp_path, replace(cord_test, **relabel), units=units)
    assert_never_silently_wrong(found, bracket[0], [code])
    assert all("unit labels" in w.text for w in found.warnings if w.code == code)


@pytest.mark.parametrize(
    "factor, acceleration, alone, code",
    [(G, "g", {"light_for_extent"}, "light_for_extent"), (1 / G, "length", set(), "heavy_for_extent")],
)
def test_acceleration_unit_label(bracket, cord_test, tmp_path, factor, acceleration, alone, code):
    """(m/s²)/N labelled g/N (9.81× light) and g/N labelled (m/s²)/N (9.81× heavy): χ² and J/m cannot see it. From
    the file alone the light bracket's inertia ellipsoid is below any solid's; the heavy one is a steel body's
    (7 070 kg/m³), which only the mesh can call wrong: --mesh names both."""
    body = bracket[0]
    found = from_file(tmp_path, replace(cord_test, frf=cord_test.frf * factor), acceleration=acceleration)
    assert found.body.mass == pytest.approx(body.mass * (G if factor < 1 else 1 / G), rel=0.01)
    assert codes_of(found.warnings) & {"heavy_for_extent", "light_for_extent"} == alone
    assert_never_silently_wrong(against_nominal(found, body), body, [code])


@pytest.mark.parametrize("seed", [0, 1])
def test_stiff_support(bracket, tmp_path, seed):
    """A short stiff cord: its bounce at ~f1/10 (200 Hz for f1 = 2.0 kHz), the pendulum modes near 1 Hz."""
    body, sensors, exciters, modes, _ = bracket
    f1 = modes.frequencies_hz[0]
    stiff = Suspension(cords=(Cord(body.cog + [0, 0, 0.02], body.mass * (2 * np.pi * f1 / 10) ** 2, 0.3),))
    setup = Acquisition(1.5 * f1, 2000)
    recording, truth = run(body, sensors, exciters, modes, stiff, TRANSVERSE, setup, seed)
    assert 0.08 < max(truth["suspension"]["modes_hz"]) / f1 < 0.12
    assert_never_silently_wrong(from_file(tmp_path, recording), body, ["tail_truncation"])


def test_soft_hammer_tip(bracket, tmp_path):
    """An 8 ms pulse (spectrum −3 dB at 74 Hz, first zero at 188 Hz) on a 16 s record to 400 Hz."""
    body, sensors, exciters, _, cord = bracket
    setup = Acquisition(400.0, 6400, impact=ImpactTest(pulse=0.008, response_noise=0.01))
    recording = run(body, sensors, exciters, None, cord, TRANSVERSE, setup, 0)[0]
    assert_never_silently_wrong(from_file(tmp_path, recording), body, ["force_roll_off"])
