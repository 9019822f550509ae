"""The rig: the support's apex straight above the CoG and a bridle of legs from surface points a technician can use
(virtual/rigging.py), on the bracket (apex 20.7 mm off its surface) and the flanged hub (apex not in its bore)."""

from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest
import trimesh

from massline.meshes import BUNDLED
from massline.meshes.clearance import segments_clear
from massline.meshes.loader import load_body
from massline.virtual.attachment import UP
from massline.virtual.band_prediction import support_candidates, support_rig
from massline.virtual.rigging import MIN_ELEVATION
from massline.virtual.suspension import GRAVITY

HUB = Path(__file__).parent / "fixtures" / "meshes" / "flanged_hub.stl"
BORE, TUBE_TOP = 15e-3, 60e-3  # m: the hub's bore radius and the tube's top (tests/hub_mesh.py)


@lru_cache(maxsize=None)
def body(name: str):
    if name == "hub":
        return load_body(HUB, "mm", 2700)
    return load_body(BUNDLED[name].path, "m", BUNDLED[name].density)


def distance_to_surface(mesh: trimesh.Trimesh, points: np.ndarray) -> np.ndarray:
    """Each point's distance (m) to the nearest triangle."""
    return np.array(
        [np.linalg.norm(trimesh.triangles.closest_point(mesh.triangles, np.tile(p, (len(mesh.faces), 1))) - p,
                        axis=1).min() for p in points]
    )  # fmt: skip


def assert_rig(mesh: trimesh.Trimesh, rig: dict, cog: np.ndarray, mass: float) -> None:
    """A rig as plan.json keeps it: legs on the surface, clear of the body, rising to an apex straight above the CoG,
    their lengths the distances, their tensions carrying the weight with every leg taut."""
    apex = np.asarray(rig["apex"])
    legs = rig["legs"]
    assert len(legs) == 3
    ends = np.array([leg["attachment"] for leg in legs])
    assert distance_to_surface(mesh, ends).max() < 1e-6
    assert np.linalg.norm((apex - cog)[:2]) < 1e-9 and apex[2] > cog[2]
    lengths = np.linalg.norm(apex - ends, axis=1)
    assert np.allclose([leg["length_m"] for leg in legs], lengths, rtol=1e-12)
    assert np.all((apex - ends)[:, 2] / lengths >= np.sin(np.radians(MIN_ELEVATION)) - 1e-12)
    assert segments_clear(mesh, ends, np.tile(apex, (3, 1))).all()
    tensions = np.array([leg["tension_n"] for leg in legs])
    assert tensions.min() > 0
    pull = ((apex - ends) / lengths[:, None]).T @ tensions
    assert np.allclose(pull, mass * GRAVITY * UP, atol=1e-9 * mass * GRAVITY)


@pytest.mark.parametrize("name", ["bracket", "hub", "structure"])
def test_bridles_hold_the_apex(name):
    """Every cord support the plan weighs is rigged: its apex above the CoG held by three legs from the surface."""
    b = body(name)
    cords = [s for s in support_candidates(b.mesh, b.nominal) if s.cords]
    assert cords
    for support in cords:
        rig = support_rig(b.mesh, b.nominal, support.cords[0].attachment)
        if len(rig.attachments):
            assert_rig(b.mesh, rig.as_dict(), b.nominal.cog, b.nominal.mass)


def test_hub_apex_not_in_the_bore():
    """On the hub the vertical through the CoG runs up the bore: an apex inside it (20 mm above the CoG, as the plan
    chose before) holds no bridle, so the apex sits above the tube and no leg is tied in the bore."""
    b = body("hub")
    inside = b.nominal.cog + 0.02 * UP
    assert inside[2] < TUBE_TOP and support_rig(b.mesh, b.nominal, inside) is None
    for support in (s for s in support_candidates(b.mesh, b.nominal) if s.cords):
        apex = support.cords[0].attachment
        assert apex[2] > TUBE_TOP
        ends = support_rig(b.mesh, b.nominal, apex).attachments
        on_bore = (np.hypot(ends[:, 0], ends[:, 1]) < BORE + 1e-4) & (ends[:, 2] < TUBE_TOP - 1e-6)
        assert not on_bore.any()


def test_bracket_plan_draws_its_rig(bracket_default_plan):
    """``massline plan bracket``: plan.json keeps the rig of its support (the apex where its cord is tied), the
    console names the legs and the report lists and draws them; the report's mount words are the console's."""
    doc = json.loads(Path(bracket_default_plan).read_text())
    b = body("bracket")
    assert np.allclose(doc["rig"]["apex"], doc["suspension"]["cords"][0]["attachment"])
    assert_rig(b.mesh, doc["rig"], b.nominal.cog, b.nominal.mass)
    folder = Path(bracket_default_plan).parents[1]
    assert "rig: bridle of 3 legs" in (folder / "stdout.txt").read_text()
    report = (Path(bracket_default_plan).parent / "report.html").read_text()
    assert "Rig (drawn in the views)" in report and "glued" not in report
