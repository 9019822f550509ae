"""A channel read through its chain: ``channel_delay`` and ``mount_resonance`` named, sized, undone; out of the
registry, ``unexplained`` at the channel with the signature their physics makes; the signatures themselves.

The plate's default plan with its elastic modes on the planned cord (the blind suite's bench), 1 % noise: a delay
of 60–200 µs and a mount at 2–4 × the band's top on one channel drawn by the seed (``blind_range``).
``python benchmarks/row_effects.py`` runs more cases through the command line and prints the hit rates
(docs/diagnosing.md).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from test_diagnosability import bench, default_plan

import massline.identify.diagnose.effects as registry
from massline.core.errors import MasslineError
from massline.identify.diagnose.effect_model import Layout
from massline.identify.diagnose.effects import BY_NAME, parse_effect
from massline.identify.diagnose.notes import finding_note
from massline.identify.diagnose.pipeline import diagnose_recording
from massline.identify.diagnose.row_factors import row_findings
from massline.identify.diagnose.signature import classify
from massline.identify.tails import BandData
from massline.virtual.scenarios import Conditions, scenario

SIGNATURE = {"channel_delay": ("phase_linear", "delay_s"), "mount_resonance": ("rising", "mount_hz")}
PLANE = Conditions("soft", "direct")


@pytest.fixture(scope="module")
def plate():
    _, plan = default_plan("plate")
    return bench("plate", plan)


def case(plate, faults, seed: int):
    """A blind file of the plate with ``faults`` concealed, its truth, and its planned band's data and layout."""
    rec, truth = scenario(plate, faults, seed, PLANE, effects=BY_NAME)
    band = BandData.from_recording(rec.frequencies, rec.frf, *truth["planned_band_hz"])
    return rec, truth, band, Layout.of(rec.sensors, rec.exciters, True)


@pytest.mark.parametrize("effect", list(SIGNATURE))
def test_each_is_named_at_its_channel_with_its_size_within_3_sigma(plate, effect):
    """Four seeds each: named first at the concealed channel, the size within 3σ; nothing else named."""
    for seed in range(4):
        _, truth, band, layout = case(plate, effect, seed)
        (fault,) = truth["faults"]
        found, left = row_findings(band, layout)
        assert [(f.effect, f.channels) for f in found] == [(effect, (fault["lines"][0] - 1,))] and not left, seed
        key = SIGNATURE[effect][1]
        p = found[0].parameters
        assert abs(p[key] - fault["size"]) <= 3 * p[f"{key}_std"], (seed, p, fault["size"])


def test_clean_files_have_no_row_named(plate):
    """No factor of frequency on a file with none: the plate's elastic tails and support are no chain's."""
    for seed in range(4):
        _, _, band, layout = case(plate, None, seed)
        assert row_findings(band, layout) == ([], [])


def test_both_undone_the_body_after_is_within_its_bounds_and_each_has_its_signature(plate):
    """A delay on one accelerometer and a mount on another in one file: both named by diagnose, each with its
    signature in the JSON and its sentence; undone, the body after within 0.3 % and 1 mm."""
    rec, truth, _, _ = case(plate, ("channel_delay", "mount_resonance"), 1)
    found = diagnose_recording(rec, tuple(truth["planned_band_hz"]), plate.body)
    named = {f.effect: f for f in found.findings if f.kind == "fault"}
    assert set(named) == set(SIGNATURE)
    for fault in truth["faults"]:
        finding = named[fault["name"]]
        assert finding.channels == (fault["lines"][0] - 1,)
        assert finding.parameters["signature"]["signature"] == SIGNATURE[fault["name"]][0]
        assert finding.evidence["row_chi2_reduced"]["after"] < finding.evidence["row_chi2_reduced"]["before"]
        assert "±" in finding_note(finding, found.sensors, found.hits)
    payload = json.loads(found.to_json())
    assert {f["parameters"]["signature"]["signature"] for f in payload["findings"] if f["kind"] == "fault"} == {
        "phase_linear", "rising"}  # fmt: skip
    assert abs(found.mass / plate.body.mass - 1) < 0.003
    assert np.abs(found.cog[:2] - plate.body.cog[:2]).max() < 1e-3


def test_out_of_the_registry_each_is_unexplained_at_its_channel_with_its_signature(plate, monkeypatch):
    """Both effects taken out of the registry: no fault named, and each channel's misfit ``unexplained`` there, a
    phase ∝ f at the delayed one, a rising magnitude at the mounted one."""
    rec, truth, _, _ = case(plate, ("channel_delay", "mount_resonance"), 1)
    monkeypatch.setattr(registry, "EFFECTS", tuple(e for e in registry.EFFECTS if e.name not in SIGNATURE))
    found = diagnose_recording(rec, tuple(truth["planned_band_hz"]), plate.body)
    assert not [f for f in found.findings if f.kind == "fault"]
    left = {f.channels[0]: f for f in found.findings if f.kind == "unexplained"}
    for fault in truth["faults"]:
        finding = left[fault["lines"][0] - 1]
        assert finding.parameters["signature"]["signature"] == SIGNATURE[fault["name"]][0]
        assert finding_note(finding, found.sensors, found.hits).startswith("unexplained")


@pytest.mark.parametrize(
    "text, words",
    [
        ("channel_delay=5@1", "delay must be"),
        ("mount_resonance=-550@2", "must lie in"),
        ("mount_resonance=nan@2", "finite"),
    ],
)
def test_sizes_outside_their_physical_range_are_refused(text, words):
    with pytest.raises(MasslineError, match=words):
        parse_effect(text)


@pytest.mark.parametrize(
    "ratio, column, expected",
    [
        (lambda f: np.exp(-2j * np.pi * f * 1e-3), False, "phase_linear"),
        (lambda f: 1 / (1 - (f / 90.0) ** 2), False, "rising"),
        (lambda f: -0.9 + 0 * f, False, "constant"),
        (lambda f: 1 + 0.1 / (1 - ((f - 25) / 0.4) ** 2 + 0.2j), False, "narrow"),
        (lambda f: 1 + 0.05 * np.cos(2 * np.pi * f / 4.0), True, "column_ripple"),
    ],
    ids=["phase", "rising", "constant", "narrow", "ripple"],
)
def test_each_signature_is_read_from_its_physics(ratio, column, expected):
    """A place's ratio over 10–40 Hz with 1 % noise: each physics gives its signature."""
    f = np.linspace(10.0, 40.0, 300)
    rng = np.random.default_rng(3)
    noisy = ratio(f) + 0.01 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2)
    assert classify(f, noisy, column)["signature"] == expected
