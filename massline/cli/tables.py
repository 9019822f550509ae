"""Tables with units for the terminal (rich)."""

from __future__ import annotations

from rich.table import Table

from massline.core.numbers import number, vector_text
from massline.core.properties import TENSOR
from massline.core.rigid_body import RigidBody


def body_table(body: RigidBody, title: str) -> Table:
    table = Table(title=title, caption="J about the CoG, tensor sign (off-diagonals = −products of inertia)")
    for col, justify in (("quantity", "left"), ("value", "right"), ("unit", "left")):
        table.add_column(col, justify=justify)
    for q in TENSOR:
        scale = q.resolution_scale(body) * q.scale
        table.add_row(q.name, number(q.value(body) * q.scale, scale=scale), q.unit)
    for k, (moment, axis) in enumerate(zip(body.principal_moments, body.principal_axes.T), 1):
        table.add_row(f"principal moment {k}", number(moment, scale=max(body.principal_moments)), "kg·m²")
        table.add_row(f"  axis {k}", vector_text(axis), "—")
    return table
