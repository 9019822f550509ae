"""``massline simulate``: plan → virtual test → UFF that identifies the body (end to end)."""

import json

import numpy as np
import pytest
import pyuff
from conftest import bundled
from test_cli import massline

from massline.identify.massline_fit import fit_band
from massline.placement.masslines import Masslines
from massline.placement.methods import identify
from massline.uff.reader import read_uff, to_recording

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def planned(tmp_path_factory):
    folder = tmp_path_factory.mktemp("plan")
    run = massline("plan", "structure", "--out", folder)
    assert run.returncode == 0, run.stderr
    return folder / "plan.json"


@pytest.fixture(scope="module")
def simulated(planned, tmp_path_factory):
    out = tmp_path_factory.mktemp("sim") / "test.uff"
    cord = "cord:at=0.0444;0.0537;0.06"  # 2 cm above the CoG, on an inner member (Appendix A's advice)
    run = massline(
        "simulate", planned, "--out", out, "--seed", "3", "--fmax", "400", "--lines", "4000", "--suspension", cord
    )
    assert run.returncode == 0, run.stderr
    assert "FE model:" in run.stdout and "massline band" in run.stdout
    return out


def test_pyuff_reads_back_what_was_written(simulated):
    truth = json.loads(simulated.with_suffix(".truth.json").read_text())
    sets = pyuff.UFF(str(simulated)).read_sets()
    frfs = [s for s in sets if s["type"] == 58 and s["func_type"] == 4]
    assert len(frfs) == 18 and {s["type"] for s in sets} >= {15, 164, 58}
    ours = to_recording(read_uff(simulated))
    for s in frfs:
        assert len(s["data"]) == 4000 and np.isfinite(s["data"]).all()
    assert ours.frf.shape == (6, 3, 4000)
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
    run = massline("simulate", planned, "--check" if "--out" not in words else "--rigid", *args)
    assert run.returncode == 2 and words in run.stderr and "Traceback" not in run.stderr


def test_nothing_is_overwritten(planned, tmp_path):
    out = tmp_path / "t.uff"
    out.write_text("precious")
    run = massline("simulate", planned, "--out", out, "--rigid")
    assert run.returncode == 2 and "--force" in run.stderr and out.read_text() == "precious"
