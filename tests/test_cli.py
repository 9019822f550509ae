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
    assert {"mass", "cog", "inertia_cog", "principal_moments", "principal_axes", "std", "band_hz", "planar"} <= set(data)
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


@pytest.mark.parametrize("args,words", [
    (("props", FIXTURE_MESHES / "soup.stl", "--units", "m", "--density", "1000"), "triangle soup"),
    (("props", FIXTURE_MESHES / "plate_holes.STL", "--units", "m", "--density", "2700"), "looks like mm"),
    (("props", FIXTURE_MESHES / "plate_holes.STL", "--density", "2700"), "--units"),
    (("props", "nothing.stl", "--units", "m", "--density", "2700"), "does not exist"),
    (("props", "plate", "--density", "2.7"), "g/cm³"),
])
def test_bad_input_is_one_line_and_exit_2(args, words):
    run = massline(*args)
    assert run.returncode == 2
    assert words in run.stderr
    assert len(run.stderr.strip().splitlines()) == 1 and "Traceback" not in run.stderr


def test_demo_runs():
    run = massline("demo")
    assert run.returncode == 0, run.stderr
    assert "Table 1" in run.stdout and "Condition numbers" in run.stdout
