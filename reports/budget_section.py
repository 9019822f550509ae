"""The identification report's uncertainty budget: each reported 1-σ split by source, and what limits it."""

from __future__ import annotations

import numpy as np

from massline.core.properties import SUMMARY
from massline.core.uncertainty_budget import SHORT_NAMES as HEADS
from massline.core.uncertainty_budget import SOURCES, UncertaintyBudget, limits, source_name
from massline.reports.html import escape, html_table, num

def budget_section(budget: UncertaintyBudget, body, planar: bool) -> str:
    """The mass, CoG and principal moments' 1-σ, and each source's, with the sentences naming what limits them:
    the mass and the moments in per cent of their value, the CoG in mm."""
    rows_by_name, total = budget.table(), budget.std()
    shown = [s for s in SOURCES if any(rows_by_name[q.name][s] > 0 for q in SUMMARY)]
    rows = []
    for q in SUMMARY:
        sigma = q.sigma(total)
        if not np.isfinite(sigma):
            continue
        relative = q.key != "cog"
        scale = 100 / abs(q.value(body, planar)) if relative else q.scale
        row = rows_by_name[q.name]
        cells = [num(sigma * scale, ".2g")]
        cells += [num(row[s] * scale, ".2g") if row[s] > 1e-6 * sigma else "0" for s in shown]
        rows.append([escape(q.name), *cells, "%" if relative else "mm"])
    head = ["property", "± 1-σ", *(HEADS[s] for s in shown), "unit"]
    widths = [22, *[70 // (len(shown) + 1)] * (len(shown) + 1), 8]
    table = html_table(head, rows, "l" + "r" * (len(shown) + 1) + "l", widths)
    named = "; ".join(f"{HEADS[s]}: {source_name(s, budget.calibration)}" for s in shown)
    sentences = " ".join(escape(s[0].upper() + s[1:]) + "." for s in limits(budget, body))
    note = (
        f"Each 1-σ is its sources in quadrature (GUM): {escape(named)}. Calibration assumed: "
        f"{escape(budget.calibration.describe())}. {sentences}"
    )
    return f"<section><h2>Uncertainty budget</h2>{table}<p class=\"note\">{note}</p></section>"
