"""Tables with units for the terminal (rich)."""

from __future__ import annotations

import numpy as np
from rich.table import Table

from massline.placement.rigid_body import RigidBody

INERTIA_ENTRIES = (("J_xx", 0, 0), ("J_yy", 1, 1), ("J_zz", 2, 2), ("J_xy", 0, 1), ("J_yz", 1, 2), ("J_xz", 0, 2))


def property_rows(mass, cog, inertia_cog) -> list[tuple[str, float, str]]:
    """(quantity, value, unit) rows; J is about the CoG, tensor sign."""
    rows = [("mass", mass, "kg")]
    rows += [(f"CoG {a}", c * 1e3, "mm") for a, c in zip("xyz", cog)]
    rows += [(name, inertia_cog[i, k], "kg·m²") for name, i, k in INERTIA_ENTRIES]
    return rows


def body_table(body: RigidBody, title: str) -> Table:
    table = Table(title=title, caption="J about the CoG, tensor sign (off-diagonals = −products of inertia)")
    for col, justify in (("quantity", "left"), ("value", "right"), ("unit", "left")):
        table.add_column(col, justify=justify)
    for name, value, unit in property_rows(body.mass, body.cog, body.inertia_cog):
        table.add_row(name, f"{value:.6g}", unit)
    for k, (moment, axis) in enumerate(zip(body.principal_moments, body.principal_axes.T), 1):
        table.add_row(f"principal moment {k}", f"{moment:.6g}", "kg·m²")
        table.add_row(f"  axis {k}", np.array2string(axis, precision=4, suppress_small=True), "—")
    return table


def comparison_table(title: str, truth: RigidBody, results: dict) -> Table:
    """Nominal values, and per method the relative error of what it identified.

    Errors are relative to the mass, the radius of gyration (CoG) and the
    largest |J| entry, so that zero entries are judged fairly.
    """
    table = Table(title=title, caption="relative errors; — : not identified by that method")
    table.add_column("quantity")
    table.add_column("unit")
    table.add_column("nominal", justify="right")
    for name in results:
        table.add_column(name, justify="right")
    truth_rows = property_rows(truth.mass, truth.cog, truth.inertia_cog)
    scale = {"kg": truth.mass, "mm": truth.radius_of_gyration * 1e3, "kg·m²": np.abs(truth.inertia_cog).max()}
    columns = [property_rows(r.mass if r.mass is not None else np.nan, r.cog, r.inertia_cog) for r in results.values()]
    for k, (name, value, unit) in enumerate(truth_rows):
        cells = []
        for col in columns:
            v = col[k][1]
            cells.append("—" if np.isnan(v) else f"{abs(v - value) / scale[unit]:.0e}")
        table.add_row(name, unit, f"{value:.4g}", *cells)
    return table
