"""One band story: the plan chooses the support and predicts its band by one per-FRF rule; simulate hangs the
body on it; the demo, the placement report and ``simulate --check`` print that band; identify's band holds it."""

import html
import json
import re

import numpy as np
import pytest
import session_cache
from conftest import bundled
from test_cli import massline

from massline.identify.pipeline import identify_recording
from massline.meshes import BUNDLED
from massline.core.band import Band, frf_scales, held_band, stray
from massline.core.masslines import synthesise
from massline.placement.on_surface import plan
from massline.core.band import band_from_dict, band_to_dict
from massline.virtual.planned_test import FEModel, plan_test, planned_suspension
from massline.uff.grid import to_recording
from massline.uff.reader import read_uff
from massline.virtual.elastic import Material
from massline.virtual.suspended import SuspendedBody
from massline.virtual.suspension import Suspension, rigid_suspension_modes, single_cord
from massline.virtual.tetmesh import default_size, size_for_dofs

SPAN = re.compile(r"([\d.]+)\s*[–-]\s*([\d.]+)")


def test_held_band_is_the_widest_run_where_every_frf_holds():
    f = np.geomspace(1, 1000, 301)
    A = np.array([[1.0, 0.01]])
    frf = np.broadcast_to(A[:, :, None], (1, 2, len(f))).astype(complex).copy()
    frf[0, 1] += 0.1 * 0.03 * ((f / 100) ** 2 + (5 / f) ** 2)  # the weak FRF strays most against √(1 · 0.01)
    low, high = held_band(f, stray(frf, A), 0.03)
    assert 5 < low < 8 and 60 < high < 100  # (5/f)² + (f/100)² ≤ 1
    assert np.isnan(held_band(f, stray(frf, A), 1e-6)[0])


def test_a_weak_frf_is_judged_on_its_sensors_and_hits_level():
    """s_ij = √(a_i b_j): a near-zero massline between a strong sensor and a strong hit is held to their level;
    the strongest FRF of its row and column, to itself."""
    A = np.array([[1.0, 1e-3], [0.5, 2.0]])
    assert np.allclose(frf_scales(A), [[1.0, np.sqrt(2.0)], [np.sqrt(2.0), 2.0]])
    frf = A[:, :, None] + np.array([[0.0, 0.02], [0.0, 0.0]])[:, :, None]  # 20× its own massline off
    assert np.isclose(stray(frf, A)[0], 0.02 / np.sqrt(2.0))


def test_the_support_and_band_round_trip_through_plan_json(structure):
    cord = single_cord(structure, 150.0, 1.0, 0.02)
    again = Suspension.from_dict(json.loads(json.dumps(cord.as_dict())))
    assert np.allclose(again.stiffness_matrix(structure), cord.stiffness_matrix(structure))
    band = Band(15.8, 51.6, 1.4, 819.0, "predicted", 0.05)
    assert band_from_dict(json.loads(json.dumps(band_to_dict(band)))) == band
    assert planned_suspension({"sensors": []}) is None and band_from_dict(None) is None  # an older plan


@pytest.mark.slow
@pytest.mark.parametrize("name", list(BUNDLED))
def test_no_frf_strays_beyond_the_tolerance_inside_the_planned_band(name):
    """On each bundled body's default plan, every FRF on a fine axis across the planned band stays within the
    band's tolerance of its massline (coarse FE modes, as the report of an older plan uses)."""
    body = bundled(name)
    planned = plan(body)
    material = Material(BUNDLED[name].youngs, BUNDLED[name].poisson, body.density)
    size = max(default_size(body.mesh), size_for_dofs(body.mesh, 8000))
    modes = session_cache.fe_modes(body.mesh, material, 20, size)
    test, _ = plan_test(body, name, planned.sensors, planned.exciters, None, FEModel(modes, material))
    band = band_from_dict(test["band"])
    assert band.exists and band.ratio >= 1.5 and band.tolerance <= 0.05
    model = SuspendedBody(body.nominal, modes, Suspension.from_dict(test["suspension"]))
    f = np.geomspace(band.low, band.high, 400)
    S, E = planned.sensors, planned.exciters
    H = model.accelerance(f, S.points, S.directions, E.points, E.directions)
    worst = stray(H, synthesise(body.nominal, S, E).values).max()
    print(f"{name}: {test['suspension']['description']}, band {band.low:.1f}-{band.high:.1f} Hz, worst {worst:.4f}")
    assert worst <= band.tolerance * (1 + 1e-9)


@pytest.fixture(scope="module")
def demo():
    """``massline demo``'s folder and console, run once this session (shared with the demo's own tests)."""
    folder = session_cache.command("demo")
    return folder / "out", (folder / "stdout.txt").read_text()


def printed(text: str) -> tuple[str, str]:
    """The first 'LOW–HIGH' pair of a text, as printed."""
    return SPAN.search(text).groups()


@pytest.mark.slow
def test_the_demo_report_and_check_print_the_plans_band(demo):
    out, stdout = demo
    doc = json.loads((out / "plan.json").read_text())
    band = band_from_dict(doc["band"])
    shown = (f"{band.low:.1f}", f"{band.high:.1f}")
    assert printed(stdout.split("planned band")[1]) == shown
    truth = json.loads((out / "truth.json").read_text())
    assert (f"{truth['planned_band_hz'][0]:.1f}", f"{truth['planned_band_hz'][1]:.1f}") == shown
    page = re.sub(r"<[^>]+>", " ", (out / "placement-report.html").read_text())
    assert printed(page.split("planned:")[1]) == shown
    check = massline("simulate", out / "plan.json", "--check")
    assert check.returncode == 0, check.stderr
    assert printed(check.stdout.split("planned:")[1].split("│", 1)[1]) == shown


@pytest.mark.slow
def test_identify_finds_a_band_holding_the_planned_one_noisy_and_noiseless(demo, tmp_path):
    """identify's band is wider above (it fits the tails) and the demo says, in numbers and words, whether it
    contains the planned band. identify's choice weighs the tails' bias against the noise and may start above the
    planned band's low edge: on the demo's noisy file and on a noiseless one (the demo's plan simulated without
    noise, on the plan's support) it still covers most of the planned band (≥ 75 % in log frequency; measured on
    the noisy file 77 %: 17.4–218.3 Hz against the planned 11.8–65.4 Hz of the structure's 9 × 5 plan)."""
    out, stdout = demo
    doc = json.loads((out / "plan.json").read_text())
    band = band_from_dict(doc["band"])
    clean = tmp_path / "clean.uff"
    fmax = json.loads((out / "truth.json").read_text())["fmax_hz"]
    run = massline("simulate", out / "plan.json", "--out", clean, "--noise", "0", "--fmax", fmax)
    assert run.returncode == 0, run.stderr
    noisy, noiseless = (identify_recording(to_recording(read_uff(p)), draws=0).band for p in (out / "test.uff", clean))
    holds = noisy.low <= band.low and noisy.high >= band.high
    said = " ".join(stdout.split())
    assert ("it contains the planned" if holds else "it does not contain the planned") in said and "fits the tails" in said
    for found in (noisy, noiseless):
        shared = np.log(min(found.high, band.high) / max(found.low, band.low)) / np.log(band.ratio)
        assert shared >= 0.75 and found.high > band.high, (found, band)


@pytest.mark.slow
def test_simulate_without_suspension_hangs_the_body_on_the_plans_support(demo, tmp_path):
    out, _ = demo
    doc = json.loads((out / "plan.json").read_text())
    run = massline("simulate", out / "plan.json", "--out", tmp_path / "t.uff", "--rigid", "--noise", "0")
    assert run.returncode == 0, run.stderr
    truth = json.loads((tmp_path / "t.uff").with_suffix(".truth.json").read_text())
    assert truth["suspension"]["cords"] == doc["suspension"]["cords"]
    support = planned_suspension(doc)
    expected = rigid_suspension_modes(bundled("structure").nominal, support)[0]
    assert np.allclose(truth["suspension"]["modes_hz"], expected, rtol=1e-6, atol=1e-6)
    given = massline("simulate", out / "plan.json", "--check", "--rigid", "--suspension", "foam")
    assert "planned: foam" in given.stdout and "departs from it (--suspension, --rigid)" in given.stdout


@pytest.mark.slow
def test_the_demo_says_on_its_console_every_warning_its_reports_list(demo):
    """What the identification and diagnosis reports warn about, the demo's console said."""
    out, stdout = demo
    said = " ".join(stdout.split())
    for report in ("identification-report.html", "diagnosis-report.html"):
        page = html.unescape(re.sub(r"<[^>]+>", "|", (out / report).read_text()))
        if "Warnings|" not in page:
            continue
        listed = [w for w in re.split(r"\|+", page.split("Warnings|", 1)[1].split("||")[0]) if w.strip()]
        for warning in listed:
            assert " ".join(warning.split())[:60] in said, (report, warning)


@pytest.mark.slow
def test_the_demo_report_prints_the_band_the_console_does(demo):
    """The diagnosis report's band is identify's band edges as the console prints them, not its first line."""
    out, stdout = demo
    said = printed(" ".join(stdout.split()).split("identify chose the band")[1])
    page = re.sub(r"<[^>]+>", " ", (out / "diagnosis-report.html").read_text())
    assert printed(page.split("diagnosis band")[1]) == said
