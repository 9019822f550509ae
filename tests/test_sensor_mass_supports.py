"""``simulate --sensor-mass`` on a small real part and the bundled bodies, on a cord, on foam and free.

The supports carry the body with its accelerometers (the cord tied above the loaded CoG, the foam under
the loaded body) and the band is judged against the loaded body's massline, which is what the test
measures: every case records, with a band.
"""

import json
import re

import pytest
from conftest import FIXTURE_MESHES

from massline.cli.app import run
from massline.meshes import BUNDLED
from massline.placement.candidates import CandidateOptions
from massline.core.files import to_json
from massline.meshes.loader import load_body
from massline.placement.on_surface import plan
from massline.placement.plan_file import plan_to_dict
from massline.placement.planner import Budget

RISER = str(FIXTURE_MESHES / "idler_riser.STL")
BODIES = {"idler riser": (RISER, "in", 2700.0, 0.001), "plate": ("plate", "m", None, 0.01)}
BODIES |= {"structure": ("structure", "m", None, 0.01), "bracket": ("bracket", "m", None, 0.01)}
# The riser's flat places, where a 10 mm base fits clear of edges, face ±z and −y only: uniaxial normals
# there cannot see every motion, three triaxial accelerometers can.
BUDGETS = {"idler riser": Budget(0, 3, 3)}


@pytest.fixture(scope="module")
def plans(tmp_path_factory) -> dict:
    folder = tmp_path_factory.mktemp("plans")
    paths = {}
    for name, (mesh, units, density, _) in BODIES.items():
        bundled = BUNDLED.get(mesh)
        body = load_body(bundled.path if bundled else mesh, units, density or bundled.density)
        planned = plan(body, BUDGETS.get(name, Budget(6, 3)), CandidateOptions(n_samples=150))
        paths[name] = folder / f"{name}.json"
        paths[name].write_text(to_json(plan_to_dict(planned, mesh, units, body.density)))
    return paths


def said(err: str) -> list:
    """What stderr says besides progress lines ("[  3.0 s] assembling mass (50 %)", written while the FE modes
    are solved when no earlier test left them in the cache)."""
    return [line for line in err.splitlines() if not re.fullmatch(r"\[\s*[\d.]+ s\] .* \(\d+ %\)", line)]


@pytest.mark.parametrize("support", ["cord", "foam", "none"])
@pytest.mark.parametrize("name", list(BODIES))
def test_sensor_mass_records_on_every_support(plans, name, support, tmp_path, capsys):
    mass = BODIES[name][3]
    out = tmp_path / "t.uff"
    argv = ["simulate", str(plans[name]), "--rigid", "--sensor-mass", str(mass), "--suspension", support]
    code = run([*argv, "--lines", "400", "--out", str(out)], show_warnings=True)
    printed, err = capsys.readouterr()
    assert code == 0 and not said(err), err
    assert "no band" not in printed and out.exists()
    truth = json.loads(out.with_suffix(".truth.json").read_text())
    assert truth["sensor_mass"] == mass and truth["loaded"]["mass"] > truth["nominal"]["mass"]


@pytest.mark.slow
def test_the_idler_riser_with_fe_modes_on_a_cord(plans, tmp_path, capsys):
    out = tmp_path / "t.uff"
    code = run(["simulate", str(plans["idler riser"]), "--sensor-mass", "0.001", "--out", str(out)], show_warnings=True)
    printed, err = capsys.readouterr()
    assert code == 0 and not said(err) and "no band" not in printed and out.exists(), err
