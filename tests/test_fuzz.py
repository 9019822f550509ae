"""Fuzzed readers: a damaged UFF or mesh is refused with a MasslineError (exit 2), never anything else.

Seeded from the real exporters' files and meshes in tests/fixtures/ and the project's own exports
(tests/mutations.py); a short derandomised run here, ``python tests/fuzz_long.py`` pushes ≥ 10,000
mutated files through the commands themselves.
"""

import random
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from mutations import FIXTURE_MESH_UNITS, fixture_meshes, fixture_uffs, mutate, own_meshes, own_uffs

from massline.core.errors import MasslineError
from massline.meshes.loader import load_body
from massline.uff.grid import to_recording
from massline.uff.reader import read_uff

SMALL_MESH = 300_000  # bytes: the larger fixtures cost seconds per load and add no new structure
FUZZ = settings(
    max_examples=500, derandomize=True, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)


@pytest.fixture(scope="module")
def uff_seeds(tmp_path_factory):
    folder = tmp_path_factory.mktemp("own-uff")
    return [(p.suffix, p.read_bytes()) for p in fixture_uffs() + own_uffs(folder)]


@pytest.fixture(scope="module")
def mesh_seeds(tmp_path_factory):
    folder = tmp_path_factory.mktemp("own-mesh")
    fixtures = [(p, FIXTURE_MESH_UNITS[p.name]) for p in fixture_meshes() if p.stat().st_size < SMALL_MESH]
    return [(p.suffix, p.read_bytes(), units) for p, units in fixtures + own_meshes(folder)]


def outcome(call):
    """``call()``'s result, or the MasslineError it raised (anything else, a warning included, fails the test)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            return call()
        except MasslineError as refused:
            return refused


def assert_refused_in_one_line(refused: MasslineError) -> None:
    """A refusal the command line prints as one line that says something."""
    text = str(refused).strip()
    assert text and "\n" not in text and "Traceback" not in text, text


@FUZZ
@given(st.data(), st.integers(1, 3), st.randoms(use_true_random=False))
def test_uff_reader_raises_only_massline_errors(uff_seeds, tmp_path, data, steps, rng: random.Random):
    suffix, seed = data.draw(st.sampled_from(uff_seeds))
    damaged, _ = mutate(seed, rng, steps)
    path = tmp_path / f"damaged{suffix}"
    path.write_bytes(damaged)
    found = outcome(lambda: to_recording(read_uff(path)))
    if isinstance(found, MasslineError):
        assert_refused_in_one_line(found)
        return
    f = found.frequencies
    assert found.frf.shape == (len(found.sensors), len(found.exciters), len(f)) and len(f) >= 1
    assert np.isfinite(f).all() and np.all(np.diff(f) > 0), f
    assert np.isfinite(found.sensors.points).all() and np.isfinite(found.exciters.points).all()
    assert np.allclose(np.linalg.norm(found.sensors.directions, axis=1), 1.0)


@settings(FUZZ, max_examples=300)
@given(st.data(), st.integers(1, 3), st.randoms(use_true_random=False))
def test_mesh_loader_raises_only_massline_errors(mesh_seeds, tmp_path, data, steps, rng: random.Random):
    suffix, seed, units = data.draw(st.sampled_from(mesh_seeds))
    damaged, _ = mutate(seed, rng, steps)
    path = tmp_path / f"damaged{suffix}"
    path.write_bytes(damaged)
    found = outcome(lambda: load_body(path, units, 2700.0).nominal)
    if isinstance(found, MasslineError):
        assert_refused_in_one_line(found)
        return
    assert found.mass > 0 and np.isfinite(found.cog).all() and np.isfinite(found.inertia_cog).all()
    assert np.linalg.eigvalsh(found.inertia_cog).min() > 0, found.inertia_cog


def test_the_seeds_are_read(uff_seeds, mesh_seeds):
    """The unmutated own exports identify-ready, the fixture meshes of known units load: mutations start from
    files the tools accept."""
    assert len(uff_seeds) >= 18 and len(mesh_seeds) >= 8


def test_commands_exit_0_or_2_on_damaged_files(tmp_path):
    """A short seeded run of tests/fuzz_long.py: mutated files through identify, diagnose and props."""
    import signal

    from fuzz_long import SHARES, _alarm, one_run, seeds

    signal.signal(signal.SIGALRM, _alarm)
    (tmp_path / "out").mkdir()
    pool, rng, failures = seeds(tmp_path), random.Random(0), []
    for k in range(80):
        command = rng.choices([c for c, _ in SHARES], [w for _, w in SHARES])[0]
        code, found, names, _ = one_run(command, rng.choice(pool[command]), rng, tmp_path)
        failures += [(command, names, found)] if found else []
    assert not failures
