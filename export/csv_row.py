"""CSV: one row of the properties and their 1-σ, the unit of each column in the header.

Comment lines starting with '#' come first (what was measured, the frame, the sign of the inertia entries);
then RFC 4180 rows: the header and the body. The inertia entries are the tensor's (J_xy = −∫xy dm), as
identify's JSON gives them; a cell is empty where the test could not observe the entry (a plate's, §2.3) or
no 1-σ is known.
"""

from __future__ import annotations

import csv
import io

import numpy as np

from massline.core.rigid_body import SIX_INDEX
from massline.export.header import commented, header_lines, real
from massline.export.units import Units

AXES = "xyz"
CONVENTION = "columns J_xx .. J_xz are the inertia tensor's entries about the CoG, J_xy = -int(xy dm)"


def columns(body, units: Units) -> list[tuple[str, float, float]]:
    """(header, value, 1-σ) of each property in ``units``: mass, CoG, the six inertia entries, principal moments."""
    std = body.std or {}
    nan3 = np.full(3, np.nan)
    sd_cog = units.lengths(std.get("cog", nan3))
    sd_J = units.inertias(std.get("inertia_cog", np.full((3, 3), np.nan)))
    sd_moments = units.inertias(std.get("principal_moments", nan3))
    cog, J, moments = units.lengths(body.cog), units.inertias(body.inertia), units.inertias(body.principal_moments)
    found = [("mass", units.mass, units.masses(body.mass), units.masses(std.get("mass", np.nan)))]
    found += [(f"cog_{a}", units.length, cog[k], sd_cog[k]) for k, a in enumerate(AXES)]
    found += [(f"J_{AXES[i]}{AXES[j]}", units.inertia, J[i, j], sd_J[i, j]) for i, j in SIX_INDEX]
    found += [(f"principal_moment_{k + 1}", units.inertia, moments[k], sd_moments[k]) for k in range(3)]
    return [(f"{name} [{unit}]", value, sd) for name, unit, value, sd in found]


def cell(value: float) -> str:
    """A number as its cell: empty for NaN (unobserved, or no 1-σ)."""
    return "" if np.isnan(value) else real(value)


def table(body, units: Units) -> str:
    """The comment lines, the header row and the row of ``body`` (a ``Body``) in ``units``."""
    found = columns(body, units)
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow([h for name, _, _ in found for h in (name, name.replace(" [", "_1sigma ["))])
    writer.writerow([c for _, value, sd in found for c in (cell(value), cell(sd))])
    return commented(header_lines(body, units, CONVENTION), "# ") + out.getvalue()
