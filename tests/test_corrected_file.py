"""``massline diagnose --write-corrected``: the recording handed back with the named faults undone in the file's
own terms, and a header record of each correction.

The structure with twelve oblique uniaxial accelerometers and its three hits (test_diagnose's bench), 400 lines to
100 Hz, 1 % noise; each case's diagnosis once per module. On every corrected file identify gives the diagnosis's
body after and diagnose names no fault. Tolerances: the FRF corrections (a gain, a sign, a swap, a delay) are
exact up to the E20.12 values the records are written with, so the body agrees to 1e-9 relative; a moved or
turned line lives in the geometry's E13.5 fields of datasets 15 and 18 (6 significant digits, ~1e-6 m and
~1e-6 rad), so there the body agrees to 1e-6 relative, a thousandth of its 1-σ (~1e-3).
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import pyuff
from conftest import bundled
from test_cli import massline
from test_diagnose import twelve_lines

from massline.identify.diagnose.corrected_file import written_faults
from massline.identify.diagnose.effects import BY_NAME, parse_effect
from massline.identify.diagnose.finding import Finding
from massline.identify.diagnose.pipeline import diagnose_recording
from massline.core.lines import Lines
from massline.identify.pipeline import identify_recording
from massline.identify.suspicions import beyond_chance
from massline.placement.hand_layouts import structure_exciters
from massline.uff.channel_geometry import placed
from massline.uff.datasets import split
from massline.uff.grid import to_recording
from massline.uff.reader import read_uff
from massline.uff.recording import Channel
from massline.uff.writer import write_runs, write_uff
from massline.virtual.acquisition import Acquisition, run

CASES = {  # name: (effects, write_uff's options, the faults named, relative tolerance of the body)
    "gain, polarity, tilt": (("sensor_gain=0.1@5", "sensor_polarity@4", "sensor_direction=12@6"), {},
                             {"sensor_gain", "sensor_polarity", "sensor_direction"}, 1e-6),
    "swap": (("channel_swap@3,9",), {}, {"channel_swap"}, 1e-9),
    "delay": (("channel_delay=0.0002@5",), {}, {"channel_delay"}, 1e-9),
    "moved, mm, 2411, binary": (("sensor_location=0.02@3",), {"units": "MM", "acceleration": "g", "binary": True,
                                 "nodes_dataset": 2411}, {"sensor_location"}, 1e-9),
}  # fmt: skip
SLOW = {"moved, mm, 2411, binary": "a moved accelerometer's diagnosis takes 30 s, and again on the corrected file"}


def each(names):
    """The cases as pytest parameters, the slow ones marked long with their reason."""
    return [pytest.param(n, marks=pytest.mark.long(reason=SLOW[n])) if n in SLOW else n for n in names]


@pytest.fixture(scope="module")
def cases(tmp_path_factory):
    """Each case's file, its diagnosis and its corrected file, made when first asked."""
    folder, made = tmp_path_factory.mktemp("corrected"), {}
    structure = bundled("structure").nominal

    def case(name: str):
        if name not in made:
            effects, options, _, _ = CASES[name]
            rec, _ = run(structure, twelve_lines(), structure_exciters(), effects=tuple(map(parse_effect, effects)),
                         setup=Acquisition(100.0, 400))  # fmt: skip
            path = folder / f"{len(made)}.uff"
            write_uff(path, rec, **options)
            found = diagnose_recording(path)
            made[name] = path, found, found.write_corrected(path, folder / f"{len(made)}.fixed.uff")[0]
        return made[name]

    return case


def header_texts(path) -> list[str]:
    """Every 151 record's title and text lines, in file order."""
    blocks = [b for b in split(path.read_bytes(), str(path)) if b.number == 151]
    return [" ".join(line.strip() for line in (b.lines[0], b.lines[1], b.lines[2])) for b in blocks]


@pytest.mark.parametrize("name", each(CASES))
def test_identify_on_the_corrected_file_is_the_body_after_and_diagnose_finds_no_fault(cases, name):
    path, found, fixed = cases(name)
    _, _, named, tolerance = CASES[name]
    assert {f.effect for f in written_faults(found.findings)} == named
    again = identify_recording(to_recording(read_uff(fixed)))
    after = found.after.body
    assert again.body.mass == pytest.approx(after.mass, rel=tolerance)
    np.testing.assert_allclose(again.body.cog, after.cog, atol=tolerance * np.abs(after.cog).max())
    np.testing.assert_allclose(again.body.inertia_cog, after.inertia_cog, atol=tolerance * after.principal_moments[2])
    assert abs(again.body.mass - after.mass) < 1e-3 * found.after.std["mass"]
    assert not beyond_chance(again.best.chi2, again.best.dof)  # the rigid model fits the corrected file within chance
    assert [f for f in diagnose_recording(fixed).findings if f.kind == "fault"] == []


@pytest.mark.parametrize("name", each(CASES))
def test_the_header_lists_each_correction_with_its_sigma_and_the_file_keeps_the_rest(cases, name):
    """One header entry per correction, its size ± 1-σ and what changed in the file, after the file's own 151;
    every dataset of the original is there in order (units, nodes, coherence), and pyuff reads the file."""
    path, found, fixed = cases(name)
    texts = header_texts(fixed)
    assert texts[0] == header_texts(path)[0]  # the exporter's header first, as it came
    for k, finding in enumerate(written_faults(found.findings), 1):
        entry = " ".join(t for t in texts if f"correction {k} of" in t)
        assert finding.effect in entry and "+/-" in entry or finding.effect in ("sensor_polarity", "channel_swap")
        assert "In this file:" in entry
    original = [b.number for b in split(path.read_bytes(), str(path))]
    corrected = iter(b.number for b in split(fixed.read_bytes(), str(fixed)))
    assert all(n in corrected for n in original)  # a subsequence: nothing dropped, nothing reordered
    units = [b for b in split(fixed.read_bytes(), "") if b.number == 164][0].text
    assert units == [b for b in split(path.read_bytes(), "") if b.number == 164][0].text
    came, now = read_uff(path), read_uff(fixed)
    assert now.functions == came.functions and [f.kind for f in now.frfs] == [f.kind for f in came.frfs]
    assert to_recording(now).coherence is not None
    sets = pyuff.UFF(str(fixed)).read_sets()
    assert sum(s["type"] == 58 for s in sets) == len(came.functions)


def test_the_command_lists_an_unexplained_finding_uncorrected_and_refuses_to_overwrite(tmp_path):
    """A 10 mm offset at channel 3 that no effect of the library explains on this layout: diagnose leaves it
    ``unexplained``; ``--write-corrected`` writes the file with it listed, not corrected (its FRFs and lines the
    file's own), and says so; an existing file (without --force), the recording itself and a file given twice
    are refused in one line before any work, exit 2."""
    structure = bundled("structure").nominal
    effects = (parse_effect("sensor_location=0.01@3"),)
    rec, _ = run(structure, twelve_lines(), structure_exciters(), effects=effects, setup=Acquisition(100.0, 400))
    path, out = tmp_path / "offset.uff", tmp_path / "fixed.uff"
    write_uff(path, rec)
    done = massline("diagnose", path, "--write-corrected", out, "--json", tmp_path / "d.json")
    assert done.returncode == 0, done.stderr
    assert "wrote" in done.stdout and "0 corrections, 1 finding not corrected" in done.stdout
    findings = json.loads((tmp_path / "d.json").read_text())["findings"]
    assert [f["kind"] for f in findings] == ["unexplained"]
    listed = " ".join(header_texts(out))
    assert "not corrected 1 of 1, unexplained" in listed and "no effect of the library explains it" in listed
    came, now = to_recording(read_uff(path)), to_recording(read_uff(out))
    np.testing.assert_array_equal(now.frf, came.frf)
    np.testing.assert_array_equal(now.sensors.points, came.sensors.points)
    assert now.sensor_labels == came.sensor_labels
    for args in ([path, "--write-corrected", out], [path, "--write-corrected", path, "--force"],
                 [path, path, "--write-corrected", tmp_path / "other.uff"]):  # fmt: skip
        refused = massline("diagnose", *args)
        assert refused.returncode == 2 and refused.stderr.count("\n") == 1 and "Traceback" not in refused.stderr


def test_a_polarity_is_the_channel_codes_sign(cases):
    """The flipped channel keeps its data and its node: its direction code is turned in the channel table."""
    path, found, fixed = cases("gain, polarity, tilt")
    (flip,) = [f for f in found.findings if f.effect == "sensor_polarity"]
    c = flip.channels[0]
    came, now = to_recording(read_uff(path)), to_recording(read_uff(fixed))
    node, code = came.sensor_labels[c]
    assert now.sensor_labels[c] == (node, -code)
    np.testing.assert_array_equal(now.frf[c], came.frf[c])


def test_a_triaxial_turned_off_orthogonal_is_split_and_one_moved_whole_keeps_its_node():
    """The geometry: a triaxial moved as one keeps its node (moved), a flipped axis is the code's sign, three axes
    no longer orthogonal are three nodes at one point, and a hit at the same node is left where it was."""
    ids, points = np.array([1, 2]), np.array([[0.1, 0.0, 0.0], [0.0, 0.2, 0.0]])
    frames, systems = np.stack([np.eye(3)] * 2), np.zeros(2, int)
    shift = np.array([0.0, 0.01, 0.0])
    moved = {("response", k): (Channel(1, k + 1), points[0] + shift, np.eye(3)[k]) for k in range(3)}
    flip = {("response", 3): (Channel(2, 3), points[1], -np.eye(3)[2])}
    out = placed(ids, points, frames, systems, [], moved | flip)
    assert [out.labels[("response", k)] for k in range(4)] == [(1, 1), (1, 2), (1, 3), (2, -3)]
    np.testing.assert_array_equal(out.moved[1].point, points[0] + shift)
    assert not out.added and not out.systems
    tilt = np.array([0.0, np.sin(0.1), np.cos(0.1)])
    turned = {("response", 2): (Channel(1, 3), points[0], tilt)} | {
        ("response", k): (Channel(1, k + 1), points[0], np.eye(3)[k]) for k in range(2)
    }
    hit = {("reference", 0): (Channel(1, 3), points[0], np.eye(3)[2])}
    out = placed(ids, points, frames, systems, [], turned | hit)
    label = out.labels[("response", 2)]
    assert label.node == 3 and out.labels[("reference", 0)] == (1, 3) and out.labels[("response", 0)] == (1, 1)
    frame = out.systems[out.added[0].system]
    np.testing.assert_allclose(np.sign(label.code) * frame[:, abs(label.code) - 1], tilt, atol=1e-15)


def test_dataset_spans_are_the_files_bytes():
    """The spans the amended writer copies: an exporter's datasets, each from its opening to its closing
    delimiter, one after another, every one read again alike from its bytes alone."""
    path = Path(__file__).parent / "fixtures" / "uff" / "ufffiles_dataset151_164_58_55.unv"
    data = path.read_bytes()
    blocks = split(data, str(path))
    assert blocks[0].span[0] == 0 and all(a.span[1] <= b.span[0] for a, b in zip(blocks, blocks[1:]))
    for block in blocks:
        (alone,) = split(data[slice(*block.span)] + b"\n", "")
        assert (alone.number, alone.text, alone.binary) == (block.number, block.text, block.binary)


def test_hits_moved_and_turned_and_a_mount_are_written_as_the_diagnosis_undoes_them(cases, tmp_path):
    """Findings a diagnosis could make, given to the swap case's run in place of its own: hit 1 landed 10 mm off,
    hit 2 went in 6° off, channel 5 read through a 300 Hz mount. The corrected file's hits are the corrected
    recording's lines (to the E13.5 geometry), channel 5's FRFs are divided by the mount's factor (to E20.12), the
    others as they came; the header names each."""
    path, found, _ = cases("swap")
    came = to_recording(read_uff(path))
    d, e = came.exciters.directions[1], came.exciters.directions[0]
    turned = np.cos(0.1) * d + np.sin(0.1) * across(d)
    shift = 0.01 * across(e)
    findings = [
        Finding("excitation_location", (), 0, {"offset_m": list(shift), "distance_mm": 10.0, "distance_std_mm": 0.4}),
        Finding("excitation_direction", (), 1, {"direction": turned.tolist(), "angle_deg": 5.73, "angle_std_deg": 0.2}),
        Finding("mount_resonance", (4,), None, {"mount_hz": 300.0, "mount_hz_std": 6.0, "damping": 0.05}),
    ]
    [fixed] = replace(found, findings=findings).write_corrected(path, tmp_path / "hits.uff")
    now = to_recording(read_uff(fixed))
    np.testing.assert_allclose(now.exciters.points[0], came.exciters.points[0] + shift, atol=1e-6)
    np.testing.assert_allclose(now.exciters.directions[1], turned, atol=1e-5)
    factor = BY_NAME["mount_resonance"].factor(came.frequencies, 300.0)
    np.testing.assert_allclose(now.frf[4], came.frf[4] / factor, rtol=1e-11)
    others = [i for i in range(len(came.sensors)) if i != 4]
    np.testing.assert_array_equal(now.frf[others], came.frf[others])
    listed = " ".join(header_texts(fixed))
    assert all(f"correction {k} of 3, {f.effect}" in listed for k, f in enumerate(findings, 1))
    assert "its node written again" in listed  # each hit's node is its own (the writer's 101, 201, ...)


def across(d: np.ndarray) -> np.ndarray:
    """A unit vector ⊥ unit ``d``."""
    side = np.cross(d, [0.0, 0.0, 1.0] if abs(d[2]) < 0.9 else [1.0, 0.0, 0.0])
    return side / np.linalg.norm(side)


@pytest.mark.long  # a first run diagnosed, then the corrected file and a second run diagnosed together (40 s)
def test_a_second_run_merges_with_the_corrected_first(tmp_path):
    """A first run of twelve accelerometers with channel 5 reading 10 % high, a second run of two more
    accelerometers at nodes of their own (13, 14), both on the structure's three hits: the first run's corrected
    file and the second run's are read together by identify and diagnose (the runs' reading, merged by node
    label): no fault named, the mass within its 1-σ, which the second run's two lines shrink."""
    structure = bundled("structure").nominal
    extra = Lines(np.random.default_rng(9).normal(size=(2, 3)) * 0.1, np.random.default_rng(9).normal(size=(2, 3)))
    rec, _ = run(structure, twelve_lines() + extra, structure_exciters(),
                 effects=(parse_effect("sensor_gain=0.1@5"),), setup=Acquisition(100.0, 400))  # fmt: skip
    first, second = rec.frf.copy(), rec.frf.copy()
    first[12:], second[:12] = np.nan, np.nan
    paths = [tmp_path / "run1.uff", tmp_path / "run2.uff"]
    write_uff(paths[0], replace(rec, frf=first))
    write_uff(paths[1], replace(rec, frf=second))
    [fixed] = diagnose_recording(paths[0]).write_corrected(paths[0], tmp_path / "run1.fixed.uff")
    alone, both = identify_recording(fixed), identify_recording([fixed, paths[1]])
    assert both.std["mass"] < 0.8 * alone.std["mass"]
    assert abs(both.body.mass - structure.mass) < 3 * both.std["mass"]
    assert [f for f in diagnose_recording([fixed, paths[1]]).findings if f.kind == "fault"] == []


@pytest.mark.long  # a test left as three runs' files diagnosed, then the corrected runs diagnosed again (40 s)
def test_each_runs_file_is_corrected_when_the_diagnosis_read_several(tmp_path):
    """The shaker moved between runs: one file per hit (``write_runs``), channel 5 reading 10 % high and channels
    3 and 9 swapped. diagnose reads the three files together; ``--write-corrected fixed.uff`` writes fixed.RUN.uff
    beside it for each run, each with the corrections; read together, identify gives the body after (1e-9) and
    diagnose names no fault."""
    structure = bundled("structure").nominal
    effects = (parse_effect("sensor_gain=0.1@5"), parse_effect("channel_swap@3,9"))
    rec, _ = run(structure, twelve_lines(), structure_exciters(), effects=effects, setup=Acquisition(100.0, 400))
    runs = write_runs(tmp_path / "test.uff", rec)
    out = tmp_path / "fixed.uff"
    done = massline("diagnose", *runs, "--write-corrected", out, "--json", tmp_path / "d.json")
    assert done.returncode == 0, done.stderr
    fixed = [out.with_name(f"fixed.{r.stem}.uff") for r in runs]
    assert all(str(f) in done.stdout for f in fixed) and "2 corrections" in done.stdout
    after = json.loads((tmp_path / "d.json").read_text())["properties"]["after"]
    again = identify_recording(fixed)
    assert again.body.mass == pytest.approx(after["mass"], rel=1e-9)
    np.testing.assert_allclose(again.body.cog, after["cog"], rtol=0, atol=1e-9 * np.abs(after["cog"]).max())
    assert [f for f in diagnose_recording(fixed).findings if f.kind == "fault"] == []
