"""The Python API a script uses: the README's "From Python" example runs as written, and the results it shows
are the body the recording holds."""

import json
import re
from pathlib import Path

import numpy as np
import pytest
import yourdfpy
from export_bodies import assert_same_body, record, rigid_bodies
from test_export_abaqus import read_by_the_manual as read_abaqus

import massline
from massline.export.units import UNITS

README = Path(__file__).resolve().parents[1] / "README.md"


def readme_example() -> str:
    """The Python block of the README's "From Python" section."""
    section = README.read_text().split("\n## From Python\n", 1)[1].split("\n## ", 1)[0]
    (code,) = re.findall(r"```python\n(.*?)```", section, re.DOTALL)
    return code


def test_the_readme_example_runs_as_written(tmp_path, monkeypatch, capsys):
    """In a folder holding test.uff (the bracket, noiseless): the body it prints and exports is the bracket's."""
    record("bracket", tmp_path / "test.uff")
    monkeypatch.chdir(tmp_path)
    scope: dict = {}
    exec(compile(readme_example(), "README.md", "exec"), scope)  # noqa: S102 (the README's own code)
    bracket = rigid_bodies()["bracket"]
    found = scope["found"]
    assert_same_body(found.mass, found.cog, found.inertia, bracket, rtol=1e-9)
    assert capsys.readouterr().out.startswith(f"{found.mass} {found.std['mass']}")
    inertial = yourdfpy.URDF.load("body.urdf", load_meshes=False).link_map["body"].inertial
    assert_same_body(inertial.mass, inertial.origin[:3, 3], inertial.inertia, bracket, rtol=1e-9)
    assert json.loads(Path("body.json").read_text())["mass"] == pytest.approx(0.3456, rel=1e-9)
    cad = scope["cad"]
    mass, cog, J = read_abaqus(Path("cad.inp").read_text(), UNITS["mm-t"])
    assert mass == pytest.approx(2.0) and np.allclose(cog, cad.cog) and np.allclose(J, cad.inertia)


def test_the_public_names_come_from_the_package_root():
    names = ("identify_recording", "diagnose_recording", "plan_test", "simulate_test", "Body")
    assert all(name in massline.__all__ and getattr(massline, name) for name in names)
    from massline.identify import identify_recording

    assert identify_recording is massline.identify_recording


def test_identify_and_diagnose_results_speak_alike(tmp_path):
    """Both results have mass, cog, inertia, std, warnings, to_json and export; a far body (2.8 m off, its
    layout moved with it) comes out of both as it went in."""
    record("far", tmp_path / "far.uff")
    far = rigid_bodies()["far"]
    found = massline.identify_recording(str(tmp_path / "far.uff"), (5, 95), draws=0)
    run = massline.diagnose_recording(tmp_path / "far.uff")
    for result in (found, run):
        assert_same_body(result.mass, result.cog, result.inertia, far, rtol=1e-9)
        assert result.std["mass"] >= 0 and isinstance(result.warnings, tuple) and '"units"' in result.to_json()
    path = run.export(tmp_path / "far.xml", source="far.uff")
    assert "far.uff, massline diagnose (faults undone: none" in " ".join(path.read_text().split())


def test_a_script_gets_the_libraries_error_not_a_flag():
    with pytest.raises(massline.MasslineError, match=r"units='ft-lb': not a unit system"):
        massline.Body(mass=1.0, cog=np.zeros(3), inertia=np.eye(3)).export("x.bdf", units="ft-lb")
