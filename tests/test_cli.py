"""The command line: tables, JSON contract, exit codes, nothing overwritten."""

import contextlib
import io
import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest
import session_cache
from conftest import FIXTURE_MESHES, bundled

from massline.identify.pipeline import PAPER_METHODS


def massline(*args, cwd=None):
    """Run the command; fail on any warning or library text it let through (MASSLINE_DEBUG shows them)."""
    env = {**os.environ, "MASSLINE_DEBUG": "1"}
    run = subprocess.run(
        [sys.executable, "-m", "massline", *map(str, args)], capture_output=True, text=True, cwd=cwd, env=env
    )
    stray = [line for line in (run.stdout + run.stderr).splitlines() if "debug:" in line or "On entry to" in line]
    assert not stray, f"stray warnings from massline {' '.join(map(str, args))}: {stray}"
    return run


@contextlib.contextmanager
def inside(folder):
    """The working directory ``folder`` (None: unchanged) while the block runs."""
    before = os.getcwd()
    os.chdir(folder or before)
    try:
        yield
    finally:
        os.chdir(before)


def cli(*args, cwd=None):
    """``massline ARGS`` run in this process, as :func:`massline` runs it in its own: the command's exit code,
    stdout and stderr (warnings shown, and failed on). For refusals, whose work is parsing and checking: the
    interpreter's second of imports is paid once (tests/test_refusals.py goes through the real entry point)."""
    from massline.cli.app import run

    out, err = io.StringIO(), io.StringIO()
    with inside(cwd), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = run([str(a) for a in args], show_warnings=True)
    done = subprocess.CompletedProcess(args, code, out.getvalue(), err.getvalue())
    stray = [line for line in (done.stdout + done.stderr).splitlines() if "debug:" in line]
    assert not stray, f"stray warnings from massline {' '.join(map(str, args))}: {stray}"
    return done


def test_bare_massline_prints_the_help():
    run = massline()
    assert run.returncode == 0 and run.stderr == "", run.stderr
    assert run.stdout.startswith("usage: massline") and "identify" in run.stdout and "diagnose" in run.stdout


def test_json_dash_writes_only_json_on_stdout(tmp_path):
    """``--json -``: the JSON alone on stdout (a pipe reads it), the console's tables on stderr, no file '-'."""
    run = massline("props", "bracket", "--json", "-", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    data = json.loads(run.stdout)
    assert data["mass"] == pytest.approx(bundled("bracket").nominal.mass, rel=1e-12)
    assert "nominal properties" in run.stderr and not (tmp_path / "-").exists()
    assert data["units"] == {"mass": "kg", "length": "m", "inertia": "kg m^2", "frequency": "Hz"}


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
    run = cli(*args)
    assert run.returncode == 2
    assert words in run.stderr
    assert len(run.stderr.strip().splitlines()) == 1 and "Traceback" not in run.stderr


def test_demo_refuses_to_overwrite_an_earlier_demo(tmp_path):
    (tmp_path / "plan.json").write_text("precious")
    run = massline("demo", "--out", tmp_path)
    assert run.returncode == 2 and "--force" in run.stderr and len(run.stderr.strip().splitlines()) == 1
    assert (tmp_path / "plan.json").read_text() == "precious" and len(list(tmp_path.iterdir())) == 1


def test_plan_writes_plan_json():
    """``massline plan structure`` as run once this session (test_simulate_cli simulates the same plan)."""
    folder = session_cache.command("plan", "structure")
    out, stdout = folder / "out", (folder / "stdout.txt").read_text()
    assert "certified" in stdout and "Hammer hits" in stdout
    doc = json.loads((out / "plan.json").read_text())
    assert {"mesh", "units", "nominal", "sensors", "exciters", "criterion", "predicted_std"} <= set(doc)
    assert len(doc["sensors"]) >= 8 and len(doc["exciters"]) >= 4  # the default: the cheapest diagnosable plan
    assert doc["diagnosability"]["diagnosable"] and "diagnosable" in stdout
    assert doc["diagnosability"]["cost"]["minimal_lines"] == 6 and doc["diagnosability"]["cost"]["minimal_hits"] == 3
    assert set(doc["sensors"][0]) == {"node", "candidate", "point", "direction", "triaxial", "mount", "reach"}
    assert {"log_det", "condition_numbers", "d_efficiency_lower_bound"} <= set(doc["criterion"])
    # the certificate bounds every layout of the budget, diagnosable or not and footprints or not: the constraints
    # cost some per cent
    assert doc["criterion"]["d_efficiency_lower_bound"] >= 0.85
    assert {"mass", "cog", "inertia_cog", "principal_moments", "principal_axes"} <= set(doc["predicted_std"])
    again = massline("plan", "structure", "--out", out)  # refused before any work: the shared plan is kept
    assert again.returncode == 2 and "--force" in again.stderr


def test_plan_minimal_is_the_papers_layout_and_says_it_cannot_locate_a_fault(tmp_path):
    run = massline("plan", "structure", "--minimal", "--out", tmp_path)
    assert run.returncode == 0, run.stderr
    doc = json.loads((tmp_path / "plan.json").read_text())
    assert (
        len(doc["sensors"]) == 6 and len(doc["exciters"]) == 3 and doc["criterion"]["d_efficiency_lower_bound"] >= 0.95
    )
    assert not doc["diagnosability"]["diagnosable"] and "not diagnosable" in run.stdout
    assert "no redundancy" in run.stdout
    both = massline("plan", "structure", "--minimal", "--sensors", "8", "--out", tmp_path / "x")
    assert both.returncode == 2 and "--minimal" in both.stderr


PROGRESS = re.compile(r"^\[ *\d+\.\d s\] \S")  # a plain progress line: seconds since the first, the stage


def test_plan_off_a_terminal_shows_progress_on_stderr_and_says_where_its_search_stopped(tmp_path):
    """Off a terminal the progress is plain lines on stderr, nothing else there, and stdout holds results only;
    a search out of evaluations plans the minimal layout and says so in the console, plan.json and the report."""
    full = session_cache.command("plan", "plate")  # seconds of work: progress lines after 1 s
    lines = (full / "stderr.txt").read_text().splitlines()
    assert lines and all(PROGRESS.match(line) for line in lines), lines
    assert not any(PROGRESS.match(line) for line in (full / "stdout.txt").read_text().splitlines())
    run = massline("plan", "plate", "--search-evaluations", "50", "--out", tmp_path)  # done within 1 s: may be silent
    assert run.returncode == 0, run.stderr
    assert all(PROGRESS.match(line) for line in run.stderr.splitlines()), run.stderr
    assert "diagnosable search: stopped after 50 of 50 diagnosability evaluations; reached" in run.stdout
    doc = json.loads((tmp_path / "plan.json").read_text())
    search = doc["diagnosability"]["search"]
    assert search["stopped"] and search["spent"] == search["limit"] == 50 and len(doc["sensors"]) == 3
    assert "stopped after 50 of 50" in (tmp_path / "report.html").read_text()
    given = massline("plan", "plate", "--minimal", "--search-evaluations", "50", "--out", tmp_path / "x")
    assert given.returncode == 2 and "--search-evaluations" in given.stderr


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
    run = cli(*args, "--out", tmp_path)
    assert run.returncode == 2 and words in run.stderr and "Traceback" not in run.stderr


def _recorded(tmp_path_factory, name, sensors, exciters):
    from massline.uff.writer import write_uff
    from massline.virtual import acquisition
    from massline.virtual.measurement import Noise
    from massline.virtual.acquisition import Acquisition

    setup = Acquisition(100.0, 200, Noise(0, 0))
    recording, _ = acquisition.run(bundled(name).nominal, sensors, exciters, setup=setup)
    path = tmp_path_factory.mktemp(name) / f"{name}.uff"
    write_uff(path, recording)
    return path


@pytest.fixture(scope="module")
def plate_uff(tmp_path_factory):
    from massline.placement.hand_layouts import plate_table1

    return _recorded(tmp_path_factory, "plate", *plate_table1())


@pytest.fixture(scope="module")
def structure_uff(tmp_path_factory):
    from massline.placement.hand_layouts import structure_exciters, structure_sensors

    return _recorded(tmp_path_factory, "structure", structure_sensors(), structure_exciters(2))


@pytest.mark.parametrize("method", ["best", "plate"])
def test_identify_plate_data_shows_unobservable_entries(plate_uff, tmp_path, method):
    out = tmp_path / "p.json"
    run = massline("identify", plate_uff, "--band", 5, 95, "--method", method, "--json", out)
    assert run.returncode == 0, run.stderr
    results = run.stdout.split("uncertainty budget")[0]  # the properties' table (the budget's follows)
    rows = {line.split("│")[1].strip(): line for line in results.splitlines() if line.count("│") > 3}
    for name in ("CoG z", "J_G zz", "J_G xz", "principal moment 3", "principal axis 3"):
        assert "unobservable" in rows[name]
    assert "nan" not in run.stdout.lower() and "0.567" in rows["mass"]
    data = json.loads(out.read_text())
    assert data["planar"] is True and data["mass"] == pytest.approx(bundled("plate").nominal.mass, rel=1e-6)
    assert data["cog"][2] is None and data["inertia_cog"][2] == [None, None, None]
    assert data["principal_moments"][2] is None and data["principal_moments"][0] is not None


def test_identify_plate_method_report_shows_unobservable_entries(plate_uff, tmp_path):
    page = tmp_path / "p.html"
    run = massline("identify", plate_uff, "--band", 5, 95, "--method", "plate", "--mesh", "plate", "--report", page)
    assert run.returncode == 0, run.stderr
    text = re.sub(r"data:[^\"']*", "", page.read_text())
    assert "unobservable" in text and not re.search(r"\bnan\b", text, re.IGNORECASE)


@pytest.mark.parametrize("method", [m for m in PAPER_METHODS if m != "plate"])
def test_identify_refuses_a_3d_method_on_plate_data(plate_uff, method):
    run = cli("identify", plate_uff, "--band", 5, 95, "--method", method)
    assert run.returncode == 2 and len(run.stderr.strip().splitlines()) == 1, run.stderr
    assert "plate data" in run.stderr and "--method plate" in run.stderr and "Traceback" not in run.stderr


def test_identify_refuses_the_plate_method_on_3d_data(structure_uff):
    run = massline("identify", structure_uff, "--band", 5, 95, "--method", "plate")
    assert run.returncode == 2 and len(run.stderr.strip().splitlines()) == 1, run.stderr
    assert "--method best" in run.stderr and "Traceback" not in run.stderr


def test_identify_rounds_each_value_to_its_sigma(structure_uff):
    run = massline("identify", structure_uff, "--band", 5, 95, "--method", "method2+method3", "--bootstrap", "20")
    assert run.returncode == 0, run.stderr
    results = run.stdout.split("uncertainty budget")[0]  # the properties' table (the budget's follows)
    rows = [line.split("│")[1:5] for line in results.splitlines() if line.count("│") > 3]
    for name, value, sigma, _ in rows:
        value, sigma = value.strip(), sigma.strip()
        if value and sigma and value != "unobservable":
            decimals = len(value.partition("e")[0].partition(".")[2])
            assert decimals == len(sigma.partition("e")[0].partition(".")[2]), (name, value, sigma)
            assert value.partition("e")[2] == sigma.partition("e")[2]
    cells = [cell.strip() for row in rows for cell in row]
    assert not any(cell.startswith(("-", "−0")) and cell.strip("−0.") == "" for cell in cells)
    assert not any("-" in cell or "[" in cell for cell in cells)


UNIT_WORDS = ("kg", "m", "mm", "Hz", "°", "degrees", "fraction", "%", "ms", "lines", "Pa", "N/m", "s", "of 1/mass")


def test_every_option_states_its_default_and_a_number_its_unit():
    """Each option that has a default says it in its help, and each numeric one names its unit (or that it is a
    fraction or a count); output paths and meshes, off unless given, are exempt."""
    import argparse

    from massline.cli.app import build_parser

    commands = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction)).choices
    missing = []
    for name, parser in commands.items():
        for action in parser._actions:
            if not action.option_strings or action.nargs == 0 or action.default in (None, [], argparse.SUPPRESS):
                continue
            text = action.help or ""
            if "default" not in text:
                missing.append(f"{name} {action.option_strings[0]}: no default in {text!r}")
            numeric = isinstance(action.default, float) or (isinstance(action.default, int) and action.type is not int)
            words = re.findall(r"[^\s(),;:]+", text)
            if numeric and not action.choices and not any(w.strip(".") in UNIT_WORDS for w in words):
                if not any(w in text for w in ("fraction", "count", "seed", "hits", "modes", "draws", "lines")):
                    missing.append(f"{name} {action.option_strings[0]}: no unit in {text!r}")
    assert not missing, "\n".join(missing)
