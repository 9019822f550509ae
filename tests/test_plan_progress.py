"""The plan's progress is honest: its fraction never goes back, and it reaches 100 % once, at the end (it said
"done (100 %)" after the certificate, then "sliding … (95 %)")."""

import argparse
from contextlib import contextmanager

from conftest import bundled
from rich.console import Console

import massline.cli.plan as plan_command
from massline.core.information import NoiseModel
from massline.placement.candidates import CandidateOptions
from massline.placement.diagnosable_plan import minimal_budget


def _told(monkeypatch) -> list:
    calls = []

    @contextmanager
    def recorded(console):
        yield lambda stage, done, total: calls.append((stage, done / total))

    monkeypatch.setattr(plan_command, "progress_bar", recorded)
    return calls


def test_the_minimal_plan_ends_once_at_one_hundred_percent(monkeypatch):
    calls = _told(monkeypatch)
    args = argparse.Namespace(relaxation="first-order", criterion="A", search_evaluations=None)
    options = CandidateOptions(n_samples=120)
    fixed = {"fixed_sensors": None, "fixed_exciters": None}
    plan_command.searched(args, bundled("bracket"), options, NoiseModel(0.01, 0.02), minimal_budget(False), fixed, Console())
    fractions = [f for _, f in calls]
    assert fractions == sorted(fractions), calls
    assert fractions.count(1.0) == 1 and calls[-1] == ("layout chosen", 1.0)
    assert any(stage.startswith("sliding") for stage, _ in calls)
