"""The diagnosis of a recording with FRFs missing: pairs not measured and a run on a coarser axis are
NaN, and the diagnosis reads each FRF on its own lines (:mod:`massline.identify.tails`). On the structure's
rigid test (soft cord, 12 random sensor lines × 3 hits, 1 % noise) it names no fault with pairs missing or a run
at half the resolution, its "before" is identify's on the same recording, and a concealed gain is still named
at its channel with the properties after closer to the truth."""

import numpy as np
import pytest
from conftest import bundled
from test_diagnose import twelve_lines
from test_runs_identify import BAND, gaps, recording

from massline.core.files import to_json
from massline.identify.diagnose.effects import parse_effect
from massline.identify.diagnose.pipeline import diagnose_recording
from massline.identify.pipeline import identify_recording
from massline.identify.suspicions import beyond_chance
from massline.placement.hand_layouts import structure_exciters
from massline.virtual.acquisition import Acquisition, run

MISSING = [(0, 0), (7, 2)]  # 2 of 36 pairs not measured


@pytest.fixture(scope="module")
def structure():
    return bundled("structure").nominal


@pytest.mark.parametrize("pairs, every_other", [(MISSING, None), ([], 2)], ids=["two_pairs", "coarser_run"])
def test_a_clean_test_with_frfs_missing_names_no_fault(structure, pairs, every_other):
    """Rigid, no fault: no fault named, the properties before are identify's on the same file, identify's χ²
    within the noise, and the fit after at the noise."""
    rec = gaps(recording(structure, 4), pairs, every_other)
    found = diagnose_recording(rec, BAND)
    assert [f.effect for f in found.findings if f.kind == "fault"] == []
    assert to_json(found.document["properties"]["before"]) == to_json(identify_recording(rec).payload)
    assert not beyond_chance(found.chi2["before"], found.chi2["dof"])
    assert found.result.relative_rms("after") < 1.1 * found.result.noise
    assert found.mass == pytest.approx(structure.mass, rel=3e-3)


def test_a_concealed_gain_is_named_with_pairs_missing_elsewhere(structure):
    """A 20 % gain on sensor 5 (row 4), two pairs of other channels not measured: the gain is named there and
    undoing it brings the mass and inertia closer to the truth."""
    effects = (parse_effect("sensor_gain=0.2@5"),)
    rec, _ = run(structure, twelve_lines(), structure_exciters(), effects=effects, setup=Acquisition(100.0, 400),
                 seed=2)  # fmt: skip
    found = diagnose_recording(gaps(rec, [(1, 0), (9, 2)]), BAND)
    faults = [f for f in found.findings if f.kind == "fault"]
    assert [(f.effect, f.channels) for f in faults] == [("sensor_gain", (4,))]
    assert abs(found.after.mass - structure.mass) < abs(found.before.mass - structure.mass) / 10
    truth = structure.inertia_cog
    after, before = (np.linalg.norm(b.inertia_cog - truth) for b in (found.after_body, found.before.body))
    assert after < before and after < 0.02 * np.linalg.norm(truth)
