"""``--effect`` sizes a lab cannot produce are refused with one line, before any work; the edges are taken."""

import pytest

from massline.core.errors import MasslineError
from massline.identify.diagnose.effects import parse_effect


@pytest.mark.parametrize(
    "text, words",
    [
        ("sensor_location=5@3", "offset of 5 m"),
        ("excitation_location=-0.01@1", "give 0 to 1 m"),
        ("sensor_direction=400@3", "400°"),
        ("excitation_direction=-91@2", "at most 90°"),
        ("sensor_gain=-2@5", "sensor_polarity flips a sign"),
        ("sensor_gain=12@5", "−0.9 < g < 10"),
        ("transverse_sensitivity=1.5@all", "broken accelerometer"),
        ("sensor_mass_loading=-0.01@2", "≥ 0 kg"),
    ],
)
def test_an_impossible_size_is_refused_naming_the_range(text, words):
    with pytest.raises(MasslineError, match=words) as refused:
        parse_effect(text)
    assert "\n" not in str(refused.value)


@pytest.mark.parametrize(
    "text",
    ["sensor_location=1@3", "sensor_location=0@3", "sensor_direction=90@1", "excitation_direction=-90@1",
     "sensor_gain=-0.89@1", "sensor_gain=9.9@1", "transverse_sensitivity=-0.05@all", "sensor_mass_loading=0@1"],
)  # fmt: skip
def test_a_size_inside_the_range_is_taken(text):
    assert parse_effect(text).size == float(text.split("=")[1].split("@")[0])


@pytest.mark.parametrize("given, system", [("m", "SI"), ("mm", "MM"), ("in", "IN"), ("SI", "SI"), ("MM", "MM")])
def test_simulate_spells_the_files_units_as_every_command_does(given, system):
    from massline.cli.simulate import file_units

    assert file_units(given) == system


def test_simulate_refuses_a_unit_system_with_one_line(tmp_path, capsys):
    from massline.cli.app import run

    code = run(["simulate", str(tmp_path / "plan.json"), "--out", str(tmp_path / "t.uff"), "--units", "ft"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "give m, mm or in" in err and "\n" not in err
