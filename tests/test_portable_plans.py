"""A plan names its mesh relative to itself: made in one folder, moved with its folder, simulated from another;
a mesh that did not move with it is named where plan.json says it is."""

import json
import shutil

import pytest
import trimesh
from test_cli import massline


@pytest.mark.slow
def test_a_plan_moved_with_its_folder_is_simulated_from_another(tmp_path):
    work = tmp_path / "work"
    work.mkdir()
    trimesh.creation.box(extents=(120.0, 80.0, 40.0)).export(work / "block.stl")  # mm
    options = ("--units", "mm", "--density", "2700", "--minimal", "--candidates", "300", "--out", "plan")
    run = massline("plan", "block.stl", *options, cwd=work)
    assert run.returncode == 0, run.stderr
    assert json.loads((work / "plan" / "plan.json").read_text())["mesh"] == "../block.stl"
    shutil.move(work, tmp_path / "moved")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    plan = tmp_path / "moved" / "plan" / "plan.json"
    simulated = massline("simulate", plan, "--rigid", "--out", "test.uff", cwd=elsewhere)
    assert simulated.returncode == 0, simulated.stderr
    assert (elsewhere / "test.uff").stat().st_size > 0
    (tmp_path / "moved" / "block.stl").unlink()
    lost = massline("simulate", plan, "--rigid", "--out", "lost.uff", cwd=elsewhere)
    assert lost.returncode == 2 and len(lost.stderr.strip().splitlines()) == 1
    assert "relative to itself" in lost.stderr and str(tmp_path / "moved" / "plan" / "../block.stl") in lost.stderr
