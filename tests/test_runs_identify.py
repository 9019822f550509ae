"""identify and diagnose on the files a test leaves: one per run, FRFs missing, a run at another resolution,
pairs measured twice."""

import json
import re
from dataclasses import replace

import numpy as np
import pytest
from conftest import bundled
from test_cli import massline
from test_diagnose import twelve_lines

from massline.core.errors import MasslineError
from massline.core.files import to_json
from massline.identify.diagnose.pipeline import diagnose_recording
from massline.identify.pipeline import identify_recording
from massline.identify.warning_codes import codes_of
from massline.placement.hand_layouts import structure_exciters
from massline.virtual.acquisition import Acquisition, run
from massline.virtual.suspension import Cord, Suspension
from massline.uff.writer import write_runs, write_uff

BAND = (5.0, 95.0)  # Hz: between the cord's modes and the record's end (no elastic modes)


@pytest.fixture(scope="module")
def structure():
    return bundled("structure").nominal


def recording(body, seed: int):
    """The structure on a soft cord, 1 % noise, coherence, rigid, 12 sensor lines × 3 hits."""
    cord = Suspension(cords=(Cord(body.cog + [0, 0, 0.02], body.mass * 9.81 / 0.25, 1.0),))
    return run(body, twelve_lines(), structure_exciters(), None, cord, (), Acquisition(100.0, 400), seed)[0]


def gaps(rec, pairs: list, every_other: int | None = None):
    """``rec`` without the FRFs of ``pairs`` (NaN) and, with ``every_other``, that exciter's FRFs on every other
    line only."""
    frf = rec.frf.copy()
    for i, j in pairs:
        frf[i, j] = np.nan
    if every_other is not None:
        frf[:, every_other, 1::2] = np.nan
    return replace(rec, frf=frf, coherence=np.where(np.isfinite(frf), rec.coherence, np.nan))


def test_one_file_per_run_identifies_as_the_whole_file(structure, tmp_path):
    rec = recording(structure, 3)
    write_uff(tmp_path / "whole.uff", rec)
    runs = write_runs(tmp_path / "test.uff", rec)
    assert [p.name for p in runs] == ["test.run1.uff", "test.run2.uff", "test.run3.uff"]
    whole = identify_recording(tmp_path / "whole.uff", BAND, draws=0)
    split = identify_recording(runs, BAND, draws=0)
    assert split.recording.runs == tuple(p.name for p in runs)
    assert split.mass == pytest.approx(whole.mass, rel=1e-12)
    np.testing.assert_allclose(split.inertia, whole.inertia, rtol=1e-10)
    assert "frf_missing" not in codes_of(split.warnings) and split.payload["runs"] == [p.name for p in runs]


@pytest.mark.parametrize("pairs, every_other", [([(0, 0), (5, 1), (11, 2)], None), ([(2, 1)], 2)])
def test_missing_frfs_and_a_coarser_run_identify_within_the_bounds(structure, tmp_path, pairs, every_other):
    """3 of 36 FRFs dropped (or one, and the third run at half the resolution): mass 0.3 %, CoG 1 mm, moments 1 %,
    each within 3σ; the missing pairs named by code."""
    rec = gaps(recording(structure, 4), pairs, every_other)
    runs = write_runs(tmp_path / "test.uff", rec)
    found = identify_recording(runs, BAND, draws=20)
    assert found.mass == pytest.approx(structure.mass, rel=0.003)
    assert abs(found.mass - structure.mass) < 3 * found.std["mass"]
    assert np.abs(found.cog - structure.cog).max() < 1e-3
    np.testing.assert_allclose(found.body.principal_moments, structure.principal_moments, rtol=0.01)
    warning = next(w for w in found.warnings if w.code == "frf_missing")
    assert warning.text.startswith(f"{len(pairs)} of 36 response-reference pairs")
    if every_other is not None:
        assert len(found.recording.frequencies) == 400 and np.isnan(found.recording.frf[0, 2]).sum() == 200


def test_a_paper_method_refuses_a_missing_pair_and_the_diagnosis_reads_the_pairs_present(structure, tmp_path):
    """One pair not measured: the paper's method needs the whole matrix and says so; diagnose (its function and
    its command) diagnoses the runs' files from the pairs present, its properties before identify's."""
    runs = write_runs(tmp_path / "test.uff", gaps(recording(structure, 5), [(0, 0)]))
    with pytest.raises(MasslineError, match="method method2\\+method3 .* needs every response against every"):
        identify_recording(runs, BAND, draws=0, method="method2+method3")
    found = diagnose_recording(runs, BAND)
    assert [f for f in found.findings if f.kind == "fault"] == []
    assert found.before.mass == identify_recording(runs).mass
    result = massline("diagnose", *runs, "--band", *map(str, BAND), "--json", str(tmp_path / "d.json"))
    assert result.returncode == 0 and "Traceback" not in result.stderr
    assert "runs: test.run1.uff, test.run2.uff, test.run3.uff; 1 pair not measured" in result.stdout
    written = json.loads((tmp_path / "d.json").read_text())["properties"]["before"]
    assert written == json.loads(to_json(found.document["properties"]["before"]))


def test_a_repeat_within_noise_is_averaged_silently_and_one_off_by_ten_percent_is_named(structure, tmp_path):
    """The first hit measured again in a second run (its own noise): silent. The same with one pair 10 % off (a
    re-mounted sensor): warned, naming the pair and both files."""
    first, again = recording(structure, 6), recording(structure, 7)
    write_uff(tmp_path / "a.uff", first)
    write_uff(tmp_path / "b.uff", again, columns=[0])
    quiet = identify_recording([tmp_path / "a.uff", tmp_path / "b.uff"], BAND, draws=0)
    assert len(quiet.recording.repeats) == 12 and "repeat_disagrees" not in codes_of(quiet.warnings)
    off = again.frf.copy()
    off[4, 0] *= 1.1
    write_uff(tmp_path / "c.uff", replace(again, frf=off), columns=[0])
    loud = identify_recording([tmp_path / "a.uff", tmp_path / "c.uff"], BAND, draws=0)
    (warning,) = [w for w in loud.warnings if w.code == "repeat_disagrees"]
    pair = f"{loud.recording.sensor_channels[4]} / {loud.recording.exciter_channels[0]}"
    assert pair in warning.text and "a.uff and c.uff" in warning.text
    assert 8 < float(re.search(r"differs by ([\d.]+) %", warning.text).group(1)) < 12


def test_pairs_that_leave_the_moments_undetermined_are_refused_naming_the_frf_to_measure(structure, tmp_path):
    """The second and third hits each measured at one response only: the moments are undetermined; identify exits 2
    with one line naming them and a missing FRF of those hits. The lost directions span two dimensions: the
    parameters named are those of the whole null space (the CoG's z, J_xx and J_xy take ≥ 0.3 of the largest
    share, J_yz the next at 0.29), not of one basis vector of it, which LAPACK picks differently by machine."""
    pairs = [(i, 1) for i in range(1, 12)] + [(i, 2) for i in range(12) if i != 1]
    runs = write_runs(tmp_path / "test.uff", gaps(recording(structure, 9), pairs))
    result = massline("identify", *runs, "--band", *map(str, BAND))
    assert result.returncode == 2 and result.stderr.count("\n") == 1 and "Traceback" not in result.stderr
    assert "leave the CoG's z, J_xx and J_xy undetermined (22 of 36 pairs missing)" in result.stderr, result.stderr
    assert re.search(r"measure response \d+:[+-][XYZ] against reference 10[23]:", result.stderr), result.stderr


def test_identify_command_lists_the_runs(structure, tmp_path):
    runs = write_runs(tmp_path / "test.uff", gaps(recording(structure, 8), [(3, 1)]))
    out = tmp_path / "found.json"
    result = massline("identify", *runs, "--band", *map(str, BAND), "--json", out, "--bootstrap", "0")
    assert result.returncode == 0, result.stderr
    assert "runs: test.run1.uff, test.run2.uff, test.run3.uff" in result.stdout
    found = json.loads(out.read_text())
    assert found["runs"] == [p.name for p in runs]
    assert any(w["code"] == "frf_missing" for w in found["warnings"])
    folder = massline("identify", tmp_path, "--band", *map(str, BAND), "--bootstrap", "0")
    assert folder.returncode == 0 and "runs: test.run1.uff" in folder.stdout
