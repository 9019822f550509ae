"""An export's header says what it holds: values given (a CAD body, no 1-σ) are not "measured", and an
identification with no sensor mass given is not called "the body as tested" nor the bare body outright."""

from types import SimpleNamespace

import numpy as np
import pytest
from export_bodies import comment_text

from massline.core.band import Band
from massline.export.body import Body
from massline.identify.pipeline import identification_note

CAD = {"mass": 0.3456, "cog": [0.0146, 0.0288, 0.0696], "inertia": np.diag([4.4e-4, 4.0e-4, 6.1e-4])}


@pytest.mark.parametrize("suffix, marker", [("inp", "**"), ("csv", "#"), ("bdf", "$"), ("adm", "!")])
def test_cad_values_are_given_not_measured(tmp_path, suffix, marker):
    text = comment_text(Body(**CAD).export(tmp_path / f"cad.{suffix}").read_text(), marker)
    assert "given, not measured (no 1-sigma" in text and "measured (value" not in text
    assert "mass = 0.3456 kg" in text and "1-sigma not given" not in text and "recording" not in text


def test_a_measured_body_keeps_its_one_sigma(tmp_path):
    body = Body(**CAD, std={"mass": 0.004, "cog": [2e-4] * 3, "inertia_cog": np.full((3, 3), 5e-6)}, note="t.uff")
    text = comment_text(body.export(tmp_path / "m.inp").read_text(), "**")
    assert "measured (value +/- 1-sigma" in text and "mass = 0.346 +/- 0.004 kg" in text and "given" not in text


def _found(count: int):
    """What the note reads of an identification: its housings taken off, fit and band."""
    housings = SimpleNamespace(count=count, describe=lambda: f"{count} accelerometer housings x 5 g")
    best = SimpleNamespace(chi2=1.02)
    return SimpleNamespace(housings=housings, best=best, band=Band(5.0, 95.0), method="best", sigma=np.ones(4))


def test_the_note_of_an_identification_says_what_was_taken_off():
    none = identification_note(_found(0), False, "t.uff")
    assert "as tested" not in none and "none taken off (no sensor mass given)" in none
    assert "the bare body only if they weigh nothing" in none
    assert "the bare body, 6 accelerometer housings x 5 g taken off" in identification_note(_found(6), False, "")
