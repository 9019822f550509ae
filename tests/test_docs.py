"""The documentation holds what the code does.

- Every ``massline COMMAND`` in README.md and docs/*.md is a command, and every ``--option`` written after it (in
  a code block or an inline code span) is in ``massline COMMAND --help``. An option in an inline span with no
  command is one of massline's (any command's) or of a script the page names (``python benchmarks/X.py``,
  ``python tests/X.py``: the option's string is in that script's source); spans that begin with a pytest option
  (``-n``, ``-k``, ``-m``) or with ``pytest`` are pytest's and not checked.
- Every relative link and image resolves to a file of the repository, and an anchor to a heading of it.
- The README's walkthrough (the ``$ massline ...`` lines of its "A test in five steps") runs as written, in order,
  in an empty folder, each exiting 0 and printing the kinds of line the README shows.
- No figure without the command that prints it: every section of docs/validation.md that states a figure names a
  script that prints it; on every other page, a paragraph or list item that states a measured figure (a χ², a
  before → after, a value ± its 1-σ, a time, a size, a count of cases, a ratio, a decimal percentage, four
  significant digits) names, in code, a script of benchmarks/ or tests/, a ``pytest`` run or a ``massline``
  command. Design values (defaults, thresholds, tolerances) are not measured and need none.
"""

import argparse
import os
import re
import subprocess
import sys
from functools import cache
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
COMMANDS = ("props", "plan", "setup", "simulate", "report", "identify", "diagnose", "demo")
OPTION = re.compile(r"(?<![\w-])--[a-z][a-z0-9-]*")
SCRIPT = re.compile(r"\b((?:benchmarks|tests)/[\w/]+\.py)\b")
FENCE = re.compile(r"^ *```(\w*)\n(.*?)^ *```", re.S | re.M)
INDENTED = re.compile(r"(?<=\n\n)(?:(?: {4}|\t).*(?:\n|\Z))+")  # a code block: it cannot interrupt a paragraph
SPAN = re.compile(r"`((?:[^`\n]|\n(?!\s*\n))+)`")  # inline code, which may wrap a line but not a paragraph


def text(page: Path) -> str:
    return page.read_text()


def prose(page_text: str, gap: str = "") -> str:
    """The page with its fenced and indented code blocks replaced by ``gap``."""
    return INDENTED.sub(gap, FENCE.sub(gap, page_text))


@cache
def help_options(command: str | None) -> frozenset[str]:
    """The options ``massline [COMMAND] --help`` prints, from the parser the command builds (in process: eight
    interpreters' imports spared; tests/test_cli.py runs the command itself)."""
    from massline.cli.app import build_parser

    parser = build_parser([command] if command else [])
    if command:
        parser = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices[command]
    return frozenset(OPTION.findall(parser.format_help()))


def every_option() -> frozenset[str]:
    return frozenset().union(help_options(None), *(help_options(c) for c in COMMANDS))


def code_blocks(page_text: str) -> list[str]:
    """Fenced blocks (not Python; of a console block its ``$`` lines, not the output) and indented blocks, each as
    its lines; a synopsis line that starts with whitespace and "[" continues the command above it."""
    blocks = [body for lang, body in FENCE.findall(page_text) if lang not in ("python", "console")]
    blocks += [
        "\n".join(line for line in body.splitlines() if line.strip().startswith("$ "))
        for lang, body in FENCE.findall(page_text)
        if lang == "console"
    ]
    for block in INDENTED.findall(FENCE.sub("", page_text)):
        lines: list[str] = []
        for line in block.splitlines():
            if lines and re.match(r"\s+\[", line):
                lines[-1] += " " + line.strip()
            else:
                lines.append(line.strip())
        blocks.append("\n".join(lines))
    return blocks


def inline_spans(page_text: str) -> list[str]:
    """The inline code of the prose, each span on one line."""
    return [" ".join(span.split()) for span in SPAN.findall(prose(page_text))]


def command_uses(page_text: str) -> list[tuple[str, str, list[str]]]:
    """(the text, the command, the options after it) for every ``massline COMMAND`` in code."""
    found = []
    pieces = [line for block in code_blocks(page_text) for line in block.splitlines()] + inline_spans(page_text)
    for piece in pieces:
        uses = list(re.finditer(r"\bmassline ([a-z]+)\b", piece))
        for k, use in enumerate(uses):
            end = uses[k + 1].start() if k + 1 < len(uses) else len(piece)
            found.append((piece, use.group(1), OPTION.findall(piece[use.end() : end])))
    return found


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_command_and_option_named_exists(page):
    wrong = []
    for piece, command, options in command_uses(text(page)):
        if command not in COMMANDS:
            wrong.append(f"massline {command}: no such command ({piece})")
            continue
        unknown = [o for o in options if o not in help_options(command)]
        wrong += [f"massline {command} {o}: not in its --help ({piece})" for o in unknown]
    assert not wrong, "\n".join(wrong)


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_option_named_in_prose_exists(page):
    """Spans with no command: massline's options, or those of a script the page names."""
    page_text = text(page)
    scripts = [ROOT / s for s in set(SCRIPT.findall(page_text))]
    missing = [s for s in scripts if not s.is_file()]
    assert not missing, f"scripts named that do not exist: {missing}"
    sources = "\n".join(s.read_text() for s in scripts)
    wrong = []
    for span in inline_spans(page_text):
        if "massline " in span or re.match(r"-[a-z]\b|(?:\S*python -m )?pytest\b", span):  # a command's, or pytest's
            continue
        script = SCRIPT.search(span)
        known = (ROOT / script.group(1)).read_text() if script else None
        for option in OPTION.findall(span):
            if known is not None:
                ok = f'"{option}"' in known or f"'{option}'" in known
            else:
                ok = option in every_option() or f'"{option}"' in sources or f"'{option}'" in sources
            if not ok:
                wrong.append(f"{option} ({span})")
    assert not wrong, "\n".join(wrong)


def slug(heading: str) -> str:
    """GitHub's anchor of a heading."""
    heading = heading.strip().lower().replace("`", "")
    return re.sub(r"[^\w\- ]", "", heading).replace(" ", "-")


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_relative_link_resolves(page):
    unfenced = FENCE.sub("", text(page))
    wrong = []
    for target in re.findall(r"!?\[[^\]]*\]\(([^)\s]+)\)", unfenced):
        if re.match(r"[a-z]+:", target):
            continue  # http(s), mailto: not the repository's
        path, _, anchor = target.partition("#")
        file = (page.parent / path).resolve() if path else page
        if not file.is_file() or ROOT not in file.parents:
            wrong.append(f"{target}: no such file in the repository")
        elif anchor and file.suffix == ".md":
            headings = {slug(h) for h in re.findall(r"^#+ (.*)$", FENCE.sub("", file.read_text()), re.M)}
            if anchor not in headings:
                wrong.append(f"{target}: no heading #{anchor} in {file.relative_to(ROOT)}")
    assert not wrong, "\n".join(wrong)


def walkthrough() -> list[tuple[str, list[str]]]:
    """The README's walkthrough: each ``$ massline ...`` line and the output lines shown under it."""
    readme = text(ROOT / "README.md")
    section = readme.split("\n## A test in five steps\n", 1)[1].split("\n## ", 1)[0]
    steps = []
    for _, body in FENCE.findall(section):
        for line in body.splitlines():
            line = line.strip()
            if line.startswith("$ "):
                steps.append((line[2:], []))
            elif line and steps:
                steps[-1][1].append(line)
    return steps


def test_the_walkthrough_is_five_massline_steps():
    steps = walkthrough()
    assert [command.split()[1] for command, _ in steps] == ["plan", "report", "simulate", "identify", "diagnose"]


def new_shell_line() -> str:
    """The README's line that a new shell runs before the walkthrough (the venv activated, an empty folder)."""
    section = text(ROOT / "README.md").split("\n## A test in five steps\n", 1)[1].split("```", 1)[0]
    [line] = [s.strip() for s in section.splitlines() if s.startswith("    ") and "activate" in s]
    return line


@pytest.mark.slow
def test_the_readme_walkthrough_runs_as_written(tmp_path):
    """In a new shell (no venv on the PATH) from the clone's folder: the README's set-up line, then each step
    exits 0 and prints each shown line's kind (its text up to the first digit: the figures are the README's run,
    the words are what the command says)."""
    if not (ROOT / ".venv" / "bin" / "activate").is_file():
        pytest.skip("the README's .venv is not in this clone: the walkthrough's set-up line activates it")
    venv_bin = str(Path(sys.executable).parent)
    path = os.pathsep.join(p for p in os.environ["PATH"].split(os.pathsep) if p != venv_bin)
    env = {k: v for k, v in os.environ.items() if k != "VIRTUAL_ENV"} | {"PATH": path, "TMPDIR": str(tmp_path)}
    env["MASSLINE_DEBUG"] = "1"
    setup = new_shell_line()
    for command, shown in walkthrough():
        assert command.split()[0] == "massline", command
    script = "set -e\n" + setup + "\n" + "\n".join(command for command, _ in walkthrough())
    run = subprocess.run(["bash", "-c", script], capture_output=True, text=True, cwd=ROOT, env=env)
    assert run.returncode == 0, run.stderr[-2000:]
    printed = run.stdout + run.stderr
    for command, shown in walkthrough():
        for line in shown:
            kind = re.split(r"[−\d]", line, maxsplit=1)[0].rstrip()
            assert kind in printed, f"{command}: {kind!r} not printed"


def sections(page_text: str) -> list[tuple[str, str]]:
    parts = re.split(r"^(#+ .*)$", page_text, flags=re.M)
    return list(zip(parts[1::2], parts[2::2]))


def test_every_figure_in_validation_names_its_command():
    """Each section of docs/validation.md that holds a digit (a table's or a measured figure) names, in code, a
    script of benchmarks/ or tests/ that prints or checks it, and that script exists."""
    unnamed = []
    for heading, body in sections(text(ROOT / "docs" / "validation.md")):
        if not re.search(r"\d", body):
            continue
        named = [s for span in SPAN.findall(body) for s in SCRIPT.findall(span)]
        if not named or not all((ROOT / s).is_file() for s in named):
            unnamed.append(heading)
    assert not unnamed, unnamed


MEASURED = re.compile(
    "|".join(
        (
            r"χ²\s+[\d.,]*\d",  # a χ² value
            r"\d\s*(?:%|mm|µm|kg|g|°|s)?\s*→\s*\d",  # before → after
            r"\d\s*±\s*\d",  # a value ± its 1-σ
            r"\b\d+(?:\.\d+)?\s*(?:s|ms|min)\b",  # a time
            r"\b\d+(?:\.\d+)?\s*(?:kB|MB|GB|GiB)\b",  # a size
            r"\b\d[\d,]* (?:of|out of) (?:its |the )?\d",  # a count of cases
            r"\b\d[\d,]*\s+(?:passed|tests|cases|files|runs)\b",
            r"\b\d+\.\d{3,}",  # four significant digits
            r"\b\d+\.\d+\s*%",  # a decimal percentage
            r"\d\.\d+\s*×",  # a ratio
        )
    )
)
NAMES_A_RUN = re.compile(r"\b(?:benchmarks|tests)/[\w/]+\.py\b|\bpytest\b|\bmassline [a-z]+\b")


def paragraphs(page_text: str) -> list[str]:
    """The prose's paragraphs and list items (code blocks and headings out; inline code kept)."""
    text_only = re.sub(r"^#+ .*$", "\n", prose(page_text, "\n"), flags=re.M)
    return [p for p in re.split(r"\n\s*\n|\n(?=\s*(?:[-*]|\d+\.) )", text_only) if p.strip()]


NEAR = 400  # characters: a figure's command is named within this distance of it, in its paragraph


def measured_figures(paragraph: str) -> list[tuple[int, str]]:
    """(where, the figure) for each measured figure in the paragraph's prose (code and link targets blanked)."""
    bare = re.sub(rf"{SPAN.pattern}|\]\([^)]*\)", lambda m: " " * len(m.group(0)), paragraph)
    return [(m.start(), m.group(0)) for m in MEASURED.finditer(bare)]


def runs_named(paragraph: str) -> list[int]:
    """Where the paragraph's code names a script of benchmarks/ or tests/ (that exists), a pytest run or a
    massline command."""
    return [
        span.start()
        for span in SPAN.finditer(paragraph)
        for name in NAMES_A_RUN.findall(" ".join(span.group(1).split()))
        if not name.endswith(".py") or (ROOT / name).is_file()
    ]


@pytest.mark.parametrize(
    "page", [p for p in PAGES if p.name != "validation.md"], ids=lambda p: p.relative_to(ROOT).as_posix()
)
def test_every_measured_figure_names_its_command(page):
    """Each measured figure has, in its paragraph and within NEAR characters, the command that prints it."""
    unnamed = []
    for paragraph in paragraphs(text(page)):
        named = runs_named(paragraph)
        alone = [f for at, f in measured_figures(paragraph) if not any(abs(at - n) <= NEAR for n in named)]
        if alone:
            unnamed.append(f"{alone} in: {paragraph.strip()[:100]}…")
    assert not unnamed, "\n".join(unnamed)


def test_every_warning_code_and_every_effect_is_documented():
    """docs/identifying.md's warnings table holds every code of ``CODES`` (and no other), and docs/diagnosing.md
    names every effect of the registry, each as a table row's first cell."""
    from massline.identify.diagnose.effects import EFFECTS
    from massline.identify.warning_codes import CODES

    def first_cells(page: str) -> set[str]:
        return set(re.findall(r"^\| `([a-z_]+)` \|", text(ROOT / "docs" / page), re.M))

    documented = first_cells("identifying.md")
    assert documented >= set(CODES), sorted(set(CODES) - documented)
    assert not documented - set(CODES) - {e.name for e in EFFECTS}, sorted(documented - set(CODES))
    named = first_cells("diagnosing.md")
    assert named >= {e.name for e in EFFECTS}, sorted({e.name for e in EFFECTS} - named)
