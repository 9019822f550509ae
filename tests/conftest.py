"""Shared bodies and paths for the tests."""

import os
import shutil
import tempfile
from pathlib import Path

# One BLAS thread per process, set before numpy loads OpenBLAS: xdist runs a worker per core, and a worker's
# OpenBLAS threads contending with the other worker's turn each small solve of the estimators into a spin
# (a 1200 × 4 least squares: 99 ms with the threads, 2.7 ms without, on 2 busy cores). The commands the tests
# run inherit it.
for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import pytest  # noqa: E402

from massline.meshes import BUNDLED  # noqa: E402
from massline.meshes.loader import load_body  # noqa: E402

FIXTURES = Path(__file__).resolve().parent / "fixtures"  # real exporters' files and CAD meshes (SOURCES.md in each)
FIXTURE_UFF = FIXTURES / "uff"
FIXTURE_MESHES = FIXTURES / "meshes"


def pytest_configure(config):
    """One FE-model cache for the session, shared by its workers and the commands they run (never the user's);
    the process that made it (xdist's controller, whose environment the workers inherit) removes it at the end."""
    if "MASSLINE_CACHE" not in os.environ:
        os.environ["MASSLINE_CACHE"] = config._massline_cache = tempfile.mkdtemp(prefix="massline-fe-")


def pytest_unconfigure(config):
    if getattr(config, "_massline_cache", None):
        shutil.rmtree(config._massline_cache, ignore_errors=True)


def bundled(name: str):
    return load_body(BUNDLED[name].path, "m", BUNDLED[name].density)


@pytest.fixture(scope="session")
def plate():
    return bundled("plate").nominal


@pytest.fixture(scope="session")
def structure():
    return bundled("structure").nominal


@pytest.fixture(scope="session")
def bracket():
    return bundled("bracket").nominal


def assert_body_close(found, expected, rtol=1e-9):
    """Mass, CoG (against the radius of gyration) and J_G (against its largest entry)."""
    import numpy as np

    assert abs(found.mass - expected.mass) <= rtol * expected.mass
    assert np.abs(found.cog - expected.cog).max() <= rtol * expected.radius_of_gyration
    assert np.abs(found.inertia_cog - expected.inertia_cog).max() <= rtol * np.abs(expected.inertia_cog).max()


@pytest.fixture(scope="session")
def bracket_default_plan(tmp_path_factory):
    """``massline plan bracket --out plan``, the README walkthrough's first step, once per session: its plan.json."""
    import subprocess
    import sys

    folder = tmp_path_factory.mktemp("bracket-default")
    run = subprocess.run([sys.executable, "-m", "massline", "plan", "bracket", "--out", str(folder)], capture_output=True,
                         text=True)  # fmt: skip
    assert run.returncode == 0, run.stderr
    return folder / "plan.json"
