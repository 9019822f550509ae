"""The FE-model cache: modes read back are the modes solved; a changed model is solved anew; a broken cache is passed over."""

import numpy as np
import trimesh
from test_cli import massline

from massline.virtual.fe_cache import cached_modes, model_key
from massline.virtual.elastic import ElasticBody, Material

ALUMINIUM = Material(70e9, 0.33, 2700.0)
BOX = trimesh.creation.box((0.1, 0.05, 0.02))


def solve(size=0.01, n=4):
    return ElasticBody.from_mesh(BOX, ALUMINIUM, size).modes(n)


def test_kept_modes_are_the_solved_modes(tmp_path, monkeypatch):
    monkeypatch.setenv("MASSLINE_CACHE", str(tmp_path))
    solved, kept = cached_modes(BOX, ALUMINIUM, 0.01, 4, solve)
    assert not kept and len(list(tmp_path.glob("*.npz"))) == 1
    again, kept = cached_modes(BOX, ALUMINIUM, 0.01, 4, lambda: 1 / 0)
    assert kept
    np.testing.assert_array_equal(again.omega, solved.omega)
    points = np.array([[0.05, 0.025, 0.01], [-0.03, 0.0, -0.01]])
    np.testing.assert_allclose(again.shapes_at(points), solved.shapes_at(points), rtol=0, atol=1e-12)


def test_a_changed_model_is_solved_anew():
    key = model_key(BOX, ALUMINIUM, 0.01, 4)
    assert key != model_key(BOX, ALUMINIUM, 0.01, 5)
    assert key != model_key(BOX, Material(70e9, 0.33, 2800.0), 0.01, 4)
    assert key != model_key(BOX, ALUMINIUM, 0.012, 4)
    assert key != model_key(trimesh.creation.box((0.1, 0.05, 0.021)), ALUMINIUM, 0.01, 4)


def test_a_broken_or_unwritable_cache_is_passed_over(tmp_path, monkeypatch):
    monkeypatch.setenv("MASSLINE_CACHE", str(tmp_path))
    (tmp_path / f"{model_key(BOX, ALUMINIUM, 0.01, 4)}.npz").write_bytes(b"not a zip")
    modes, kept = cached_modes(BOX, ALUMINIUM, 0.01, 4, solve)
    assert not kept and len(modes.omega) == 4
    blocked = tmp_path / "file"
    blocked.write_text("")
    monkeypatch.setenv("MASSLINE_CACHE", str(blocked / "sub"))
    assert not cached_modes(BOX, ALUMINIUM, 0.01, 4, solve)[1]
    monkeypatch.setenv("MASSLINE_CACHE", "off")
    assert not cached_modes(BOX, ALUMINIUM, 0.01, 4, solve)[1]
    assert not list(tmp_path.glob("*.part"))


def test_simulate_reads_the_model_plan_solved(tmp_path, monkeypatch):
    monkeypatch.setenv("MASSLINE_CACHE", str(tmp_path / "cache"))
    plan = massline("plan", "plate", "--out", tmp_path / "plan")
    assert plan.returncode == 0, plan.stderr
    assert "kept from an earlier run" not in plan.stdout
    run = massline("simulate", tmp_path / "plan" / "plan.json", "--out", tmp_path / "sim")
    assert run.returncode == 0, run.stderr
    assert "kept from an earlier run" in run.stdout
