"""The documented deterministic planner figures (docs/validation.md) are what the benchmarks named there print.

``python benchmarks/default_plans.py`` prints the table of default and minimal plans as docs/validation.md shows
it: each row must stand there verbatim. ``python benchmarks/criteria.py`` prints criterion E against D on the
minimal layouts: the page's sentence gives E's gain in λ_min (to 0.01), its certified efficiency (to 1 %) and
log det F before and after (to 0.1), body by body, as the benchmark prints them. ``python
benchmarks/planned_bands.py`` prints each default plan's support and band: each row stands there verbatim.
Layouts, λ_min, log det and bands do not depend on the machine; the figures that do (seconds) are stated with
their machine and are not checked here.
"""

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
VALIDATION = (ROOT / "docs" / "validation.md").read_text()  # the figures moved here from the README (issue 30)


def printed(script: str) -> list[str]:
    """The lines ``python benchmarks/SCRIPT`` prints (it plans through the command line, as a user does)."""
    done = subprocess.run([sys.executable, str(ROOT / "benchmarks" / script)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout.splitlines()


def table_rows(script: str) -> tuple[list[str], list[str]]:
    """The table rows ``python benchmarks/SCRIPT`` prints (its header rule, which begins "|-", left out), and those
    of them that do not stand verbatim in docs/validation.md."""
    rows = [line for line in printed(script) if line.startswith("| ")]
    return rows, [row for row in rows if row not in VALIDATION]


@pytest.mark.slow
def test_the_default_plans_table_is_what_its_benchmark_prints():
    rows, missing = table_rows("default_plans.py")
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
    rows, missing = table_rows("planned_bands.py")
    assert len(rows) == 1 + 4  # the header and four plans
    assert not missing, missing
