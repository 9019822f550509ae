"""Abaqus input export, read by a parser written here from the Abaqus Keywords Reference: keyword lines start
with '*', comment lines with '**', data lines are comma-separated; ``*NODE``: id, x, y, z; ``*ELEMENT``: id,
node; ``*MASS``: the mass; ``*ROTARY INERTIA``: I11, I22, I33, I12, I13, I23 with I12 = −∫x₁x₂ dm (Analysis
User's Guide, "Rotary inertia"), so the tensor is [[I11, I12, I13], [I12, I22, I23], [I13, I23, I33]]."""

import numpy as np
import pytest
from export_bodies import assert_same_body, measured, rigid_bodies

from massline.export import export_text
from massline.export.units import UNITS


def keyword_blocks(text: str) -> list[tuple[str, dict, list[list[str]]]]:
    """(keyword, parameters, data lines split at commas) of each keyword line, in order."""
    blocks = []
    for line in text.splitlines():
        if line.startswith("**") or not line.strip():
            continue
        if line.startswith("*"):
            keyword, *options = [part.strip() for part in line[1:].split(",")]
            parameters = dict(option.split("=") for option in options)
            blocks.append((keyword.upper(), {k.upper(): v for k, v in parameters.items()}, []))
        else:
            blocks[-1][2].append([value.strip() for value in line.split(",") if value.strip()])
    return blocks


def read_by_the_manual(text: str, units) -> tuple[float, np.ndarray, np.ndarray]:
    """The mass and rotary inertia of the MASS and ROTARYI elements on one node, and that node's position, in SI."""
    blocks = keyword_blocks(text)
    nodes = {
        int(row[0]): np.array([float(v) for v in row[1:4]]) for k, _, rows in blocks if k == "NODE" for row in rows
    }
    element_node = {
        p["ELSET"]: int(rows[0][1]) for k, p, rows in blocks if k == "ELEMENT" and p["TYPE"] in ("MASS", "ROTARYI")
    }
    types = {p["TYPE"]: p["ELSET"] for k, p, _ in blocks if k == "ELEMENT"}
    (mass_rows,) = [rows for k, p, rows in blocks if k == "MASS" and p["ELSET"] == types["MASS"]]
    (inertia_rows,) = [rows for k, p, rows in blocks if k == "ROTARY INERTIA" and p["ELSET"] == types["ROTARYI"]]
    node = element_node[types["MASS"]]
    assert element_node[types["ROTARYI"]] == node  # both on the node at the CoG
    I11, I22, I33, I12, I13, I23 = (float(v) for v in inertia_rows[0])
    J = np.array([[I11, I12, I13], [I12, I22, I23], [I13, I23, I33]])
    length, mass = units.per_metre, units.per_kilogram
    return float(mass_rows[0][0]) / mass, nodes[node] / length, J / (mass * length**2)


@pytest.mark.parametrize("name", ["bracket", "far"])
@pytest.mark.parametrize("units", list(UNITS))
def test_the_manuals_layout_reads_the_body_back(name, units):
    body = rigid_bodies()[name]
    text = export_text(measured(body), "body.inp", UNITS[units])
    assert_same_body(*read_by_the_manual(text, UNITS[units]), body, rtol=1e-9)


def test_the_products_of_inertia_are_the_tensors_entries():
    """Abaqus's I12 = −∫x₁x₂ dm is J_xy itself: the bracket's negative J_xy is written negative."""
    body = rigid_bodies()["bracket"]
    blocks = keyword_blocks(export_text(measured(body), "b.inp"))
    (rows,) = [rows for k, _, rows in blocks if k == "ROTARY INERTIA"]
    assert body.inertia_cog[0, 1] < 0 and float(rows[0][3]) == pytest.approx(body.inertia_cog[0, 1], rel=1e-9)
