"""The documented deterministic planner figures (docs/validation.md) are what the benchmarks named there print.

``python benchmarks/default_plans.py`` prints the table of default and minimal plans as docs/validation.md shows
it: each row must stand there verbatim. ``python benchmarks/criteria.py`` prints criterion E against D on the
minimal layouts: the page's sentence gives E's gain in λ_min (to 0.01), its certified efficiency (to 1 %) and
log det F before and after (to 0.1), body by body, as the benchmark prints them. ``python
benchmarks/planned_bands.py`` prints each default plan's support and band: each row stands there verbatim.
Layouts, λ_min, log det and bands do not depend on the machine; the figures that do (seconds) are stated with
their machine and are not checked here, and what the diagnosable search spent, which the BLAS kernel's rounding
steers, is checked against the range the page gives over the kernels measured.
"""

import os
import platform
import re
import subprocess
import sys
from pathlib import Path

import pytest

from massline.placement.diagnosable_plan import EVALUATIONS

# the long tier (pytest -m long): each check replays a benchmark that plans the bundled bodies; CI runs it
pytestmark = pytest.mark.long

ROOT = Path(__file__).resolve().parents[1]
VALIDATION = (ROOT / "docs" / "validation.md").read_text()  # the measured figures, each with its command
SPREAD = 1.5  # how far beyond the documented range of the diagnosable search's count a machine's count may lie


def one_kernel() -> dict:
    """The environment with OpenBLAS's Haswell kernel where this CPU runs it (x86-64 with AVX2 and FMA): the
    planner's search breaks ties of exactly equal excess leverage by rounding, which the kernel's summation order
    steers (an older CPU's kernel ends the bracket's search at another layout), so the figures are printed with
    the kernel they were documented with; other CPUs run their own."""
    flags = Path("/proc/cpuinfo").read_text().split() if Path("/proc/cpuinfo").exists() else []
    haswell = platform.machine() in ("x86_64", "AMD64") and {"avx2", "fma"} <= set(flags)
    return {**os.environ, "OPENBLAS_CORETYPE": "Haswell"} if haswell else dict(os.environ)


def printed(script: str) -> list[str]:
    """The lines ``python benchmarks/SCRIPT`` prints (it plans through the command line, as a user does), with
    the documented BLAS kernel (:func:`one_kernel`)."""
    command = [sys.executable, str(ROOT / "benchmarks" / script)]
    done = subprocess.run(command, capture_output=True, text=True, env=one_kernel())
    assert done.returncode == 0, done.stderr
    return done.stdout.splitlines()


def table_rows(lines: list[str]) -> tuple[list[str], list[str]]:
    """The table rows of a benchmark's printed ``lines`` (its header rule, which begins "|-", left out), and those
    of them that do not stand verbatim in docs/validation.md."""
    rows = [line for line in lines if line.startswith("| ")]
    return rows, [row for row in rows if row not in VALIDATION]


def counts(text: str) -> dict[str, tuple[int, int]]:
    """``structure 57,895–62,600, plate 5,219`` → {name: (low, high)} (a single count is both)."""
    found = re.findall(r"(\w+)\s+([\d,]+)(?:–([\d,]+))?", text)
    return {name: (int(low.replace(",", "")), int((high or low).replace(",", ""))) for name, low, high in found}


@pytest.mark.slow
def test_the_default_plans_table_is_what_its_benchmark_prints():
    rows, missing = table_rows(printed("default_plans.py"))
    assert len(rows) == 1 + 3  # the header and the three bundled bodies
    assert not missing, missing


@pytest.mark.slow
def test_the_criterion_sentence_is_what_its_benchmark_prints():
    figures = {}
    for line in printed("criteria.py")[1:]:
        name, _, _, gain, efficiency, _, log_d, log_e = line.split()
        figures[name] = (gain, efficiency, f"{log_d} → {log_e}")
    order = ("structure", "bracket", "plate")
    sentence = re.search(r"E raises λ_min over D (.*?)\n\n", VALIDATION, re.S).group(1)  # to the paragraph's end
    sentence = " ".join(sentence.split())
    gains = ", ".join(f"{figures[n][0]} ({n})" for n in order)
    assert gains in sentence, (gains, sentence)
    assert "E-efficiency ≥ " + " / ".join(figures[n][1] for n in order) + " %" in sentence, sentence
    assert "(" + ", ".join(figures[n][2] for n in order) + ")" in sentence, sentence


@pytest.mark.slow
def test_the_planned_bands_table_is_what_its_benchmark_prints():
    """The table's rows verbatim: layouts, supports, bands and tolerances. What each default plan's diagnosable
    search spent depends on the machine's BLAS kernel (validation.md, beside the table): it ended before the
    search's budget, and lies within the range the page gives over the kernels measured, widened by SPREAD either
    way (the kernels measured spread one body's count over a factor 1.34)."""
    lines = printed("planned_bands.py")
    rows, missing = table_rows(lines)
    assert len(rows) == 1 + 4  # the header and four plans
    assert not missing, missing
    spent = counts(next(line for line in lines if line.startswith("diagnosable search, evaluations")).split(": ")[1])
    documented = counts(re.search(r"over\s+the\s+kernels\s+measured:\s+(.*?)\s+evaluations", VALIDATION).group(1))
    assert spent.keys() == documented.keys(), (spent, documented)
    for name, (count, _) in spent.items():
        low, high = documented[name]
        assert count < EVALUATIONS and low / SPREAD <= count <= high * SPREAD, (name, count, (low, high))
