"""A plan given no ``--sensor-mass`` says it planned weightless accelerometers, and what typical housings
(5 g each, a triaxial once) would do to the body — in the console, plan.json and the placement report — with a
warning when that is more than the test resolves."""

import json

import numpy as np
import session_cache

from massline.core.lines import Lines
from massline.core.rigid_body import RigidBody
from massline.virtual.housing_loading import TYPICAL_HOUSING_KG, assumed_loading, assumed_sentence

STD = {"mass": 0.003, "cog": [2e-4, 2e-4, 2e-4], "principal_moments": [2e-6, 4e-6, 5e-6]}


def _hub() -> RigidBody:
    """The issue's aluminium hub: 0.295 kg, a tube on a flange (inertia of a Ø80 × 60 mm solid of that mass)."""
    m, r, h = 0.295, 0.04, 0.06
    side = m * (3 * r**2 + h**2) / 12
    return RigidBody(m, [0.0, 0.0, 0.02], np.diag([side, side, m * r**2 / 2]))


def test_eight_typical_accelerometers_on_the_hub_are_a_warning():
    angles = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    points = np.column_stack([0.04 * np.cos(angles), 0.04 * np.sin(angles), np.full(8, 0.03)])
    sensors = Lines(points, np.column_stack([np.cos(angles), np.sin(angles), np.zeros(8)]))
    assumed = assumed_loading(_hub(), sensors, STD)
    typical = assumed["typical"]
    assert assumed["sensor_mass_kg"] == 0.0 and assumed["beyond_predicted_std"]
    assert typical["housings"] == 8 and np.isclose(typical["total_kg"], 8 * TYPICAL_HOUSING_KG)
    assert np.isclose(typical["mass_percent"], 100 * 0.040 / 0.295)  # 13.56 %
    sentence = assumed_sentence(assumed)
    assert sentence.startswith("warning: accelerometers planned weightless") and "13.6 % of the body" in sentence
    assert "--sensor-mass" in sentence


def test_a_triaxial_counts_once_and_a_heavy_body_is_no_warning():
    sensors = Lines.triaxials([[0.5, 0.0, 0.0], [0.0, 0.5, 0.0]])
    sensors = Lines(
        np.vstack([sensors.points, [[0.0, 0.0, 0.5], [0.0, 0.0, -0.5]]]),
        np.vstack([sensors.directions, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]]),
        np.concatenate([sensors.triaxial, [-1, -1]]),
    )
    heavy = RigidBody(80.0, np.zeros(3), np.diag([8.0, 9.0, 10.0]))
    loose = {"mass": 0.5, "cog": [0.01] * 3, "principal_moments": [0.5, 0.5, 0.5]}
    assumed = assumed_loading(heavy, sensors, loose)
    assert assumed["typical"]["housings"] == 4 and not assumed["beyond_predicted_std"]
    assert not assumed_sentence(assumed).startswith("warning")


def test_the_bracket_plan_states_its_weightless_accelerometers(bracket_default_plan):
    doc = json.loads(bracket_default_plan.read_text())
    assumed = doc["sensor_mass_assumed"]
    housings = assumed["typical"]["housings"]
    assert "loading" not in doc and housings == len({s["triaxial"] if s["triaxial"] is not None else -k - 1
                                                      for k, s in enumerate(doc["sensors"])})
    assert np.isclose(assumed["typical"]["mass_percent"], 100 * housings * 0.005 / doc["nominal"]["mass"])
    folder = session_cache.command("plan", "bracket")
    said = "accelerometers planned weightless (no --sensor-mass)"
    assert said in " ".join((folder / "stdout.txt").read_text().split())
    assert said in (folder / "out" / "report.html").read_text()  # the placement report says it too
