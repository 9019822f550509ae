"""The plan's FE model solved in a second process (virtual/fe_process.py): the same modes as solved here, an
error met there raised here, and no process left behind."""

import numpy as np
import pytest
import trimesh
from conftest import bundled

from massline.core.errors import MasslineError
from massline.meshes.loader import BodyMesh
from massline.virtual.fe_process import FEInProcess
from massline.virtual.planned_test import plan_fe_model


def test_the_second_process_solves_the_same_model(monkeypatch):
    monkeypatch.setenv("MASSLINE_CACHE", "off")
    body = bundled("plate")
    solving = FEInProcess(body, "plate")
    stages = []
    there = solving.result(lambda *stage: stages.append(stage))
    here = plan_fe_model(body, "plate")
    np.testing.assert_allclose(there.modes.omega, here.modes.omega, rtol=1e-9)
    first = np.abs(here.modes.shapes[:, 0]).max()  # the first mode (ARPACK's random start moves the last digits)
    np.testing.assert_allclose(np.abs(there.modes.shapes[:, 0]), np.abs(here.modes.shapes[:, 0]), atol=1e-6 * first)
    assert there.material == here.material and not there.kept and there.modes.n_dofs == here.modes.n_dofs
    assert not solving._process.is_alive() and stages[0][0] == "meshing" and stages[-1][1] == stages[-1][2]


def test_an_error_in_the_second_process_is_raised_here(monkeypatch):
    """Two boxes apart: more than six zero-frequency modes, refused there, the refusal raised here."""
    monkeypatch.setenv("MASSLINE_CACHE", "off")
    two = trimesh.util.concatenate([trimesh.creation.box((0.1, 0.1, 0.1)), trimesh.creation.box((0.1, 0.1, 0.1))])
    two.vertices[len(two.vertices) // 2 :] += [0.3, 0, 0]
    with pytest.raises(MasslineError, match="separate pieces"):
        FEInProcess(BodyMesh(two, 2700.0), None).result()


def test_closing_stops_the_process():
    solving = FEInProcess(bundled("bracket"), "bracket")
    solving.close()
    assert not solving._process.is_alive() and solving._process.exitcode is not None


def test_a_failed_solve_is_raised_by_check_while_the_search_runs(monkeypatch):
    """``check`` (called at each step of the layout search) raises the refusal once the solve has met it: the plan
    is refused then, not after the search; before that it returns at once."""
    import time

    monkeypatch.setenv("MASSLINE_CACHE", "off")
    two = trimesh.util.concatenate([trimesh.creation.box((0.1, 0.1, 0.1)), trimesh.creation.box((0.1, 0.1, 0.1))])
    two.vertices[len(two.vertices) // 2 :] += [0.3, 0, 0]
    solving = FEInProcess(BodyMesh(two, 2700.0), None)
    deadline = time.monotonic() + 120
    with pytest.raises(MasslineError, match="separate pieces"):
        while time.monotonic() < deadline:
            started = time.monotonic()
            solving.check()
            assert time.monotonic() - started < 1.0
            time.sleep(0.05)
    assert not solving._process.is_alive()
    solving.close()


def test_a_process_that_ends_without_a_word_is_raised_by_check():
    """Killed (as the system kills a process out of memory): ``check`` says so at the search's next step."""
    solving = FEInProcess(bundled("bracket"), "bracket")
    solving._process.kill()
    solving._process.join()
    with pytest.raises(RuntimeError, match="ended with exit code -9"):
        solving.check()
    assert solving._pipe.closed
