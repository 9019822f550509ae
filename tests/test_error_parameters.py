"""Library errors name the caller's parameters; the command line names its flags for the same mistake."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import bundled

from massline.cli.app import run
from massline.core.errors import MasslineError, param
from massline.core.masslines import synthesise
from massline.identify.pipeline import identify_recording
from massline.core.housing_masses import HousingMasses
from massline.cli.options import FLAGS
from massline.placement.hand_layouts import structure_exciters, structure_sensors
from massline.uff.recording import Recording
from massline.uff.writer import write_uff


@pytest.fixture(scope="module")
def massline_file(tmp_path_factory) -> tuple[Recording, str]:
    """A recording of the bundled structure's pure masslines, 0.5 Hz apart from 2 to 100 Hz, and its UFF."""
    body = bundled("structure").nominal
    data = synthesise(body, structure_sensors(), structure_exciters())
    f = np.arange(2.0, 100.5, 0.5)
    frf = np.repeat(data.values[:, :, None], len(f), axis=2).astype(complex)
    recording = Recording(f, frf, data.sensors, data.exciters)
    path = tmp_path_factory.mktemp("masslines") / "masslines.uff"
    write_uff(path, recording)
    return recording, str(path)


def cli_error(argv: list[str], capsys) -> str:
    assert run(argv) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.splitlines()) == 1
    return err.strip()


def test_a_marked_parameter_is_spelled_by_whoever_reads_the_error():
    err = MasslineError(f"x: give {param('band', '(lo, hi)', cli='LO HI')} or pass {param('force', 'True', cli='')}")
    assert str(err) == "x: give band=(lo, hi) or pass force=True"
    assert err.spelled({"band": "--band", "force": "--force"}) == "x: give --band LO HI or pass --force"
    assert err.spelled({}) == str(err) and err.parameters == ("band", "force")
    assert str(MasslineError("no parameter here")) == "no parameter here"


def test_every_parameter_the_cli_maps_has_a_flag():
    assert all(flag.startswith("--") and " " not in flag for flag in FLAGS.values())


def test_a_bad_band_names_the_parameter_to_a_library_caller_and_the_flag_on_the_command_line(massline_file, capsys):
    recording, path = massline_file
    with pytest.raises(MasslineError) as library:
        identify_recording(recording, (10.0, 10.5), draws=0)
    assert str(library.value).startswith("band=(10, 10.5) Hz holds fewer than")
    assert "--" not in str(library.value) and library.value.parameters == ("band",)
    line = cli_error(["identify", path, "--band", "10", "10.5"], capsys)
    assert line.startswith("massline: error: --band 10 10.5 Hz holds fewer than"), line


def test_a_bad_sensor_mass_names_the_parameter_to_a_library_caller_and_the_flag_on_the_command_line(
    massline_file, capsys
):
    recording, path = massline_file
    with pytest.raises(MasslineError) as library:
        identify_recording(recording, (5.0, 95.0), draws=0, sensor_mass=-1.0)
    assert str(library.value).startswith("sensor_mass='-1': a housing's mass is a number of kg")
    assert "--" not in str(library.value)
    with pytest.raises(MasslineError) as parsed:
        HousingMasses.parse(["-1"])
    assert str(parsed.value).startswith("sensor_mass='-1': a housing's mass is a number of kg")
    line = cli_error(["identify", path, "--sensor-mass", "-1"], capsys)
    assert "--sensor-mass '-1': a housing's mass is a number of kg" in line, line


def test_a_budget_below_the_papers_minimum_names_the_budget_field():
    from massline.placement.plans import Budget

    with pytest.raises(MasslineError) as library:
        Budget(6, 2).check(planar=False)
    assert str(library.value).endswith("the paper's minimum is 3 (budget.exciters=3)")
    assert library.value.spelled(FLAGS).endswith("the paper's minimum is 3 (--exciters 3)")
