"""The lab-realism matrix (tests/lab_matrix.py) in CI: every body on every support from the exporter's file,
and each other file style once (the runs' styles on a soft cord). The whole matrix (3 seeds, 189 cells) is
``python tests/lab_matrix.py``."""

import pytest
from lab_matrix import BODIES, SUPPORTS, cell

CASES = [(body, "exporter", support) for body in BODIES for support in SUPPORTS] + [
    ("bracket", "impact", "soft"),
    ("structure", "local", "foam"),
    ("plate", "plain", "stiff"),
    ("bracket", "gaps", "soft"),  # one file per reference, 5 % of the FRFs dropped
    ("structure", "halfres", "soft"),  # one file per reference, the last at half the resolution
]


@pytest.mark.slow
@pytest.mark.parametrize("body, style, support", CASES)
def test_identify_is_within_bounds_or_covered_and_warned(body, style, support, tmp_path):
    """Mass 0.3 %, CoG 1 mm, principal moments 1 %, tensor 1.5 % — or within 2σ with a warning saying why."""
    c = cell(body, style, support, 0, tmp_path)
    assert not c.outcome, c.outcome
    assert c.passed, (c.errors, c.z, c.warnings)
    if support == "soft":
        assert c.within, (c.errors, c.warnings)
