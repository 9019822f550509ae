"""Printed numbers: a value to what its ± supports, no "−0", no numpy repr."""

import math
import re

import pytest
from hypothesis import given
from hypothesis import strategies as st

from massline.core.numbers import formatted, number, sigma_place, sigma_text, value_with_sigma, vector_text

finite = st.floats(min_value=-1e12, max_value=1e12, allow_nan=False, allow_infinity=False)
positive = st.floats(min_value=1e-15, max_value=1e12, allow_nan=False, allow_infinity=False)


def parsed(text: str) -> float:
    return float(text.replace("−", "-"))


def last_digit(text: str) -> float:
    """The unit of the last digit a printed number shows."""
    mantissa, _, exponent = text.replace("−", "-").partition("e")
    decimals = len(mantissa.partition(".")[2])
    return 10.0 ** (int(exponent or 0) - decimals)


def significant(text: str, place: int) -> int:
    """Significant digits of a printed σ whose last digit is at 10**place."""
    return math.floor(math.log10(parsed(text)) + 1e-9) - place + 1


def leading_three(sigma: float) -> int:
    """σ's three leading digits, truncated (the PDG rule's)."""
    digits = repr(sigma).partition("e")[0].replace(".", "").lstrip("0")
    return int((digits + "00")[:3])


@given(finite, positive)
def test_the_value_is_within_half_a_unit_of_its_last_digit(value, sigma):
    shown, _ = value_with_sigma(value, sigma)
    unit = 10.0 ** sigma_place(sigma)
    assert last_digit(shown) <= unit * (1 + 1e-9)
    assert abs(parsed(shown) - value) <= 0.5 * unit * (1 + 1e-9) + 1e-12 * abs(value)


@given(finite, positive)
def test_sigma_keeps_the_pdg_digits_and_the_value_its_place(value, sigma):
    shown, spread = value_with_sigma(value, sigma)
    three = leading_three(sigma)
    assert significant(spread, sigma_place(sigma)) == (1 if 355 <= three <= 949 else 2)
    assert last_digit(shown) == pytest.approx(last_digit(spread))
    assert last_digit(spread) <= 10.0 ** sigma_place(sigma) * (1 + 1e-9)
    assert parsed(spread) == pytest.approx(sigma, rel=0.15)


@given(finite, positive)
def test_no_negative_zero_and_a_shared_exponent(value, sigma):
    shown, spread = value_with_sigma(value, sigma)
    for text in (shown, spread, number(value), vector_text([value, -value, 0.0])):
        assert not re.search(r"(^|[^\d.])−0(\.0*)?($|[^\d.])", text), text
        assert "-" not in text
    assert shown.partition("e")[2] == spread.partition("e")[2]


@given(st.lists(finite, min_size=3, max_size=3))
def test_a_vector_has_no_numpy_repr(vector):
    text = vector_text(vector)
    assert text.startswith("(") and text.endswith(")") and text.count(",") == 2
    assert "[" not in text and "  " not in text


@pytest.mark.parametrize(
    "value,sigma,expected",
    [
        (4.00127, 0.035, ("4.001", "0.035")),
        (4.00127, 0.05, ("4.00", "0.05")),
        (12.5, 0.0996, ("12.50", "0.10")),
        (2.0, 355.0, ("0", "400")),
        (-0.0001, 0.05, ("0.00", "0.05")),
        (-2.5, 0.5, ("−2.5", "0.5")),
        (4.25368e-5, 3e-7, ("4.254e−5", "0.030e−5")),
        (3e9, 2e8, ("3.00e9", "0.20e9")),
        (1.0, 0.0, ("1", "0")),
        (2.0, math.inf, ("2", "∞")),
        (math.nan, 1.0, ("unobservable", "")),
        (1.0, math.nan, ("unobservable", "")),
        (0.567, None, ("0.567", "")),
    ],
)
def test_value_with_sigma_examples(value, sigma, expected):
    assert value_with_sigma(value, sigma) == expected


def test_sigma_place_follows_the_pdg_rule():
    assert [sigma_place(s) for s in (0.0354, 0.0355, 0.0949, 0.095, 1.0)] == [-3, -2, -2, -2, -1]
    assert sigma_text(0.0996) == "0.10" and sigma_text(3e-12) == "3.0e−12" and sigma_text(math.nan) == "—"


def test_numbers_and_vectors_examples():
    assert number(0.00425368125) == "0.00425368" and number(-7.2e-18) == "−7.2e−18" and number(-0.0) == "0"
    assert vector_text([2.2e-15, 1.0, -0.0]) == "(0, 1, 0)"
    assert vector_text([0.0, 0.0, -1.0]) == "(0, 0, −1)"
    assert vector_text([0.16, 0.06, 0.006]) == "(0.16, 0.06, 0.006)"
    assert (
        formatted(-0.0001, "+.2f") == "+0.00"
        and formatted(-0.0001, ".1%") == "0.0%"
        and formatted(-3.25, ".1f") == "−3.2"
    )
    assert formatted(1650.0, ".3g") == "1.65e3" and formatted(-2.5e-5, ".2g") == "−2.5e−5"


def test_a_value_below_its_scales_resolution_is_written_zero():
    """Rounding noise is no value: 1e−16 m of CoG on a 0.1 m body prints 0; 1e−9 of the scale and above
    prints as it is, and so does any value without a scale."""
    assert number(-1.1721e-16, scale=0.1) == "0" and number(1.76668e-14 * 1e-3, scale=0.0136) == "0"
    assert number(2e-10, scale=0.1) == "2e−10" and number(-1.1721e-16) == "−1.1721e−16"


def test_props_of_a_centred_box_prints_no_rounding_noise(tmp_path):
    """A box centred on the origin: CoG and products of inertia are 0 (the mesh integrals leave ~1e−17)."""
    import trimesh

    from massline.cli.app import run
    from massline.core.properties import TENSOR
    from massline.meshes.loader import load_body
    from massline.cli.tables import body_table

    path = tmp_path / "box.stl"
    trimesh.creation.box(extents=(0.3, 0.2, 0.1)).export(path)
    body = load_body(path, "m", 2700.0).nominal
    raw = [q.value(body) for q in TENSOR if q.key == "cog" or q.index in ((0, 1), (0, 2), (1, 2))]
    assert max(abs(v) for v in raw) < 1e-12  # what the mesh gives: 0 up to rounding, maybe not exactly 0
    rows = {cells[0]: cells[1] for cells in zip(*(col._cells for col in body_table(body, "box").columns))}
    assert all(rows[name] == "0" for name in ("CoG x", "CoG y", "CoG z", "J_G xy", "J_G xz", "J_G yz")), rows
    assert run(["props", str(path), "--units", "m", "--density", "2700"]) == 0


def test_the_plans_accuracy_table_of_a_cylinder_prints_no_rounding_noise():
    """A cylinder centred on the origin (64 facets): CoG 0 up to ~1e−16 m prints 0, and its two equal moments'
    axes, whose 1-σ runs to 10⁵°, are said to be any axis, not given a ±."""
    from types import SimpleNamespace

    import numpy as np
    import trimesh

    from massline.cli.plan_console import AXIS_UNDETERMINED, std_table
    from massline.core.accuracy import predicted_std
    from massline.core.model import RigidModel
    from massline.meshes.loader import BodyMesh

    body = BodyMesh(trimesh.creation.cylinder(radius=0.04, height=0.12, sections=64), 2700.0).nominal
    body = type(body)(body.mass, body.cog + [-1.1721e-16, 0, 0], body.inertia_cog)
    model = RigidModel(body)
    information = np.diag(1e6 * np.arange(1, 11.0))
    table = std_table(SimpleNamespace(model=model, predicted_std=predicted_std(model, information)))
    rows = {cells[0]: cells[1:3] for cells in zip(*(col._cells for col in table.columns))}
    assert rows["CoG x"][0] == "0", rows
    assert rows["principal axis 2"][1] == rows["principal axis 3"][1] == AXIS_UNDETERMINED, rows
    assert rows["principal axis 1"][1] != AXIS_UNDETERMINED
