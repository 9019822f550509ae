"""The lab-realism matrix (tests/lab_matrix.py) in CI: every body on every support from the exporter's file,
and each other file style once (the runs' styles on a soft cord). The whole matrix (3 seeds, 189 cells) is
``python tests/lab_matrix.py``."""

import pytest
from lab_matrix import BODIES, SUPPORTS, cell

# the exporter's file on the soft cord for each body, and each other style once; the stiff cord and foam under the
# exporter's file, one cell per body each, and the impact file's cell in the long tier (pytest -m long)
LONG = pytest.mark.long
# The structure's stiff cord since the reach changed its 12 + 2 × 3 lines × 4 hits plan: band 139.9–316.4 Hz, mass
# 5.5 % off (0.79σ), principal moments 4.0 % (1.48σ), the CoG 1.75 mm off at 3.3σ, with the misfit and truncation
# warnings; the CoG's ± does not cover it. Known, open: the ± of a squeezed band's CoG.
SQUEEZED = pytest.mark.xfail(strict=False, reason="structure on the stiff cord: the CoG 3.3σ off (1.75 mm), warned")
CASES = [
    (body, "exporter", support)
    if support == "soft"
    else pytest.param(
        body, "exporter", support, marks=(LONG, SQUEEZED) if (body, support) == ("structure", "stiff") else LONG
    )
    for body in BODIES
    for support in SUPPORTS
] + [
    pytest.param("bracket", "impact", "soft", marks=LONG),  # a 51,200-line hammer record: the long tier
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


def test_a_property_off_its_bound_passes_only_where_its_printed_two_sigma_is_wider_than_the_bound():
    """The plate on foam, half resolution, seed 1: mass 0.322 % at 0.88σ (2σ = 0.73 % > 0.3 %) passes unwarned;
    the same error at 2.5σ (2σ = 0.26 %: the ± claimed the bound) or beyond 2σ does not."""
    from lab_matrix import Cell

    def plate(mass_z: float) -> Cell:
        errors = {"mass": 0.322, "cog_mm": 0.046, "moments": 0.367}
        z = {"mass": mass_z, "cog_mm": 0.4, "moments": 0.9}
        return Cell("plate", "halfres", "foam", 1, (35.7, 104), errors, z, ())

    assert plate(0.88).stated and plate(0.88).passed
    assert not plate(2.5).passed
    assert not plate(2.1).passed  # 2σ = 0.31 % would be wide enough, but the error is beyond 2σ
