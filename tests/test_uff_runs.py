"""Several runs' files merged into one recording; missing pairs, other axes and repeats kept as they are."""

import numpy as np
import pyuff
import pytest

from massline.core.errors import MasslineError
from massline.uff.grid import to_recording
from massline.uff.reader import read_uff
from massline.uff.runs import combined, read_runs, run_paths, union_axis
from test_uff_reader import ALL, EXCITERS, FREQUENCIES, GRID, POINTS, SENSORS, function, nodes, write


def by_reference(tmp_path, functions=ALL) -> list:
    """One file per reference (a shaker moved between runs), in a folder of their own."""
    folder = tmp_path / "runs"
    folder.mkdir()
    return [
        write(folder / f"run{j + 1}.uff", [f for f in functions if (f["ref_node"], f["ref_dir"]) == e])
        for j, e in enumerate(EXCITERS)
    ]


def test_one_file_per_reference_is_the_whole_test(tmp_path):
    whole = to_recording(read_uff(write(tmp_path / "all.uff", ALL)))
    paths = by_reference(tmp_path)
    for given in (paths, [paths[0].parent]):
        runs = to_recording(read_runs(given))
        assert runs.runs == ("run1.uff", "run2.uff", "run3.uff")
        np.testing.assert_array_equal(runs.frf, whole.frf)
        np.testing.assert_array_equal(runs.sensors.points, whole.sensors.points)
        assert runs.present.all() and not runs.repeats


def test_a_pair_not_measured_is_nan_and_named(tmp_path):
    found = to_recording(read_uff(write(tmp_path / "gap.uff", ALL[:-1])))
    assert not found.present[2, 2] and found.present.sum() == 8
    assert np.isnan(found.frf[2, 2]).all() and np.isfinite(found.frf[:2]).all()
    assert (str(found.sensor_channels[2]), str(found.exciter_channels[2])) == ("3:+Z", "13:+Z")


def test_an_frf_on_a_coarser_axis_keeps_its_own_lines(tmp_path):
    coarse = function(SENSORS[2], EXCITERS[2], GRID[2, 2, ::2], f=FREQUENCIES[::2])
    found = to_recording(read_uff(write(tmp_path / "coarse.uff", [*ALL[:8], coarse])))
    np.testing.assert_array_equal(found.frequencies, FREQUENCIES)
    np.testing.assert_allclose(found.frf[2, 2, ::2], GRID[2, 2, ::2], rtol=1e-9)
    assert np.isnan(found.frf[2, 2, 1::2]).all() and np.isfinite(found.frf[0, 0]).all()


def test_a_shorter_second_run_joins_on_the_union_of_the_axes(tmp_path):
    finer = FREQUENCIES[0] + 0.25 * np.arange(2 * len(FREQUENCIES) - 1)  # twice the resolution
    second = function(SENSORS[0], (11, 2), GRID[0, 0, 0] * np.ones(len(finer)), f=finer)
    found = to_recording(read_uff(write(tmp_path / "two.uff", [*ALL, second])))
    union, index = union_axis([FREQUENCIES, finer])
    np.testing.assert_array_equal(found.frequencies, union)
    assert len(union) == len(finer) and np.isnan(found.frf[0, 0, 1::2]).all()
    assert np.isnan(found.frf[1:, 3]).all() and np.isfinite(found.frf[0, 3]).all()
    np.testing.assert_array_equal(index[0], np.arange(0, len(finer), 2))


def test_a_pair_measured_twice_is_their_mean_and_kept_as_a_repeat(tmp_path):
    again = function(SENSORS[0], EXCITERS[0], 1.1 * GRID[0, 0])
    found = to_recording(read_uff(write(tmp_path / "twice.uff", [*ALL, again])))
    np.testing.assert_allclose(found.frf[0, 0], 1.05 * GRID[0, 0], rtol=1e-9)
    (repeat,) = found.repeats
    assert (repeat.sensor, repeat.exciter, repeat.runs) == (0, 0, ("FRF 1", "FRF 10"))
    np.testing.assert_allclose(repeat.frf[1], 1.1 * GRID[0, 0], rtol=1e-9)
    assert found.kept(found.frequencies > 10).repeats[0].frf.shape[1] == (FREQUENCIES > 10).sum()


def test_repeats_are_weighted_by_their_coherence():
    frf = np.array([[1.0, np.nan, 3.0], [3.0, 2.0, np.nan]], dtype=complex)
    weights = np.array([[1.0, 1.0, 1.0], [3.0, 1.0, 1.0]])
    mean, gamma2 = combined(frf, weights)
    np.testing.assert_allclose(mean, [2.5, 2.0, 3.0])
    np.testing.assert_allclose(gamma2, [4 / 5, 1 / 2, 1 / 2])
    assert np.isnan(combined(np.full((2, 1), np.nan + 0j), None)[0]).all()


def test_a_node_placed_apart_in_two_runs_is_refused_with_both_positions(tmp_path):
    paths = by_reference(tmp_path)
    moved = {**POINTS, 2: [0, 0.201, 0]}
    x, y, z = np.array(list(moved.values())).T
    n = len(moved)
    geometry = pyuff.prepare_15(node_nums=list(moved), def_cs=[0] * n, disp_cs=[0] * n, color=[8] * n,
                                x=list(x), y=list(y), z=list(z))  # fmt: skip
    sets = [f for f in ALL if (f["ref_node"], f["ref_dir"]) == EXCITERS[1]]
    pyuff.UFF(str(paths[1])).write_sets([geometry, *sets], mode="overwrite")
    with pytest.raises(MasslineError, match=r"node 2 is at \(0 200 0\) mm in .*run1.uff and \(0 201 0\) mm in"):
        read_runs(paths)


def test_a_folder_without_runs_and_a_file_given_twice_are_refused(tmp_path):
    (tmp_path / "empty").mkdir()
    with pytest.raises(MasslineError, match="holds no .uff or .unv file"):
        run_paths([tmp_path / "empty"])
    path = write(tmp_path / "all.uff", ALL)
    with pytest.raises(MasslineError, match="is given twice"):
        run_paths([path, tmp_path / "." / "all.uff"])
    assert nodes() and run_paths([path]) == [path]
