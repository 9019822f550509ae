"""CSV export, read by Python's csv module: one row of the properties and their 1-σ, units in the header."""

import csv
import io

import numpy as np
import pytest
from export_bodies import RELATIVE_SIGMA, assert_same_body, measured, rigid_bodies

from massline.export import Body, export_text
from massline.export.units import UNITS


def read_row(text: str) -> dict[str, str]:
    """The one data row by its header (comment lines, '#', set aside)."""
    rows = list(
        csv.DictReader(io.StringIO("".join(line for line in text.splitlines(True) if not line.startswith("#"))))
    )
    assert len(rows) == 1
    return rows[0]


def tensor(row: dict, unit: str, key: str = "") -> np.ndarray:
    """J from its six columns (J_xy is the tensor's entry, −∫xy dm)."""
    e = {n: float(row[f"J_{n}{key} [{unit}]"]) for n in ("xx", "yy", "zz", "xy", "yz", "xz")}
    return np.array([[e["xx"], e["xy"], e["xz"]], [e["xy"], e["yy"], e["yz"]], [e["xz"], e["yz"], e["zz"]]])


@pytest.mark.parametrize("name", ["bracket", "far"])
@pytest.mark.parametrize("units", list(UNITS))
def test_the_row_is_the_body_in_the_units_of_its_header(name, units):
    body, u = rigid_bodies()[name], UNITS[units]
    row = read_row(export_text(measured(body), "body.csv", u))
    mass = float(row[f"mass [{u.mass}]"]) / u.per_kilogram
    cog = np.array([float(row[f"cog_{a} [{u.length}]"]) for a in "xyz"]) / u.per_metre
    scale = u.per_kilogram * u.per_metre**2
    assert_same_body(mass, cog, tensor(row, u.inertia) / scale, body, rtol=1e-9)
    moments = [float(row[f"principal_moment_{k} [{u.inertia}]"]) / scale for k in (1, 2, 3)]
    np.testing.assert_allclose(moments, body.principal_moments, rtol=1e-9)
    assert float(row[f"mass_1sigma [{u.mass}]"]) == pytest.approx(RELATIVE_SIGMA * body.mass * u.per_kilogram)


def test_a_plate_leaves_its_unobserved_cells_empty():
    J = np.array([[1e-3, 2e-4, np.nan], [2e-4, 2e-3, np.nan], [np.nan, np.nan, np.nan]])
    row = read_row(export_text(Body(mass=0.5, cog=[0.01, 0.02, np.nan], inertia=J), "plate.csv"))
    assert row["cog_z [m]"] == row["J_zz [kg m^2]"] == row["J_xz [kg m^2]"] == row["mass_1sigma [kg]"] == ""
    assert float(row["J_xy [kg m^2]"]) == 2e-4 and float(row["cog_y [m]"]) == 0.02
