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
    """One FE-model cache for the session, shared by its workers and the commands they run (never the user's), and
    one folder of plans and virtual tests built once for every worker (:mod:`session_cache`); the process that made
    them (xdist's controller, whose environment the workers inherit) removes them at the end."""
    config._massline_folders = []
    for variable, prefix in (("MASSLINE_CACHE", "massline-fe-"), ("MASSLINE_TEST_SHARED", "massline-shared-")):
        if variable not in os.environ:
            os.environ[variable] = tempfile.mkdtemp(prefix=prefix)
            config._massline_folders.append(os.environ[variable])


def pytest_unconfigure(config):
    for folder in getattr(config, "_massline_folders", ()):
        shutil.rmtree(folder, ignore_errors=True)


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
def bracket_default_plan():
    """``massline plan bracket --out plan``, the README walkthrough's first step, once per session for every worker
    (:mod:`session_cache`): its plan.json."""
    import session_cache

    return session_cache.plan("bracket")


# Modules of a minute or more, sent to the workers first (xdist hands out whole modules in collection order) so that
# the two workers finish together instead of one running the last long module alone; the band story builds the demo
# that the identification report's module then reads (session_cache).
FIRST = ("test_simulate_cli", "test_band_story", "test_cli", "test_support_fit", "test_diagnosability", "test_footprints",
         "test_mains", "test_warning_premises", "test_lab_matrix", "test_identification_report", "test_report",
         "test_identify", "test_elastic", "test_round_parts", "test_mountable")  # fmt: skip


def pytest_collection_modifyitems(config, items):
    rank = {name: k for k, name in enumerate(FIRST)}
    items.sort(key=lambda item: rank.get(getattr(item.module, "__name__", ""), len(FIRST)))  # stable: each module's order is kept
