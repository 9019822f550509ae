"""The command line: tables, JSON contract, exit codes, nothing overwritten."""

import json
import subprocess
import sys

import numpy as np
import pytest
from conftest import FIXTURE_MESHES, bundled


def massline(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "massline", *map(str, args)], capture_output=True, text=True, cwd=cwd)


def test_props_prints_a_table_with_units():
    run = massline("props", "structure")
    assert run.returncode == 0, run.stderr
    assert "kg·m²" in run.stdout and "mm" in run.stdout and "principal moment 3" in run.stdout


def test_props_json_has_identify_keys(tmp_path):
    out = tmp_path / "props.json"
    run = massline("props", FIXTURE_MESHES / "featuretype.STL", "--units", "in", "--density", "2700", "--json", out)
    assert run.returncode == 0, run.stderr
    data = json.loads(out.read_text())
    assert {"mass", "cog", "inertia_cog", "principal_moments", "principal_axes", "std", "band_hz", "planar"} <= set(
        data
    )
    J = np.array(data["inertia_cog"])
    axes = np.array(data["principal_axes"])
    np.testing.assert_allclose(axes @ np.diag(data["principal_moments"]) @ axes.T, J, atol=1e-12)


def test_props_json_matches_the_bundled_body(tmp_path):
    out = tmp_path / "p.json"
    assert massline("props", "plate", "--json", out).returncode == 0
    data = json.loads(out.read_text())
    assert data["mass"] == pytest.approx(bundled("plate").nominal.mass, rel=1e-12)


def test_output_is_never_overwritten_without_force(tmp_path):
    out = tmp_path / "p.json"
    out.write_text("precious")
    run = massline("props", "plate", "--json", out)
    assert run.returncode == 2 and "--force" in run.stderr
    assert out.read_text() == "precious"
    assert massline("props", "plate", "--json", out, "--force").returncode == 0
    assert json.loads(out.read_text())["planar"] is False
    assert not list(tmp_path.glob(".*tmp"))


@pytest.mark.parametrize(
    "args,words",
    [
        (("props", FIXTURE_MESHES / "soup.stl", "--units", "m", "--density", "1000"), "triangle soup"),
        (("props", FIXTURE_MESHES / "plate_holes.STL", "--units", "m", "--density", "2700"), "looks like mm"),
        (("props", FIXTURE_MESHES / "plate_holes.STL", "--density", "2700"), "--units"),
        (("props", "nothing.stl", "--units", "m", "--density", "2700"), "does not exist"),
        (("props", "plate", "--density", "2.7"), "g/cm³"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(args, words):
    run = massline(*args)
    assert run.returncode == 2
    assert words in run.stderr
    assert len(run.stderr.strip().splitlines()) == 1 and "Traceback" not in run.stderr


def test_demo_refuses_to_overwrite_an_earlier_demo(tmp_path):
    (tmp_path / "plan.json").write_text("precious")
    run = massline("demo", "--out", tmp_path)
    assert run.returncode == 2 and "--force" in run.stderr and len(run.stderr.strip().splitlines()) == 1
    assert (tmp_path / "plan.json").read_text() == "precious" and len(list(tmp_path.iterdir())) == 1


def test_plan_writes_plan_json(tmp_path):
    out = tmp_path / "plan"
    run = massline("plan", "structure", "--out", out)
    assert run.returncode == 0, run.stderr
    assert "certified" in run.stdout and "Hammer hits" in run.stdout
    doc = json.loads((out / "plan.json").read_text())
    assert {"mesh", "units", "nominal", "sensors", "exciters", "criterion", "predicted_std"} <= set(doc)
    assert len(doc["sensors"]) == 6 and len(doc["exciters"]) == 3
    assert set(doc["sensors"][0]) == {"node", "point", "direction", "triaxial"}
    assert {"log_det", "condition_numbers", "d_efficiency_lower_bound"} <= set(doc["criterion"])
    assert doc["criterion"]["d_efficiency_lower_bound"] >= 0.95
    assert {"mass", "cog", "inertia_cog", "principal_moments", "principal_axes"} <= set(doc["predicted_std"])
    again = massline("plan", "structure", "--out", out)
    assert again.returncode == 2 and "--force" in again.stderr


def test_plan_reads_back(tmp_path):
    from massline.placement.plan_file import read_plan

    assert massline("plan", "plate", "--out", tmp_path, "--sensors", "4").returncode == 0
    sensors, exciters, doc = read_plan(tmp_path / "plan.json")
    assert len(sensors) == 4 and len(exciters) == 3 and doc["planar"] is True
    assert doc["predicted_std"]["cog"][2] is None  # unobservable for a plate


def test_plan_on_a_real_cad_part_in_inches(tmp_path):
    run = massline(
        "plan",
        FIXTURE_MESHES / "idler_riser.STL",
        "--units",
        "in",
        "--density",
        "2700",
        "--candidates",
        "150",
        "--triaxial",
        "2",
        "--sensors",
        "3",
        "--out",
        tmp_path,
    )
    assert run.returncode == 0, run.stderr
    doc = json.loads((tmp_path / "plan.json").read_text())
    assert sum(s["triaxial"] is not None for s in doc["sensors"]) == 6


@pytest.mark.parametrize(
    "args,words",
    [
        (("plan", "structure", "--sensors", "4"), "at least 6"),
        (("plan", "structure", "--exciters", "2"), "minimum is 3"),
        (("plan", "structure", "--exclude-box", "-1", "-1", "-1", "1", "1", "1"), "no candidate point is left"),
    ],
)
def test_plan_bad_budgets_exit_2(tmp_path, args, words):
    run = massline(*args, "--out", tmp_path)
    assert run.returncode == 2 and words in run.stderr and "Traceback" not in run.stderr
