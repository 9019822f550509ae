"""plan's predicted accuracy: the uncertainty budget identify will state of the planned test, before it.

The budget (:mod:`massline.placement.predicted_budget`) is taken over the band plan.json predicts, at the virtual
test's analyser (``band_lines``), with each line's assumed noise (``--line-noise``) and the chain's calibration
(``--calibration``); without a predicted band, the Cramér–Rao table of the criterion's noise model.
"""

from __future__ import annotations

import argparse

import numpy as np
from rich.console import Console

from massline.cli.budget_console import budget_table
from massline.cli.options import add_calibration_argument, fraction
from massline.cli.plan_console import std_table
from massline.core.calibration import Calibration
from massline.core.uncertainty_budget import UncertaintyBudget, limits
from massline.placement.predicted_budget import predicted_budget
from massline.virtual.acquisition import LINES
from massline.virtual.planned_test import planned_band

LINE_NOISE = 0.01  # assumed relative noise of each FRF line: the virtual test's default (simulate --noise)


def add_budget_arguments(parser: argparse.ArgumentParser) -> None:
    """What the predicted accuracy (the uncertainty budget) assumes of the test: each line's noise, the chain's
    calibration."""
    parser.add_argument(
        "--line-noise",
        type=fraction(low_open=True),
        default=LINE_NOISE,
        metavar="REL",
        help=f"assumed noise of each FRF on each spectral line, a fraction of it, after averaging (default "
        f"{LINE_NOISE:g}: the virtual test's --noise; a coherence γ² = 1/(1 + REL²))",
    )
    add_calibration_argument(parser, "the predicted accuracy's type-B sources")


def predicted_accuracy(result, doc: dict, line_noise: float, calibration: Calibration) -> UncertaintyBudget | None:
    """The budget identify will state of this layout's test (:mod:`massline.placement.predicted_budget`) over the
    band plan.json predicts, at the virtual test's analyser (``band_lines``); None without a band."""
    frequencies = band_lines(planned_band(doc))
    if len(frequencies) <= 4:
        return None
    return predicted_budget(result.model, result.sensors, result.exciters, line_noise=line_noise,
                            frequencies=frequencies, calibration=calibration)  # fmt: skip


def budget_entries(budget: UncertaintyBudget, result, doc: dict, line_noise: float) -> dict:
    """plan.json's ``predicted_std`` (the budget's total) and ``uncertainty_budget`` (identify's keys, with the
    noise assumed and the band's lines)."""
    payload = budget.payload() | {"limits": limits(budget, result.model.nominal)}
    payload |= {"line_noise": line_noise, "band_lines": len(band_lines(planned_band(doc)))}
    return {"predicted_std": budget.std(), "uncertainty_budget": payload}


def band_lines(band) -> np.ndarray:
    """The spectral lines (Hz) of the band ``band`` at the virtual test's analyser: LINES lines to 1.5 × the first
    elastic mode (40 × the top support mode for a rigid body)."""
    if band is None or not band.exists:
        return np.zeros(0)
    fmax = 1.5 * band.first_elastic if np.isfinite(band.first_elastic) else 40 * max(band.suspension_top, 1.0)
    f = fmax / LINES * np.arange(1, LINES + 1)
    return f[(f >= band.low) & (f <= band.high)]


def print_accuracy(console: Console, result, budget: UncertaintyBudget | None, lines: int) -> None:
    """The predicted accuracy: the budget's table and what limits each property, or (no band) the Cramér–Rao
    table of the criterion's noise model."""
    if budget is None:
        console.print(std_table(result))
        return
    title = f"Predicted accuracy: the uncertainty budget over the band's {lines} lines"
    console.print(budget_table(budget, result.model.nominal, result.model.planar, title))
    for sentence in limits(budget, result.model.nominal):
        console.print(f"budget: {sentence}")
