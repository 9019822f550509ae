"""What a plan states is what it can stand behind: no efficiency above 100 % (the certificate covers the candidate
layout; sliding's gain is a gain beside it), one certified row, counts in their number, commands set as code."""

import numpy as np
import pytest
from conftest import bundled

from massline import plan_layout, plan_to_dict
from massline.core.numbers import counted
from massline.cli.plan_console import criterion_text
from massline.reports.html import escape
from massline.reports.placement_report import criterion_html


@pytest.fixture(scope="module", params=["plate", "structure"])
def planned(request):
    body = bundled(request.param)
    return body, plan_layout(body)


def test_no_efficiency_above_100_percent_and_sliding_is_a_gain_beside_it(planned):
    body, plan = planned
    assert plan.log_det > plan.candidate_log_det  # sliding raised the criterion ...
    assert 0 < plan.d_efficiency_lower_bound <= 1 and 0 < plan.efficiency_lower_bound <= 1  # ... not the bound
    doc = plan_to_dict(plan, "plate", "m", body.density)
    assert doc["criterion"]["d_efficiency_lower_bound"] <= 1 and doc["criterion"]["sliding"]["gain"] > 0


def test_the_certified_efficiency_is_stated_once(planned):
    body, plan = planned
    text = criterion_text(plan)
    assert text.count("efficiency") == 1 and "candidate layout's certified D-efficiency" in text
    html = criterion_html(plan_to_dict(plan, "plate", "m", body.density))
    assert html.count("certified D-efficiency") == 1


def test_counts_take_their_number_and_commands_are_code():
    assert [counted(n, "hit") for n in (0, 1, 3)] == ["0 hits", "1 hit", "3 hits"]
    assert counted(1, "accelerometer channel") == "1 accelerometer channel"
    assert escape("`massline simulate` <hangs> it") == "<code>massline simulate</code> &lt;hangs&gt; it"
