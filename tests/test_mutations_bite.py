"""The suite fails when the science is wrong: known mutations of the code, each caught by a test.

Each mutation is applied to a copy of the package (laid out as pyproject.toml maps it into ``massline``) by an
exact string replacement that must match once, so this check fails loudly when the code moves; the test files
that should catch it then run against the copy, in a subprocess with the copy first on the path, and must fail.
The unmutated copy must pass the same selection, so a failure is the mutation's.

* eq. (13)'s J_xy coefficient with its sign flipped (the plate method): the Table 1 plate has J_xy = 0 and
  cannot see it; the rotated plates of ``test_oblique_bodies`` do.
* the covariance not scaled by the reduced χ²: no test with χ² ≈ 1 can see it; the concealed fault of
  ``test_oblique_bodies`` (χ² ≈ 100) does.
* each labelled housing taken off one point along (``Housings.on``'s branch for a file's node labels): recordings
  simulated in memory carry no labels, and housings all alike are the same wherever they sit; the bracket's
  25 g and 8 g housings written as a Universal File and read back (``test_housing_masses``) put its CoG 3.4 mm
  off, hundreds of σ.
* the certified efficiency made 10 % optimistic: a bound clipped at 100 % still looked plausible; the stated
  D-efficiency must be the certificate's own and at most the true one against a brute-forced best, above 1 an
  error (``test_criterion``, a 12 × 9 candidate problem).
* the misfit warning's false-alarm rate (``CHANCE``) 10 times likelier or rarer: above ~30 degrees of freedom the
  floor on the reduced χ² decides and hides it; the threshold is pinned at 10 degrees of freedom, where the rate
  decides, against the stated one in a thousand (``test_warning_premises``).
* kgf read as a newton: no file of the tests labels its force in kgf; every spelling the UFF reader accepts is read
  at its SI factor (``test_unit_labels``).
* the mesh's mass check back at 20 %: a body 13.6 % heavier than its mesh (8 accelerometers of 5 g on a 0.295 kg
  hub) went unsaid; 3σ and 2 % name it (``test_warning_premises``).
"""

import os
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

# it checks the suite, not the product: each mutation reruns test files on a copy (minutes in all): the long tier
pytestmark = pytest.mark.long

ROOT = Path(__file__).resolve().parent.parent
TESTS = Path(__file__).resolve().parent

MUTATIONS = {
    "eq. 13's J_xy sign": (
        "core/plate.py",
        "np.column_stack([ax, 0 * ax, ay])",
        "np.column_stack([ax, 0 * ax, -ay])",
        ["test_oblique_bodies.py", "-k", "plate"],
    ),
    "covariance not scaled by χ²": (
        "identify/estimator.py",
        "covariance = np.linalg.inv(system.step()[2]) * (max(chi2, 1.0) if np.isfinite(chi2) else 1.0)",
        "covariance = np.linalg.inv(system.step()[2])",
        ["test_oblique_bodies.py", "-k", "fault"],
    ),
    "housings one point off their node labels": (
        "identify/sensor_mass.py",
        "labels_k, points = labels_k[order], sensors.points[first[order]]",
        "labels_k, points = labels_k[order], np.roll(sensors.points[first[order]], 1, axis=0)",
        ["test_housing_masses.py", "-k", "node_labels"],
    ),
    "certified efficiency 10 % optimistic": (
        "placement/certification.py",
        "efficiency = criterion.efficiency(value, max(bounds.values()), p)",
        "efficiency = 1.1 * criterion.efficiency(value, max(bounds.values()), p)",
        ["test_criterion.py", "-k", "stated_d_efficiency"],
    ),
    "misfit false alarms 10 times likelier": (
        "identify/suspicions.py",
        "CHANCE = 1e-3",
        "CHANCE = 1e-2",
        ["test_warning_premises.py", "-k", "false_alarm"],
    ),
    "misfit false alarms 10 times rarer": (
        "identify/suspicions.py",
        "CHANCE = 1e-3",
        "CHANCE = 1e-4",
        ["test_warning_premises.py", "-k", "false_alarm"],
    ),
    "kgf read as a newton": (
        "uff/frf_kind.py",
        '"kgf": (G, FORCE),',
        '"kgf": (1.0, FORCE),',
        ["test_unit_labels.py", "-k", "unit_spelling"],
    ),
    "the mesh's mass check back at 20 %": (
        "identify/plausibility.py",
        "NOMINAL = 0.02",
        "NOMINAL = 0.2",
        ["test_warning_premises.py", "-k", "heavier_than_its_mesh"],
    ),
}


def package_copy(folder: Path) -> Path:
    """The package tree as ``massline`` under ``folder`` (pyproject's package-dir), returned as the path root."""
    mapping = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-dir"]
    for package, source in sorted(mapping.items()):
        target = folder.joinpath(*package.split("."))
        shutil.copytree(ROOT / source, target, ignore=shutil.ignore_patterns("__pycache__"), dirs_exist_ok=True)
    return folder


def mutate(root: Path, source: str, old: str, new: str) -> None:
    """Replace ``old`` by ``new`` in the copy's ``source`` (a repository path), where it occurs exactly once."""
    package = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-dir"]
    top, rest = source.split("/", 1)
    [name] = [k for k, v in package.items() if v == top]
    path = root.joinpath(*name.split("."), rest)
    text = path.read_text()
    assert text.count(old) == 1, f"the mutation's target moved: {old!r} occurs {text.count(old)}× in {source}"
    path.write_text(text.replace(old, new))


def run_tests(root: Path, selection: list[str], basetemp: Path) -> subprocess.CompletedProcess:
    """pytest on the repository's ``selection`` (files in tests/, then options) with the copy as ``massline``."""
    env = {**os.environ, "PYTHONPATH": str(root)}
    where = "import massline.core.plate as p, massline.identify.estimator as e; print(p.__file__, e.__file__)"
    check = subprocess.run([sys.executable, "-c", where], env=env, capture_output=True, text=True, cwd=TESTS)
    assert all(Path(f).is_relative_to(root) for f in check.stdout.split()), check.stdout + check.stderr
    files, options = (
        [str(TESTS / s) for s in selection if s.endswith(".py")],
        [s for s in selection if not s.endswith(".py")],
    )
    command = [sys.executable, "-m", "pytest", *files, *options, "-n", "0", "-q", "-p", "no:cacheprovider"]
    return subprocess.run(command + [f"--basetemp={basetemp}"], env=env, capture_output=True, text=True, cwd=TESTS)


@pytest.mark.slow
@pytest.mark.parametrize("name", MUTATIONS)
def test_the_mutation_makes_a_test_fail(name, tmp_path):
    source, old, new, selection = MUTATIONS[name]
    clean = package_copy(tmp_path / "clean")
    passed = run_tests(clean, selection, tmp_path / "run-clean")
    assert passed.returncode == 0, passed.stdout[-3000:] + passed.stderr[-2000:]
    mutated = package_copy(tmp_path / "mutated")
    mutate(mutated, source, old, new)
    failed = run_tests(mutated, selection, tmp_path / "run-mutated")
    assert failed.returncode == 1 and " failed" in failed.stdout, failed.stdout[-3000:] + failed.stderr[-2000:]
