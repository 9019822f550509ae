"""``massline simulate``: plan → virtual test → UFF that identifies the body (end to end)."""

import json
import re
from pathlib import Path

import numpy as np
import pytest
import session_cache
import pyuff
from conftest import bundled
from test_cli import cli, massline

from massline.identify.massline_fit import fit_band
from massline.core.masslines import Masslines
from massline.core.methods import identify
from massline.uff.grid import to_recording
from massline.uff.reader import read_uff

pytestmark = pytest.mark.slow


def default_plan(body: str, tmp_path_factory):
    """``massline plan BODY`` with its defaults, run once this session; the path of its plan.json."""
    return session_cache.plan(body)


@pytest.fixture(scope="module")
def planned(tmp_path_factory):
    return default_plan("structure", tmp_path_factory)


@pytest.fixture(scope="module")
def simulated(planned, tmp_path_factory):
    out = tmp_path_factory.mktemp("sim") / "test.uff"
    cord = "cord:at=0.0444;0.0537;0.06"  # 2 cm above the CoG, on an inner member (Appendix A's advice)
    run = massline(
        "simulate", planned, "--out", out, "--seed", "3", "--fmax", "400", "--lines", "4000", "--suspension", cord,
        "--ideal",  # the file's masslines against the body's to 0.2 %: no chain's calibration drawn
    )
    assert run.returncode == 0, run.stderr
    assert "FE model:" in run.stdout and "massline band" in run.stdout
    return out


def shape(plan: Path) -> tuple[int, int]:
    """Sensor lines × hits of a plan.json."""
    doc = json.loads(plan.read_text())
    return len(doc["sensors"]), len(doc["exciters"])


def test_pyuff_reads_back_what_was_written(planned, simulated):
    truth = json.loads(simulated.with_suffix(".truth.json").read_text())
    sets = pyuff.UFF(str(simulated)).read_sets()
    frfs = [s for s in sets if s["type"] == 58 and s["func_type"] == 4]
    n_s, n_e = shape(planned)
    assert len(frfs) == n_s * n_e and {s["type"] for s in sets} >= {15, 164, 58}
    ours = to_recording(read_uff(simulated))
    for s in frfs:
        assert len(s["data"]) == 4001 and np.isfinite(s["data"]).all()  # 4000 lines + DC
    assert ours.frf.shape == (n_s, n_e, 4001)
    assert truth["fe"]["dofs"] > 10_000


def test_band_averaged_masslines_identify_the_mass(simulated):
    truth = json.loads(simulated.with_suffix(".truth.json").read_text())
    rec = to_recording(read_uff(simulated))
    low, high = truth["band_hz"]
    keep = (rec.frequencies >= low) & (rec.frequencies <= high)
    mass = bundled("structure").nominal.mass
    averaged = identify(Masslines(rec.frf[:, :, keep].real.mean(axis=2), rec.sensors, rec.exciters))
    assert averaged.mass == pytest.approx(mass, rel=0.005)
    fitted = fit_band(rec.frequencies, rec.frf, low / 2, 3 * high)
    assert identify(Masslines(fitted.values, rec.sensors, rec.exciters)).mass == pytest.approx(mass, rel=0.002)


def test_truth_holds_the_concealed_effect(planned, tmp_path):
    out = tmp_path / "t.uff"
    run = massline("simulate", planned, "--out", out, "--rigid", "--effect", "sensor_polarity@2", "--binary")
    assert run.returncode == 0, run.stderr
    truth = json.loads(out.with_suffix(".truth.json").read_text())
    assert truth["effects"] == [{"effect": "sensor_polarity", "size": 0.0, "lines": [2]}]
    assert truth["elastic_hz"] == []


def test_split_runs_write_one_file_per_exciter_that_identify_reads_together(planned, tmp_path):
    """--split-runs: FILE.run1.uff … one per hit, every node in each; refused whole when one exists; identify on
    the files (or their folder) gives the file's body."""
    out = tmp_path / "runs" / "t.uff"
    out.parent.mkdir()
    run = massline("simulate", planned, "--out", out, "--rigid", "--split-runs", "--seed", "2")
    assert run.returncode == 0, run.stderr
    n_s, n_e = shape(planned)
    files = sorted(out.parent.glob("t.run*.uff"))
    assert [f.name for f in files] == [f"t.run{j + 1}.uff" for j in range(n_e)] and "one file per exciter" in run.stdout
    for f in files:
        contents = read_uff(f)
        assert len(contents.frfs) == n_s and len({frf.reference for frf in contents.frfs}) == 1
    again = massline("simulate", planned, "--out", out, "--rigid", "--split-runs")
    assert again.returncode == 2 and "t.run1.uff" in again.stderr and "--force" in again.stderr
    whole = tmp_path / "whole.uff"
    assert massline("simulate", planned, "--out", whole, "--rigid", "--seed", "2").returncode == 0
    found = [tmp_path / f"{name}.json" for name in ("runs", "whole")]
    for given, json_out in ((out.parent, found[0]), (whole, found[1])):
        result = massline("identify", given, "--json", json_out, "--bootstrap", "0")
        assert result.returncode == 0, result.stderr
    runs, one = (json.loads(f.read_text()) for f in found)
    assert runs["mass"] == pytest.approx(one["mass"], rel=1e-9) and len(runs["runs"]) == n_e


def test_check_predicts_the_band_and_plots_it(planned, tmp_path):
    png = tmp_path / "band.png"
    run = massline("simulate", planned, "--check", "--rigid", "--suspension", "cord:k=2000,L=0.3", "--plot", png)
    assert run.returncode == 0, run.stderr
    assert "recommended" in run.stdout and png.read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize(
    "args,words",
    [
        (("--effect", "wobble=2"), "unknown effect"),
        (("--effect", "sensor_gain=0.1@40"), "no sensor 40"),
        (("--suspension", "rope"), "unknown suspension"),
        (("--suspension", "cord:k=soft"), "numbers are needed"),
        (("--material", "cheese"), "--material"),
        ((), "--out"),
    ],
)
def test_bad_options_are_named(planned, args, words):
    run = cli("simulate", planned, "--check" if "--out" not in words else "--rigid", *args)
    assert run.returncode == 2 and words in run.stderr and "Traceback" not in run.stderr


def test_nothing_is_overwritten(planned, tmp_path):
    out = tmp_path / "t.uff"
    out.write_text("precious")
    run = massline("simulate", planned, "--out", out, "--rigid")
    assert run.returncode == 2 and "--force" in run.stderr and out.read_text() == "precious"


def test_the_file_is_what_a_lab_exports_and_identify_sets_its_dc_line_aside(planned, tmp_path):
    """Default: lines + DC (a real outlier, low coherence), coherence records, mm geometry, accelerance in g/N.
    The same test written in inches with (in/s²)/lbf, nodes in 2411 and no DC line reads back the same."""
    lab, plain = tmp_path / "lab.uff", tmp_path / "plain.uff"
    assert massline("simulate", planned, "--out", lab, "--rigid", "--ideal").returncode == 0
    options = ("--units", "in", "--acceleration", "length", "--nodes", "2411", "--no-dc", "--ideal")
    run = massline("simulate", planned, "--out", plain, "--rigid", *options)
    assert run.returncode == 0, run.stderr
    assert "geometry in in, accelerance in (in/s²)/lbf" in " ".join(run.stdout.split())
    sets = pyuff.UFF(str(lab)).read_sets()
    assert sets[1]["units_code"] == 5 and {s["type"] for s in sets} >= {15, 58}
    frfs = [s for s in sets if s["type"] == 58 and s["func_type"] == 4]
    n = np.prod(shape(planned))
    assert len(frfs) == n and sum(s["type"] == 58 and s["func_type"] == 6 for s in sets) == n
    assert (frfs[0]["ordinate_axis_units_lab"], frfs[0]["orddenom_axis_units_lab"]) == ("g", "N")
    assert frfs[0]["x"][0] == 0.0 and all(s["data"][0].imag == 0 for s in frfs)
    found, other = to_recording(read_uff(lab)), to_recording(read_uff(plain))
    assert found.frequencies[0] == 0 and found.coherence[:, :, 0].max() < 0.5
    assert found.coherence[:, :, 1:].min() > 0.99  # 1 % noise: γ² = 1/(1 + 0.01²)
    assert other.frequencies[0] > 0 and {15, 2411} & set(read_uff(plain).datasets) == {2411}
    np.testing.assert_allclose(other.frf, found.above_zero().frf, rtol=1e-10)
    np.testing.assert_allclose(found.sensors.points, other.sensors.points, rtol=5e-6)  # dataset 15: 6 digits
    out = tmp_path / "id.json"
    identified = massline("identify", lab, "--json", out, "--bootstrap", "0")
    assert identified.returncode == 0, identified.stderr
    assert "0 Hz line set aside" in identified.stdout
    assert json.loads(out.read_text())["mass"] == pytest.approx(bundled("structure").nominal.mass, rel=0.005)


@pytest.mark.parametrize(
    "args, words",
    [
        (("--impact", "0.5", "--fmax", "3000", "--lines", "2000"), "warning: a record of 0.667 s"),
        (("--impact", "8"), "warning: a 8 ms pulse's spectrum falls"),
    ],
)
def test_a_truncating_setting_is_kept_with_a_warning(planned, tmp_path, args, words):
    out = tmp_path / "t.uff"
    run = massline("simulate", planned, "--out", out, "--rigid", *args)
    assert run.returncode == 0, run.stderr
    [line] = [line for line in run.stdout.splitlines() if line.startswith("warning:")]
    assert line.startswith(words) and "choose --" in line
    assert json.loads(out.with_suffix(".truth.json").read_text())["warnings"] == [line.removeprefix("warning: ")]


@pytest.mark.long  # the analyser's default record for the pendulum modes, 51,200 lines: the long tier
def test_default_impact_test_of_the_bracket_identifies_its_mass(bracket_default_plan, tmp_path):
    """An analyser set up as a lab would: a record long enough for the pendulum modes, fmax a few times the
    band's top; identify given the predicted band the console printed recovers the mass."""
    out = tmp_path / "impact.uff"
    run = massline("simulate", bracket_default_plan, "--impact", "--out", out)
    assert run.returncode == 0, run.stderr
    assert "warning" not in run.stdout
    truth = json.loads(out.with_suffix(".truth.json").read_text())
    support = [f for f in truth["suspension"]["modes_hz"] if f > 0.01]
    low, high = re.search(r"planned: .*?([\d.]+) – ([\d.]+)", run.stdout).groups()
    assert float(high) == pytest.approx(truth["band_hz"][1], abs=0.05)
    assert truth["record_s"] >= np.log(100) / (0.05 * 2 * np.pi * min(support))  # window adds ≤ 5 % damping
    assert truth["lines"] in [400 * 2**k for k in range(8)] and 3 <= truth["fmax_hz"] / truth["band_hz"][1] < 4
    result = massline("identify", out, "--band", low, high, "--json", tmp_path / "id.json", "--bootstrap", "0")
    assert result.returncode == 0, result.stderr
    mass = json.loads((tmp_path / "id.json").read_text())["mass"]
    assert mass == pytest.approx(bundled("bracket").nominal.mass, rel=0.005)
