"""The uncertainty budget as identify and plan print it: each 1-σ of the mass, CoG and principal moments split by
source (:mod:`massline.core.uncertainty_budget`)."""

from __future__ import annotations

import numpy as np
from rich.table import Table

from massline.core.numbers import number
from massline.core.properties import SUMMARY
from massline.core.uncertainty_budget import SHORT_NAMES, SOURCES, UncertaintyBudget


def budget_table(budget: UncertaintyBudget, body, planar: bool, title: str) -> Table:
    """Mass, CoG and principal moments' 1-σ split by the sources that move any of them: the mass and moments in
    per cent of ``body``'s value, the CoG in mm."""
    table = Table(title=f"{title} (1-σ; {budget.calibration.describe()})")
    rows, total = budget.table(), budget.std()
    shown = [s for s in SOURCES if any(rows[q.name][s] > 0 for q in SUMMARY)]
    for col in ("quantity", "± 1-σ", *(SHORT_NAMES[s] for s in shown), "unit"):
        table.add_column(col, justify="right")
    for q in SUMMARY:
        sigma = q.sigma(total)
        if np.isnan(sigma):
            continue
        relative = q.key != "cog"
        scale = 100 / abs(q.value(body, planar)) if relative else q.scale
        row = rows[q.name]
        parts = (number(row[s] * scale, 2) if row[s] > 1e-6 * sigma else "0" for s in shown)
        cells = [number(sigma * scale, 2), *parts]
        table.add_row(q.name, *cells, "%" if relative else q.unit)
    return table
