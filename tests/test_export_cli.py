"""``--export`` on identify and diagnose: the identified body in every format at once, read back by the formats'
readers; the body as tested on request; refusals in one line, exit 2, before any work."""

import json
import re

import numpy as np
import pytest
import yourdfpy
from conftest import bundled
from export_bodies import assert_same_body, comment_text, record, rigid_bodies
from test_cli import cli, massline
from test_export_adams import read_by_the_manual as read_adams
from test_export_csv import read_row
from test_export_mjcf import loaded
from test_export_nastran import read_by_the_manual as read_nastran

from massline.export import FORMATS
from massline.placement.hand_layouts import plate_table1
from massline.uff.writer import write_uff
from massline.virtual.acquisition import Acquisition, run
from massline.virtual.measurement import Noise

EXACT = ("--band", "5", "95", "--bootstrap", "0")  # noiseless data: the band the simulation is exact on


@pytest.fixture(scope="module")
def far_uff(tmp_path_factory):
    path = tmp_path_factory.mktemp("far") / "far.uff"
    record("far", path)
    return path


def test_identify_exports_every_format_that_its_reader_loads(far_uff, tmp_path):
    """The far bracket identified from a noiseless test: each file holds the body to 1e-9."""
    body = rigid_bodies()["far"]
    files = [tmp_path / f"far{suffix}" for suffix in FORMATS]
    args = [a for f in files for a in ("--export", f)]
    result = massline("identify", far_uff, *EXACT, "--json", tmp_path / "far.json", *args)
    assert result.returncode == 0, result.stderr
    assert all(f"wrote {f}" in result.stdout for f in files)
    assert_same_body(*loaded((tmp_path / "far.xml").read_text()), body, rtol=1e-9)
    inertial = yourdfpy.URDF.load(str(tmp_path / "far.urdf"), load_meshes=False).link_map["body"].inertial
    assert_same_body(inertial.mass, inertial.origin[:3, 3], inertial.inertia, body, rtol=1e-9)
    assert_same_body(*read_nastran((tmp_path / "far.bdf").read_text()), body, rtol=1e-9)
    assert_same_body(*read_adams((tmp_path / "far.adm").read_text()), body, rtol=1e-9)
    found = json.loads((tmp_path / "far.json").read_text())
    row = read_row((tmp_path / "far.csv").read_text())
    assert float(row["mass [kg]"]) == pytest.approx(body.mass, rel=1e-9)
    assert float(row["mass_1sigma [kg]"]) == pytest.approx(found["std"]["mass"], rel=1e-9)
    text = comment_text((tmp_path / "far.inp").read_text(), "**")
    assert "far.uff, massline identify (method best, band 5-95 Hz" in text and "as tested" not in text
    assert "the body with its accelerometers on, none taken off (no sensor mass given)" in " ".join(text.split())
    assert float(row["J_xy [kg m^2]"]) == pytest.approx(found["inertia_cog"][0][1], rel=1e-9)


def test_the_body_as_tested_on_request(far_uff, tmp_path):
    """With 0.2 g housings taken off (6 accelerometer points), the export is the bare body; --export-as-tested
    writes the body they weighed: the far bracket, exactly."""
    bare, tested = tmp_path / "bare.csv", tmp_path / "tested.csv"
    common = ("identify", far_uff, *EXACT, "--sensor-mass", "0.0002")
    assert massline(*common, "--export", bare).returncode == 0
    assert massline(*common, "--export", tested, "--export-as-tested").returncode == 0
    bare_mass = float(read_row(bare.read_text())["mass [kg]"])
    tested_mass = float(read_row(tested.read_text())["mass [kg]"])
    assert tested_mass == pytest.approx(rigid_bodies()["far"].mass, rel=1e-9)
    assert tested_mass - bare_mass == pytest.approx(6 * 0.0002, rel=1e-6)
    assert "the bare body, 6 accelerometer housings x 0.2 g taken off" in comment_text(bare.read_text(), "#")
    assert "the body as tested, 6 accelerometer housings x 0.2 g on" in comment_text(tested.read_text(), "#")


def test_export_units_scale_lengths_and_masses(far_uff, tmp_path):
    out = tmp_path / "far.adm"
    assert massline("identify", far_uff, *EXACT, "--export", out, "--export-units", "mm-t").returncode == 0
    assert "MASS = TONNE, LENGTH = MILLIMETER" in out.read_text()
    assert_same_body(*read_adams(out.read_text()), rigid_bodies()["far"], rtol=1e-9)


@pytest.mark.slow
def test_diagnose_exports_the_body_after_the_diagnosis(far_uff, tmp_path):
    out = tmp_path / "after.bdf"
    result = massline("diagnose", far_uff, "--export", out, "--json", tmp_path / "d.json")
    assert result.returncode == 0, result.stderr
    after = json.loads((tmp_path / "d.json").read_text())["properties"]["after"]
    mass, cog, inertia = read_nastran(out.read_text())
    assert mass == pytest.approx(after["mass"], rel=1e-9)
    np.testing.assert_allclose(cog, after["cog"], rtol=1e-9)
    np.testing.assert_allclose(inertia, after["inertia_cog"], rtol=0, atol=1e-9 * max(after["principal_moments"]))
    assert "massline diagnose (faults undone: none" in out.read_text()


REFUSALS = {
    "unknown suffix": (
        ["--export", "{tmp}/body.step"],
        r"--export: .*body\.step: no export format has the suffix '\.step'",
    ),
    "no such folder": (["--export", "{tmp}/missing/body.urdf"], r"folder .*missing does not exist"),
    "a folder": (["--export", "{tmp}"], r"no export format has the suffix"),
    "units URDF cannot take": (
        ["--export", "{tmp}/b.urdf", "--export-units", "mm-t"],
        r"--export-units 'mm-t'|--export-units mm-t: URDF",
    ),
    "two outputs one file": (["--export", "{tmp}/b.csv", "--json", "{tmp}/b.csv"], r"--json and --export both name"),
    "exists": (["--export", "{tmp}/old.bdf"], r"old\.bdf exists; pass --force"),
}


@pytest.mark.parametrize("case", list(REFUSALS))
@pytest.mark.parametrize("command", ["identify", "diagnose"])
def test_refusals_come_before_any_work_in_one_line(tmp_path, case, command):
    """The recording named does not exist: a refusal that reads it would say so instead."""
    (tmp_path / "old.bdf").write_text("$ a deck\n")
    args, words = REFUSALS[case]
    result = cli(command, tmp_path / "no-such.uff", *(a.format(tmp=tmp_path) for a in args))
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert result.stderr.count("\n") == 1 and re.search(words, result.stderr), result.stderr


def test_a_plate_recording_is_refused_before_the_identification(tmp_path):
    """A plate's test leaves z_G and J's z row unobserved: URDF cannot hold it, CSV can (empty cells)."""
    plate = bundled("plate").nominal
    recording, _ = run(plate, *plate_table1(), setup=Acquisition(100.0, 200, Noise(0, 0)))
    path = tmp_path / "plate.uff"
    write_uff(path, recording)
    refused = massline("identify", path, *EXACT, "--export", tmp_path / "plate.csv", "--export", tmp_path / "p.urdf")
    assert refused.returncode == 2 and "unobserved (plate data)" in refused.stderr and refused.stdout == ""
    assert not (tmp_path / "plate.csv").exists()
    assert massline("identify", path, *EXACT, "--export", tmp_path / "plate.csv").returncode == 0
    row = read_row((tmp_path / "plate.csv").read_text())
    assert row["cog_z [m]"] == "" and float(row["mass [kg]"]) == pytest.approx(plate.mass, rel=1e-9)
