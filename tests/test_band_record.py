"""An impact test's record sized to the band (``simulate --impact --record band``): ≥ 100 lines between the band's
edges and the exponential window adding ≤ 5 % of critical damping at its low edge, not at the 0.49 Hz pendulum."""

import numpy as np
from test_cli import massline

from massline.core.band import Band
from massline.virtual.analyser import BAND_LINES, LINE_COUNTS, impact_setup

BRACKET_BAND = Band(26.0, 218.4)  # the bracket's --minimal plan on its cord
PENDULUM = np.array([0.0, 0.487, 0.487, 0.997, 2.66, 4.22])  # Hz (0: yaw, free)


def test_the_band_record_is_the_shortest_line_count_the_band_needs():
    long, short = impact_setup(BRACKET_BAND, PENDULUM, 0.01), impact_setup(BRACKET_BAND, PENDULUM, 0.01, record="band")
    assert short.fmax == long.fmax == 800.0 and short.warnings == ()
    assert (short.lines, short.record) == (800, 1.0) and (long.lines, long.record) == (25600, 32.0)
    assert np.log(100) / short.record <= 0.05 * 2 * np.pi * BRACKET_BAND.low  # ≤ 5 % at the band's low edge
    assert short.record * (BRACKET_BAND.high - BRACKET_BAND.low) >= BAND_LINES
    half = LINE_COUNTS[LINE_COUNTS.index(short.lines) - 1] / short.fmax
    assert np.log(100) / half > 0.05 * 2 * np.pi * BRACKET_BAND.low or half * 192.4 < BAND_LINES


def test_a_band_without_a_low_edge_keeps_the_supports_record_and_a_short_hand_record_is_said():
    rigid = impact_setup(Band(np.nan, np.inf), PENDULUM, 0.01, record="band")
    assert rigid.lines == impact_setup(Band(np.nan, np.inf), PENDULUM, 0.01).lines
    [said] = impact_setup(BRACKET_BAND, PENDULUM, 0.01, lines=400, record="band").warnings
    assert "too short for the band's low edge at 26 Hz" in said and "choose --lines 800" in said


def test_record_without_impact_is_refused(tmp_path):
    plan = tmp_path / "plan.json"
    plan.write_text('{"mesh": "bracket", "sensors": [{"point": [0, 0, 0], "direction": [0, 0, 1]}], '
                    '"exciters": [{"point": [0, 0, 0], "direction": [0, 0, 1]}]}')
    run = massline("simulate", plan, "--record", "band", "--out", tmp_path / "t.uff")
    assert run.returncode == 2 and "give --impact" in run.stderr and len(run.stderr.strip().splitlines()) == 1
